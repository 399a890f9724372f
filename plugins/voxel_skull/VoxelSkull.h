#pragma once
// A rigid skull kept as CT density voxels: voxels denser than `isovalue` are
// bone. VoxelSkull keeps and drills the data; its collision back-end
// (`backend`: NativeVoxelBackend, the thesis's point-by-point method of
// section 3.2, or one a plugin adds) answers the tools' queries. With `drill`,
// a running burr removes bone:
//  - removal="force" (default): the bone under the burr recedes at a speed
//    set by the thrust, the burr and the bone's hardness (RemovalLaw.h); the
//    burr's sphere, advanced by that speed times the frame, is carved out of
//    the density with a one-voxel ramp, so the surface follows the burr
//    sub-voxel and nothing beyond the burr's radius plus one voxel changes;
//  - removal="thesis": the voxels the tool touches lose `drillRate` density
//    per haptic frame until they fall below the isovalue, whatever the force.
#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "framework/core/ChannelHub.h"
#include "framework/core/Component.h"
#include "framework/geometry/DrillableVolume.h"
#include "framework/geometry/ExactShape.h"
#include "framework/geometry/ShellContactTarget.h"
#include "framework/data/DensityVolume.h"
#include "plugins/voxel_skull/FootprintCut.h"
#include "plugins/voxel_skull/RemovalLaw.h"
#include "plugins/voxel_skull/SolidGrid.h"
#include "plugins/voxel_skull/SurfaceHandover.h"
#include "plugins/voxel_skull/VoxelBackend.h"

namespace trephine::voxel {

class MeshVoxelBackend;

class VoxelSkull final : public Component, public ShellContactTarget, public ExactShapeSource, public DrillableVolume {
 public:
  static constexpr std::string_view kTypeName = "VoxelSkull";

  void init(InitContext& context) override;
  void finish(FinishContext& context) override;
  void reportCounters(std::vector<Counter>& counters) const override;
  void reportFacts(std::vector<Fact>& facts) const override;
  void declareOutputs(std::vector<OutputFile>& outputs) const override;

  // SurfaceTarget
  Box3 bounds() const override;
  std::optional<size_t> broadPhase(const Pose& X_WT, std::span<const ShellPoint> shell) override;
  // A phantom's solid (file="phantom:..."); none for a scan.
  LevelSet exactShape() const override;
  std::optional<ScanAsRead> scanAsRead() const override;
  std::optional<SurfaceHit> raycast(const Vec3& origin, const Vec3& direction, double maxDistance) const override;
  // ShellContactTarget
  ContactMemory reserveShell(std::span<const ShellPoint> shell) override;
  void describeTool(std::span<const ShellPoint> shell, const ToolSolid& solid) override;
  SweepResult sweep(const SweepQuery& query) const override;
  ShellContact collide(const Pose& X_WT, std::span<const ShellPoint> shell, bool cutting,
                       ContactMemory& memory) override;
  bool overlaps(const Pose& X_WT, std::span<const ShellPoint> shell) const override;
  double contactDepth() const override { return 0.1 * m_grid.smallestSide(); }
  double resolution() const override { return m_volume.spacing().maxCoeff(); }  // mm, the voxels' largest side
  // Applies the cuts the tools asked for in the frame before (once a frame).
  TargetFrame beginFrame(double t) override;
  // Queues the frame's cuts for the start of the next frame, in their order
  // (the contact frame's): every cut of a frame acts on the shape all the
  // tools saw, whatever the order they are listed in.
  void respond(double t, std::span<const ContactResponse> responses) override;

  const DensityVolume& volume() const { return m_volume; }
  const SolidGrid& grid() const { return m_grid; }
  // ShellContactTarget and DrillableVolume
  bool drills() const override { return d_drill.value(); }
  // DrillableVolume (initialisation only: a reader on another thread that
  // keeps its own copy of the codes).
  const VoxelGrid& voxelGrid() const override { return m_grid; }
  void recordEdits(std::shared_ptr<ChangeQueue<VoxelEdit>> edits) override { m_grid.edits.push_back(std::move(edits)); }
  uint64_t voxelsRemoved() const { return m_voxelsRemoved; }
  // Init only, for a SkullSurfaceRebuild: the back-end when it keeps a copy
  // of the surface of its own (a triangle engine's), else null (the native
  // back-end reads the codes themselves).
  MeshVoxelBackend* meshBackend() const;
  // The rebuild's hand-over (SurfaceHandover.h): the skull adopts the copies
  // `rebuilder` publishes and answers with the copy it queries. An error
  // when another component already rebuilds this skull's surface.
  std::optional<std::string> followSurfaceRebuild(const Component& rebuilder, ChannelHub& channels);
  const RemovalLaw& removalLaw() const { return m_law; }
  // Replaces the volume (tests and tools); call before the run.
  void setVolume(DensityVolume volume);

