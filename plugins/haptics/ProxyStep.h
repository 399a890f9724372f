#pragma once
// The god-object proxy's haptic frame as a function, in the manner of
// MuJoCo's mj_step(model, data) and Box2D's world step: what is fixed for a
// run (ProxySettings), what the proxy keeps from one frame to the next
// (ProxyMemory) and this frame's inputs (ProxyInput) give this frame's answer
// (ProxyFrame) and the memory for the next. The target is the world it is
// stepped against: its collide() only answers (a cut is the response's, after
// the force is known, and acts on the next frame's shape). Nothing else is carried
// between frames, so a copy of the memory replays the frames after it exactly,
// and a test drives the proxy without a scene graph.
//
// Each haptic frame (each stage a function of ProxyStep.cpp, named here):
//  1. sweep before moving (sweepTowardsDevice): the proxy moves from its last position towards the
//     device until the target stops it (placed contactDepth into the target);
//  2. detection at that position (detectContact): colliding shell points, contact normal and
//     raw penetration from the target, and what a cut would take (the
//     tool's ContactMemory keeps them);
//  3. god-object projection (followSurface, godObjectGoal): the device is projected on the constraint plane
//     through the proxy (lifted out to the contact depth when the raw
//     penetration is deeper), so the proxy slides along the surface;
//  4. rectifying sweep (rectifySlide) from the proxy to that projection, so the new position
//     never crosses another part of the target;
//  5. penetration (renderSpring) = the depth of the device below the constraint plane (the
//     device-proxy distance along the normal) plus the proxy's own contact depth;
//  6. on a target being drilled (holdAnchorToDeviceMotion), the spring's anchor (the proxy lifted by that
//     depth) ends no farther from the device than last frame's anchor now is,
//     so the proxy's own moves never stretch the spring (PassiveAnchor.h:
//     passive at the sampled-data bound);
//  7. a new place (keepDisplayedToolOutside) that shows the tool inside the target, where last frame's
//     did not, goes back along the move to the farthest free place.
// In a crease, where this frame's projection would cross the last frame's
// constraint plane, the proxy goes to the nearest point on both planes (the
// god-object with two constraints, Zilles and Salisbury) and the force points
// from the device to it.
// When the sweep stopped the sphere's leading point but no shell point
// collides there (a shell without a point right at its front, on a surface
// curving away), the proxy settles towards the device by the shell's sag
// (the largest gap between its sphere and its points) and detects again.
// Still none (the two conflicting cases of the rigid method), the normal is
// against the sweep direction and the penetration is the device-proxy distance.
#include <cstdint>
#include <optional>
#include <span>

#include "framework/geometry/ShellContactTarget.h"

