#include "plugins/haptics/ProxyStep.h"

#include <algorithm>
#include <cmath>

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
// Halvings of a move that ended inside the target, to the last free place
// along it (1/64 of the move: 0.01 mm of a 0.6 mm jump).
constexpr int kFreeSearchSteps = 6;

// One frame's work: the settings, the memory, the inputs and the target.
class Frame {
 public:
  Frame(const ProxySettings& settings, ProxyMemory& memory, const ProxyInput& input, ShellContactTarget& target)
      : m_settings(settings), m_memory(memory), m_input(input), m_target(target) {}

  ProxyFrame run();

 private:
  // mm: how far the proxy may slide along its constraint plane this frame.
  double slideAllowance(const Vec3& device) const {
    // The device's own move, but no more than the tool's leading radius: the
    // constraint plane stands for the surface only over the contact patch, so
    // a longer slide along it (a device that jumped far beneath a tilted
    // plane projects onto it metres away) would leave the surface it was
    // measured on. The proxy covers a longer way over several frames, its
    // contact measured anew after each step.
    return std::min((device - m_memory.lastDevice).norm(), m_input.leadingRadius) + kCatchUp;
  }
  SweepResult sweepPath(const Vec3& from, const Vec3& to) const {
    SweepQuery query;
    query.from = from;
    query.to = to;
    query.orientation = m_input.toolPose.orientation;
    query.probe = m_settings.probe;
    query.leadingRadius = m_input.leadingRadius;
    query.shell = m_input.shell;
    return m_target.sweep(query);
  }
  bool overlapsAt(const Vec3& position) const {
    return m_target.overlaps({position, m_input.toolPose.orientation}, m_input.shell);
  }
  // Neither the sweep from `from` to the device nor the tool at the device meets the target.
  bool nothingBetween(const Vec3& from, const Vec3& device) const {
    if (m_settings.sweeps && sweepPath(from, device).blocked) return false;
    return !overlapsAt(device);
  }
  void letGo();
  // A frame with a valid device, in its stages (the numbers of ProxyStep.h).
  ProxyFrame contactFrame();
  void sweepTowardsDevice();                        // 1
  ShellContact detectContact();                     // 2
  ShellContact settleOntoShell();                   // 2: the sweep stopped the sphere, but no point
  Vec3 contactNormal(const ShellContact& contact);  // 2: the last one when the contact's cancels out
  // 3 to 5, with the surface in contact: projection, relaxation, rectifying sweep, spring.
  void followSurface(const ShellContact& contact, const Vec3& normal);
  Vec3 godObjectGoal(const Vec3& onPlane, const Vec3& normal, bool& crease) const;  // 3
  bool rectifySlide(const Vec3& lifted, const Vec3& goal);                          // 4
  void renderSpring(const Vec3& normal, double skin, bool heldByTarget);            // 5
  // Without a surface in contact: last frame's plane gone, or the conflicting case.
  void letGoOfVanishedPlane();
  void springToDevice();
  void holdAnchorToDeviceMotion();  // 6
  void fadeEndedContact();          // 6b
  void keepPlaneForNextFrame();
  void holdOnNonFinite();
  void keepDisplayedToolOutside();  // 7

  const ProxySettings& m_settings;
  ProxyMemory& m_memory;
  const ProxyInput& m_input;
  ShellContactTarget& m_target;
  ProxyFrame m_out;
  // This frame's places (mm) and what the stages found.
  Vec3 m_device = Vec3::Zero();  // D, where the device puts the tool
  Vec3 m_start = Vec3::Zero();   // the proxy at the start of the frame
  Vec3 m_swept = Vec3::Zero();   // where the sweep towards the device left it
  Vec3 m_proxy = Vec3::Zero();   // where it ends the frame
  bool m_heldBack = false;       // the sweep's end held short of the device by last frame's plane
  bool m_beneathPlane = false;   // held because the device is beneath that plane
  bool m_blocked = false;        // the target stopped the sweep short of the device
  Vec3 m_blockedAt = Vec3::Zero();  // where the probe that stopped it met the target
  // This frame's constraint plane, for the next frame.
  Vec3 m_planePoint = Vec3::Zero(), m_planeNormal = Vec3::Zero();
  bool m_hasPlane = false;
};

