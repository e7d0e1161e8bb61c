// What three's BVHLoader does not handle or report in a BVH file: joints without a CHANNELS line
// (valid: zero channels), which joints carry position channels, the frame count and frame time.
// Read from the text in file order (the loader's bone order).

const POSITION_CHANNEL = /^[XYZ]position$/i;

function firstWord(line) {
  return line.trim().split(/\s+/)[0].toUpperCase();
}

export function readBvhLayout(text) {
  const joints = [];  // { name, endSite, hasPosition }
  let frames = NaN;
  let frameTime = NaN;
  const lines = text.split(/\r\n|\r|\n/);
  const out = [];
  let inMotion = false;
  let awaitingChannels = false;  // a ROOT/JOINT whose OFFSET was read, CHANNELS not yet
  for (const raw of lines) {
    const line = raw.trim();
    out.push(raw);
    if (!line) continue;
    const tokens = line.split(/\s+/);
    const keyword = firstWord(line);
    if (inMotion) {
      if (/^frames:?$/i.test(tokens[0])) frames = Number(tokens[tokens.length - 1]);
      else if (/^frame$/i.test(tokens[0]) && /^time:?$/i.test(tokens[1] ?? '')) frameTime = Number(tokens[tokens.length - 1]);
      continue;
    }
    if (awaitingChannels && keyword !== 'CHANNELS') {
      out.splice(out.length - 1, 0, 'CHANNELS 0');
    }
    awaitingChannels = false;
    if (keyword === 'ROOT' || keyword === 'JOINT') {
      joints.push({ name: tokens[1] ?? '', endSite: false, hasPosition: false });
    } else if (keyword === 'END') {
      joints.push({ name: 'ENDSITE', endSite: true, hasPosition: false });
    } else if (keyword === 'OFFSET') {
      awaitingChannels = joints.length > 0 && !joints[joints.length - 1].endSite;
    } else if (keyword === 'CHANNELS' && joints.length) {
      joints[joints.length - 1].hasPosition = tokens.slice(2).some((c) => POSITION_CHANNEL.test(c));
    } else if (keyword === 'MOTION') {
      inMotion = true;
    }
  }
  return { joints, frames, frameTime, text: out.join('\n') };
}