 private:
  // The pending cuts, in the order they came, at time `now` (s: events are
  // logged then); returns the voxels removed.
  int applyPendingCuts(double now);
  // The thesis's law: the voxels the tool touched, and the point a sweep stopped it at.
  int cutTouched(std::span<const int64_t> touched);
  int cutAt(const Vec3& point_W);
  // The force law; `history`: the cutting tool's breakthrough test.
  int cutUnderLoad(ContactMemory& history, const CuttingLoad& load, double now);
  // Drills one voxel by m_drillStep; 1 if it was bone and is not any more.
  int lowerVoxel(int64_t voxel);
  // Whether bone lies ahead of a burr's front along `direction` (unit), within
  // one voxel: the breakthrough test.
  bool boneAhead(const Vec3& front, const Vec3& direction) const;
  void checkRemovalFields(InitContext& context);
  // Warns when a scan read from a file does not look like Hounsfield units
  // while the isovalue is the default, given in HU.
  void checkHounsfieldUnits(InitContext& context, const DensityVolume& volume) const;
  // HU: a CT's air is near -1000; a scan whose lowest value is above this has none.
  static constexpr double kNoAirAbove = -500.0;

  FilePathField d_file{this,
                       "file",
                       {.help = "Density volume: MetaImage (.mhd/.mha), NRRD (.nrrd/.nhdr), NIfTI-1 or NIfTI-2 (.nii/.nii.gz, or a .hdr with its .img), "
                                "a DICOM series (its directory, DIR/?series=UID to pick one of several, or one "
                                "DICOM file); or a generated phantom, e.g. phantom:skull?voxel=1.0",
                        .required = true},
                       FilePathField::Role::InputOrDirectory,
                       {"phantom"}};
  Field<std::string> d_backend{this,
                               "backend",
                               "native",
                               {.help = "Collision back-end answering the contact, sweep and overlap queries: native "
                                        "(the voxel method of the thesis) or one a plugin adds (its name; the "
                                        "scene needs that plugin's <RequiredPlugin/>)"}};
  // 400: in Hounsfield units above soft tissue (20 to 80 HU) and blood, and
  // below the skull's diploe (about 500 to 900 HU) and cortical bone (1200 to
  // 2000 HU); the phantoms use the same scale.
  Field<double> d_isovalue{this,
                           "isovalue",
                           400.0,
                           {.help = "Voxels denser than this are bone. The default suits a CT in Hounsfield units "
                                    "(DICOM series are rescaled to them): above soft tissue (20 to 80 HU), below "
                                    "the diploe (about 500 to 900 HU) and cortical bone (1200 to 2000 HU)",
                            .unit = "HU"}};
  Field<double> d_voxelSize{
      this,
      "voxelSize",
      0.0,
      {.help = "Resample to cubic voxels of this size on load; 0 keeps the file's voxels", .unit = "mm", .min = 0.0}};
  Field<bool> d_drill{this, "drill", false, {.help = "Remove the bone the tool touches"}};
  EnumField d_removal{this,
                      "removal",
                      {"force", "thesis"},
                      "force",
                      {.help = "Removal law of drilling. force: the surface under the burr recedes at "
                               "sharpness * w * (F - thrustThreshold H) / (pi r cuttingEnergy H), H the hardness of "
                               "the bone ahead from its density, capped at maxCutSpeed (a constant specific cutting "
                               "energy); thesis: drillRate per touched voxel and frame, whatever the force"}};
  // Calibrated, not measured: 0.2 J/mm^3 puts the thrust of a 1 mm/s feed into
  // cortical bone (density 1500) with the default 2.5 mm burr at 60,000 rpm
  // near 1.1 N, so feeds up to 2 mm/s stay below a Phantom Omni's 3.3 N
  // (docs/results.md, drilling). Hand-held burrs in animal bone take 4 to 19 N
  // on average (peaks 6 to 24 N, "Investigation of variable factors in
  // drilling bone"), beyond desktop devices: forces are scaled to the device.
  Field<double> d_cuttingEnergy{this,
                                "cuttingEnergy",
                                0.2,
                                {.help = "Specific cutting energy of bone of referenceDensity: work per volume "
                                         "removed (removal=\"force\")",
                                 .unit = "J/mm^3",
                                 .min = 0.0,
                                 .minExclusive = true}};
  Field<double> d_referenceDensity{this,
                                   "referenceDensity",
                                   1500.0,
                                   {.help = "Density of the bone that has cuttingEnergy: cortical bone (about 1500 "
                                            "HU in a CT, the phantom's outer table)",
                                    .unit = "HU",
                                    .min = 0.0,
                                    .minExclusive = true}};
  Field<double> d_hardnessExponent{this,
                                   "hardnessExponent",
                                   2.0,
                                   {.help = "Cutting energy grows as (density / referenceDensity)^e: bone strength "
                                            "grows with the square of its apparent density (Carter and Hayes 1977), "
                                            "so diploe of 700 HU cuts 4.6 times faster than cortical bone of 1500 HU",
                                    .min = 0.0,
                                    .max = 4.0}};
  Field<double> d_thrustThreshold{
      this,
      "thrustThreshold",
      0.3,
      {.help = "Thrust below which the burr polishes without cutting bone of referenceDensity (a spinning burr "
               "pressed lightly rides on the surface); scaled by the hardness for other bone",
       .unit = "N",
       .min = 0.0}};
  Field<double> d_maxCutSpeed{this,
                              "maxCutSpeed",
                              20.0,
                              {.help = "Fastest the surface recedes, whatever the thrust: bounds the removal per "
                                       "frame (20 mm/s is 0.02 mm per frame at 1 kHz, a twenty-fifth of a 0.5 mm "
                                       "voxel)",
                               .unit = "mm/s",
                               .min = 0.0,
                               .minExclusive = true}};
  Field<int> d_cutSlices{this,
                         "cutSlices",
                         2,
                         {.help = "removal=\"force\": each haptic frame cuts one of this many interleaved sets of "
                                  "the footprint's voxel rows, with this many frames' worth of removal, so a "
                                  "frame's removal work is bounded; every voxel is still cut every cutSlices frames "
                                  "(2 ms at 1 kHz by default, while the burr moves 0.04 mm at 20 mm/s; 4 and more "
                                  "make the force steps from the cut larger)",
                          .min = 1.0,
                          .max = 16.0}};
  // 10 per frame: the thesis removed 1.0 per frame from bone a few hundred above
  // its isovalue, about 0.1 s of contact per voxel; CT cortical bone (about
  // 1500) is 1100 above an isovalue of 400, so 10 per frame keeps that speed.
  Field<double> d_drillRate{this,
                            "drillRate",
                            10.0,
                            {.help = "removal=\"thesis\": density removed from each touched voxel per haptic frame "
                                     "(10 at 1 kHz erodes cortical bone of 1500 to an isovalue of 400 in 0.11 s of "
                                     "contact)",
                             .unit = "density/frame",
                             .min = 0.0,
                             .minExclusive = true}};
  EnumField d_penetration{this,
                          "penetration",
                          {"auto", "deepest-point", "algorithm1"},
                          "auto",
                          {.help = "Penetration of a contact. algorithm1 (thesis, McNeely tangent planes): per "
                                   "colliding voxel the mean distance of its points to the plane through the voxel "
                                   "centre along their normals, the largest voxel mean taken. deepest-point: each "
                                   "colliding point's distance along its normal to where the bone ends, projected "
                                   "on the contact normal, the largest taken. auto: deepest-point on the smooth "
                                   "surface, algorithm1 on voxels (the more accurate of the two on each, see "
                                   "docs/results.md)"}};
  EnumField d_surface{this,
                      "surface",
                      {"smooth", "voxels"},
                      "smooth",
                      {.help = "Bone surface: voxels (thesis) makes each voxel above the isovalue a solid box, a "
                               "staircase; smooth takes the isosurface of the density interpolated trilinearly "
                               "between voxel centres, with the density gradient as its normal"}};
  Field<std::string> d_saveDrilled{this,
                                   "saveDrilled",
                                   "",
                                   {.help = "Write the drilled volume to this MetaImage file (.mha/.mhd) in the run "
                                            "directory after the run; empty writes nothing"}};

