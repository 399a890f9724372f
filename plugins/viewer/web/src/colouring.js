// What each part can be coloured by, and the colours themselves (bytes RGB
// per point or per triangle, for vtk.js's direct scalars).
//   brain (a tetrahedral mesh): its tissue colour, or |displacement| (mm)
//     and |force| (N) at its nodes, or von Mises stress (kPa) per element;
//   skull (blocks): bone colour, or the density beneath the surface (the
//     volume's units: Hounsfield units for a CT), or where the drill cut it
//     (coloured by when, up to the time shown; uncut bone stays bone).
import { colourInto } from './colourMap.js';

export const kMeshModes = {
  tissue: null,
  displacement: { title: '|displacement| (mm)', array: 'displacement', range: 'displacement', cells: false },
  force: { title: 'node force (N)', array: 'force', range: 'force', cells: false },
  stress: { title: 'von Mises stress (kPa)', array: 'von_mises', range: 'von_mises', cells: true },
};
export const kSkullModes = {
  bone: null,
  density: { title: 'density beneath (volume units)' },
  cut: { title: 'cut by the drill at (s)' },
};

// The modes a mesh part's files and ranges offer.
export function meshModesOf(part) {
  return Object.keys(kMeshModes).filter((mode) => !kMeshModes[mode] || (part.ranges && part.ranges[kMeshModes[mode].range] !== undefined));
}

// Colours of a mesh file in `mode`: {bytes, cells} or null (plain).
export function meshColours(file, mode, faceCells, ranges) {
  const spec = kMeshModes[mode];
  if (!spec) return null;
  const values = spec.cells ? file.array('CellData', spec.array) : file.array('PointData', spec.array);
  const high = ranges[spec.range] || 1;
  if (!values) return null;
  if (spec.cells) {
    const bytes = new Uint8Array(3 * faceCells.length);
    for (let f = 0; f < faceCells.length; ++f) colourInto(bytes, f, values[faceCells[f]], 0, high);
    return { bytes, cells: true };
  }
  const count = values.length / 3;
  const bytes = new Uint8Array(3 * count);
  for (let i = 0; i < count; ++i) colourInto(bytes, i, Math.hypot(values[3 * i], values[3 * i + 1], values[3 * i + 2]), 0, high);
  return { bytes, cells: false };
}

// Per piece of a skull's surface ({points, triangles}), computed once: the
// density beneath each point and the first time it was cut.
const pieceSamples = new WeakMap();
function samplesOf(piece, volume, wantDensity) {
  let samples = pieceSamples.get(piece);
  if (!samples || samples.volume !== volume) {
    const n = piece.points.length / 3;
    samples = { volume, density: null, cut: new Float32Array(n) };
    for (let i = 0; i < n; ++i) samples.cut[i] = volume.cutTimeAt([piece.points[3 * i], piece.points[3 * i + 1], piece.points[3 * i + 2]]);
    pieceSamples.set(piece, samples);
  }
  if (!samples.density && wantDensity) {
    const n = piece.points.length / 3;
    samples.density = new Float32Array(n);
    // Within two voxels of the surface: the bone under it, not the far table.
    const depth = 2 * Math.max(...volume.spacing);
    for (let i = 0; i < n; ++i)
      samples.density[i] = volume.densityBeneath([piece.points[3 * i], piece.points[3 * i + 1], piece.points[3 * i + 2]], depth);
  }
  return samples;
}

// The density range a legend shows: from the isovalue (the surface) to the densest.
export function densityRange(volume) {
  const low = Number.isFinite(volume.isovalue) ? volume.isovalue : volume.range[0];
  return [low, Math.max(volume.range[1], low + 1)];
}

// Colours of a skull's pieces (point after point, pieces in order) in
// `mode` at time `t` (s, for cut); `end`: the run's end (s).
export function skullColours(pieces, mode, volume, t, end, bone) {
  if (!kSkullModes[mode] || !volume) return null;
  let total = 0;
  for (const piece of pieces) total += piece.points.length / 3;
  const bytes = new Uint8Array(3 * total);
  const [low, high] = densityRange(volume);
  const boneBytes = bone.map((v) => Math.round(255 * v));
  let at = 0;
  for (const piece of pieces) {
    const samples = samplesOf(piece, volume, mode === 'density');
    const n = piece.points.length / 3;
    for (let i = 0; i < n; ++i, ++at) {
      if (mode === 'density') colourInto(bytes, at, samples.density[i], low, high);
      else if (samples.cut[i] <= t) colourInto(bytes, at, samples.cut[i], 0, end);
      else bytes.set(boneBytes, 3 * at);
    }
  }
  return bytes;
}
