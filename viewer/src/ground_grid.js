// The ground: a square grid on y = 0, lines every `cell` metres, brighter on whole metres. Each line
// is cut into one segment per cell, so a line running under the camera is still drawn in front of
// it (some WebGL implementations, SwiftShader among them, drop a segment that crosses the camera plane).
import { BufferGeometry, Color, Float32BufferAttribute, LineBasicMaterial, LineSegments } from 'three';

export function groundGrid(size, cell, { major = '#8a94a3', minor = '#454d58' } = {}) {
  const half = size / 2;
  const count = Math.round(size / cell);
  const positions = [];
  const colours = [];
  const majorColour = new Color(major);
  const minorColour = new Color(minor);
  for (let i = 0; i <= count; i++) {
    const along = -half + i * cell;
    const colour = Math.abs(along - Math.round(along)) < 1e-6 ? majorColour : minorColour;
    for (let j = 0; j < count; j++) {
      const from = -half + j * cell;
      positions.push(along, 0, from, along, 0, from + cell, from, 0, along, from + cell, 0, along);
      for (let k = 0; k < 4; k++) colours.push(colour.r, colour.g, colour.b);
    }
  }
  const geometry = new BufferGeometry();
  geometry.setAttribute('position', new Float32BufferAttribute(positions, 3));
  geometry.setAttribute('color', new Float32BufferAttribute(colours, 3));
  return new LineSegments(geometry, new LineBasicMaterial({ vertexColors: true }));
}
