// The 3D stage: renderer, scene, lights, ground grid, a perspective camera with orbit controls,
// and drawing either all clips over each other or each clip in its own panel, side by side.
import { Color, DirectionalLight, HemisphereLight, PerspectiveCamera, Scene, Vector3,
  WebGLRenderer } from 'three';
import { OrbitControls } from 'three/examples/jsm/controls/OrbitControls.js';
import { groundGrid } from './ground_grid.js';

const BACKGROUND = '#1d2127';
const FOV_DEGREES = 40;

export class Stage {
  // Throws when WebGL is unavailable.
  constructor(holder) {
    this.holder = holder;
    this.renderer = new WebGLRenderer({ antialias: true });
    this.renderer.setPixelRatio(Math.min(2, window.devicePixelRatio || 1));
    this.renderer.setScissorTest(true);
    holder.appendChild(this.renderer.domElement);
    this.scene = new Scene();
    this.scene.background = new Color(BACKGROUND);
    this.scene.add(new HemisphereLight('#ffffff', '#445060', 2.2));
    const sun = new DirectionalLight('#ffffff', 1.6);
    sun.position.set(3, 6, 4);
    this.scene.add(sun);
    this.grid = null;
    this.camera = new PerspectiveCamera(FOV_DEGREES, 1, 0.05, 500);
    this.controls = new OrbitControls(this.camera, this.renderer.domElement);
    this.controls.enableDamping = true;
    this.panels = 1;
  }

  add(object) {
    this.scene.add(object);
  }

  remove(object) {
    this.scene.remove(object);
  }

  // A grid of 0.5 m cells on y = 0 under the motion's ground-plane extent (lines on whole metres).
  setGround(bounds) {
    if (this.grid) this.scene.remove(this.grid);
    const size = 2 * Math.ceil(Math.max(bounds.max.x - bounds.min.x, bounds.max.z - bounds.min.z) / 2 + 1);
    this.grid = groundGrid(size, 0.5);
    this.grid.position.set(Math.round((bounds.min.x + bounds.max.x) / 2), 0, Math.round((bounds.min.z + bounds.max.z) / 2));
    this.scene.add(this.grid);
  }

  // Points the camera at `bounds` from the side its longer ground-plane extent faces (a walk is
  // seen crossing the view), just far enough back for every corner to fit one panel of `panels`.
  fit(bounds, panels) {
    this.panels = panels;
    const size = bounds.getSize(new Vector3());
    const centre = bounds.getCenter(new Vector3());
    const back = (size.x >= size.z ? new Vector3(0.34, 0.3, 1) : new Vector3(1, 0.3, -0.34)).normalize();
    const right = new Vector3().crossVectors(new Vector3(0, 1, 0), back).normalize();
    const up = new Vector3().crossVectors(back, right);
    const tanVertical = Math.tan((FOV_DEGREES * Math.PI) / 360);
    const tanHorizontal = tanVertical * this.panelAspect();
    let distance = 1;
    const corner = new Vector3();
    for (let i = 0; i < 8; i++) {
      corner.set(i & 1 ? bounds.max.x : bounds.min.x, i & 2 ? bounds.max.y : bounds.min.y, i & 4 ? bounds.max.z : bounds.min.z);
      corner.sub(centre);
      const towardCamera = corner.dot(back);
      distance = Math.max(distance, towardCamera + Math.abs(corner.dot(right)) / tanHorizontal,
        towardCamera + Math.abs(corner.dot(up)) / tanVertical);
    }
    distance *= 1.15;
    this.camera.position.copy(centre).addScaledVector(back, distance);
    this.camera.near = Math.max(0.01, distance / 200);
    this.camera.far = distance * 20;
    this.controls.target.copy(centre);
    this.controls.update();
  }

  // Moves the camera with its target so the target is `point` (the view keeps its angle and distance).
  follow(point) {
    const delta = point.clone().sub(this.controls.target);
    this.controls.target.add(delta);
    this.camera.position.add(delta);
  }

  panelAspect() {
    const { clientWidth: w, clientHeight: h } = this.holder;
    return Math.max(1, w) / this.panels / Math.max(1, h);
  }

  // panels, left to right: { layers: the render layers it shows, offset: where its camera stands
  // relative to the shared one (each panel centred on its own clips) }.
  render(panels) {
    const { clientWidth: w, clientHeight: h } = this.holder;
    const canvas = this.renderer.domElement;
    const ratio = this.renderer.getPixelRatio();
    if (canvas.width !== Math.floor(w * ratio) || canvas.height !== Math.floor(h * ratio)) {
      this.renderer.setSize(w, h, false);
    }
    this.controls.update();
    const panelWidth = w / panels.length;
    this.camera.aspect = panelWidth / Math.max(1, h);
    this.camera.updateProjectionMatrix();
    panels.forEach(({ layers, offset }, i) => {
      const x = Math.round(i * panelWidth);
      const width = Math.round((i + 1) * panelWidth) - x;
      this.renderer.setViewport(x, 0, width, h);
      this.renderer.setScissor(x, 0, width, h);
      this.camera.layers.set(0);
      for (const layer of layers) this.camera.layers.enable(layer);
      this.camera.position.add(offset);
      this.renderer.render(this.scene, this.camera);
      this.camera.position.sub(offset);
    });
    this.camera.layers.enableAll();
  }
}
