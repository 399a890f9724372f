#pragma once
// A target that a pointshell tool collides with (a voxel skull, a tetrahedral
// brain). The god-object proxy drives it through three queries, all called
// from the haptic loop (no allocation, no exception):
//   sweep    - how far the tool can move along a segment before entering the target;
//   collide  - which shell points are inside, and the contact normal and
//              penetration they give (and, for a drillable target, removal);
//   overlaps - whether a displayed tool pose visibly overlaps the target.
#include <optional>
#include <span>
#include <string_view>

#include "framework/geometry/PointShellTool.h"
#include "framework/geometry/SurfaceTarget.h"

namespace trephine {

// What a tool placement collides with this frame.
struct ShellContact {
  int points = 0;              // shell points inside the target
  int primitives = 0;          // colliding primitives (voxels, tetrahedra)
  int removed = 0;             // primitives removed this frame (drilling)
  Vec3 normal = Vec3::Zero();  // unit, out of the target towards the tool; zero if undefined
  double penetration = 0;      // mm, depth of the tool in the target as the target measures it
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
  // this target (the span stays valid for the run): preallocates per-point
  // working memory and any per-shell data. Other shells are not tested.
  virtual void reserveShell(std::span<const ShellPoint> shell) = 0;
  // Called right after reserveShell() with the solid the shell samples, for
  // targets whose back-ends test primitives; may throw when the target cannot
  // take the tool (a load error at the caller).
  virtual void describeTool(std::span<const ShellPoint> shell, const ToolSolid& solid) {
    (void)shell;
    (void)solid;
  }
  virtual SweepResult sweep(const SweepQuery& query) const = 0;
  // `removeMaterial`: the tool cuts now (a drill that is running); a target
  // that cannot be cut, or is not set to, ignores it.
  virtual ShellContact collide(const Pose& X_WT, std::span<const ShellPoint> shell, bool removeMaterial) = 0;
  virtual bool overlaps(const Pose& X_WT, std::span<const ShellPoint> shell) const = 0;
  // Only the broad phase of collide() (the search for candidate primitives),
  // so that studies can time it apart; returns the candidates, or nothing
  // when the target does not split its query so.
  virtual std::optional<size_t> broadPhase(const Pose& X_WT, std::span<const ShellPoint> shell) {
    (void)X_WT;
    (void)shell;
    return std::nullopt;
  }
  // The tool cuts where a sweep stopped it although none of its shell points
  // is inside there (the probe is between them): returns the primitives
  // removed. A target that cannot be cut, or is not set to, does nothing.
  virtual int cutAt(const Vec3& point_W) { return 0; }
  // A spinning burr loaded against the target this frame (force-driven
  // removal): returns the primitives removed. The force of this frame acts on
  // the next frame's shape. A target that cannot be cut, or is not set to,
  // does nothing.
  virtual int cutUnderLoad(const CuttingLoad& load) { return 0; }
  // Whether tools cut this target (it is set to be drilled): material only
  // ever leaves it, so the space free of it only grows, and its cut surface is
  // rough at the scale of its primitives.
  virtual bool drills() const { return false; }
  // How far the proxy is placed into the target when a sweep stops it (mm):
  // enough for the shell points to register contact at the stop.
  virtual double contactDepth() const = 0;
  // Called by each tool at the start of its haptic frame, before any query: a
  // deforming target takes its latest shape here, so that every query of the
  // frame sees the same one.
  virtual void refresh() {}
  // The force (N) the tool's contact exerts on the target this frame (the
  // opposite of the force rendered to the user), from the last collide():
  // for a deformable target to pass on to its deformation model. Called every
  // haptic frame, with zero when the tool touches nothing.
  virtual void applyContactForce(const Vec3& forceOnTarget_N, double t) {}
  // How many times what shapes this target has failed so far, its shape
  // jumping (a deformation model that diverged and restarted from rest, a
  // frame of positions that was not this target's). Read after refresh(): a
  // tool that sees the count grow lets go of its contact, whose proxy and
  // constraint plane belong to a shape that is gone.
  virtual uint64_t shapeFailures() const { return 0; }
};

}  // namespace trephine