  DensityVolume m_volume;
  std::string m_initialChecksum;  // of the codes as loaded (volume_checksum_initial)
  SolidGrid m_grid;
  int32_t m_drillStep = 1;     // codes removed per frame (removal="thesis")
  bool m_forceRemoval = true;  // d_removal, read once at init
  RemovalLaw m_law;
  // The cuts of the frame before, for the next frame's start; capacity: one
  // per reserved shell. Their spans view the cutting tools' memories, which
  // hold until the tools' next collide() (after that start).
  std::vector<ContactResponse> m_pendingCuts;
  size_t m_reservedShells = 0;
  ContactMemory m_anonymousHistory;  // a cut's history when its response names no tool's memory
  EventLog* m_events = nullptr;
  double m_removedCodes = 0;  // code steps removed by the force law, summed over voxels
  double m_maxCutSpeed = 0;   // mm/s, largest recession speed reached
  uint64_t m_cutFrames = 0, m_breakthroughs = 0;
  bool m_algorithm1 = false;          // d_penetration resolved for the surface, once in setVolume
  double m_framesToDrillDensest = 0;  // frames of contact that empty the densest voxel

  // The collision back-end (d_backend), bound to m_volume and m_grid.
  std::unique_ptr<VoxelBackend> m_backend;
  // A SkullSurfaceRebuild's copies of the back-end's surface, and the answer.
  std::optional<ChannelReader<SurfaceCopy>> m_surfaceReady;
  Channel<SurfaceCopy>* m_surfaceInUse = nullptr;
  bool m_bound = false;  // m_backend is bound to the loaded volume
  uint64_t m_voxelsRemoved = 0;
};

}  // namespace trephine::voxel
