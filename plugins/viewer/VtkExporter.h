#pragma once
// Writes what a scene names as VTK XML files that ParaView plays in time
// (after SOFA's VTKExporter): at its own rate (30 Hz by default), in a group
// of its own, it reads the latest state through channels and writes
//   brain_NNNNN.vtu  the brain's mesh at its current node positions, with the
//                    node displacements (mm), the tool's forces on the nodes
//                    (N), the tissue labels and, when its deformer computes
//                    stresses (the TLED FEM's element_stress), each
//                    element's von Mises stress (kPa, "von_mises");
//   tool_NNNNN.vtp   the device and the proxy (mm), joined by a line, and in
//                    contact the contact point (where the displayed tool
//                    meets the surface: the proxy less the tool's radius
//                    along the contact normal), with the force rendered to
//                    the hand (N), the contact normal, the penetration (mm)
//                    and the radius of the tool in hand (mm);
//   toolshape_NNNNN.vtp  the tool in hand in its true shape at the proxy, in
//                    the device's orientation (ShellTool::displaySurface: a
//                    burr and its shaft; a plugin's tool, the surface it
//                    declares), when `force` holds its tools (HeldTools);
//   skull_NNNNN.vtm  the skull's surface (the isosurface of its interpolated
//                    density, as the mesh back-ends see it), block by block:
//                    each block of 16^3 cells in skull/bBBBBB_NNNNN.vtp, at
//                    the start for every block and then, while the drill
//                    removes bone (at most every `skullInterval`), only for
//                    the blocks it changed; each .vtm lists every block's
//                    latest file;
//   skull_density.mhd/.zraw  the skull's densities as the run starts
//                    (MetaImage, zlib), for a viewer's colours and its volume
//                    rendering, with skull_volume.json giving its isovalue;
//   skull_removed.csv  every voxel the drill took below the isovalue: i,j,k
//                    (its index in that volume) and t (s, the exporter frame
//                    that saw it go), written at the end;
// into the directory `directory` of the run, and `directory`.pvd beside it
// listing every file with its time. Only what the links name is written. The
// haptic and FEM threads only copy into the channels' slots; the files are
// written here, off their threads. The brain is written again only when its
// nodes moved or the tool's forces on it changed. Under `trephine run
// --realtime --view PORT` it also serves the browser viewer and streams the
// same parts to it (LiveStream).
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "framework/channels/Channel.h"
#include "framework/core/Component.h"
#include "framework/core/Link.h"
#include "framework/core/SampleSource.h"
#include "framework/formats/vtk/VtkXml.h"
#include "framework/data/IsoSurface.h"
#include "framework/geometry/DeformableMesh.h"
#include "framework/geometry/DrillableVolume.h"
#include "plugins/viewer/LiveSkull.h"
#include "plugins/viewer/LiveStream.h"

namespace trephine::viewer {

class VtkExporter final : public Component {
 public:
  static constexpr std::string_view kTypeName = "VtkExporter";
  VtkExporter();
  ~VtkExporter() override;

  void init(InitContext& context) override;
  void prepare(const RunPlan& plan) override;
  void tick(const TickContext& context) override;
  void finish(FinishContext& context) override;
  void reportCounters(std::vector<Counter>& counters) const override;
  void declareOutputs(std::vector<OutputFile>& outputs) const override;

 private:
  std::string pvdName() const;
  // Reads the brain's nodes and forces; true when they changed since the
  // last frame written (or streamed).
  bool updateBrain();
  void writeBrain(double t);
  void sendTool(double t);
  // Where the displayed tool touches (mm), from a ForceFeedback sample; none
  // out of contact.
  std::optional<Vec3> contactPoint(const Sample& s) const;
  void startLiveView(const RunPlan& plan);
  void writeTool(double t);
  // Applies the drill's changes to the copy of the codes, noting the voxels
  // that went below the isovalue at `t` (s); true if any.
  bool applySkullEdits(double t);
  void writeSkullVolume();
  void writeRemovedVoxels();
  void writeSkull(double t);
  // Writes through `write`, keeping the first failure for finish() instead of
  // stopping the run (what was written so far stays listed).
  template <class Write>
  void attempt(const std::string& file, double t, int part, Write&& write);

