// Joint world positions of a BVH file as three.js's BVHLoader reads it (the loader the viewer and
// most web tools use). Prints "JOINT FRAME X Y Z" lines in file units.
//   usage: node viewer/test/bvh_positions.mjs FILE.bvh [MAX_FRAMES]
// (Beside viewer/node_modules, which has three: npm ci in viewer/, as the build does.)
// The loader's keyframes are applied to its bones directly rather than through an AnimationMixer,
// whose property bindings cannot address names with ':' (every Mixamo joint): the loader's reading
// (offsets, channel order, root translation) is what is checked.
import { readFileSync } from 'node:fs';
import { BVHLoader } from 'three/addons/loaders/BVHLoader.js';

const [file, maxFramesArg] = process.argv.slice(2);
const { skeleton, clip } = new BVHLoader().parse(readFileSync(file, 'utf8'));
const bones = new Map(skeleton.bones.map((bone) => [bone.name, bone]));
const tracks = clip.tracks.map((track) => {
  const dot = track.name.lastIndexOf('.');
  return { bone: bones.get(track.name.slice(0, dot)), property: track.name.slice(dot + 1), values: track.values };
});
const frames = Math.min(clip.tracks[0].times.length, Number(maxFramesArg ?? Infinity));
const lines = [];
for (let f = 0; f < frames; f++) {
  for (const { bone, property, values } of tracks) {
    if (property === 'position') bone.position.fromArray(values, 3 * f);
    if (property === 'quaternion') bone.quaternion.fromArray(values, 4 * f);
  }
  skeleton.bones[0].updateMatrixWorld(true);
  for (const bone of skeleton.bones) {
    if (!bone.name || bone.name === 'ENDSITE') continue;
    const p = bone.getWorldPosition(bone.position.clone());
    lines.push(`${bone.name} ${f} ${p.x} ${p.y} ${p.z}`);
  }
}
process.stdout.write(lines.join('\n') + '\n');
