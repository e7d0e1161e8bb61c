// How sure the reconstruction is of each body landmark (the "expected_error" of `mocap reconstruct`'s
// frames, docs/method.md "Confidence"): a see-through ball around the landmark's joint whose radius
// is the expected error, green when it is small, through yellow, to red.
import { Color, Mesh, MeshBasicMaterial, SphereGeometry, Group, Vector3 } from 'three';

const LANDMARKS = 14;
const haloGeometry = new SphereGeometry(1, 16, 12);
const SURE = new Color('#2fbf4f');
const UNSURE = new Color('#e0402a');
const MIDDLE = new Color('#f2c12e');

// Metres to colour: ≤ 3 cm green, 10 cm yellow, ≥ 25 cm red.
export function haloColour(metres, out = new Color()) {
  const t = Math.max(0, Math.min(1, (metres - 0.03) / 0.22));
  return t < 0.32 ? out.copy(SURE).lerp(MIDDLE, t / 0.32) : out.copy(MIDDLE).lerp(UNSURE, (t - 0.32) / 0.68);
}

export class ConfidenceHalos {
  // errors: 14 numbers per frame (metres); landmarks: the joint name of each landmark ('' where none).
  constructor(bvhClip, errors, landmarks) {
    this.group = new Group();
    this.items = [];
    if (!Array.isArray(errors) || !Array.isArray(landmarks) || errors.length < LANDMARKS) return;
    this.errors = errors;
    this.frames = Math.floor(errors.length / LANDMARKS);
    landmarks.slice(0, LANDMARKS).forEach((name, k) => {
      const bone = name && bvhClip.bones.find((b) => b.name === name);
      if (!bone) return;
      const material = new MeshBasicMaterial({ transparent: true, opacity: 0.28, depthWrite: false });
      const mesh = new Mesh(haloGeometry, material);
      this.group.add(mesh);
      this.items.push({ k, bone, mesh });
    });
  }

  get summary() {
    return this.items.length ? 'halos: expected error' : '';
  }

  // Bones' matrixWorld must be current.
  setFrame(f) {
    const frame = Math.max(0, Math.min(this.frames - 1, f));
    const p = new Vector3();
    for (const { k, bone, mesh } of this.items) {
      const metres = this.errors[frame * LANDMARKS + k];
      mesh.visible = metres > 0;
      bone.getWorldPosition(p);
      mesh.position.copy(p);
      mesh.scale.setScalar(Math.max(metres, 0.005));
      haloColour(metres, mesh.material.color);
    }
  }
}
