// Trajectories that came with a clip (the wrist inputs and estimated ankles of `mocap reconstruct`):
// a line through every frame's point (world metres, Y up) and a ball at the current frame.
import { BufferGeometry, Color, Float32BufferAttribute, Group, Line, LineBasicMaterial, LineDashedMaterial, Mesh,
  MeshBasicMaterial, SphereGeometry } from 'three';

const MARKER_RADIUS = 0.025;
const markerGeometry = new SphereGeometry(1, 12, 8);

export class Traces {
  // traces: [{ label, kind: 'wrist' | 'ankle' | ..., points: [x, y, z, ...] }]
  constructor(traces, colour) {
    this.group = new Group();
    const light = new Color(colour).lerp(new Color('#ffffff'), 0.45);
    this.items = traces.filter((t) => Array.isArray(t.points) && t.points.length >= 3).map((trace) => {
      const geometry = new BufferGeometry();
      geometry.setAttribute('position', new Float32BufferAttribute(trace.points, 3));
      const dashed = trace.kind === 'ankle';
      const material = dashed
        ? new LineDashedMaterial({ color: light, dashSize: 0.05, gapSize: 0.035 })
        : new LineBasicMaterial({ color: light });
      const line = new Line(geometry, material);
      if (dashed) line.computeLineDistances();
      const marker = new Mesh(markerGeometry, new MeshBasicMaterial({ color: light }));
      marker.scale.setScalar(MARKER_RADIUS);
      this.group.add(line, marker);
      return { trace, marker, count: trace.points.length / 3 };
    });
  }

  // What the legend says: "wrist inputs, estimated ankles" (each trace's label for other kinds).
  get summary() {
    const names = { wrist: 'wrist inputs', ankle: 'estimated ankles' };
    return [...new Set(this.items.map(({ trace }) => names[trace.kind] ?? trace.label))].join(', ');
  }

  setFrame(f) {
    for (const { trace, marker, count } of this.items) {
      const i = Math.max(0, Math.min(count - 1, f)) * 3;
      marker.position.set(trace.points[i], trace.points[i + 1], trace.points[i + 2]);
    }
  }

  forEachPoint(callback, step = 1) {
    for (const { trace, count } of this.items) {
      for (let i = 0; i < count; i += step) callback(trace.points[i * 3], trace.points[i * 3 + 1], trace.points[i * 3 + 2]);
    }
  }
}
