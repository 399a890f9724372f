// The boundary of a tetrahedral mesh: the faces that belong to one
// tetrahedron only, turned outward. Computed once per topology; each frame
// then only moves the points.

// VTK cell type of a linear tetrahedron.
const kTetra = 10;

// Faces opposite each corner, outward for a tetrahedron of positive volume.
const kFaces = [
  [1, 2, 3],
  [0, 3, 2],
  [0, 1, 3],
  [0, 2, 1],
];

// Returns the triangles as [3, a, b, c, 3, ...] (vtk.js cell array layout),
// and the cell each triangle is a face of (`faceCells`: to colour the surface
// by a quantity of the cells).
export function tetBoundary(points, connectivity, offsets, types) {
  const tets = [];
  const cells = [];
  let start = 0;
  for (let cell = 0; cell < offsets.length; ++cell) {
    const end = offsets[cell];
    if (types[cell] === kTetra && end - start === 4) {
      tets.push(start);
      cells.push(cell);
    }
    start = end;
  }
  const faceCount = tets.length * 4;
  const corners = new Int32Array(faceCount * 3);  // oriented
  const sorted = new Int32Array(faceCount * 3);   // ascending, the key
  const signedVolume = (a, b, c, d) => {
    const p = (i, k) => points[3 * i + k] - points[3 * a + k];
    const x = [p(b, 0), p(b, 1), p(b, 2)];
    const y = [p(c, 0), p(c, 1), p(c, 2)];
    const z = [p(d, 0), p(d, 1), p(d, 2)];
    return x[0] * (y[1] * z[2] - y[2] * z[1]) - x[1] * (y[0] * z[2] - y[2] * z[0]) + x[2] * (y[0] * z[1] - y[1] * z[0]);
  };
  tets.forEach((at, t) => {
    const v = connectivity.subarray(at, at + 4);
    const flip = signedVolume(v[0], v[1], v[2], v[3]) < 0;
    kFaces.forEach((face, f) => {
      const o = (4 * t + f) * 3;
      corners[o] = v[face[0]];
      corners[o + 1] = v[flip ? face[2] : face[1]];
      corners[o + 2] = v[flip ? face[1] : face[2]];
      const s = [corners[o], corners[o + 1], corners[o + 2]].sort((p, q) => p - q);
      sorted.set(s, o);
    });
  });
  const order = new Uint32Array(faceCount);
  for (let i = 0; i < faceCount; ++i) order[i] = i;
  const compare = (i, j) =>
    sorted[3 * i] - sorted[3 * j] || sorted[3 * i + 1] - sorted[3 * j + 1] || sorted[3 * i + 2] - sorted[3 * j + 2];
  order.sort(compare);
  const boundary = [];
  for (let i = 0; i < faceCount; ) {
    let j = i + 1;
    while (j < faceCount && compare(order[i], order[j]) === 0) ++j;
    if (j - i === 1) boundary.push(order[i]);
    i = j;
  }
  const polys = new Uint32Array(boundary.length * 4);
  const faceCells = new Uint32Array(boundary.length);
  boundary.forEach((face, k) => {
    polys[4 * k] = 3;
    polys.set(corners.subarray(3 * face, 3 * face + 3), 4 * k + 1);
    faceCells[k] = cells[Math.floor(face / 4)];
  });
  return { polys, faceCells };
}
