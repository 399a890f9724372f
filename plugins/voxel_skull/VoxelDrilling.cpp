// VoxelSkull: force-driven drilling (removal="force"). The removal law gives
// the speed v at which the bone surface under the burr recedes (RemovalLaw.h);
// each frame the density of the voxels in the burr's footprint falls by
// w v dt |grad rho|, so the interpolated isosurface moves by about v dt:
//  - |grad rho| is each voxel's own density gradient (one-sided differences),
//    so the same law cuts a sharp cortical edge, a soft drilled wall and the
//    rim of an opening alike;
//  - w = min(1, cos(angle from the load) + 0.25) x a radial falloff (1 inside
//    the burr and up to half a voxel beyond, smoothly 0 one voxel beyond): a
//    sphere advancing along the load recedes the surface at v cos(angle), the
//    flutes cut its sides a little too, and nothing beyond the burr's radius
//    plus one voxel changes;
//  - the fall of each code is rounded up or down at random in proportion to
//    its fraction (seeded by voxel and frame, so runs are reproducible), so
//    slow cuts of less than one code per frame still remove bone on average.
// Removal is incremental, never a target shape: it can neither stall nor run
// ahead of the law wherever the proxy happens to sit.
#include <algorithm>
#include <cmath>

#include "framework/logs/EventLog.h"
#include "plugins/voxel_skull/VoxelSkull.h"