  Link<DeformableMesh> l_brain{
      this, "brain", {.help = "Brain whose mesh is written at its current node positions", .initOnly = true}};
  Link<SampleSource> l_force{this,
                             "force",
                             {.help = "ForceFeedback whose device, proxy, force, normal and penetration are written",
                              .initOnly = true}};
  Link<DrillableVolume> l_skull{
      this, "skull", {.help = "Skull whose surface is written (again where drilled)", .initOnly = true}};
  RateField d_rate{this, 30.0, "Frames per second of the files (ParaView plays them at their times)"};
  Field<double> d_skullInterval{
      this,
      "skullInterval",
      0.1,
      {.help = "While the skull is drilled, its changed blocks are written at most this often (0: every frame of "
               "the exporter that follows a change; each skull frame also writes an index of every block, 180 KB "
               "for a 0.5 mm skull); the last state is written at the end",
       .unit = "s",
       .min = 0.0}};
  Field<int> d_viewTriangles{this,
                             "viewTriangles",
                             15000,
                             {.help = "Triangles of the skull at the start of a live view (trephine run --view): the "
                                      "isosurface of its volume averaged over the fewest voxels that give at most "
                                      "this many; where the drill changes it, the full-resolution surface replaces it",
                             .min = 1000.0}};
  Field<std::string> d_directory{
      this,
      "directory",
      "vtk",
      {.help = "Folder of the files in the run directory; the index is this name with .pvd beside it"}};

  // Brain.
  std::optional<ChannelReader<NodePositions>> m_positions;  // none: a rigid brain
  std::optional<ChannelReader<NodeForces>> m_nodeForces;
  std::optional<ChannelReader<ElementStress>> m_elementStress;  // none: the deformer computes none
  std::optional<formats::VtkTetCells> m_cells;  // compressed once, again after a resection removed tetrahedra
  ChangeQueue<int32_t>* m_removals = nullptr;   // the brain's removed tetrahedra
  std::vector<uint8_t> m_removedTets;           // per tetrahedron of the mesh
  std::vector<float> m_vonMisesAll;             // kPa, per tetrahedron of the mesh
  bool m_cellsChanged = false;
  // The cells of the tetrahedra that remain (and their labels), compressed.
  void compressRemainingCells();
  formats::VtkDataArray m_displacement{"displacement", 3, {}}, m_force{"force", 3, {}};
  formats::VtkDataArray m_vonMises{"von_mises", 1, {}};  // kPa, per element
  bool m_brainWritten = false;
  std::vector<Vec3> m_writtenNodes;  // the positions of the last file
  // Tool: the source's columns, by name.
  std::optional<ChannelReader<Sample>> m_samples;
  int m_device = -1, m_proxy = -1, m_forceColumn = -1, m_normal = -1, m_penetration = -1, m_toolRadius = -1;
  int m_toolInHand = -1, m_toolOrientation = -1;
  std::vector<TriangleMesh> m_toolSurfaces;  // tool frame, one per held tool (HeldTools' order)
  formats::VtkPolyData m_toolShape;          // the one in hand this frame, in the world
  // The surface of the tool in hand at the sample's proxy and orientation
  // into m_toolShape; false when there is none to draw.
  bool placeToolSurface(const Sample& s);
  void writeToolShape(double t);

  // Skull: a copy of its codes, kept current from the drill's changes (the
  // haptic thread pushes them into m_edits), and its surface in blocks.
  std::shared_ptr<ChangeQueue<VoxelEdit>> m_edits;
  std::vector<VoxelCode> m_skullCodes;
  VoxelGrid m_skullGrid;  // over m_skullCodes
  BlockedIsoSurface m_skullSurface;
  std::vector<uint8_t> m_blockChanged;       // per block: to write at the next skull frame
  std::vector<std::string> m_blockFiles;     // per block: its latest file (relative to the .vtm), "" when empty
  bool m_skullChanged = false;
  double m_lastSkullWrite = -INFINITY;  // s
  uint64_t m_skullEdits = 0, m_skullFiles = 0;
  struct RemovedVoxel {
    int64_t voxel;  // linear index
    float t;        // s
  };
  std::vector<RemovedVoxel> m_removed;  // in the order they went

  // The live view (trephine run --view): its server, and the blocks changed
  // since they were last sent.
  std::unique_ptr<LiveStream> m_live;
  std::unique_ptr<LiveSkull> m_liveSkull;
  std::vector<uint8_t> m_liveBlockChanged;

  std::filesystem::path m_root;  // the run directory, empty: write nothing
  std::optional<OutputFolder> m_folder;  // its `directory` inside, opened once
  formats::PvdCollection m_collection;
  uint64_t m_frames = 0, m_files = 0, m_failed = 0;
  std::string m_firstFailure;
};

}  // namespace trephine::viewer
