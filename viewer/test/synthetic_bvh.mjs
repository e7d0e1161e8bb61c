// A small humanoid BVH written by the test (not captured data): pelvis, spine, head, two arms, two
// legs, stepping in place with swinging arms; in centimetres or metres; and a `mocap reconstruct`
// style JSON with wrist and ankle points for it.

const SIDES = [['Left', 1], ['Right', -1]];

// [name, offset in cm, children]; a joint without children ends in an End Site of `end` offset.
const limb = (names, offsets, end) => names.reduceRight((child, name, i) => [[name, offsets[i], child ?? [], i === names.length - 1 ? end : undefined]], null)[0];
function body() {
  const arm = (side, s) => limb([`${side}Shoulder`, `${side}Arm`, `${side}ForeArm`, `${side}Hand`],
    [[6 * s, 18, 0], [12 * s, 0, 0], [28 * s, 0, 0], [25 * s, 0, 0]], [8 * s, 0, 0]);
  const leg = (side, s) => limb([`${side}UpLeg`, `${side}Leg`, `${side}Foot`, `${side}Toe`],
    [[9 * s, -3, 0], [0, -44, 0], [0, -42, 0], [0, -6, 13]], [0, 0, 5]);
  const head = limb(['Neck', 'Head'], [[0, 22, 0], [0, 10, 0]], [0, 16, 0]);
  const chest = ['Chest', [0, 20, 0], [head, ...SIDES.map(([side, s]) => arm(side, s))]];
  return ['Hips', [0, 0, 0], [['Spine', [0, 10, 0], [chest]], ...SIDES.map(([side, s]) => leg(side, s))]];
}

function hierarchy(unit) {
  const lines = ['HIERARCHY'];
  const offset = (o) => `OFFSET ${o.map((v) => v * unit).join(' ')}`;
  const emit = ([name, o, children, end], depth) => {
    const pad = '  '.repeat(depth);
    lines.push(`${pad}${depth === 0 ? 'ROOT' : 'JOINT'} ${name}`, `${pad}{`, `${pad}  ${offset(o)}`,
      `${pad}  CHANNELS ${depth === 0 ? '6 Xposition Yposition Zposition' : '3'} Zrotation Xrotation Yrotation`);
    for (const child of children) emit(child, depth + 1);
    if (end) lines.push(`${pad}  End Site`, `${pad}  {`, `${pad}    ${offset(end)}`, `${pad}  }`);
    lines.push(`${pad}}`);
  };
  emit(body(), 0);
  return lines.join('\n');
}

function frame(t, unit, phase) {
  const w = 2 * Math.PI * t + phase;
  const values = [0, (95 + 1.5 * Math.sin(2 * w)) * unit, 0, 0, 0, 0];  // Hips
  values.push(0, 2 * Math.sin(w), 0, 0, 0, 0, 0, 0, 0, 0, 0, 0);  // Spine, Chest, Neck, Head
  for (const [, s] of SIDES) {
    // Shoulder, Arm (down, swinging), ForeArm (bent), Hand.
    values.push(0, 0, 0, -75 * s, 25 * Math.sin(w) * s, 0, 0, -20, 0, 0, 0, 0);
  }
  for (const [, s] of SIDES) {
    const swing = Math.sin(w) * s;
    // UpLeg, Leg (knee bends backwards), Foot, Toe.
    values.push(0, 20 * swing, 0, 0, 15 * (1 + swing), 0, 0, 0, 0, 0, 0, 0);
  }
  return values.map((v) => v.toFixed(5)).join(' ');
}

// unit: 1 for centimetres, 0.01 for metres.
export function humanoidBvh({ unit = 1, frames = 90, frameTime = 1 / 30, phase = 0 } = {}) {
  const lines = [hierarchy(unit), 'MOTION', `Frames: ${frames}`, `Frame Time: ${frameTime.toFixed(7)}`];
  for (let f = 0; f < frames; f++) lines.push(frame(f * frameTime, unit, phase));
  return `${lines.join('\n')}\n`;
}

// The shape of `mocap reconstruct`'s JSON that `mocap view` reads: frames with wrists and ankles (m).
export function reconstructionJson({ frames = 90, frameTime = 1 / 30 } = {}) {
  const point = (x, y, z) => ({ x, y, z });
  return JSON.stringify({
    frames: Array.from({ length: frames }, (_, f) => {
      const w = 2 * Math.PI * f * frameTime;
      return {
        index: f,
        left_wrist: point(0.3, 0.95, 0.2 * Math.sin(w)),
        right_wrist: point(-0.3, 0.95, -0.2 * Math.sin(w)),
        left_ankle: point(0.09, 0.08, 0.15 * Math.sin(w)),
        right_ankle: point(-0.09, 0.08, -0.15 * Math.sin(w)),
        // docs/method.md "Confidence": a few centimetres, the ankles least sure.
        expected_error: { pelvis: 0.04, head: 0.05, left_wrist: 0.01, right_wrist: 0.01, left_ankle: 0.12 + 0.05 * Math.sin(w),
          right_ankle: 0.12 },
      };
    }),
  });
}
