#include "plugins/haptics/GodObjectProxy.h"

#include <algorithm>

#include "framework/core/Lifecycle.h"

namespace trephine::haptics {

namespace {
// Below this the proxy and the device coincide (mm).
constexpr double kSamePlace = 1e-9;
}  // namespace

void GodObjectProxy::init(InitContext& context) { l_target->reserveShell(l_tool->shellPoints()); }

SweepResult GodObjectProxy::sweepPath(const Vec3& from, const Vec3& to, const Quat& orientation) const {
  SweepQuery query;
  query.from = from;
  query.to = to;
  query.orientation = orientation;
  query.probe = d_sweep.is("cylinder")  ? SweepProbe::Cylinder
                : d_sweep.is("spheres") ? SweepProbe::Spheres
                                        : SweepProbe::Line;
  query.leadingRadius = l_tool->leadingRadius();
  query.shell = l_tool->shellPoints();
  return l_target->sweep(query);
}

void GodObjectProxy::tick(const TickContext&) {
  PointShellTool& tool = *l_tool;
  ShellContactTarget& target = *l_target;
  const DeviceState& device = tool.device().state();
  ProxyState s;
  s.deviceValid = device.valid;
  if (!device.valid) {
    s.proxy = m_state.proxy;
    m_state = s;
    return;
  }
  const Pose X_WT = tool.toolPose(device.pose);
  const Vec3 D = X_WT.position;
  const Quat& q = X_WT.orientation;
  if (!m_started) {
    m_state.proxy = D;  // the proxy starts with the device, wherever that is
    m_started = true;
  }
  const Vec3 P = m_state.proxy;
  s.device = D;

  // 1. Sweep before moving.
  Vec3 P1 = D;
  bool blocked = false;
  const Vec3 path = D - P;
  const double length = path.norm();
  if (!d_sweep.is("none") && length > kSamePlace) {
    const SweepResult r = sweepPath(P, D, q);
    if (r.blocked) {
      const double travel = r.freeFraction * length + (r.startsInside ? 0.0 : target.contactDepth());
      P1 = P + std::min(travel, length) / length * path;
      blocked = (D - P1).norm() > kSamePlace;
      if (blocked) ++m_blockedSweeps;
    }
  }

  // 2. Detection (and drilling) where the proxy now is.
  const bool cutting = d_drillButton.value() == 0 || (device.buttons >> (d_drillButton.value() - 1)) & 1u;
  const ShellContact c = target.collide({P1, q}, tool.shellPoints(), cutting);
  s.points = c.points;
  s.primitives = c.primitives;
  s.removed = c.removed;
  s.rawPenetration = c.penetration;

  Vec3 normal = c.normal;
  if (c.points > 0 && normal.squaredNorm() < 0.5) {
    // Contacts all round cancel out (the tool buried in the target): keep the last direction.
    ++m_degenerateNormals;
    normal = m_lastNormal;
  }
  Vec3 P2 = P1;
  if (c.points > 0 && normal.squaredNorm() > 0.5) {
    // 3. God-object projection on the constraint plane, lifted to the contact depth.
    const double skin = std::min(c.penetration, target.contactDepth());
    const Vec3 onPlane = P1 + (c.penetration - skin) * normal;
    Vec3 goal = P1;
    if (d_godObject.value()) goal = D + std::max(0.0, (onPlane - D).dot(normal)) * normal;
    // 4. Rectifying sweep to the new position.
    P2 = goal;
    const Vec3 move = goal - P1;
    const double moveLength = move.norm();
    if (d_rectify.value() && !d_sweep.is("none") && moveLength > kSamePlace) {
      const SweepResult r = sweepPath(P1, goal, q);
      if (r.blocked) P2 = P1 + r.freeFraction * move;
    }
    // 5. Rendered penetration.
    s.penetration = std::max(0.0, (P2 - D).dot(normal)) + skin;
    s.normal = normal;
    s.contact = true;
  } else if (blocked) {
    // Conflicting case: the proxy is free where the sweep stopped it but the device is beyond.
    ++m_conflictFrames;
    s.normal = (P1 - D).normalized();
    s.penetration = (D - P1).norm();
    s.contact = true;
  }
  if (s.contact) {
    ++m_contactFrames;
    m_lastNormal = s.normal;
  }
  s.proxy = P2;
  s.proxyInside = target.overlaps({P2, q}, tool.shellPoints());
  m_state = s;
}

void GodObjectProxy::reportCounters(std::vector<Counter>& counters) const {
  counters.push_back({"contact_frames", double(m_contactFrames)});
  counters.push_back({"blocked_sweeps", double(m_blockedSweeps)});
  counters.push_back({"conflict_frames", double(m_conflictFrames)});
  counters.push_back({"degenerate_normals", double(m_degenerateNormals)});
}

}  // namespace trephine::haptics