namespace trephine::voxel {

namespace {
// A uniform number in [0, 1) from a voxel and a frame (splitmix64): the same
// on every run and machine, independent between neighbouring voxels and frames.
double unitHash(uint64_t voxel, uint64_t frame) {
  uint64_t x = voxel * 0x9E3779B97F4A7C15ull ^ (frame + 0x632BE59BD9B4E019ull);
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  x ^= x >> 31;
  return double(x >> 11) * 0x1.0p-53;
}

// The flutes also cut sideways what the burr's side touches, at this share of
// the speed ahead: the hole comes out a little wider than the burr (at most the
// falloff's voxel), so the burr never wedges in a bore exactly its own size.
constexpr double kSideCut = 0.25;

// A pause in cutting longer than this (s) disarms the breakthrough test: the
// burr was lifted, and the next contact starts afresh.
constexpr double kCutPause = 0.05;
}  // namespace

int VoxelSkull::lowerVoxelTo(int64_t voxel, int32_t code) {
  VoxelCode& current = m_volume.codes()[voxel];
  if (current <= code) return 0;
  const bool emptied = current >= m_grid.threshold && code < m_grid.threshold;
  m_removedCodes += double(current - code);
  current = static_cast<VoxelCode>(code);
  m_grid.noteLowered(voxel, current);  // keeps the point test's occupancy cells true
  return emptied ? 1 : 0;
}

double VoxelSkull::localSlope(int64_t i, int64_t j, int64_t k) const {
  // Per axis the larger one-sided difference, not the central one: a last
  // layer of bone with air on both sides has no central difference at all.
  const auto larger = [](double c, double a, double b) { return std::max(std::abs(c - a), std::abs(c - b)); };
  if (i > 0 && j > 0 && k > 0 && i + 1 < m_grid.nx && j + 1 < m_grid.ny && k + 1 < m_grid.nz) {
    // Away from the grid's faces: the six neighbours by stride, no bounds checks.
    const VoxelCode* v = m_grid.codes + m_grid.linear(i, j, k);
    const int64_t sy = m_grid.nx, sz = int64_t(m_grid.nx) * m_grid.ny;
    const double c = v[0];
    const double gx = larger(c, v[-1], v[1]) * m_grid.inverseSpacing.x();
    const double gy = larger(c, v[-sy], v[sy]) * m_grid.inverseSpacing.y();
    const double gz = larger(c, v[-sz], v[sz]) * m_grid.inverseSpacing.z();
    return std::sqrt(gx * gx + gy * gy + gz * gz);
  }
  const double c = m_grid.codeAtCell(i, j, k);
  const Vec3 g(larger(c, m_grid.codeAtCell(i - 1, j, k), m_grid.codeAtCell(i + 1, j, k)) * m_grid.inverseSpacing.x(),
               larger(c, m_grid.codeAtCell(i, j - 1, k), m_grid.codeAtCell(i, j + 1, k)) * m_grid.inverseSpacing.y(),
               larger(c, m_grid.codeAtCell(i, j, k - 1), m_grid.codeAtCell(i, j, k + 1)) * m_grid.inverseSpacing.z());
  return g.norm();
}

bool VoxelSkull::boneAhead(const Vec3& front, const Vec3& direction) const {
  const double h = m_grid.smallestSide();
  return m_grid.solidAt(front + 0.5 * h * direction) || m_grid.solidAt(front + h * direction);
}

int VoxelSkull::cutUnderLoad(const CuttingLoad& load) {
  if (!d_drill.value() || !m_forceRemoval) return 0;
  const double thrust = load.force_N.norm();  // N
  if (!(thrust > 0) || !std::isfinite(thrust) || !load.center_W.allFinite() || !(load.dt > 0) ||
      !(load.radius > 0))
    return 0;
  const Vec3 d = load.force_N / thrust;  // unit, into the bone
  const double h = m_grid.smallestSide();
  // The bone surface ahead of the burr: its radius less the skin it sits in.
  const double reach = load.radius - std::clamp(load.overlap, 0.0, load.radius);  // mm
  const Vec3 front = load.center_W + reach * d;

  // Breakthrough: bone ahead of the burr at the last cut, none now; once per
  // stretch of drilling (a pause longer than kCutPause starts a new one).
  const bool ahead = boneAhead(front, d);
  if (load.t - m_lastCutTime > kCutPause) m_boneAhead = m_brokeThrough = false;
  if (m_boneAhead && !ahead && !m_brokeThrough) {
    ++m_breakthroughs;
    m_brokeThrough = true;
    if (m_events) m_events->log(load.t, "breakthrough", "no bone ahead of the burr", this, thrust,
                                {front.x(), front.y(), front.z()});
  }
  m_boneAhead = ahead;
  m_lastCutTime = load.t;

  // How fast the surface recedes: the hardness of the bone one voxel ahead.
  const DensityEncoding& e = m_volume.encoding();
  const double densityAhead = e.offset + e.scale * m_grid.codeAt(front + h * d);
  const double speed = m_law.recessionSpeed(thrust, densityAhead, load.burr, load.radius);  // mm/s
  if (!(speed > 0)) return 0;
  ++m_cutFrames;
  m_maxCutSpeed = std::max(m_maxCutSpeed, speed);

  const double advance = speed * load.dt;  // mm the surface recedes this frame, at full weight

  // Voxels whose centre is within the burr plus one voxel, ahead of its centre.
  const Vec3& P = load.center_W;
  const double inner = load.radius + 0.5 * h, outer = load.radius + h;  // mm, the radial falloff
  const int32_t floorCode = static_cast<int32_t>(std::ceil(m_grid.outsideCode));
  // Index bounds, clamped as doubles first: a burr far outside the grid must
  // not overflow the conversion to integers.
  const Vec3 lo = (P - Vec3::Constant(outer) - m_grid.corner).cwiseProduct(m_grid.inverseSpacing);
  const Vec3 hi = (P + Vec3::Constant(outer) - m_grid.corner).cwiseProduct(m_grid.inverseSpacing);
  const auto first = [](double u, int32_t n) { return int64_t(std::clamp(std::floor(u), 0.0, double(n))); };
  const auto last = [](double u, int32_t n) { return int64_t(std::clamp(std::floor(u), -1.0, double(n - 1))); };
  const int64_t i0 = first(lo.x(), m_grid.nx), i1 = last(hi.x(), m_grid.nx);
  const int64_t j0 = first(lo.y(), m_grid.ny), j1 = last(hi.y(), m_grid.ny);
  const int64_t k0 = first(lo.z(), m_grid.nz), k1 = last(hi.z(), m_grid.nz);
  int removed = 0;
  for (int64_t k = k0; k <= k1; ++k) {
    const double z = m_grid.corner.z() + (double(k) + 0.5) * m_grid.spacing.z();
    for (int64_t j = j0; j <= j1; ++j) {
      const double y = m_grid.corner.y() + (double(j) + 0.5) * m_grid.spacing.y();
      // Only the voxels of this row inside the footprint's sphere.
      const double across2 = outer * outer - (y - P.y()) * (y - P.y()) - (z - P.z()) * (z - P.z());
      if (!(across2 > 0)) continue;
      const double across = std::sqrt(across2);
      const int64_t rowFirst = std::max(i0, first((P.x() - across - m_grid.corner.x()) * m_grid.inverseSpacing.x() - 0.5, m_grid.nx));
      const int64_t rowLast = std::min(i1, last((P.x() + across - m_grid.corner.x()) * m_grid.inverseSpacing.x() + 0.5, m_grid.nx));
      const VoxelCode* row = m_volume.codes() + m_grid.linear(0, j, k);
      for (int64_t i = rowFirst; i <= rowLast; ++i) {
        // Air first: most of a footprint in a drilled hole has nothing to cut.
        const int32_t current = row[i];
        if (current <= floorCode) continue;
        const Vec3 offset = Vec3(m_grid.corner.x() + (double(i) + 0.5) * m_grid.spacing.x(), y, z) - P;
        const double along = offset.dot(d);
        if (along <= -kSideCut * outer) continue;  // behind the burr: the load does not press there
        const double distance = offset.norm();
        if (distance >= outer) continue;
        const double u = std::clamp((outer - distance) / (outer - inner), 0.0, 1.0);
        const double facing = std::min(1.0, along / distance + kSideCut);  // cosine, plus the flutes' side cut
        if (!(facing > 0)) continue;
        const double weight = facing * u * u * (3.0 - 2.0 * u);  // x smoothstep
        const int64_t voxel = m_grid.linear(i, j, k);
        // Stochastic rounding of the fall, seeded by voxel and frame.
        // The isosurface moves by (fall of the density) / |gradient|, so each
        // voxel falls by the advance times its own gradient (codes per mm,
        // one-sided differences): the surface recedes by the advance wherever the
        // burr touches it, a sharp cortical edge, a soft drilled wall or the
        // rim of an opening alike, and bone not yet reached (flat inside) waits.
        const double exact = weight * advance * localSlope(i, j, k);
        const double whole = std::floor(exact);
        const double fraction = exact - whole;
        const int32_t step = int32_t(whole) + (unitHash(uint64_t(voxel), m_cutFrames) < fraction ? 1 : 0);
        if (step > 0) removed += lowerVoxelTo(voxel, std::max(floorCode, current - step));
      }
    }
  }
  m_voxelsRemoved += removed;
  return removed;
}

}  // namespace trephine::voxel
