// What three's BVHLoader does not report about a BVH file: which joints carry position channels,
// the frame count and the frame time. Read from the text in file order (the loader's bone order).

const POSITION_CHANNEL = /^[XYZ]position$/i;

export function readBvhLayout(text) {
  const joints = [];  // { name, endSite, hasPosition }
  let frames = NaN;
  let frameTime = NaN;
  const lines = text.split(/\r\n|\r|\n/);
  let inMotion = false;
  for (const raw of lines) {
    const line = raw.trim();
    if (!line) continue;
    const tokens = line.split(/\s+/);
    const keyword = tokens[0].toUpperCase();
    if (!inMotion) {
      if (keyword === 'ROOT' || keyword === 'JOINT') {
        joints.push({ name: tokens[1] ?? '', endSite: false, hasPosition: false });
      } else if (keyword === 'END') {
        joints.push({ name: 'ENDSITE', endSite: true, hasPosition: false });
      } else if (keyword === 'CHANNELS' && joints.length) {
        joints[joints.length - 1].hasPosition = tokens.slice(2).some((c) => POSITION_CHANNEL.test(c));
      } else if (keyword === 'MOTION') {
        inMotion = true;
      }
    } else if (/^frames:?$/i.test(tokens[0])) {
      frames = Number(tokens[tokens.length - 1]);
    } else if (/^frame$/i.test(tokens[0]) && /^time:?$/i.test(tokens[1] ?? '')) {
      frameTime = Number(tokens[tokens.length - 1]);
      break;
    }
  }
  return { joints, frames, frameTime };
}