void Frame::letGo() {
  // What shapes the target failed and its shape jumped: the proxy's place
  // and its constraint plane belong to a shape that is gone, and the spring
  // to them may point anywhere, into the target or away from the tool. The
  // proxy goes to the device and renders nothing (ForceFeedback takes the
  // force it rendered to zero along its ramp) until the tool is clear of the
  // target; then it starts again there. Already let go, it stays so (one
  // event, however many failures follow before the tool is clear).
  if (m_memory.released) return;
  ++m_memory.counters.releases;
  m_memory.released = true;
  m_memory.lastNormal = Vec3::Zero();
  m_memory.hadDevice = m_memory.heldBack = m_memory.hadPlane = false;
  m_out.letGo = true;
}

ProxyFrame Frame::run() {
  ProxyState& s = m_out.state;
  s.deviceValid = m_input.deviceValid;
  s.removed = m_input.frame.removed;
  if (!m_input.deviceValid) {
    s.proxy = m_memory.state.proxy;
    m_memory.state = s;
    return m_out;
  }
  const Vec3 D = m_input.toolPose.position;
  if (!m_memory.started) {
    m_memory.state.proxy = D;  // the proxy starts with the device, wherever that is
    m_memory.started = true;
    if (overlapsAt(D)) {
      m_out.startedInside = true;
      ++m_memory.counters.startsInside;
    }
  }
  if (m_input.frame.shapeFailures != m_memory.seenShapeFailures) {
    m_memory.seenShapeFailures = m_input.frame.shapeFailures;
    letGo();
  }
  if (m_memory.released) {
    // While let go: the proxy at the device, until the tool is clear of the target.
    s.device = s.proxy = D;
    s.released = true;
    // Clear of the target: from the next frame the proxy works from here again.
    if (!overlapsAt(D)) m_memory.released = false;
    m_memory.state = s;
    return m_out;
  }
  return contactFrame();
}

ProxyFrame Frame::contactFrame() {
  m_device = m_input.toolPose.position;
  m_start = m_memory.state.proxy;
  m_out.state.device = m_device;
  sweepTowardsDevice();
  ShellContact c = detectContact();
  if (c.points == 0 && m_blocked && m_input.shellSag > 0) c = settleOntoShell();
  const Vec3 normal = contactNormal(c);
  if (c.points > 0 && normal.squaredNorm() > 0.5) {
    followSurface(c, normal);
  } else if (m_heldBack && !m_blocked && m_beneathPlane && nothingBetween(m_swept, m_device)) {
    letGoOfVanishedPlane();
  } else if (m_blocked || m_heldBack) {
    springToDevice();
  }
  // (Also a contact whose spring measures nothing now, where last frame's
  // pressed: a lone point grazing a wall at an angle must not drop the force.)
  if (m_out.state.contact && (m_out.state.penetration > 0 || m_memory.state.penetration > 0) &&
      m_memory.hadDevice && (!m_target.deforms() || m_target.resects()))
    holdAnchorToDeviceMotion();
  fadeEndedContact();
  if (m_out.state.contact) ++m_memory.counters.contactFrames;
  keepPlaneForNextFrame();
  holdOnNonFinite();
  keepDisplayedToolOutside();
  m_memory.lastDevice = m_device;
  m_memory.hadDevice = true;
  m_out.state.proxy = m_proxy;
  m_memory.state = m_out.state;
  return m_out;
}

