#pragma once
// A brain as a tetrahedral mesh, touched by pointshell tools (thesis chapter
// 4). TetraBrain keeps the data: the mesh read from its file (scaled, placed,
// reoriented), its topology, the node positions a deformation component
// publishes each frame, and the reaction forces on the nodes it publishes in
// turn. The queries go to the collision back-end the `backend` field picks:
// NativeTetBackend (the thesis's uniform grid and boundary-face methods) or a
// plugin's, on the boundary triangles.
#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "framework/channels/ChangeQueue.h"
#include "framework/core/ChannelHub.h"
#include "framework/core/Component.h"
#include "framework/geometry/ExactShape.h"
#include "framework/geometry/ShellContactTarget.h"
#include "framework/data/MeshDeformation.h"
#include "framework/geometry/DeformableMesh.h"
#include "plugins/tetra_brain/BrainResection.h"
#include "plugins/tetra_brain/TetBackend.h"
#include "plugins/tetra_brain/TissueTable.h"
#include "framework/data/TetMesh.h"
#include "framework/data/TetTopology.h"

namespace trephine::tetra {

class TetraBrain final : public Component, public ShellContactTarget, public ExactShapeSource, public DeformableMesh {
 public:
  static constexpr std::string_view kTypeName = "TetraBrain";

  void init(InitContext& context) override;
  void prepare(const RunPlan& plan) override;
  void reportCounters(std::vector<Counter>& counters) const override;
  void declareOutputs(std::vector<OutputFile>& outputs) const override;
  void finish(FinishContext& context) override;

  // SurfaceTarget
  Box3 bounds() const override { return m_bounds; }  // grown by the current displacement bound
  // A phantom's solid (file="phantom:..."), undeformed; none for a mesh file.
  LevelSet exactShape() const override;
  std::optional<SurfaceHit> raycast(const Vec3& origin, const Vec3& direction, double maxDistance) const override;
  // ShellContactTarget
  ContactMemory reserveShell(std::span<const ShellPoint> shell) override;
  void describeTool(std::span<const ShellPoint> shell, const ToolSolid& solid) override;
  SweepResult sweep(const SweepQuery& query) const override;
  ShellContact collide(const Pose& X_WT, std::span<const ShellPoint> shell, bool cutting,
                       ContactMemory& memory) override;
  std::optional<size_t> broadPhase(const Pose& X_WT, std::span<const ShellPoint> shell) override;
  bool overlaps(const Pose& X_WT, std::span<const ShellPoint> shell) const override;
  double contactDepth() const override { return d_contactDepth.value(); }
  double resolution() const override;  // mm, the median edge of the tetrahedra at rest
  TargetFrame beginFrame(double t) override;
  uint64_t shapeFailures() const override { return m_shapeFailures; }
  bool resects() const override { return m_resection != nullptr; }
  // The node forces: the sum of the frame's responses, in their order,
  // published once a frame (when they change).
  void respond(double t, std::span<const ContactResponse> responses) override;
  void reportFacts(std::vector<Fact>& facts) const override;

  // Publishes the node_forces channel (init() calls it; tests that build the
  // mesh with setMesh() call it themselves).
  void connectChannels(ChannelHub& channels);
  // Called by a deformation component in its init(): from then on the nodes
  // are read from its node_positions channel. Returns an error message when
  // another component already deforms this mesh.
  std::optional<std::string> followDeformation(const Component& deformer, ChannelHub& channels) override;
  bool isDeformable() const { return m_positions.has_value(); }
  // The component that deforms this mesh (followDeformation), or null.
  const Component* deformer() const override { return m_deformer; }
  bool deforms() const override { return m_deformer != nullptr; }
  // Called by a TetGridRebuild in its init(): from then on the grids it
  // publishes on its "grids" channel are adopted at the start of a frame.
  std::optional<std::string> followGridRebuild(const Component& rebuilder, ChannelHub& channels);

  // A Tissue component in its init(): the tetrahedra of its label are that
  // tissue. An error when the mesh has no tetrahedron of that label, or
  // another tissue has the label or the name.
  std::optional<std::string> declareTissue(const TissueSpec& tissue);
  const TissueTable& tissues() const { return m_tissues; }
  // A PlacedTumour in its init: the tetrahedra whose centre (at rest) lies
  // in the ball take `label`. An error (and nothing changed) when none does,
  // the label is in use, or a tissue or a deformation already read the labels.
  struct PlacedRegion {
    size_t tets = 0;
    double volume = 0;  // mm^3
    std::string error;
    bool atLabel = false;  // the error is the label's
  };
  PlacedRegion labelBall(const Vec3& centre, double radius, int32_t label);
  // A Resection component in its init, after the tissues: from now on tools
  // with a tissue action remove and coagulate this brain's tissues
  // (BrainResection). An error message when the back-end cannot follow
  // removals, or resection is enabled twice.
  std::optional<std::string> enableResection(EventLog& events);
  // Null unless resection is enabled.
  const BrainResection* resection() const { return m_resection.get(); }
  // A reader of the removed tetrahedra (the FEM, an exporter), in its init:
  // every tetrahedron removed from then on is pushed, once, to its own queue
  // (room for every tetrahedron: it never overflows).
  ChangeQueue<int32_t>& subscribeRemovals() override;

