#pragma once
// VoxelSkull's own collision back-end (backend="native", the thesis's method,
// section 3.2): the pointshell tested point by point against the voxels or the
// smooth isosurface of the interpolated density, in flat vectorised loops
// over occupancy cells; penetration by Algorithm 1 or the deepest point;
// sweeps of the leading point, of ring lines or of the whole shell; no surface
// mesh. NativeVoxelContact.cpp has the contact and overlap tests, NativeVoxelSweep.cpp
// the sweeps and the ray cast.
#include <vector>

#include "plugins/voxel_skull/ShellPointClassifier.h"
#include "plugins/voxel_skull/VoxelBackend.h"
#include "plugins/voxel_skull/VoxelGroups.h"

namespace trephine::voxel {

class NativeVoxelBackend final : public VoxelBackend {
 public:
  void bind(const VoxelData& data) override;
  void reserveShell(std::span<const ShellPoint> shell) override;
  VoxelContact collide(const Pose& X_WT, std::span<const ShellPoint> shell, bool touchedVoxels) override;
  size_t broadPhase(const Pose& X_WT, std::span<const ShellPoint> shell) override;
  SweepResult sweep(const SweepQuery& query) const override;
  bool overlaps(const Pose& X_WT, std::span<const ShellPoint> shell) const override;
  std::optional<SurfaceHit> raycast(const Vec3& origin, const Vec3& direction, double maxDistance) const override;
  void reportCounters(std::vector<Counter>& counters) const override;

 private:
  const SolidGrid& grid() const { return *m_data.grid; }
  const DensityVolume& volume() const { return *m_data.volume; }
  Vec3 densityGradient(const Vec3& p) const;
  // The line and cylinder sweeps on the smooth surface, all lines a step at a
  // time (NativeVoxelSweep.cpp); needs m_probeLines sized for the query.
  SweepResult sweepSmoothLines(const SweepQuery& query, bool buried) const;
  // Sizes the smooth sweep's working memory for the reserved shells' radii.
  void reserveProbeLines();
  // The finest feature the sweeps resolve for a tool of radius R (mm): a
  // voxel, but no finer than R / kToolResolution. With voxels far finer than
  // the tool (1e-6 mm from a unit slip, a micro-CT under a 2.5 mm burr) the
  // rings' lines and the steps along a path stay bounded by the tool's size,
  // not by the voxels it spans. At CT resolutions the voxel decides (0.02 mm
  // for a 2.5 mm burr is below any clinical CT's voxel).
  static constexpr double kToolResolution = 128;
  double resolvedFeature(double R) const;
  // The fractions [t0, t1] of the path from -> to where a tool reaching
  // `reach` mm from its reference point can meet the grid's interpolated
  // field; false when it stays clear of it all the way.
  bool clipPathToGrid(const Vec3& from, const Vec3& to, double reach, double& t0, double& t1) const;

  VoxelData m_data;
  struct ReservedShell {
    const ShellPoint* source = nullptr;
    size_t size = 0;
    ShellArrays arrays;
    ShellArrays
        inset;  // the shell pulled one voxel inwards, points a voxel apart: the overlap test of a displayed proxy
    double radius = 0;  // mm, farthest point from the reference point
    // mm, per point: how far the tool extends from it along its inward normal
    // (its width there: 2 radii for a sphere, the shaft's diameter on a shaft's
    // wall). A point whose normal stays in bone farther than that is buried: the
    // whole tool is in bone along that line, and its normal says nothing.
    std::vector<double> width;
    bool sphere = true;  // every point at `radius` (to 1e-9): its normals meet at the centre
  };
  const ReservedShell* findShell(std::span<const ShellPoint> shell) const;
  std::vector<ReservedShell> m_shells;
  ShellPointTestFunction m_pointTest = bestShellPointTest(false);
  ShellPointTestFunction m_voxelPointTest = bestShellPointTest(false);
  // Per-frame working memory, sized by reserveShell().
  struct Hit {
    int64_t voxel;
    int32_t point;
  };
  std::vector<Hit> m_hits;
  mutable std::vector<int64_t> m_voxels;
  mutable std::vector<uint8_t> m_solid;
  std::vector<double> m_depths;        // per hit, mm
  std::vector<Vec3> m_normals;         // per hit, unit, out of the bone
  std::vector<uint8_t> m_buried;       // per hit: its normal stays in bone across the tool
  std::vector<int64_t> m_touched;      // the voxels the thesis's law cuts this frame (8 per hit at most)
  VoxelGroups m_groups;                // the hits grouped by voxel
  std::vector<Vec3> m_groupNormals;    // per group: sum of its points' normals
  std::vector<double> m_groupDepths;   // per group, Algorithm 1: -sum(offset . normal), mm
  std::vector<int32_t> m_groupPoints;  // per group: its points
  mutable std::vector<uint8_t> m_wasSolid;
  // The smooth line sweep's lines and one step's points, sized by reserveProbeLines().
  struct ProbeLine {
    Vec3 offset;    // mm, from the tool's reference point
    bool front;     // blocks when it starts in bone (unless the tool is buried)
    bool skipping;  // still in the bone it started in
  };
  mutable std::vector<ProbeLine> m_probeLines;
  mutable ShellArrays m_probePoints;
  mutable std::vector<int64_t> m_probeVoxels;
  mutable std::vector<uint8_t> m_probeSolid;
  uint64_t m_contactFrames = 0, m_maxCollidingVoxels = 0, m_unreservedShellCalls = 0;
  // The most steps one smooth or shell sweep took: bounded by the tool's and
  // the grid's sizes (resolvedFeature, clipPathToGrid), whatever the voxels.
  mutable uint64_t m_mostSweepSteps = 0;
};

}  // namespace trephine::voxel
