#pragma once
// A target that a pointshell tool collides with (a voxel skull, a tetrahedral
// brain). Each haptic frame its rate group's ContactFrame (ContactFrame.h)
// drives it through one contract, whatever the number of tools touching it:
//   beginFrame - once a frame, before any query: takes the target's latest
//                shape and applies the cuts of the frame before;
//   sweep      - how far a tool can move along a segment before entering the target;
//   collide    - which shell points are inside, the contact normal and
//                penetration they give, and what the response needs (the sites
//                it presses, the primitives a cut lowers), kept in the asking
//                tool's own ContactMemory: its answer is the value, and
//                depends on no other tool's query;
//   overlaps   - whether a displayed tool pose visibly overlaps the target;
//   respond    - once a frame, after every tool's force is known: all of the
//                frame's responses at once, in a fixed order (the renderers'
//                paths). Forces of several tools add up; cuts act on the next
//                frame's shape.
// A target keeps nothing per tool. All are called from the haptic loop (no
// allocation, no exception); the tools that share a target tick in one rate
// group (one thread).
#include <array>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "framework/geometry/ShellTool.h"
#include "framework/geometry/SurfaceTarget.h"

namespace trephine {

// Where a contact presses on a deformable target: up to four nodes with
// weights summing to 1 (a tetrahedron's barycentric coordinates, or a boundary
// triangle's with a zero fourth), and how deep (mm). The contact force is
// shared among the sites by depth, then among each site's nodes by weight.
struct ContactSite {
  std::array<int32_t, 4> nodes{-1, -1, -1, -1};
  std::array<double, 4> weights{0, 0, 0, 0};
  double depth = 0;
};

// What a tool placement collides with this frame. The spans stay valid until
// the same shell's next collide() on this target.
struct ShellContact {
  int points = 0;              // shell points inside the target
  int primitives = 0;          // colliding primitives (voxels, tetrahedra)
  Vec3 normal = Vec3::Zero();  // unit, out of the target towards the tool; zero if undefined
  double penetration = 0;      // mm, depth of the tool in the target as the target measures it
  std::span<const ContactSite> sites;  // deformable target: where the tool presses
  std::span<const int64_t> touched;    // the primitives a cut lowers (drillable target, asked for a cut) or
                                       // the tool touches (a target that resects)
};

// What one tool keeps for its queries of one target, from frame to frame:
// owned by the tool's step (its proxy), sized by the target's reserveShell(),
// so that no tool's query depends on another's.
struct ContactMemory {
  std::vector<ContactSite> sites;  // collide()'s sites (ShellContact::sites views them); capacity reserved
  std::vector<int64_t> touched;    // collide()'s primitives a cut lowers (ShellContact::touched); capacity reserved
  int32_t searchStart = 0;         // a search that starts at the last contact: its primitive
  // A drilling tool's breakthrough test: bone ahead of its burr at its last
  // cut (armed), when that cut was, and whether this stretch's was reported.
  bool boneAhead = false;
  double lastCutTime = -1e300;  // s
  bool brokeThrough = false;
};

// What a spinning burr does to a drillable target in one haptic frame: the
// target's removal law turns the load into removed material (force-driven
// drilling). Everything the law needs is here, so the cut depends on no state
// left by an earlier query.
struct CuttingLoad {
  Vec3 center_W = Vec3::Zero();  // mm, centre of the burr sphere as displayed (the proxy)
  double radius = 0;             // mm, burr radius
  double overlap = 0;            // mm, how deep the displayed burr sits in the target (its contact skin)
  Vec3 force_N = Vec3::Zero();   // N, force of the tool on the target this frame
  double dt = 0;                 // s, duration of the frame
  double t = 0;                  // s, time of the frame (for events)
  CuttingBurr burr;
  TissueAction action;  // the tool's action on tissue (a target that resects reads it)
};

// What one tool does to the target in one haptic frame, once its force is
// known: built from what this frame's collide() returned.
struct ContactResponse {
  double t = 0;                         // s, time of the frame
  Vec3 forceOnTarget_N = Vec3::Zero();  // N, the opposite of the force rendered to the user; zero without contact
  std::span<const ContactSite> sites;   // collide()'s sites
  // The drill runs and the tool is in contact: the target's removal law cuts,
  // from the load (force-driven), or from the primitives collide() touched
  // and the point where a sweep stopped the tool between its shell points
  // (the thesis's law).
  bool cutting = false;
  CuttingLoad load;
  std::span<const int64_t> touched;
  std::optional<Vec3> stoppedAt;  // mm, world
  ContactMemory* memory = nullptr;  // the responding tool's (its breakthrough test); null: no per-tool history
};

// What a tool learns at the start of a frame: the same for every tool of the frame.
struct TargetFrame {
  // How many times what shapes the target has failed so far, its shape
  // jumping (a deformation model that diverged and restarted from rest, a
  // frame of positions that was not this target's). A tool that sees the
  // count grow lets go of its contact, whose proxy and constraint plane belong
  // to a shape that is gone.
  uint64_t shapeFailures = 0;
  int removed = 0;  // primitives the cuts of the frame before removed (every tool's)
};

// How the sweep probes the path of a tool.
enum class SweepProbe {
  Line,      // the leading point of the tool (reference + leadingRadius along the motion)
  Cylinder,  // the leading point and a ring of lines at leadingRadius around the path
  Spheres,   // the whole pointshell at steps along the path (a string of spheres)
};

struct SweepQuery {
  Vec3 from;                            // mm, tool reference point at the start
  Vec3 to;                              // mm, and at the end
  Quat orientation = Quat::Identity();  // tool orientation along the path
  SweepProbe probe = SweepProbe::Line;
  double leadingRadius = 0;           // mm
  std::span<const ShellPoint> shell;  // tool frame (used by Spheres)
};

struct SweepResult {
  double freeFraction = 1;           // fraction of the segment travelled before entering the target
  bool blocked = false;              // the target stops the tool before `to`
  bool startsInside = false;         // blocked right at `from` (the tool already presses in this direction)
  Vec3 contactPoint = Vec3::Zero();  // mm, where the probe that stopped the tool met the target
};

class ShellContactTarget : public SurfaceTarget {
 public:
  static constexpr std::string_view kTypeName = "ShellContactTarget";