void Frame::sweepTowardsDevice() {
  // 1. Sweep before moving, towards the device. While the device presses
  // beneath last frame's constraint plane, the proxy slides along that plane
  // no farther than the device's own move plus kCatchUp (as in followSurface):
  // a straight sweep to a device millimetres inside the bone would otherwise
  // carry the proxy across a groove in one frame wherever the probe sees no
  // bone, and the spring's direction would jump with it.
  const ProxyMemory& m = m_memory;
  const Vec3& D = m_device;
  const Vec3& P = m_start;
  Vec3 sweepEnd = D;
  if (m.hadPlane && m.hadDevice) {
    const Vec3 toDevice = D - P;
    const double into = toDevice.dot(m.lastNormal);  // < 0: the device is beneath the plane
    const Vec3 along = toDevice - into * m.lastNormal;
    const double slideLimit = slideAllowance(D);
    // Also while the device rises off the plane, when the proxy was held back
    // and pulled on the device last frame: it lifts with the device at once
    // but closes the lag along the plane at the same pace, so a drag of
    // millimetres built up while sliding (at the force limit) fades instead
    // of dropping in one frame.
    const bool dragging = m.heldBack && m.state.penetration > 0;
    if ((into < 0 || dragging) && along.norm() > slideLimit) {
      sweepEnd = P + into * m.lastNormal + slideLimit / along.norm() * along;
      m_beneathPlane = into < 0;
    }
  }
  m_heldBack = (D - sweepEnd).norm() > kSamePlace;
  m_memory.heldBack = m_heldBack;
  m_swept = sweepEnd;
  const Vec3 path = sweepEnd - P;
  const double length = path.norm();
  if (m_settings.sweeps && length > kSamePlace) {
    const SweepResult r = sweepPath(P, sweepEnd);
    if (r.blocked) {
      const double travel = r.freeFraction * length + (r.startsInside ? 0.0 : m_target.contactDepth());
      m_swept = P + std::min(travel, length) / length * path;
      m_blocked = (D - m_swept).norm() > kSamePlace;
      m_blockedAt = r.contactPoint;
      if (m_blocked) ++m_memory.counters.blockedSweeps;
    }
  }
  m_proxy = m_swept;
}

ShellContact Frame::detectContact() {
  // 2. Detection (and drilling) where the sweep left the proxy.
  ProxyState& s = m_out.state;
  s.cutting = m_input.cutting;
  const ShellContact c =
      m_target.collide({m_swept, m_input.toolPose.orientation}, m_input.shell, m_input.cutting, *m_input.contactMemory);
  m_out.contact = c;
  s.points = c.points;
  s.primitives = c.primitives;
  s.rawPenetration = c.penetration;
  return c;
}

ShellContact Frame::settleOntoShell() {
  // The sweep stopped the sphere's leading point contactDepth into the
  // surface, but no shell point is there: the shell has no point right at
  // its front and the surface curves away from it. Left so, the proxy would
  // stay blocked with nothing in contact each frame (a force with no site on
  // the target, a deforming target never pressed). It goes on towards the
  // device by the shell's sag, no farther than the device, and detects again.
  const Vec3 toDevice = m_device - m_swept;
  const double distance = toDevice.norm();
  if (!(distance > kSamePlace)) return m_out.contact;
  m_swept += std::min(m_input.shellSag, distance) / distance * toDevice;
  m_proxy = m_swept;
  ++m_memory.counters.settledFrames;
  return detectContact();
}

Vec3 Frame::contactNormal(const ShellContact& c) {
  if (c.points > 0 && c.normal.squaredNorm() < 0.5) {
    // Contacts all round cancel out (the tool buried in the target): keep the last direction.
    ++m_memory.counters.degenerateNormals;
    return m_memory.lastNormal;
  }
  return c.normal;
}

Vec3 Frame::godObjectGoal(const Vec3& onPlane, const Vec3& normal, bool& crease) const {
  // 3. God-object projection of the device on the constraint plane (through
  // onPlane, lifted to the contact depth).
  const ProxyMemory& m = m_memory;
  const Vec3& D = m_device;
  Vec3 goal = D + std::max(0.0, (onPlane - D).dot(normal)) * normal;
  // In a crease the new plane's projection crosses the last frame's plane:
  // the god-object then sits on both (their intersection nearest the device),
  // instead of alternating between them frame by frame.
  if (m.hadPlane && m.lastNormal.dot(normal) < kSamePlane && (goal - m.lastPlanePoint).dot(m.lastNormal) < 0) {
    const double a = normal.dot(m.lastNormal);
    const double det = 1.0 - a * a;
    const double b0 = (onPlane - D).dot(normal), b1 = (m.lastPlanePoint - D).dot(m.lastNormal);
    const double l0 = (b0 - a * b1) / det, l1 = (b1 - a * b0) / det;
    // Opposite planes (a near -1) have no useful intersection near the device.
    if (det > 1e-3 && l0 >= 0 && l1 >= 0) {
      goal = D + l0 * normal + l1 * m.lastNormal;
      crease = true;
    }
  }
  return goal;
}

