// One clip on the stage: its bones (scaled to metres and turned Y up as the page's data says),
// its drawn body and traces, all on one render layer (so side-by-side views can show it alone).
import { Group } from 'three';
import { BvhClip } from './bvh_clip.js';
import { SkeletonFigure } from './skeleton_figure.js';
import { Traces } from './traces.js';
import { ConfidenceHalos } from './confidence_halos.js';

// Without the unit from `mocap`'s analysis: a body spanning more than 5 units is in cm (or mm).
function guessMetresPerUnit(clip, figure) {
  clip.setFrame(0);
  clip.root.updateMatrixWorld(true);
  const points = [];
  figure.forEachJointPosition((p) => points.push(p.clone()));
  let span = 0;
  for (const a of points) for (const b of points) span = Math.max(span, a.distanceTo(b));
  return span > 500 ? 0.001 : span > 5 ? 0.01 : 1;
}

export class ClipActor {
  // spec: one clip of the page's data ({ name, bvh, metresPerUnit?, toYUp?, pelvis?, head?, landmarks?, traces?,
  // expectedErrors? }).
  // Throws an Error naming the problem when the BVH cannot be read.
  constructor(spec, colour, layer) {
    this.name = spec.name;
    this.colour = colour;
    this.clip = new BvhClip(spec.bvh);
    this.container = new Group();
    this.container.add(this.clip.root);
    this.figure = new SkeletonFigure(this.clip, colour, spec);
    const scale = spec.metresPerUnit > 0 ? spec.metresPerUnit : guessMetresPerUnit(this.clip, this.figure);
    this.container.scale.setScalar(scale);
    if (Array.isArray(spec.toYUp) && spec.toYUp.length === 4) this.container.quaternion.fromArray(spec.toYUp);
    this.traces = new Traces(spec.traces ?? [], colour);
    this.group = new Group();
    this.halos = new ConfidenceHalos(this.clip, spec.expectedErrors, spec.landmarks);
    this.group.add(this.container, this.figure.group, this.traces.group, this.halos.group);
    this.group.traverse((o) => o.layers.set(layer));
    this.layer = layer;
  }

  get duration() {
    return this.clip.duration;
  }

  frameAt(seconds) {
    return Math.min(this.clip.frameCount - 1, Math.floor(seconds / this.clip.frameTime + 1e-6));
  }

  setTime(seconds) {
    const f = this.frameAt(seconds);
    this.clip.setFrame(f);
    this.group.updateMatrixWorld(true);
    this.figure.update();
    this.traces.setFrame(f);
    this.halos.setFrame(f);
  }

  // Calls back with the world positions of the body's joints at the current frame.
  forEachCurrentJoint(callback) {
    this.figure.forEachJointPosition((p) => callback(p.x, p.y, p.z));
  }

  // Calls back with world points the camera should see: joints over the clip and trace points.
  forEachExtentPoint(callback) {
    const step = Math.max(1, Math.floor(this.clip.frameCount / 60));
    for (let f = 0; f < this.clip.frameCount; f += step) {
      this.clip.setFrame(f);
      this.group.updateMatrixWorld(true);
      this.figure.forEachJointPosition((p) => callback(p.x, p.y, p.z));
    }
    this.traces.forEachPoint(callback, step);
  }
}
