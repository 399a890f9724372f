#include "plugins/haptics/GodObjectProxy.h"

#include <algorithm>

#include "framework/core/Lifecycle.h"
#include "plugins/haptics/PassiveAnchor.h"

namespace trephine::haptics {

namespace {
// Below this the proxy and the device coincide (mm).
constexpr double kSamePlace = 1e-9;
// Fraction of the way to the god-object position the proxy moves each frame.
constexpr double kProxyRelaxation = 0.5;
// Planes whose normals are closer than this (cosine, about 2.6 degrees) are one plane.
constexpr double kSamePlane = 0.999;
// How far (mm) the proxy may slide in a frame beyond the device's own move:
// 0.02 mm, so k = 3 N/mm renders at most 0.06 N of catch-up per frame.
constexpr double kCatchUp = 0.02;
}  // namespace

void GodObjectProxy::init(InitContext& context) {
  m_tool = &*l_tool;
  m_target = &*l_target;
  m_target->reserveShell(m_tool->shellPoints());
  m_target->describeTool(m_tool->shellPoints(), m_tool->solid());
  if (l_toolChange) {
    if (!l_nextTool && !l_nextTarget)
      context.error(l_toolChange, "a tool change needs nextTool, nextTarget or both (what changes)");
    ShellTool& nextTool = l_nextTool ? *l_nextTool : *l_tool;
    ShellContactTarget& nextTarget = l_nextTarget ? *l_nextTarget : *l_target;
    nextTarget.reserveShell(nextTool.shellPoints());
    nextTarget.describeTool(nextTool.shellPoints(), nextTool.solid());
    if (&nextTool.device() != &l_tool->device())
      context.error(l_nextTool, "the next tool must follow the same device as the first (" +
                                    l_tool->device().path() + ")");
  } else {
    if (l_nextTool) context.error(l_nextTool, "has no effect without a toolChange");
    if (l_nextTarget) context.error(l_nextTarget, "has no effect without a toolChange");
  }
  m_seenShapeFailures = m_target->shapeFailures();
  m_sweeps = !d_sweep.is("none");
  m_probe = d_sweep.is("cylinder")  ? SweepProbe::Cylinder
            : d_sweep.is("spheres") ? SweepProbe::Spheres
                                    : SweepProbe::Line;
}

ContactResponse GodObjectProxy::response(const Vec3& forceOnTool_N, double t) const {
  ContactResponse response;
  response.t = t;
  if (m_state.contact) {
    response.forceOnTarget_N = -forceOnTool_N;
    response.sites = m_frameContact.sites;
    if (m_state.cutting) {
      response.cutting = true;
      CuttingLoad& load = response.load;
      load.center_W = m_state.proxy;
      load.radius = m_tool->leadingRadius();
      load.overlap = m_state.overlap;
      load.force_N = -forceOnTool_N;
      load.dt = 1.0 / d_rate.value();
      load.t = t;
      load.burr = m_tool->cuttingBurr();
      response.touched = m_frameContact.touched;
      response.stoppedAt = m_stoppedAt;
    }
  }
  return response;
}

double GodObjectProxy::slideAllowance(const Vec3& device) const {
  // The device's own move, but no more than the tool's leading radius: the
  // constraint plane stands for the surface only over the contact patch, so a
  // longer slide along it (a device that jumped far beneath a tilted plane
  // projects onto it metres away) would leave the surface it was measured
  // on. The proxy covers a longer way over several frames, its contact
  // measured anew after each step.
  return std::min((device - m_lastDevice).norm(), m_tool->leadingRadius()) + kCatchUp;
}

bool GodObjectProxy::nothingBetween(const Vec3& from, const Vec3& device, const Quat& orientation) const {
  if (m_sweeps && sweepPath(from, device, orientation).blocked) return false;
  return !m_target->overlaps({device, orientation}, m_tool->shellPoints());
}

SweepResult GodObjectProxy::sweepPath(const Vec3& from, const Vec3& to, const Quat& orientation) const {
  SweepQuery query;
  query.from = from;
  query.to = to;
  query.orientation = orientation;
  query.probe = m_probe;
  query.leadingRadius = m_tool->leadingRadius();
  query.shell = m_tool->shellPoints();
  return m_target->sweep(query);
}

void GodObjectProxy::letGo(const TickContext& context) {
  // What shapes the target failed and its shape jumped: the proxy's place
  // and its constraint plane belong to a shape that is gone, and the spring
  // to them may point anywhere, into the target or away from the tool. The
  // proxy goes to the device and renders nothing (ForceFeedback takes the
  // force it rendered to zero along its ramp) until the tool is clear of the
  // target; then it starts again there. Already let go, it stays so (one
  // event, however many failures follow before the tool is clear).
  if (m_released) return;
  ++m_releases;
  m_released = true;
  m_lastNormal = Vec3::Zero();
  m_hadDevice = m_heldBack = m_hasPlane = m_hadPlane = false;
  if (context.events)
    context.events->log(context.t, "haptic_released", "the target's shape failed: proxy released to the device",
                        this);
}

void GodObjectProxy::followDevice(ProxyState& s, const Vec3& device, const Quat& orientation) {
  s.device = s.proxy = device;
  s.released = true;
  // Clear of the target: from the next frame the proxy works from here again.
  if (!m_target->overlaps({device, orientation}, m_tool->shellPoints())) m_released = false;
  m_state = s;
}

void GodObjectProxy::changeTools(const TickContext& context) {
  // The first target hears that the contact ended; the proxy starts again
  // where the device is, with no plane and no history of the old contact.
  ContactResponse ended;
  ended.t = context.t;
  m_target->respond(m_tool->shellPoints(), ended);
  if (l_nextTool) m_tool = &*l_nextTool;
  if (l_nextTarget) m_target = &*l_nextTarget;
  m_state = ProxyState{};
  m_lastNormal = Vec3::Zero();
  m_hadDevice = m_heldBack = m_hasPlane = m_hadPlane = m_started = false;
  m_changedTools = true;
  m_seenShapeFailures = m_target->shapeFailures();
  m_released = false;
}

void GodObjectProxy::tick(const TickContext& context) {
  if (l_toolChange && !m_changedTools && l_toolChange->changed()) changeTools(context);
  ShellTool& tool = *m_tool;
  ShellContactTarget& target = *m_target;
  const TargetFrame frame = target.beginFrame(context.t);
  m_frameContact = ShellContact{};
  m_stoppedAt.reset();
  const DeviceState& device = tool.device().state();
  ProxyState s;
  s.deviceValid = device.valid;
  s.removed = frame.removed;
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
  if (frame.shapeFailures != m_seenShapeFailures) {
    m_seenShapeFailures = frame.shapeFailures;
    letGo(context);
  }
  if (m_released) {
    followDevice(s, D, q);
    return;
  }
  const Vec3 P = m_state.proxy;
  s.device = D;

  // 1. Sweep before moving, towards the device. While the device presses
  // beneath last frame's constraint plane, the proxy slides along that plane
  // no farther than the device's own move plus kCatchUp (as in step 3): a
  // straight sweep to a device millimetres inside the bone would otherwise
  // carry the proxy across a groove in one frame wherever the probe sees no
  // bone, and the spring's direction would jump with it.
  Vec3 sweepEnd = D;
  bool beneathPlane = false;  // held because the device is beneath last frame's plane
  if (m_hadPlane && m_hadDevice) {
    const Vec3 toDevice = D - P;
    const double into = toDevice.dot(m_lastNormal);  // < 0: the device is beneath the plane
    const Vec3 along = toDevice - into * m_lastNormal;
    const double slideLimit = slideAllowance(D);
    // Also while the device rises off the plane, when the proxy was held back
    // and pulled on the device last frame: it lifts with the device at once
    // but closes the lag along the plane at the same pace, so a drag of
    // millimetres built up while sliding (at the force limit) fades instead
    // of dropping in one frame.
    const bool dragging = m_heldBack && m_state.penetration > 0;
    if ((into < 0 || dragging) && along.norm() > slideLimit) {
      sweepEnd = P + into * m_lastNormal + slideLimit / along.norm() * along;
      beneathPlane = into < 0;
    }
  }
  const bool heldBack = (D - sweepEnd).norm() > kSamePlace;
  m_heldBack = heldBack;
  Vec3 P1 = sweepEnd;
  bool blocked = false;
  Vec3 blockedAt = Vec3::Zero();
  const Vec3 path = sweepEnd - P;
  const double length = path.norm();
  if (m_sweeps && length > kSamePlace) {
    const SweepResult r = sweepPath(P, sweepEnd, q);
    if (r.blocked) {
      const double travel = r.freeFraction * length + (r.startsInside ? 0.0 : target.contactDepth());
      P1 = P + std::min(travel, length) / length * path;
      blocked = (D - P1).norm() > kSamePlace;
      blockedAt = r.contactPoint;
      if (blocked) ++m_blockedSweeps;
    }
  }

  // 2. Detection (and drilling) where the proxy now is.
  const bool cutting = d_drillButton.value() == 0 || (device.buttons >> (d_drillButton.value() - 1)) & 1u;
  s.cutting = cutting;
  const ShellContact c = target.collide({P1, q}, tool.shellPoints(), cutting);
  m_frameContact = c;
  s.points = c.points;
  s.primitives = c.primitives;
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
    s.overlap = skin;
    const Vec3 onPlane = P1 + (c.penetration - skin) * normal;
    Vec3 goal = P1;
    bool crease = false;
    if (d_godObject.value()) {
      goal = D + std::max(0.0, (onPlane - D).dot(normal)) * normal;
      // In a crease the new plane's projection crosses the last frame's plane:
      // the god-object then sits on both (their intersection nearest the device),
      // instead of alternating between them frame by frame.
      if (m_hadPlane && m_lastNormal.dot(normal) < kSamePlane && (goal - m_lastPlanePoint).dot(m_lastNormal) < 0) {
        const double a = normal.dot(m_lastNormal);
        const double det = 1.0 - a * a;
        const double b0 = (onPlane - D).dot(normal), b1 = (m_lastPlanePoint - D).dot(m_lastNormal);
        const double l0 = (b0 - a * b1) / det, l1 = (b1 - a * b0) / det;
        // Opposite planes (a near -1) have no useful intersection near the device.
        if (det > 1e-3 && l0 >= 0 && l1 >= 0) {
          goal = D + l0 * normal + l1 * m_lastNormal;
          crease = true;
        }
      }
    }
    // Half the slide along the surface each frame (the lift off it in full): on
    // a curved or rough surface the normal depends on where the proxy is, and a
    // full step lets proxy and normal chase each other frame by frame (the
    // projection moves the proxy by the device depth times the change of
    // normal). Halving converges geometrically and lags a steady slide by one
    // frame's motion at most.
    const Vec3 step = goal - P1;
    // The lift off the surface, along the normal the depth was measured on:
    // at least the measured depth less the skin. While last frame's plane
    // holds the proxy back (step 1), only that much: the rest of the way
    // towards a device that is out of this contact's plane (the contact
    // switched to another wall of a groove) is part of the slide, so the
    // proxy does not jump to the device in one frame.
    const double outOfDepth = std::max(0.0, c.penetration - skin);
    const double along = step.dot(normal);
    const Vec3 lift = (heldBack ? std::min(along, outOfDepth) : along) * normal;
    // The slide is also held to the device's own move this frame plus
    // kCatchUp: a proxy freed from a pit it was held in (a burr pressed into
    // its own cut, then slid) catches up over several frames instead of
    // jumping, so the force it renders changes by at most k kCatchUp beyond
    // what the hand's motion explains.
    Vec3 slide = kProxyRelaxation * (step - lift);
    const double slideLimit = slideAllowance(D);
    if (m_hadDevice && slide.norm() > slideLimit) slide *= slideLimit / slide.norm();
    goal = P1 + lift + slide;
    // 4. Rectifying sweep of the slide. The lift out along the contact normal
    // is taken first, unswept: the proxy is in the target when it is lifted, so
    // a sweep from there would stop it at once and keep it inside (a burr that
    // slipped into a drilled groove could never climb out).
    const Vec3 lifted = P1 + lift;
    P2 = goal;
    const Vec3 move = goal - lifted;
    const double moveLength = move.norm();
    bool heldByTarget = false;  // the target stops the proxy short of its goal
    if (d_rectify.value() && m_sweeps && moveLength > kSamePlace) {
      const SweepResult r = sweepPath(lifted, goal, q);
      if (r.blocked) {
        P2 = lifted + r.freeFraction * move;
        heldByTarget = (goal - P2).norm() > kSamePlace;
      }
    }
    // 5. Rendered penetration: the spring from the device to the proxy lifted
    // out by its skin, P2 + skin n - D, in its own direction. The proxy and the
    // device move continuously, so this vector does; the contact normal alone
    // does not (in a drilled groove it swings as points enter and leave the
    // bone, and times the device depth that is a jump of force). Held on a
    // surface it is the normal times the depth; sliding, it trails the device
    // by the proxy's lag (a drag); held by two planes, it points from the
    // device to the crease. Without the god-object the proxy is not over the
    // device: the thesis's depth along the normal.
    const Vec3 spring =
        d_godObject.value() ? Vec3(P2 + skin * normal - D) : Vec3(((P2 - D).dot(normal) + skin) * normal);
    if (crease) ++m_creaseFrames;
    // The device presses when the spring points out along this contact's
    // normal or the last frame's (a normal that swings for a frame in a
    // drilled pit must not drop the force for that frame), or when the target
    // holds the proxy back from the device: the proxy is then constrained and
    // the spring acts whatever the normal says. On a vertex or an edge (the
    // apex of a tetrahedron, the rim of a crack) the nearest face of a point
    // on it may be a side face, and its horizontal normal is orthogonal to a
    // device pressing straight down: judged by the normal alone, the proxy
    // would be held with no force.
    const bool pressing = spring.dot(normal) > kSamePlace || (m_hadPlane && spring.dot(m_lastNormal) > kSamePlace) ||
                          (heldByTarget && spring.norm() > kSamePlace);
    if (pressing) {
      s.penetration = spring.norm();
      s.normal = spring / s.penetration;
    } else {
      s.normal = normal;  // the device is out of the target: no push
      s.penetration = 0;
    }
    s.contact = true;
    m_planePoint = onPlane;
    m_planeNormal = normal;
    m_hasPlane = true;
  } else if (heldBack && !blocked && beneathPlane && nothingBetween(P1, D, q)) {
    // Held to last frame's plane, but no surface is there any more: the proxy
    // slid off the edge the plane came from (a device far beneath a tilted
    // plane, after a jump), and neither the way to the device nor the device
    // itself meets the target. Nothing holds the proxy: it joins the device,
    // and nothing is rendered (a plane kept here would pull the hand
    // sideways from wherever the proxy is, in free space).
    ++m_releasedHolds;
    P2 = D;
  } else if (blocked || heldBack) {
    // Conflicting case: the proxy is free where the sweep stopped it, or where
    // its slide along last frame's plane was held, but the device is beyond:
    // the spring to the device acts.
    ++m_conflictFrames;
    // A cutting tool cuts what stopped it, even between its shell points.
    if (cutting && blocked) m_stoppedAt = blockedAt;
    s.normal = (P1 - D).normalized();
    s.penetration = (D - P1).norm();
    s.contact = true;
    if (heldBack && !blocked) {
      // Still held to that plane next frame, so the proxy keeps catching up at
      // the same pace instead of jumping to the device.
      m_planePoint = m_lastPlanePoint;
      m_planeNormal = m_lastNormal;
      m_hasPlane = true;
    }
  }
  // 6. On a target being drilled, the spring's anchor (the proxy lifted by its
  // skin) moves no farther from the device than last frame's anchor now is
  // (PassiveAnchor.h): a re-projection on the cut surface never pushes harder
  // than the device's own move explains. Elsewhere the anchor may have to
  // move out: a deforming target pushes the tool, and a proxy that a sweep
  // left inside a rigid target is lifted out of it.
  if (s.contact && s.penetration > 0 && m_hadDevice && target.drills()) {
    const Vec3 wanted = D + s.penetration * s.normal;
    const Vec3 anchor = passiveAnchor(m_lastDevice + m_state.penetration * m_state.normal, wanted, D);
    if (anchor != wanted) {
      if ((anchor - wanted).norm() > kSamePlace) ++m_heldAnchors;  // not a rounding
      P2 += anchor - wanted;
      s.penetration = (anchor - D).norm();
      if (s.penetration > 0) s.normal = (anchor - D) / s.penetration;
    }
  }
  if (s.contact) ++m_contactFrames;
  // The constraint plane of this frame, for the next one.
  m_hadPlane = m_hasPlane;
  m_lastPlanePoint = m_planePoint;
  m_lastNormal = m_hasPlane ? m_planeNormal : (s.contact ? s.normal : m_lastNormal);
  m_hasPlane = false;
  if (!P2.allFinite() || !s.normal.allFinite() || !std::isfinite(s.penetration)) {
    // Never expected; if it happens the proxy and the force hold, and it is counted.
    ++m_nonFiniteFrames;
    const int removed = s.removed;
    s = m_state;
    s.device = D;
    s.removed = removed;
    P2 = m_state.proxy;
  }
  m_lastDevice = D;
  m_hadDevice = true;
  s.proxy = P2;
  s.proxyInside = target.overlaps({P2, q}, tool.shellPoints());
  m_state = s;
}

void GodObjectProxy::reportCounters(std::vector<Counter>& counters) const {
  counters.push_back({"contact_frames", double(m_contactFrames)});
  counters.push_back({"blocked_sweeps", double(m_blockedSweeps)});
  counters.push_back({"conflict_frames", double(m_conflictFrames)});
  counters.push_back({"degenerate_normals", double(m_degenerateNormals)});
  counters.push_back({"crease_frames", double(m_creaseFrames)});
  counters.push_back({"released_holds", double(m_releasedHolds)});
  counters.push_back({"releases", double(m_releases)});
  counters.push_back({"held_anchor_frames", double(m_heldAnchors)});
  if (m_nonFiniteFrames) counters.push_back({"non_finite_frames", double(m_nonFiniteFrames)});
}

}  // namespace trephine::haptics