  // Replaces the mesh (tests and tools): validates, reorients and binds the
  // back-end to it (the native one when init() chose none, nor setBackend()).
  void setMesh(TetMesh mesh);
  // The back-end for the next setMesh() (tests and tools, without a registry).
  void setBackend(std::unique_ptr<TetBackend> backend) {
    m_backend = std::move(backend);
    m_bound = false;
  }
  const TetMesh& mesh() const override { return m_mesh; }
  const TetTopology& topology() const { return m_topology; }
  const MeshReport& report() const { return m_report; }
  // The back-end answering the queries (null before init() or setMesh()).
  const TetBackend* backend() const { return m_backend.get(); }
  TetBackend* backend() { return m_backend.get(); }
  // Current position of a node (mm): the rest position unless deformed.
  const Vec3& node(int32_t index) const { return m_nodes[index]; }

 private:
  TetQueryOptions queryOptions() const;
  void bindBackend();
  void warnUnusedNodes(InitContext& context, const MeshReport& report) const;
  void checkNativeOnlyFields(InitContext& context);
  // Takes the deformation's latest shape and grids (beginFrame, finish).
  void takeLatestShape();
  void reserveNodeForces(size_t entries);
  void buildForceSpread();
  // The node forces of one frame's responses, shared out and published.
  void publishNodeForces(double t, std::span<const ContactResponse> responses);

  FilePathField d_file{this,
                       "file",
                       {.help = "Tetrahedral mesh: TetGen .node/.ele, Medit .mesh, Gmsh .msh (ASCII 4.1, 4.0, 2.x, "
                                "legacy), VTK .vtk or .vtu (format read from the content, gzip allowed); or a "
                                "phantom: phantom:cube?cells=22, phantom:brain?tets=22000",
                        .required = true},
                       FilePathField::Role::Input,
                       {"phantom"}};
  EnumField d_inverted{this,
                       "inverted",
                       {"reorient", "refuse"},
                       "reorient",
                       {.help = "Tetrahedra with negative volume: swap two nodes (and report how many), or refuse "
                                "the mesh"}};
  Field<double> d_scale{this,
                        "scale",
                        1.0,
                        {.help = "Multiplies the node coordinates of the file, before the translation: the size of "
                                 "the file's unit in mm (1000 for a mesh in metres)",
                         .unit = "mm per file unit",
                         .min = 0.0,
                         .minExclusive = true}};
  Field<Vec3> d_translation{
      this, "translation", Vec3::Zero(), {.help = "Moves the mesh after loading (and scaling)", .unit = "mm"}};
  Field<std::string> d_backend{this,
                               "backend",
                               "native",
                               {.help = "Collision back-end answering the contact, sweep and overlap queries: native "
                                        "(the uniform grid and boundary faces of the thesis) or one a plugin adds "
                                        "(its name; the scene needs that plugin's <RequiredPlugin/>)"}};
  Field<double> d_cellSize{this,
                           "cellSize",
                           0.0,
                           {.help = "Side of the uniform grid's cells; 0 picks it by cellSizeRule",
                            .unit = "mm",
                            .min = 0.0}};
  EnumField d_cellSizeRule{
      this,
      "cellSizeRule",
      {"tool-cost", "half-edge", "edge"},
      "tool-cost",
      {.help = "The cell side when cellSize is not given. tool-cost: the minimiser of the tool query's cost model "
               "for the pointshells of the tools that touch this mesh (the cells their points occupy, the "
               "tetrahedra each cell lists, the point tests; `trephine cellsize MESH --tool R` prints it). "
               "half-edge: half the average edge length. edge: the average edge length (Teschner et al.)"}};
  EnumField d_search{this,
                     "search",
                     {"grid", "first-tetrahedron", "previous-contact"},
                     "grid",
                     {.help = "How colliding tetrahedra are found. grid: every shell point looks up the tetrahedra "
                              "of its cell (cost independent of the mesh size). first-tetrahedron (thesis): scan the "
                              "tetrahedra from the first for one whose box meets the tool and holds a point, then "
                              "test its neighbours up to two rings. previous-contact (thesis, improved): the same "
                              "scan, started at the last frame's first colliding tetrahedron"}};
  EnumField d_penetration{this,
                          "penetration",
                          {"nearest-face", "algorithm2"},
                          "nearest-face",
                          {.help = "algorithm2 (thesis): the normal averages the outward normals of every boundary "
                                   "face of the colliding tetrahedra, the penetration is the largest distance of a "
                                   "colliding point to the plane of one of those faces (wrong when a tetrahedron is "
                                   "much larger than the tool, blind where the colliding tetrahedra have no boundary "
                                   "face). nearest-face: each colliding point measures to the boundary face nearest "
                                   "to it (of its tetrahedron, else of the mesh); normals are weighted by depth"}};
  Field<double> d_displacementMargin{
      this,
      "displacementMargin",
      0.0,
      {.help = "With a deformation component: how far (mm) nodes may move from their rest positions before the "
               "grid queries widen (results stay exact, the cost grows with the excess). 0 uses a quarter of the "
               "average edge length. Larger margins put more tetrahedra in each cell",
       .unit = "mm",
       .min = 0.0}};
  EnumField d_boxRefresh{this,
                         "boxRefresh",
                         {"all", "moved"},
                         "all",
                         {.help = "Thesis searches on a deforming mesh: every frame, refresh the box of every "
                                  "tetrahedron, or only of those with a node the deformation moved. The grid search "
                                  "refreshes nothing (displacement margin)"}};
  Field<double> d_forceSpread{
      this,
      "forceSpread",
      0.0,
      {.help = "Share the tool's force on the mesh among the boundary nodes within this distance (rest shape) "
               "of the nodes it presses, with smooth weights, instead of those nodes alone. Under a small tool a "
               "coarse soft mesh otherwise carries the force on a few nodes, which invert their elements near 1 N. "
               "0: the nodes of the contact's tetrahedra (the thesis)",
       .unit = "mm",
       .min = 0.0}};
  Field<std::string> d_saveDeformed{this,
                                    "saveDeformed",
                                    "",
                                    {.help = "Write the mesh with its node positions at the end of the run to this "
                                             "file in the run directory: .vtu (VTK XML), .mesh or .mesh.gz (Medit); "
                                             "empty writes nothing"}};
  Field<double> d_contactDepth{this,
                               "contactDepth",
                               0.05,
                               {.help = "How far a swept proxy is placed into the surface so that its points register "
                                        "contact",
                                .unit = "mm",
                                .min = 0.0,
                                .minExclusive = true}};

