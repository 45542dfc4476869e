// Reading tailor's output for the viewer: ASCII VTK XML unstructured grids (.vtu, as
// forward/mesh/write_vtu.cpp writes them); frame series are read by series.js.
const TETRA = 10, TRIANGLE = 5;

function numbers(text) {
  const parts = text.trim().split(/\s+/);
  const out = new Float64Array(parts.length);
  for (let i = 0; i < parts.length; ++i) out[i] = Number(parts[i]);
  return out;
}

function arrays(parent) {
  const fields = [];
  if (!parent) return fields;
  for (const a of parent.getElementsByTagName('DataArray')) {
    fields.push({ name: a.getAttribute('Name'), components: Number(a.getAttribute('NumberOfComponents') || 1), values: numbers(a.textContent) });
  }
  return fields;
}

// { positions (Float32Array, 3 per point), cells: {connectivity, offsets, types}, pointFields, cellFields }
export function parseVtu(text) {
  const doc = new DOMParser().parseFromString(text, 'application/xml');
  if (doc.getElementsByTagName('parsererror').length) throw new Error('not an XML file');
  const piece = doc.getElementsByTagName('Piece')[0];
  if (!piece) throw new Error('no Piece in the VTU file');
  const points = arrays(piece.getElementsByTagName('Points')[0])[0];
  const cellArrays = arrays(piece.getElementsByTagName('Cells')[0]);
  const byName = (name) => cellArrays.find((a) => a.name === name).values;
  return {
    positions: Float32Array.from(points.values),
    connectivity: byName('connectivity'),
    offsets: byName('offsets'),
    types: byName('types'),
    pointFields: arrays(piece.getElementsByTagName('PointData')[0]),
    cellFields: arrays(piece.getElementsByTagName('CellData')[0]),
  };
}

// The boundary triangles of the grid's tets (faces that belong to one tet) and its triangles,
// with the cell each came from: { triangles: Uint32Array, owners: Uint32Array }.
export function boundarySurface(grid) {
  const faces = new Map();
  const tris = [], owners = [];
  let start = 0;
  for (let c = 0; c < grid.types.length; ++c) {
    const end = grid.offsets[c];
    const v = grid.connectivity.subarray(start, end);
    if (grid.types[c] === TETRA) {
      for (const [a, b, d] of [[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]]) {
        const face = [v[a], v[b], v[d]];
        const key = [...face].sort((x, y) => x - y).join(',');
        if (faces.has(key)) faces.delete(key);
        else faces.set(key, { face, cell: c });
      }
    } else if (grid.types[c] === TRIANGLE) {
      tris.push(v[0], v[1], v[2]);
      owners.push(c);
    }
    start = end;
  }
  for (const { face, cell } of faces.values()) {
    tris.push(face[0], face[1], face[2]);
    owners.push(cell);
  }
  return { triangles: Uint32Array.from(tris), owners: Uint32Array.from(owners) };
}

// A field's scalar per point or cell: the value, or the vector's length.
export function scalarValues(field) {
  const n = field.values.length / field.components;
  const out = new Float64Array(n);
  for (let i = 0; i < n; ++i) {
    if (field.components === 1) out[i] = field.values[i];
    else {
      let s = 0;
      for (let k = 0; k < field.components; ++k) s += field.values[i * field.components + k] ** 2;
      out[i] = Math.sqrt(s);
    }
  }
  return out;
}
