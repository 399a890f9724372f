// VoxelSkull: drilling, on the data it keeps (the collision back-end only
// reads it). The thesis's law (removal="thesis") cuts the voxels a contact
// touches, as the back-end reports them. Force-driven drilling
// (removal="force", the default): the removal law gives the speed v at which
// the bone surface under the burr recedes (RemovalLaw.h);
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
// ahead of the law wherever the proxy happens to sit. The footprint walk
// itself is FootprintCut.cpp.
#include <algorithm>
#include <cmath>
#include <tuple>

#include "framework/geometry/BackendBinding.h"
#include "framework/logs/EventLog.h"
#include "plugins/voxel_skull/FootprintCut.h"
#include "plugins/voxel_skull/VoxelSkull.h"

namespace trephine::voxel {

namespace {
// A pause in cutting longer than this (s) disarms the breakthrough test: the
// burr was lifted, and the next contact starts afresh.
constexpr double kCutPause = 0.05;
}  // namespace

// The thesis's law (removal="thesis"): each voxel the tool touches loses
// m_drillStep codes per frame.
int VoxelSkull::lowerVoxel(int64_t voxel) {
  VoxelCode& code = m_volume.codes()[voxel];
  // Never below the emptiest voxel of the volume (air).
  const int32_t floor = static_cast<int32_t>(std::ceil(m_grid.outsideCode));
  const int32_t lowered = std::max<int32_t>(int32_t(code) - m_drillStep, std::min<int32_t>(code, floor));
  const bool emptied = code >= m_grid.threshold && lowered < m_grid.threshold;  // bone that became empty
  const VoxelCode before = code;
  code = static_cast<VoxelCode>(lowered);
  m_grid.noteLowered(voxel, code, before);
  return emptied ? 1 : 0;
}

int VoxelSkull::cutTouched(std::span<const int64_t> touched) {
  int removed = 0;
  for (const int64_t voxel : touched) removed += lowerVoxel(voxel);
  m_voxelsRemoved += removed;
  return removed;
}

int VoxelSkull::cutAt(const Vec3& point_W) {
  if (!point_W.allFinite()) return 0;
  int removed = 0;
  if (!m_grid.smooth) {
    // The probe met the bone at a voxel face: the voxel just beyond, within a tenth of a voxel.
    const int64_t voxel = m_grid.voxelOf(point_W);
    if (voxel >= 0 && m_grid.codes[voxel] >= m_grid.threshold) removed = lowerVoxel(voxel);
  } else {
    const Vec3 u = (point_W - m_grid.corner).cwiseProduct(m_grid.inverseSpacing) - Vec3::Constant(0.5);
    const int64_t i = int64_t(std::floor(u.x())), j = int64_t(std::floor(u.y())), k = int64_t(std::floor(u.z()));
    for (int corner = 0; corner < 8; ++corner) {
      const int64_t a = i + (corner & 1), b = j + ((corner >> 1) & 1), c = k + (corner >> 2);
      if (m_grid.inside(a, b, c)) removed += lowerVoxel(m_grid.linear(a, b, c));
    }
  }
  m_voxelsRemoved += removed;
  return removed;
}

ShellContact VoxelSkull::collide(const Pose& X_WT, std::span<const ShellPoint> shell, bool cutting,
                                 ContactMemory& memory) {
  if (!m_bound) return {};
  // The thesis's law cuts the voxels the contact touches: asked for only then.
  const bool thesisCut = cutting && d_drill.value() && !m_forceRemoval;
  const VoxelContact c = askBackend(*this, d_backend, [&] { return m_backend->collide(X_WT, shell, thesisCut); });
  ShellContact contact = c.contact;
  if (thesisCut) {
    // Copied into the tool's memory: the back-end's span lasts only until its
    // next query, which may be another tool's.
    const size_t kept = std::min(c.touched.size(), memory.touched.capacity());
    memory.touched.assign(c.touched.begin(), c.touched.begin() + kept);
    contact.touched = memory.touched;
  }
  return contact;
}

void VoxelSkull::respond(double, std::span<const ContactResponse> responses) {
  if (!d_drill.value()) return;
  for (const ContactResponse& response : responses)
    if (response.cutting && m_pendingCuts.size() < m_pendingCuts.capacity()) m_pendingCuts.push_back(response);
}

TargetFrame VoxelSkull::beginFrame(double t) {
  // A copy of the surface the rebuild brought up to date: queried from this
  // frame on, and the rebuild told so (it may then update the other one).
  if (m_surfaceReady && m_surfaceReady->fetch()) {
    const SurfaceCopy& ready = m_surfaceReady->read();
    m_backend->adoptSurface(ready.copy);
    m_surfaceInUse->publish(ready);
  }
  return {0, applyPendingCuts(t)};
}

int VoxelSkull::applyPendingCuts(double now) {
  // A force-driven cut lowers codes by their own gradients, so two cuts that
  // overlap depend on their order: the contact frame's (the renderers' paths).
  int removed = 0;
  for (const ContactResponse& cut : m_pendingCuts) {
    if (m_forceRemoval) {
      removed += cutUnderLoad(cut.memory ? *cut.memory : m_anonymousHistory, cut.load, now);
    } else {
      removed += cutTouched(cut.touched);
      if (cut.stoppedAt) removed += cutAt(*cut.stoppedAt);
    }
  }
  m_pendingCuts.clear();
  return removed;
}

bool VoxelSkull::boneAhead(const Vec3& front, const Vec3& direction) const {
  const double h = m_grid.smallestSide();
  return m_grid.solidAt(front + 0.5 * h * direction) || m_grid.solidAt(front + h * direction);
}

int VoxelSkull::cutUnderLoad(ContactMemory& slot, const CuttingLoad& load, double now) {
  const double thrust = load.force_N.norm();  // N
  if (!(thrust > 0) || !std::isfinite(thrust) || !load.center_W.allFinite() || !(load.dt > 0) || !(load.radius > 0))
    return 0;
  const Vec3 d = load.force_N / thrust;  // unit, into the bone
  const double h = m_grid.smallestSide();
  // The bone surface ahead of the burr: its radius less the skin it sits in.
  const double reach = load.radius - std::clamp(load.overlap, 0.0, load.radius);  // mm
  const Vec3 front = load.center_W + reach * d;

  // Breakthrough: bone ahead of the burr at the last cut, none now; once per
  // stretch of drilling (a pause longer than kCutPause starts a new one).
  const bool ahead = boneAhead(front, d);
  if (load.t - slot.lastCutTime > kCutPause) slot.boneAhead = slot.brokeThrough = false;
  if (slot.boneAhead && !ahead && !slot.brokeThrough) {
    ++m_breakthroughs;
    slot.brokeThrough = true;
    if (m_events)
      m_events->log(now, "breakthrough", "no bone ahead of the burr", this, thrust,
                    {front.x(), front.y(), front.z()});
  }
  slot.boneAhead = ahead;
  slot.lastCutTime = load.t;

  // How fast the surface recedes: the hardness of the bone one voxel ahead.
  const DensityEncoding& e = m_volume.encoding();
  const double densityAhead = e.offset + e.scale * m_grid.codeAt(front + h * d);
  const double speed = m_law.recessionSpeed(thrust, densityAhead, load.burr, load.radius);  // mm/s
  if (!(speed > 0)) return 0;
  ++m_cutFrames;
  m_maxCutSpeed = std::max(m_maxCutSpeed, speed);

  const double advance = speed * load.dt;  // mm the surface recedes this frame, at full weight

  FootprintCut cut;
  cut.center = load.center_W;
  cut.direction = d;
  cut.radius = load.radius;
  // Interleaved: this frame's slice of rows, with `slices` frames' worth of advance.
  const int slices = d_cutSlices.value();
  cut.advance = advance * slices;
  cut.frame = m_cutFrames;
  cut.slices = slices;
  cut.slice = int(m_cutFrames % uint64_t(slices));
  const FootprintCutResult result = cutFootprint(m_grid, cut);
  if (result.lowered > 0 && m_backend) {
    // The footprint's voxel box, for a back-end with its own copy of the surface.
    const double reach = load.radius + h;
    std::array<int64_t, 3> first{}, last{};
    for (int a = 0; a < 3; ++a) {
      first[a] = SolidGrid::floorOf((load.center_W[a] - reach - m_grid.corner[a]) * m_grid.inverseSpacing[a]);
      last[a] = SolidGrid::floorOf((load.center_W[a] + reach - m_grid.corner[a]) * m_grid.inverseSpacing[a]);
    }
    askBackend(*this, d_backend, [&] { m_backend->dataChanged(first, last); });
  }
  m_removedCodes += result.codesRemoved;
  const int removed = result.emptied;
  m_voxelsRemoved += removed;
  return removed;
}

}  // namespace trephine::voxel
