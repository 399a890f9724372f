#include "plugins/voxel_skull/NativeVoxelBackend.h"

#include <algorithm>

#include "framework/geometry/FrontRings.h"

namespace trephine::voxel {

void NativeVoxelBackend::bind(const VoxelData& data) {
  m_data = data;
  m_pointTest = bestShellPointTest(grid().smooth);
  reserveProbeLines();  // the voxel size may have changed
}

void NativeVoxelBackend::reserveShell(std::span<const ShellPoint> shell) {
  if (findShell(shell)) return;
  ReservedShell reserved;
  reserved.source = shell.data();
  reserved.size = shell.size();
  reserved.arrays.assign(shell);
  // Pulled in by one voxel, never past the reference point (a tool thinner than a
  // voxel is judged by its centre), and thinned to points about a voxel apart:
  // the test's tolerance is a voxel, and bone narrower than a voxel does not
  // exist at the volume's resolution (a 466-point burr of 2.5 mm keeps about
  // 200 points on 0.5 mm voxels, 50 on 1 mm).
  const double inset = grid().spacing.maxCoeff();
  const double apart = 0.9 * grid().smallestSide();
  std::vector<ShellPoint> pulled;
  for (const ShellPoint& p : shell) {
    ShellPoint q = p;
    q.position += std::min(inset, p.position.norm()) * p.inwardNormal;
    bool near = false;
    for (const ShellPoint& kept : pulled) near = near || (kept.position - q.position).squaredNorm() < apart * apart;
    if (!near) pulled.push_back(q);
  }
  reserved.inset.assign(pulled);
  for (const ShellPoint& p : shell) reserved.radius = std::max(reserved.radius, p.position.norm());
  for (const ShellPoint& p : shell) reserved.sphere = reserved.sphere && p.position.norm() > (1 - 1e-9) * reserved.radius;
  reserved.width.resize(shell.size());
  for (size_t i = 0; i < shell.size(); ++i) {
    double farthest = 0;
    for (const ShellPoint& q : shell) farthest = std::max(farthest, (q.position - shell[i].position).dot(shell[i].inwardNormal));
    reserved.width[i] = farthest;
  }
  m_shells.push_back(std::move(reserved));
  const size_t n = std::max(shell.size(), m_hits.size());
  m_hits.resize(n);
  m_voxels.resize(n);
  m_solid.resize(n);
  m_depths.resize(n);
  m_normals.resize(n);
  m_buried.resize(n);
  m_touched.resize(8 * n);
  m_groups.reserve(n);
  m_groupNormals.resize(n);
  m_groupDepths.resize(n);
  m_groupPoints.resize(n);
  m_wasSolid.resize(n);
  reserveProbeLines();
}

void NativeVoxelBackend::reserveProbeLines() {
  double radius = 0;
  for (const ReservedShell& s : m_shells) radius = std::max(radius, s.radius);
  if (!m_data.grid || !(radius > 0) || !(grid().smallestSide() > 0)) return;
  const size_t lines = 1 + size_t(frontRingPointCount(radius, resolvedFeature(radius)));
  if (lines <= m_probeLines.size()) return;
  m_probeLines.resize(lines);
  m_probePoints.x.reserve(lines);
  m_probePoints.y.reserve(lines);
  m_probePoints.z.reserve(lines);
  m_probeVoxels.resize(lines);
  m_probeSolid.resize(lines);
}

const NativeVoxelBackend::ReservedShell* NativeVoxelBackend::findShell(std::span<const ShellPoint> shell) const {
  for (const ReservedShell& s : m_shells)
    if (s.source == shell.data() && s.size == shell.size()) return &s;
  return nullptr;
}

void NativeVoxelBackend::reportCounters(std::vector<Counter>& counters) const {
  counters.push_back({"contact_frames", double(m_contactFrames)});
  counters.push_back({"max_colliding_voxels", double(m_maxCollidingVoxels)});
  if (m_unreservedShellCalls) counters.push_back({"unreserved_shell_calls", double(m_unreservedShellCalls)});
  counters.push_back({"most_sweep_steps", double(m_mostSweepSteps)});
}

}  // namespace trephine::voxel