namespace trephine::haptics {

// What the proxy renders this frame.
struct ProxyState {
  Vec3 device = Vec3::Zero();  // mm, tool reference point where the device puts it
  Vec3 proxy = Vec3::Zero();   // mm, displayed tool reference point
  Vec3 normal = Vec3::Zero();  // unit contact normal (out of the target); zero without contact
  double penetration = 0;      // mm, rendered depth
  double rawPenetration = 0;   // mm, as detected before rectification
  double overlap = 0;          // mm, depth of the displayed tool in the target (its contact skin)
  int points = 0;              // colliding shell points
  int primitives = 0;          // colliding voxels / tetrahedra
  int removed = 0;  // primitives the target lost at the start of this frame (every tool's cuts of the frame before)
  bool contact = false;
  bool cutting = false;      // the drill runs this frame (pedal held, or no pedal)
  bool proxyInside = false;  // the displayed proxy visibly overlaps the target
  bool deviceValid = false;
  // Let go after what shapes the target failed: the proxy is at the device and
  // no contact is rendered until the tool is clear of the target.
  bool released = false;
};

// Fixed for a run (the scene's fields).
struct ProxySettings {
  bool sweeps = true;  // false: the proxy jumps to the device (sweep="none")
  SweepProbe probe = SweepProbe::Line;
  bool rectify = true;    // sweep again from the proxy to its god-object position
  bool godObject = true;  // project the device on the constraint plane
};

// This frame's inputs.
struct ProxyInput {
  bool deviceValid = false;
  Pose toolPose;                      // mm, the tool's pose where the device puts it (when valid)
  bool cutting = false;               // the drill runs
  TargetFrame frame;                  // what the target's beginFrame() said this frame
  std::span<const ShellPoint> shell;  // the tool's shell, tool frame
  ContactMemory* contactMemory = nullptr;  // the tool's, for its queries of this target (reserveShell())
  double leadingRadius = 0;           // mm
  double shellSag = 0;                // mm, shellSag() of the shell (ShellSampling.h)
};

// Running totals, reported as the proxy's counters.
struct ProxyCounters {
  uint64_t contactFrames = 0;
  uint64_t blockedSweeps = 0;
  uint64_t conflictFrames = 0;  // the sweep or the plane held the proxy where no shell point collides
  uint64_t degenerateNormals = 0;
  uint64_t creaseFrames = 0;
  uint64_t nonFiniteFrames = 0;
  uint64_t releasedHolds = 0;  // a hold to last frame's plane found no surface and let the proxy go
  uint64_t releases = 0;       // times the proxy was let go after a shape failure
  uint64_t heldAnchors = 0;    // frames whose anchor was held to the last one's distance from the device
  uint64_t startsInside = 0;   // starts (first valid device frame, tool changes) with the tool in the target
  uint64_t heldOutside = 0;    // frames whose new place was inside the target: held at the last free one
  uint64_t fadedReleases = 0;  // frames whose ended contact's spring faded at the pace it may change
  uint64_t settledFrames = 0;  // a sweep stopped the sphere but no shell point: settled by the shell's sag
};

// What the proxy keeps from one frame to the next.
struct ProxyMemory {
  ProxyState state;  // last frame's
  Vec3 lastNormal = Vec3::Zero();
  Vec3 lastDevice = Vec3::Zero();      // mm, the device's point last frame
  Vec3 lastPlanePoint = Vec3::Zero();  // mm, a point on last frame's constraint plane (normal: lastNormal)
  bool hadDevice = false;
  bool heldBack = false;  // last frame's sweep towards the device was held to the plane
  bool hadPlane = false;
  bool started = false;            // the proxy has been placed (on the device's first valid frame)
  bool released = false;           // let go after a shape failure, until the tool is clear
  // A contact that ended because the tissue in front of the tool was removed
  // (a resected target): its spring fades at the pace it may change, over
  // the frames after, until it is gone or a contact comes back.
  bool fadingRemoval = false;
  uint64_t seenShapeFailures = 0;  // the target's shapeFailures last seen
  ProxyCounters counters;

  // A new start against a target whose failures so far are `shapeFailures`:
  // no contact, no plane, no history; the counters run on.
  void restart(uint64_t shapeFailures);
};

// This frame's answer.
struct ProxyFrame {
  ProxyState state;
  // What collide() returned (its spans view the tool's ContactMemory, until
  // its next collide()) and the point where a sweep stopped a cutting tool
  // between its shell points: what the target's response takes.
  ShellContact contact;
  std::optional<Vec3> stoppedAt;
  bool letGo = false;  // this frame let the proxy go after a shape failure (an event)
  // The tool's first pose (at the start, or after a tool change) overlaps
  // the target: the proxy starts where the device is, inside, and the
  // god-object lifts it out, so the spring renders the whole depth (an event).
  bool startedInside = false;
};

// One haptic frame. Allocation-free; the target's queries are the only calls out.
ProxyFrame stepProxy(const ProxySettings& settings, ProxyMemory& memory, const ProxyInput& input,
                     ShellContactTarget& target);

}  // namespace trephine::haptics
