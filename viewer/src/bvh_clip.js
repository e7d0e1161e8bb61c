// One BVH clip parsed by three's BVHLoader into bones and per-frame tracks, posed frame by frame.
// Parse problems (the loader logs most of them and carries on) become one readable Error.
import { BVHLoader } from 'three/examples/jsm/loaders/BVHLoader.js';
import { readBvhLayout } from './bvh_layout.js';

function parseQuietly(text) {
  const problems = [];
  const saved = { error: console.error, warn: console.warn };
  console.error = console.warn = (...args) => problems.push(args.join(' ').replace(/^THREE\.BVHLoader:\s*/, ''));
  try {
    return { result: new BVHLoader().parse(text), problems };
  } catch (thrown) {
    return { thrown, problems };
  } finally {
    console.error = saved.error;
    console.warn = saved.warn;
  }
}

function describeFailure(problems, thrown) {
  if (problems.length) return problems[0];
  if (thrown instanceof TypeError) return 'the file ends before its hierarchy or frames are complete';
  return thrown ? String(thrown.message || thrown) : 'unreadable file';
}

// Non-root joints with position channels (Bandai's rig has them on every joint) carry the joint's
// translation itself, not an addition to its OFFSET: the reading of the project's own BVH reader.
// BVHLoader adds the OFFSET to every position track, so it is taken out again here.
function undoOffsetOnNonRootPositions(bones, layout, tracksByBone) {
  bones.forEach((bone, index) => {
    const joint = layout.joints[index];
    if (index === 0 || !joint || !joint.hasPosition) return;
    const track = tracksByBone.get(bone)?.position;
    if (!track) return;
    const v = track.values;
    for (let i = 0; i < v.length; i += 3) {
      v[i] -= bone.position.x;
      v[i + 1] -= bone.position.y;
      v[i + 2] -= bone.position.z;
    }
  });
}

export class BvhClip {
  // Throws an Error whose message says what is wrong with the text.
  constructor(text) {
    const layout = readBvhLayout(text);
    const { result, thrown, problems } = parseQuietly(layout.text);
    if (!result) throw new Error(describeFailure(problems, thrown));
    if (problems.length) throw new Error(problems[0]);
    if (!(layout.frames >= 1)) throw new Error('the file has no frames');
    if (!(layout.frameTime > 0)) throw new Error('the "Frame Time:" line is missing or not a positive number');
    this.bones = result.skeleton.bones;
    if (layout.joints.length !== this.bones.length) throw new Error('the hierarchy could not be read');
    const byName = new Map(this.bones.filter((b) => b.name !== 'ENDSITE').map((b) => [b.name, b]));
    this.tracksByBone = new Map();
    for (const track of result.clip.tracks) {
      const dot = track.name.lastIndexOf('.');
      const bone = byName.get(track.name.slice(0, dot));
      if (!bone) continue;
      for (const value of track.values) {
        if (!Number.isFinite(value)) throw new Error(`frame values of joint ${bone.name} are not all numbers`);
      }
      const entry = this.tracksByBone.get(bone) ?? {};
      entry[track.name.slice(dot + 1)] = track;
      this.tracksByBone.set(bone, entry);
    }
    const firstTrack = result.clip.tracks[0];
    if (!firstTrack || firstTrack.times.length < layout.frames) throw new Error(`the file declares ${layout.frames} frames but holds fewer`);
    undoOffsetOnNonRootPositions(this.bones, layout, this.tracksByBone);
    this.frameCount = layout.frames;
    this.frameTime = layout.frameTime;
    this.root = this.bones[0];
  }

  get duration() {
    return this.frameCount * this.frameTime;
  }

  // Poses the bones at frame `f` (clamped); world matrices are the caller's to update.
  setFrame(f) {
    const frame = Math.max(0, Math.min(this.frameCount - 1, f));
    for (const [bone, tracks] of this.tracksByBone) {
      if (tracks.position) bone.position.fromArray(tracks.position.values, frame * 3);
      if (tracks.quaternion) bone.quaternion.fromArray(tracks.quaternion.values, frame * 4);
    }
  }
}