void Frame::followSurface(const ShellContact& c, const Vec3& normal) {
  ProxyState& s = m_out.state;
  const ProxyMemory& m = m_memory;
  const Vec3& D = m_device;
  const Vec3& P1 = m_swept;
  const double skin = std::min(c.penetration, m_target.contactDepth());
  s.overlap = skin;
  const Vec3 onPlane = P1 + (c.penetration - skin) * normal;
  bool crease = false;
  Vec3 goal = m_settings.godObject ? godObjectGoal(onPlane, normal, crease) : P1;
  // Half the slide along the surface each frame (the lift off it in full): on
  // a curved or rough surface the normal depends on where the proxy is, and a
  // full step lets proxy and normal chase each other frame by frame (the
  // projection moves the proxy by the device depth times the change of
  // normal). Halving converges geometrically and lags a steady slide by one
  // frame's motion at most.
  const Vec3 step = goal - P1;
  // The lift off the surface, along the normal the depth was measured on:
  // at least the measured depth less the skin. While last frame's plane
  // holds the proxy back (sweepTowardsDevice), only that much: the rest of
  // the way towards a device that is out of this contact's plane (the
  // contact switched to another wall of a groove) is part of the slide, so
  // the proxy does not jump to the device in one frame.
  const double outOfDepth = std::max(0.0, c.penetration - skin);
  const double along = step.dot(normal);
  const Vec3 lift = (m_heldBack ? std::min(along, outOfDepth) : along) * normal;
  // The slide is also held to the device's own move this frame plus
  // kCatchUp: a proxy freed from a pit it was held in (a burr pressed into
  // its own cut, then slid) catches up over several frames instead of
  // jumping, so the force it renders changes by at most k kCatchUp beyond
  // what the hand's motion explains.
  Vec3 slide = kProxyRelaxation * (step - lift);
  const double slideLimit = slideAllowance(D);
  if (m.hadDevice && slide.norm() > slideLimit) slide *= slideLimit / slide.norm();
  goal = P1 + lift + slide;
  const bool heldByTarget = rectifySlide(P1 + lift, goal);
  if (crease) ++m_memory.counters.creaseFrames;
  renderSpring(normal, skin, heldByTarget);
  s.contact = true;
  m_planePoint = onPlane;
  m_planeNormal = normal;
  m_hasPlane = true;
}

bool Frame::rectifySlide(const Vec3& lifted, const Vec3& goal) {
  // 4. Rectifying sweep of the slide. The lift out along the contact normal
  // is taken first, unswept: the proxy is in the target when it is lifted, so
  // a sweep from there would stop it at once and keep it inside (a burr that
  // slipped into a drilled groove could never climb out). Returns whether the
  // target stops the proxy short of its goal.
  m_proxy = goal;
  const Vec3 move = goal - lifted;
  if (!(m_settings.rectify && m_settings.sweeps && move.norm() > kSamePlace)) return false;
  const SweepResult r = sweepPath(lifted, goal);
  if (!r.blocked) return false;
  m_proxy = lifted + r.freeFraction * move;
  return (goal - m_proxy).norm() > kSamePlace;
}

void Frame::renderSpring(const Vec3& normal, double skin, bool heldByTarget) {
  // 5. Rendered penetration: the spring from the device to the proxy lifted
  // out by its skin, P + skin n - D, in its own direction. The proxy and the
  // device move continuously, so this vector does; the contact normal alone
  // does not (in a drilled groove it swings as points enter and leave the
  // bone, and times the device depth that is a jump of force). Held on a
  // surface it is the normal times the depth; sliding, it trails the device
  // by the proxy's lag (a drag); held by two planes, it points from the
  // device to the crease. Without the god-object the proxy is not over the
  // device: the thesis's depth along the normal.
  ProxyState& s = m_out.state;
  const Vec3& D = m_device;
  const Vec3 spring =
      m_settings.godObject ? Vec3(m_proxy + skin * normal - D) : Vec3(((m_proxy - D).dot(normal) + skin) * normal);
  // The device presses when the spring points out along this contact's
  // normal or the last frame's (a normal that swings for a frame in a
  // drilled pit must not drop the force for that frame), or when the target
  // holds the proxy back from the device: the proxy is then constrained and
  // the spring acts whatever the normal says. On a vertex or an edge (the
  // apex of a tetrahedron, the rim of a crack) the nearest face of a point
  // on it may be a side face, and its horizontal normal is orthogonal to a
  // device pressing straight down: judged by the normal alone, the proxy
  // would be held with no force.
  const bool pressing = spring.dot(normal) > kSamePlace ||
                        (m_memory.hadPlane && spring.dot(m_memory.lastNormal) > kSamePlace) ||
                        (heldByTarget && spring.norm() > kSamePlace);
  if (pressing) {
    s.penetration = spring.norm();
    s.normal = spring / s.penetration;
  } else {
    s.normal = normal;  // the device is out of the target: no push
    s.penetration = 0;
  }
}

