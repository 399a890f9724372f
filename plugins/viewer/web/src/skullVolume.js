// The skull's volume as `trephine view` packs it (plugins/viewer/ViewerVolume.h):
// the densities as the run started ("VOL1") and, per voxel, the first time
// the drill took it below the isovalue ("RMV1"). Sampled at the skull's
// surface to colour it by the density beneath and by where it was cut.
export class SkullVolume {
  constructor(volumeBytes, removedBytes, name) {
    const view = new DataView(volumeBytes.buffer, volumeBytes.byteOffset, volumeBytes.byteLength);
    const magic = String.fromCharCode(...volumeBytes.subarray(0, 4));
    if (magic !== 'VOL1' || volumeBytes.length < 56) throw new Error(`${name}: not a VOL1 volume`);
    this.dims = [0, 1, 2].map((a) => view.getUint32(4 + 4 * a, true));
    this.origin = [0, 1, 2].map((a) => view.getFloat32(16 + 4 * a, true));  // mm, centre of voxel 0
    this.spacing = [0, 1, 2].map((a) => view.getFloat32(28 + 4 * a, true));  // mm
    this.isovalue = view.getFloat32(40, true);
    this.offset = view.getFloat32(44, true);
    this.scale = view.getFloat32(48, true);
    const count = this.dims[0] * this.dims[1] * this.dims[2];
    if (volumeBytes.length !== 52 + 2 * count) throw new Error(`${name}: ${volumeBytes.length} bytes for ${this.dims.join(' x ')} voxels`);
    this.codes = new Int16Array(volumeBytes.slice(52).buffer);
    let low = Infinity;
    let high = -Infinity;
    for (const c of this.codes) {
      if (c < low) low = c;
      if (c > high) high = c;
    }
    this.range = [this.offset + this.scale * low, this.offset + this.scale * high];  // densities
    // The first time each voxel was cut (s); Infinity: never.
    this.removedAt = new Float32Array(count).fill(Infinity);
    this.removedTimes = [];
    this.removedOrder = [];  // {voxel, t}, in time order (as the file lists them)
    if (removedBytes) {
      const r = new DataView(removedBytes.buffer, removedBytes.byteOffset, removedBytes.byteLength);
      if (String.fromCharCode(...removedBytes.subarray(0, 4)) !== 'RMV1') throw new Error(`${name}: not an RMV1 list`);
      const n = r.getUint32(4, true);
      if (removedBytes.length !== 8 + 8 * n) throw new Error(`${name}: ${removedBytes.length} bytes for ${n} removed voxels`);
      for (let i = 0; i < n; ++i) {
        const voxel = r.getUint32(8 + 8 * i, true);
        const t = r.getFloat32(12 + 8 * i, true);
        if (voxel < count) this.removedAt[voxel] = Math.min(this.removedAt[voxel], t);
        this.removedTimes.push(t);
        if (voxel < count) this.removedOrder.push({ voxel, t });
      }
    }
  }

  // The density at point p (mm), trilinear; the lowest outside the grid.
  densityAt(p) {
    const f = [0, 1, 2].map((a) => (p[a] - this.origin[a]) / this.spacing[a]);
    const i0 = f.map(Math.floor);
    const [nx, ny, nz] = this.dims;
    let sum = 0;
    for (let c = 0; c < 8; ++c) {
      const i = i0[0] + (c & 1);
      const j = i0[1] + ((c >> 1) & 1);
      const k = i0[2] + ((c >> 2) & 1);
      const w = (c & 1 ? f[0] - i0[0] : 1 - f[0] + i0[0]) * ((c >> 1) & 1 ? f[1] - i0[1] : 1 - f[1] + i0[1]) *
                ((c >> 2) & 1 ? f[2] - i0[2] : 1 - f[2] + i0[2]);
      const inside = i >= 0 && j >= 0 && k >= 0 && i < nx && j < ny && k < nz;
      sum += w * (inside ? this.offset + this.scale * this.codes[i + nx * (j + ny * k)] : this.range[0]);
    }
    return sum;
  }

  // The densest of the bone beneath a surface point: the largest density
  // from p to `depth` mm along the density's gradient (into the bone).
  densityBeneath(p, depth) {
    const h = Math.min(...this.spacing);
    const gradient = [0, 1, 2].map((a) => {
      const q1 = p.slice();
      const q0 = p.slice();
      q1[a] += h;
      q0[a] -= h;
      return this.densityAt(q1) - this.densityAt(q0);
    });
    const norm = Math.hypot(...gradient) || 1;
    let most = this.densityAt(p);
    for (let s = h / 2; s <= depth; s += h / 2)
      most = Math.max(most, this.densityAt(p.map((v, a) => v + (s * gradient[a]) / norm)));
    return most;
  }

  // The first time (s) any voxel of the 2 x 2 x 2 around p was cut; Infinity: never.
  cutTimeAt(p) {
    const f = [0, 1, 2].map((a) => (p[a] - this.origin[a]) / this.spacing[a]);
    const i0 = f.map(Math.floor);
    const [nx, ny, nz] = this.dims;
    let first = Infinity;
    for (let c = 0; c < 8; ++c) {
      const i = i0[0] + (c & 1);
      const j = i0[1] + ((c >> 1) & 1);
      const k = i0[2] + ((c >> 2) & 1);
      if (i >= 0 && j >= 0 && k >= 0 && i < nx && j < ny && k < nz) first = Math.min(first, this.removedAt[i + nx * (j + ny * k)]);
    }
    return first;
  }
}