  // Called during initialisation for each tool shell that will collide with
  // this target (the span stays valid for the run): preallocates the
  // target's per-point working memory for it, and returns the memory the
  // tool keeps for its queries (its buffers reserved). Other shells are not tested.
  virtual ContactMemory reserveShell(std::span<const ShellPoint> shell) = 0;
  // Called right after reserveShell() with the solid the shell samples, for
  // targets whose back-ends test primitives; may throw when the target cannot
  // take the tool (a load error at the caller).
  virtual void describeTool(std::span<const ShellPoint> shell, const ToolSolid& solid) {
    (void)shell;
    (void)solid;
  }
  virtual SweepResult sweep(const SweepQuery& query) const = 0;
  // `cutting`: the tool's drill runs this frame; the answer then also holds
  // what its cut needs (ShellContact::touched). Nothing is removed here.
  // `memory`: the asking tool's (reserveShell()'s answer for this shell); the
  // answer's spans view it until the tool's next collide().
  virtual ShellContact collide(const Pose& X_WT, std::span<const ShellPoint> shell, bool cutting,
                               ContactMemory& memory) = 0;
  virtual bool overlaps(const Pose& X_WT, std::span<const ShellPoint> shell) const = 0;
  // Only the broad phase of collide() (the search for candidate primitives),
  // so that studies can time it apart; returns the candidates, or nothing
  // when the target does not split its query so.
  virtual std::optional<size_t> broadPhase(const Pose& X_WT, std::span<const ShellPoint> shell) {
    (void)X_WT;
    (void)shell;
    return std::nullopt;
  }
  // The finest detail the target's shape resolves (mm): its voxels' largest
  // side, its tetrahedra's median edge. A study takes the setting that
  // resolves its targets finest as the reference where there is no exact
  // shape. NaN: the target does not say.
  virtual double resolution() const { return std::numeric_limits<double>::quiet_NaN(); }
  // Whether the target's shape moves by itself (a deformation model drives
  // it): its surface may push the tool, so a proxy's spring follows it at
  // once. A rigid target's surface moves only where tools cut it.
  virtual bool deforms() const { return false; }
  // Whether tools cut this target (it is set to be drilled): material only
  // ever leaves it, so the space free of it only grows, and its cut surface is
  // rough at the scale of its primitives.
  virtual bool drills() const { return false; }
  // Whether tools remove this target's primitives as they touch it
  // (resection of a tetrahedral brain): its surface then recedes from under a
  // tool a primitive at a time, and the tool's spring follows at the pace the
  // device's own motion explains.
  virtual bool resects() const { return false; }
  // How far the proxy is placed into the target when a sweep stops it (mm):
  // enough for the shell points to register contact at the stop.
  virtual double contactDepth() const = 0;
  // Once a haptic frame (time t, s), before any query; see the top of this file.
  virtual TargetFrame beginFrame(double t) {
    (void)t;
    return {};
  }
  // The failure count beginFrame() reports, as it stands (for a tool that
  // starts on this target).
  virtual uint64_t shapeFailures() const { return 0; }
  // The frame's responses (see ContactResponse), once a frame, in a fixed
  // order, none when no tool touches it: a deformable target passes the sum
  // of the forces on to its deformation model (one value a frame), a
  // drillable one cuts at the start of the next frame, in this order.
  // `t`: the frame's time (s).
  virtual void respond(double t, std::span<const ContactResponse> responses) {
    (void)t;
    (void)responses;
  }
};

}  // namespace trephine