void Frame::letGoOfVanishedPlane() {
  // Held to last frame's plane, but no surface is there any more: the proxy
  // slid off the edge the plane came from (a device far beneath a tilted
  // plane, after a jump), and neither the way to the device nor the device
  // itself meets the target. Nothing holds the proxy: it joins the device,
  // and nothing is rendered (a plane kept here would pull the hand sideways
  // from wherever the proxy is, in free space).
  ++m_memory.counters.releasedHolds;
  m_proxy = m_device;
}

void Frame::springToDevice() {
  // Conflicting case: the proxy is free where the sweep stopped it, or where
  // its slide along last frame's plane was held, but the device is beyond:
  // the spring to the device acts.
  ProxyState& s = m_out.state;
  ++m_memory.counters.conflictFrames;
  // A cutting tool cuts what stopped it, even between its shell points.
  if (m_input.cutting && m_blocked) m_out.stoppedAt = m_blockedAt;
  s.normal = (m_swept - m_device).normalized();
  s.penetration = (m_device - m_swept).norm();
  s.contact = true;
  if (m_heldBack && !m_blocked) {
    // Still held to that plane next frame, so the proxy keeps catching up at
    // the same pace instead of jumping to the device.
    m_planePoint = m_memory.lastPlanePoint;
    m_planeNormal = m_memory.lastNormal;
    m_hasPlane = true;
  }
}

void Frame::holdAnchorToDeviceMotion() {
  // 6. On a target being drilled, the spring's anchor (the proxy lifted by its
  // skin) moves no farther from the device than last frame's anchor now is
  // (PassiveAnchor.h): a re-projection on the cut surface never pushes harder
  // than the device's own move explains. Elsewhere the anchor may have to
  // move out: a deforming target pushes the tool (not called for it, unless
  // it is resected: tissue removed from under the tool would otherwise drop
  // the force by the depth of a tetrahedron at once), and a proxy that a
  // sweep left inside a rigid target is lifted out of it.
  // The spring (anchor less device) also changes by no more than the
  // device's own move plus kCatchUp in a frame: bone cut from under the burr,
  // or a contact normal that swings as its points enter and leave a rough
  // cut, otherwise changes the force at once by k times the jump of the
  // anchor, a step the hand's motion does not explain. So held, it changes
  // by at most k kCatchUp beyond what the motion explains (0.04 N at 2 N/mm),
  // and the anchor catches up over the next frames.
  ProxyState& s = m_out.state;
  const ProxyMemory& m = m_memory;
  const Vec3& D = m_device;
  const Vec3 proposed = D + s.penetration * s.normal;
  const Vec3 lastSpring = m.state.penetration * m.state.normal;
  const Vec3 change = (proposed - D) - lastSpring;
  const double allowance = (D - m.lastDevice).norm() + kCatchUp;
  const Vec3 wanted = change.norm() > allowance ? Vec3(D + lastSpring + allowance / change.norm() * change) : proposed;
  const Vec3 anchor = m_target.drills() ? passiveAnchor(m.lastDevice + lastSpring, wanted, D) : wanted;
  if (anchor != proposed) {
    if ((anchor - proposed).norm() > kSamePlace) ++m_memory.counters.heldAnchors;  // not a rounding
    m_proxy += anchor - proposed;
    s.penetration = (anchor - D).norm();
    if (s.penetration > 0) s.normal = (anchor - D) / s.penetration;
  }
}