  TetMesh m_mesh;  // rest shape
  TetTopology m_topology;
  const Vec3* m_nodes = nullptr;  // current node positions: the rest nodes, or the deformation's latest
  MeshReport m_report;
  size_t m_reoriented = 0;
  Box3 m_restBounds, m_bounds;            // m_bounds: the rest bounds grown by the displacement bound
  std::unique_ptr<TetBackend> m_backend;  // d_backend, bound to m_mesh
  bool m_bound = false;
  size_t m_reservedSites = 0;  // the sites every reserved shell's contact may hold at once

  // Deformation (followDeformation).
  std::optional<ChannelReader<NodePositions>> m_positions;
  const Component* m_deformer = nullptr;
  std::optional<ChannelReader<TetGridSet>> m_grids;  // from a TetGridRebuild
  uint64_t m_lastStep = 0;
  double m_largestBound = 0;  // mm
  uint64_t m_deformationFrames = 0, m_rejectedFrames = 0;
  uint64_t m_deformationResets = 0;  // the deformation's reset count last seen
  uint64_t m_shapeFailures = 0;      // resets seen and frames rejected (shapeFailures())

  // Reaction forces on the nodes (computed only when a component reads them).
  Channel<NodeForces>* m_nodeForces = nullptr;
  NodeForces m_nodeForceValue;
  std::vector<int32_t> m_nodeSlot;                    // per node: its entry in m_nodeForceValue, or -1
  // forceSpread: per node, the boundary nodes that share a force on it and
  // their weights (compressed rows, built in prepare()); the spread forces.
  std::vector<uint32_t> m_spreadStart;
  std::vector<int32_t> m_spreadNodes;
  std::vector<double> m_spreadWeights;
  NodeForces m_spreadValue;
  TissueTable m_tissues;  // declared by the scene's Tissue components
  std::unique_ptr<BrainResection> m_resection;
  std::vector<std::unique_ptr<ChangeQueue<int32_t>>> m_removalReaders;
  EventLog* m_events = nullptr;
  // Removes the tetrahedra the frame before's responses took (beginFrame):
  // the back-end and every reader follow. Returns how many.
  int applyRemovals(double t);
  uint64_t m_contactFrames = 0;
  uint64_t m_largestNodeForceCount = 0;  // entries of the largest node-force frame published
  mutable uint64_t m_queries = 0;  // counted by the const queries too
};

}  // namespace trephine::tetra
