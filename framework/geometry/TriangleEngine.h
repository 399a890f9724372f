#pragma once
// A library that queries a closed triangle surface in blocks (TriangleBlocks)
// for a tool's shell: contact, the sweep of a proxy, the overlap of a
// displayed one, rays. Bullet and Embree each implement it, in their plugin
// (registered as back-ends of kind kTriangleEngineKind); a target that keeps
// its surface as triangles (the skull's isosurface, the brain's boundary)
// puts one adapter of its own over whichever engine the scene names
// (Registry::addEngineAdapter). The engine reads the blocks in place and
// never changes them; the target re-extracts or moves them and says which.
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "framework/core/CollisionBackend.h"
#include "framework/core/Interface.h"
#include "framework/data/TriangleBlocks.h"
#include "framework/geometry/MeshSurfaceCounters.h"
#include "framework/geometry/ShellContactTarget.h"
#include "framework/geometry/ShellTool.h"
#include "framework/geometry/SurfaceTarget.h"

namespace trephine {

// The scale of a target's sphere queries (mm): what its own surface and
// contact rules make small.
struct SphereQueryScale {
  double skin = 0;       // how deep a proxy rests (the sweep's allowance, MeshSphereContact.h)
  double sweepStep = 0;  // a sweep that samples the exact depth samples it this far apart
  double inset = 0;      // a displayed sphere pulled in this far that still reaches the surface overlaps it
};

// How an engine takes a shell it was told of.
enum class ShellSupport {
  kSphere,     // every point at one radius: the exact sphere
  kPointwise,  // point by point (no nearest triangle for the contact)
  kSolid,      // through the solid the tool describes (describeTool), refused if it describes none
};

// A contact, and where the surface is nearest the tool's reference point (a
// sphere's centre), when the engine found it: the triangle and the point.
struct TriangleContact {
  ShellContact contact;
  TriangleRef nearest;
  Vec3 nearestPoint = Vec3::Zero();  // mm
};

class TREPHINE_INTERFACE TriangleEngine : public CollisionBackend {
 public:
  ~TriangleEngine() override;

  // The engine's name (the `backend` value that picks it), for messages.
  virtual std::string_view name() const = 0;
  // A new, empty engine of the same library: a second copy of a surface, to
  // be brought up to date on another thread while this one is queried.
  virtual std::unique_ptr<TriangleEngine> another() const = 0;
  // Builds every block of `blocks`, kept by reference (they must outlive the
  // engine's use). `deformationMargin` (mm): the blocks' vertices will move by
  // up to this much from where they are at each build; 0 for a surface that
  // does not move. Throws when the library fails.
  virtual void build(const TriangleBlocks& blocks, double deformationMargin) = 0;
  // The triangles of these blocks changed (re-extracted): rebuilds them. In
  // the haptic loop: a block the library cannot take is counted, not thrown.
  virtual void rebuildBlocks(std::span<const size_t> changed) = 0;
  // The vertices of a block moved in place (same arrays, same triangles):
  // refits its tree, or rebuilds it when `rebuild`.
  virtual void moveVertices(size_t block, bool rebuild) = 0;
  // No triangles were built.
  virtual bool empty() const = 0;
  // What the engine counted of its surface; the adapter adds the extraction
  // to buildMs.
  virtual MeshSurfaceCounters& counts() = 0;

  // A tool's shell (kept by address) and how the engine will take it.
  virtual ShellSupport reserveShell(std::span<const ShellPoint> shell) = 0;
  // The solid a reserved shell samples; throws, naming `owner` (the target's
  // back-end, for the message), when the engine takes the shell only through
  // a solid and this one has none it can use.
  virtual void describeTool(std::span<const ShellPoint> shell, const ToolSolid& solid, const std::string& owner) = 0;

  // The tool at X_WT against the surface; nothing for a shell not reserved.
  virtual TriangleContact contact(const Pose& X_WT, std::span<const ShellPoint> shell) const = 0;
  // The broad phase alone: the triangles within the tool's reach.
  virtual size_t broadPhase(const Pose& X_WT, std::span<const ShellPoint> shell) const = 0;
  virtual SweepResult sweep(const SweepQuery& query, const SphereQueryScale& scale) const = 0;
  virtual bool overlaps(const Pose& X_WT, std::span<const ShellPoint> shell, const SphereQueryScale& scale) const = 0;
  virtual std::optional<SurfaceHit> raycast(const Vec3& origin, const Vec3& direction, double maxDistance) const = 0;
};

// A target's back-end `Adapter` (constructed from a
// std::unique_ptr<TriangleEngine>) over `engine`, as a registry's engine
// adapter returns it; null when `engine` is not a TriangleEngine.
template <class Adapter>
std::unique_ptr<CollisionBackend> adaptEngine(std::unique_ptr<CollisionBackend> engine) {
  auto* triangles = dynamic_cast<TriangleEngine*>(engine.get());
  if (!triangles) return nullptr;
  engine.release();
  return std::make_unique<Adapter>(std::unique_ptr<TriangleEngine>(triangles));
}

}  // namespace trephine
