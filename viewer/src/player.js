// The player: the page's clip sets ("scenes") on the stage, one shared timeline in seconds
// (the first clip's frames count it), the animation loop and the controls' actions.
import { Box3, Vector3 } from 'three';
import { ClipActor } from './clip_actor.js';
import { Controls, LAYOUTS, SPEEDS } from './controls.js';
import { CLIP_COLOURS } from './palette.js';
import { Stage } from './stage.js';

const MAX_STEP_SECONDS = 0.25;

// The box around clips' joints (over the whole motion, or at the current frame) down to the ground.
function panelBounds(actors, now) {
  const bounds = new Box3();
  const point = new Vector3();
  const add = (x, y, z) => bounds.expandByPoint(point.set(x, y, z));
  for (const actor of actors) {
    if (now) actor.forEachCurrentJoint(add);
    else actor.forEachExtentPoint(add);
  }
  return bounds.expandByPoint(point.set(bounds.min.x, 0, bounds.min.z));
}

function setState(root, state) {
  root.dataset.state = state;
  document.body.dataset.viewerState = state;
}

export class Player {
  // options: { layout, play, speed, scene, frame, follow } (from the page's URL)
  constructor(root, data, options = {}) {
    this.root = root;
    this.scenes = data.scenes;
    this.layout = LAYOUTS[options.layout] ? options.layout : LAYOUTS[data.layout] ? data.layout : 'overlay';
    this.speed = SPEEDS.includes(options.speed) ? options.speed : 1;
    this.playing = Boolean(options.play);
    this.following = Boolean(options.follow ?? data.follow);
    this.time = 0;
    this.actors = [];
    this.controls = new Controls(root, this.scenes, {
      onPlayToggle: () => this.setPlaying(!this.playing),
      onSeek: (frame) => this.seek(frame),
      onSpeed: (speed) => { this.speed = speed; },
      onLayout: (layout) => this.setLayout(layout),
      onFollow: (on) => this.setFollow(on),
      onScene: (index) => this.loadScene(index),
    });
    this.controls.select('speed', this.speed);
    this.controls.select('layout', this.layout);
    this.controls.select('follow', this.following);
    this.controls.showPlaying(this.playing);
    this.stage = new Stage(this.controls.viewport);
    const scene = Number.isInteger(options.scene) && options.scene >= 0 && options.scene < this.scenes.length ? options.scene : 0;
    this.controls.select('scene', scene);
    this.loadScene(scene);
    if (Number.isInteger(options.frame)) this.seek(options.frame);
    this.listenToKeys();
    this.lastTick = null;
    requestAnimationFrame((now) => this.tick(now));
  }

  loadScene(index) {
    for (const actor of this.actors) this.stage.remove(actor.group);
    this.actors = [];
    const errors = [];
    this.scenes[index].clips.forEach((spec) => {
      const name = spec.name || 'clip';
      if (spec.error) {
        errors.push(`${name} could not be read: ${spec.error}`);
        return;
      }
      const colour = CLIP_COLOURS[this.actors.length % CLIP_COLOURS.length];
      try {
        const actor = new ClipActor(spec, colour, this.actors.length + 1);
        actor.note = spec.note;
        this.actors.push(actor);
        this.stage.add(actor.group);
      } catch (error) {
        errors.push(`${name} could not be read: ${error.message}`);
      }
    });
    this.controls.showClips(this.actors.map(({ name, colour, note, traces, halos }) => ({
      name, colour, note: [note, traces.summary && `traces: ${traces.summary}`, halos.summary].filter(Boolean).join(' · '),
    })));
    this.controls.showErrors(errors);
    if (this.actors.length === 0) {
      this.rendered = false;
      setState(this.root, 'error');
      return;
    }
    const reference = this.actors[0].clip;
    this.frameRate = 1 / reference.frameTime;
    this.frames = Math.max(...this.actors.map((a) => Math.round(a.duration * this.frameRate)));
    this.duration = this.frames / this.frameRate;
    this.controls.setTimeline(this.frames);
    this.time = Math.min(this.time, this.duration - 1e-9);
    this.fitCamera();
    this.rendered = false;
    setState(this.root, 'loading');
  }

  // Each panel (all clips overlaid, or one clip each side by side) centred on its own clips, seen
  // by one camera: the whole motion in view, or, when following, the bodies as they are now.
  fitCamera() {
    const groups = this.panelGroups();
    const whole = groups.map((actors) => panelBounds(actors, false));
    this.stage.setGround(whole.reduce((all, b) => all.union(b), new Box3()));
    this.setActorsTime();
    const boxes = this.following ? groups.map((actors) => panelBounds(actors, true).expandByScalar(0.6)) : whole;
    this.centres = boxes.map((b) => b.getCenter(new Vector3()));
    const fitted = new Box3();
    boxes.forEach((b, i) => fitted.union(b.clone().translate(this.centres[0].clone().sub(this.centres[i]))));
    this.stage.fit(fitted, groups.length);
  }

  setFollow(on) {
    this.following = on;
    if (this.actors.length) this.fitCamera();
  }

  setActorsTime() {
    for (const actor of this.actors) actor.setTime(this.time);
  }

  panelGroups() {
    if (this.layout === 'side-by-side' && this.actors.length > 1) return this.actors.map((a) => [a]);
    return [this.actors];
  }

  setLayout(layout) {
    this.layout = layout;
    if (this.actors.length) this.fitCamera();
  }

  setPlaying(playing) {
    this.playing = playing;
    this.controls.showPlaying(playing);
  }

  seek(frame) {
    if (!this.frames) return;
    this.time = Math.max(0, Math.min(this.frames - 1, frame)) / this.frameRate;
  }

  step(frames) {
    this.setPlaying(false);
    this.seek(this.currentFrame() + frames);
  }

  currentFrame() {
    return Math.min(this.frames - 1, Math.floor(this.time * this.frameRate + 1e-6));
  }

  listenToKeys() {
    this.root.tabIndex = 0;
    this.root.addEventListener('keydown', (event) => {
      if (event.target.closest && event.target.closest('select, input')) return;
      if (event.key === ' ') this.setPlaying(!this.playing);
      else if (event.key === 'ArrowRight') this.step(1);
      else if (event.key === 'ArrowLeft') this.step(-1);
      else return;
      event.preventDefault();
    });
  }

  tick(now) {
    requestAnimationFrame((t) => this.tick(t));
    const elapsed = this.lastTick === null ? 0 : Math.min(MAX_STEP_SECONDS, (now - this.lastTick) / 1000);
    this.lastTick = now;
    if (!this.actors.length) return;
    if (this.playing) this.time = (this.time + elapsed * this.speed) % this.duration;
    this.setActorsTime();
    const groups = this.panelGroups();
    if (this.following) {
      this.centres = groups.map((actors) => panelBounds(actors, true).getCenter(new Vector3()));
      this.stage.follow(this.centres[0]);
    }
    this.controls.showFrame(this.currentFrame(), this.time);
    this.stage.render(groups.map((actors, i) => ({
      layers: actors.map((a) => a.layer), offset: this.centres[i].clone().sub(this.centres[0]) })));
    if (!this.rendered) {
      this.rendered = true;
      setState(this.root, 'ready');
    }
  }
}
