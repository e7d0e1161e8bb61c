// A clip drawn as a body: a capsule per bone and a ball per joint in the clip's colour, in world
// metres, rebuilt from the bones' world positions every frame. Only the body proper is drawn
// (the pelvis' subtree), not placeholder roots such as Bandai's static joint_Root at the origin.
import { CylinderGeometry, Group, Mesh, MeshStandardMaterial, SphereGeometry, Vector3 } from 'three';

const BONE_RADIUS = 0.022;
const JOINT_RADIUS = 0.032;
const HEAD_RADIUS = 0.085;
const UP = new Vector3(0, 1, 0);

const boneGeometry = new CylinderGeometry(1, 1, 1, 10, 1).translate(0, 0.5, 0);
const ballGeometry = new SphereGeometry(1, 14, 10);

// The pelvis named by the page's data, else the first bone below the root with two or more
// children (the root often is a placeholder with one child).
function bodyTop(bones, pelvisName) {
  const named = pelvisName && bones.find((b) => b.name === pelvisName);
  if (named) return named;
  let bone = bones[0];
  while (bone.children.length === 1) bone = bone.children[0];
  return bone;
}

function subtree(top) {
  const bones = [];
  top.traverse((b) => bones.push(b));
  return bones;
}

export class SkeletonFigure {
  constructor(bvhClip, colour, { pelvis, head } = {}) {
    this.group = new Group();
    const material = new MeshStandardMaterial({ color: colour, roughness: 0.55, metalness: 0.0 });
    this.bones = subtree(bodyTop(bvhClip.bones, pelvis));
    const inBody = new Set(this.bones);
    // The head is a ball between the head joint and its end (no stick out of the top of the head).
    const headBone = head && this.bones.find((b) => b.name === head);
    this.headEnd = headBone && headBone.children.length === 1 ? headBone.children[0] : null;
    this.segments = [];
    for (const bone of this.bones) {
      if (bone === this.headEnd) continue;
      if (bone.parent && inBody.has(bone.parent)) {
        const mesh = new Mesh(boneGeometry, material);
        this.group.add(mesh);
        this.segments.push({ from: bone.parent, to: bone, mesh });
      }
    }
    this.joints = this.bones.filter((b) => b.name !== 'ENDSITE').map((bone) => {
      const mesh = new Mesh(ballGeometry, material);
      mesh.scale.setScalar(bone === headBone ? HEAD_RADIUS : JOINT_RADIUS);
      this.group.add(mesh);
      return { bone, mesh, end: bone === headBone ? this.headEnd : null };
    });
  }

  // Bones' matrixWorld must be current.
  update() {
    const a = new Vector3();
    const b = new Vector3();
    for (const { from, to, mesh } of this.segments) {
      from.getWorldPosition(a);
      to.getWorldPosition(b);
      const direction = b.sub(a);
      const length = direction.length();
      mesh.visible = length > 1e-4;
      if (!mesh.visible) continue;
      mesh.position.copy(a);
      mesh.quaternion.setFromUnitVectors(UP, direction.divideScalar(length));
      mesh.scale.set(BONE_RADIUS, length, BONE_RADIUS);
    }
    for (const { bone, mesh, end } of this.joints) {
      bone.getWorldPosition(mesh.position);
      if (end) mesh.position.add(end.getWorldPosition(a)).multiplyScalar(0.5);
    }
  }

  // World positions of the drawn joints (for camera fitting).
  forEachJointPosition(callback) {
    const p = new Vector3();
    for (const bone of this.bones) callback(bone.getWorldPosition(p));
  }
}