void Frame::fadeEndedContact() {
  // 6b. A contact that ends on a rigid target, with a spring longer than the
  // pace it may change a frame (the device's move plus kCatchUp): the spring
  // fades at that pace instead of dropping at once. A proxy that lagged
  // (held against the wall of a fissure and lifted over its rim, a drag at
  // the force limit) would otherwise let go of newtons in a frame that the
  // hand's motion does not explain; the true god-object's spring shrinks to
  // nothing as the device leaves the rounded rim. A device that jumped lets
  // go at once (its move is the pace), and so does a spring longer than the
  // tool's leading radius (a proxy left behind a device that jumped away
  // belongs to no contact: the plane stands for the surface only over the
  // contact patch); a drilled target's breakthrough and a deforming target's
  // surface moving away are real and drop at once.
  // On a resected target, tissue removed from in front of the tool ends the
  // contact too (the removal the frame began with, or one this fade goes on
  // from): its spring fades the same way, however long it was and although
  // the target deforms, since nothing in the hand's motion explains the drop.
  ProxyState& s = m_out.state;
  ProxyMemory& m = m_memory;
  const bool tissueWent = m_target.resects() && (m_input.frame.removed > 0 || m.fadingRemoval);
  m.fadingRemoval = false;
  if (s.contact || !m.state.contact || !(m.state.penetration > 0) || !m.hadDevice) return;
  if (!tissueWent &&
      (m.state.penetration > m_input.leadingRadius || m_target.deforms() || m_target.drills()))
    return;
  const double fade = m.state.penetration - ((m_device - m.lastDevice).norm() + kCatchUp);
  if (fade > 0) {
    s.contact = true;
    s.normal = m.state.normal;
    s.penetration = fade;
    m_proxy = m_device + fade * s.normal;
    m.fadingRemoval = tissueWent;
    ++m_memory.counters.fadedReleases;
  }
}

void Frame::keepPlaneForNextFrame() {
  ProxyMemory& m = m_memory;
  m.hadPlane = m_hasPlane;
  if (m_hasPlane) m.lastPlanePoint = m_planePoint;
  m.lastNormal = m_hasPlane ? m_planeNormal : (m_out.state.contact ? m_out.state.normal : m.lastNormal);
}

void Frame::holdOnNonFinite() {
  ProxyState& s = m_out.state;
  if (m_proxy.allFinite() && s.normal.allFinite() && std::isfinite(s.penetration)) return;
  // Never expected; if it happens the proxy and the force hold, and it is counted.
  ++m_memory.counters.nonFiniteFrames;
  const int removed = s.removed;
  s = m_memory.state;
  s.device = m_device;
  s.removed = removed;
  m_proxy = m_memory.state.proxy;
}

void Frame::keepDisplayedToolOutside() {
  ProxyState& s = m_out.state;
  const ProxyMemory& m = m_memory;
  s.proxyInside = overlapsAt(m_proxy);
  if (!(m_settings.godObject && s.proxyInside && m.hadDevice && !m.state.proxyInside && s.contact &&
        !overlapsAt(m_start)))
    return;
  // 7. The new place shows the tool inside the target, where last frame's
  // did not: a sweep that missed a fold between two probes (the line probe
  // sees only the leading point's path). The proxy goes back along its move
  // to the farthest place that is still free, and the spring's anchor with
  // it, so the displayed tool never enters the target.
  Vec3 free = m_start, inside = m_proxy;
  for (int i = 0; i < kFreeSearchSteps; ++i) {
    const Vec3 middle = 0.5 * (free + inside);
    (overlapsAt(middle) ? inside : free) = middle;
  }
  const Vec3 anchor = m_device + s.penetration * s.normal + (free - m_proxy);
  s.penetration = (anchor - m_device).norm();
  if (s.penetration > 0) s.normal = (anchor - m_device) / s.penetration;
  m_proxy = free;
  s.proxyInside = false;
  ++m_memory.counters.heldOutside;
}

}  // namespace

void ProxyMemory::restart(uint64_t shapeFailures) {
  const ProxyCounters kept = counters;
  *this = ProxyMemory{};
  counters = kept;
  seenShapeFailures = shapeFailures;
}

ProxyFrame stepProxy(const ProxySettings& settings, ProxyMemory& memory, const ProxyInput& input,
                     ShellContactTarget& target) {
  return Frame(settings, memory, input, target).run();
}

}  // namespace trephine::haptics
