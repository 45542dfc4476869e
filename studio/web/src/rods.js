// Rods in the viewer: the line cells of a grid (VTK lines and polylines, as the discrete elastic
// rods write them, docs/rods.md) drawn as tubes, each segment a prism whose cross-section is laid
// out in the segment's material frame (cell fields m1, m2) so that twist shows, and the frame
// itself as two short glyphs at each segment's middle (m1 red, m2 blue). The tube radius is a
// drawing choice (the cross-section's radius is not in the .vtu): a fifth of the median segment,
// at most 1% of the scene's size.
const LINE = 3, POLY_LINE = 4, SIDES = 8;

// The grid's segments: { segments: Uint32Array (2 point indices each), owners: Uint32Array (cell) }.
export function lineSegments(grid) {
  const segments = [], owners = [];
  let start = 0;
  for (let c = 0; c < grid.types.length; ++c) {
    const end = grid.offsets[c];
    if (grid.types[c] === LINE || grid.types[c] === POLY_LINE)
      for (let i = start; i + 1 < end; ++i) {
        segments.push(grid.connectivity[i], grid.connectivity[i + 1]);
        owners.push(c);
      }
    start = end;
  }
  return { segments: Uint32Array.from(segments), owners: Uint32Array.from(owners) };
}

// The number of separate rods (connected chains of segments).
export function countRods(segments) {
  const parent = new Map();
  const find = (a) => {
    while (parent.get(a) !== a) a = parent.get(a);
    return a;
  };
  for (let i = 0; i < segments.length; i += 2) {
    for (const v of [segments[i], segments[i + 1]]) if (!parent.has(v)) parent.set(v, v);
    parent.set(find(segments[i]), find(segments[i + 1]));
  }
  return new Set([...parent.keys()].map(find)).size;
}

const sub = (p, a, b) => [p[3 * a] - p[3 * b], p[3 * a + 1] - p[3 * b + 1], p[3 * a + 2] - p[3 * b + 2]];
const norm = (v) => Math.hypot(v[0], v[1], v[2]);
const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
const scaled = (v, s) => [v[0] * s, v[1] * s, v[2] * s];

export function tubeRadius(positions, segments, sceneSize) {
  const lengths = [];
  for (let i = 0; i < segments.length; i += 2) lengths.push(norm(sub(positions, segments[i + 1], segments[i])));
  lengths.sort((a, b) => a - b);
  const median = lengths.length ? lengths[lengths.length >> 1] : sceneSize;
  return Math.min(0.2 * median, 0.01 * sceneSize) || 0.01 * sceneSize || 1e-3;
}

// The frame of segment s: (m1, m2) from the cell fields, else two unit vectors normal to it.
function segmentFrame(grid, positions, segments, owners, s) {
  const m1 = grid.cellFields.find((f) => f.name === 'm1' && f.components === 3);
  const m2 = grid.cellFields.find((f) => f.name === 'm2' && f.components === 3);
  const c = owners[s];
  if (m1 && m2) return [Array.from(m1.values.subarray(3 * c, 3 * c + 3)), Array.from(m2.values.subarray(3 * c, 3 * c + 3))];
  const t = sub(positions, segments[2 * s + 1], segments[2 * s]);
  const helper = Math.abs(t[0]) < 0.9 * norm(t) ? [1, 0, 0] : [0, 1, 0];
  const a = cross(t, helper), b = cross(t, a);
  return [scaled(a, 1 / norm(a)), scaled(b, 1 / norm(b))];
}

// Appends the tubes of `grid` to `out` ({ positions: [], triangles: [], values: [] } with values
// per triangle when `cellValues` is given, else per vertex from `pointValues`) and returns the
// frame glyphs: { positions: [], colors: [] } (pairs of points).
export function appendTubes(grid, { segments, owners }, radius, out, cellValues, pointValues) {
  const p = grid.positions;
  const glyphs = { positions: [], colors: [] };
  for (let s = 0; s < owners.length; ++s) {
    const a = segments[2 * s], b = segments[2 * s + 1];
    const [m1, m2] = segmentFrame(grid, p, segments, owners, s);
    const base = out.positions.length / 3;
    for (const v of [a, b]) {
      for (let k = 0; k < SIDES; ++k) {
        const phi = (2 * Math.PI * k) / SIDES, cs = Math.cos(phi) * radius, sn = Math.sin(phi) * radius;
        out.positions.push(p[3 * v] + cs * m1[0] + sn * m2[0], p[3 * v + 1] + cs * m1[1] + sn * m2[1], p[3 * v + 2] + cs * m1[2] + sn * m2[2]);
        if (!cellValues) out.values.push(pointValues ? pointValues[v] : NaN);
      }
    }
    for (let k = 0; k < SIDES; ++k) {
      const k1 = (k + 1) % SIDES;
      out.triangles.push(base + k, base + k1, base + SIDES + k1, base + k, base + SIDES + k1, base + SIDES + k);
      if (cellValues) out.values.push(cellValues[owners[s]], cellValues[owners[s]]);
    }
    const mid = [0, 1, 2].map((k) => (p[3 * a + k] + p[3 * b + k]) / 2);
    const length = 0.45 * norm(sub(p, b, a)) + radius;
    for (const [m, color] of [[m1, [0.85, 0.15, 0.1]], [m2, [0.1, 0.3, 0.9]]]) {
      glyphs.positions.push(...mid, mid[0] + length * m[0], mid[1] + length * m[1], mid[2] + length * m[2]);
      glyphs.colors.push(...color, ...color);
    }
  }
  return glyphs;
}
