#pragma once
// A brain as a tetrahedral mesh, touched by a pointshell tool (thesis chapter
// 4). Shell points are located in tetrahedra through a uniform grid of cells
// listing the tetrahedra whose boxes overlap them, so the cost of a frame
// depends on the tool's neighbourhood, not on the size of the mesh. Normal and
// penetration come from the boundary faces: each colliding point measures to
// the nearest one (its tetrahedron's, the ones around its nodes, else the
// mesh's), or, as the thesis's Algorithm 2, the normals of the colliding
// tetrahedra's boundary faces are averaged and the deepest point below them
// gives the penetration.
//
// A deformation component may move the nodes (followDeformation): the grids
// stay those of the rest shape, with every box grown by a displacement margin,
// and each frame reads the current node positions. While the deformation's
// displacement bound stays within the margin nothing is refreshed; beyond it
// the queries widen by the excess, so the results stay exact and only the cost
// grows. The thesis's scans instead refresh tetrahedron boxes every frame
// (all of them, or those of the moved nodes).
#include <optional>
#include <vector>

#include "framework/core/ChannelHub.h"
#include "framework/core/Component.h"
#include "framework/geometry/ExactShape.h"
#include "framework/geometry/ShellContactTarget.h"
#include "plugins/tetra_brain/MeshDeformation.h"
#include "plugins/tetra_brain/ShellLocator.h"
#include "plugins/tetra_brain/TetMesh.h"
#include "plugins/tetra_brain/TetTopology.h"
#include "plugins/tetra_brain/UniformGrid.h"
#include "plugins/tetra_brain/VisitStamps.h"

namespace trephine::tetra {

class TetraBrain final : public Component, public ShellContactTarget, public ExactShapeSource {
 public:
  static constexpr std::string_view kTypeName = "TetraBrain";

  void init(InitContext& context) override;
  void prepare(const RunPlan& plan) override;
  void reportCounters(std::vector<Counter>& counters) const override;

  // SurfaceTarget
  Box3 bounds() const override { return m_bounds; }  // grown by the current displacement bound
  // A phantom's solid (file="phantom:..."), undeformed; none for a mesh file.
  LevelSet exactShape() const override;
  std::optional<SurfaceHit> raycast(const Vec3& origin, const Vec3& direction, double maxDistance) const override;
  // ShellContactTarget
  void reserveShell(std::span<const ShellPoint> shell) override;
  SweepResult sweep(const SweepQuery& query) const override;
  ShellContact collide(const Pose& X_WT, std::span<const ShellPoint> shell, bool removeMaterial) override;
  bool overlaps(const Pose& X_WT, std::span<const ShellPoint> shell) const override;
  double contactDepth() const override { return d_contactDepth.value(); }
  void refresh() override;
  void applyContactForce(const Vec3& forceOnTarget_N, double t) override;

  // Publishes the node_forces channel (init() calls it; tests that build the
  // mesh with setMesh() call it themselves).
  void connectChannels(ChannelHub& channels);
  // Called by a deformation component in its init(): from then on the nodes
  // are read from its node_positions channel. Returns an error message when
  // another component already deforms this mesh.
  std::optional<std::string> followDeformation(const Component& deformer, ChannelHub& channels);
  bool isDeformable() const { return m_positions.has_value(); }
  double displacementMargin() const { return m_margin; }  // mm

  // The search step of collide(), alone (benchmarks split the frame with it):
  // the colliding shell points and their tets; returns how many (0 for a shell
  // larger than any reserved).
  size_t findHits(const Pose& X_WT, std::span<const ShellPoint> shell);
  // The rest of collide(): contact normal and penetration of the hits the last
  // findHits() found (`hits` is what it returned).
  ShellContact contactOfHits(std::span<const ShellPoint> shell, size_t hits);

  // Replaces the mesh (tests and tools): validates, reorients and rebuilds the grids.
  void setMesh(TetMesh mesh);
  const TetMesh& mesh() const { return m_mesh; }
  const TetTopology& topology() const { return m_topology; }
  const MeshReport& report() const { return m_report; }
  // The tet containing p (the lowest index when p is on a shared face), or -1.
  int32_t locate(const Vec3& p) const;
  // locate() for many points at once (tets[i] for points[i]); true if any is
  // inside. `stopAtFirst`: return at the first point found inside (the rest
  // of `tets` is then incomplete).
  bool locatePoints(std::span<const Vec3> points, std::span<int32_t> tets, bool stopAtFirst) const;
  // Current position of a node (mm): the rest position unless deformed.
  const Vec3& node(int32_t index) const { return m_nodes[index]; }
  // Depth of p below the nearest boundary face (mm, > 0 inside) and that face's outward normal.
  double depthBelowSurface(const Vec3& p, Vec3& normal) const;
  // Distance of p to the nearest boundary face around the nodes of `tet`, or infinity when none.
  double depthToIncidentFaces(int32_t tet, const Vec3& p, Vec3& normal) const;

 private:
  void buildAccelerations();
  void reserveNodeForces(size_t entries);
  void refreshBoxes(const NodePositions& frame, bool all);
  Box3 currentBox(int32_t tet) const;
  // Barycentric coordinates of p in a tet (current nodes).
  std::array<double, 4> barycentric(int32_t tet, const Vec3& p) const;
  bool inside(int32_t tet, const Vec3& p) const;
  Vec3 faceNormal(const BoundaryFace& face) const;
  ShellContact contactAlgorithm2(const Eigen::Matrix3d& R, const Vec3& t, std::span<const ShellPoint> shell,
                                 size_t hits);
  ShellContact contactNearestFace(const Eigen::Matrix3d& R, const Vec3& t, std::span<const ShellPoint> shell,
                                  size_t hits);
  // First entry into the mesh along a -> b (fraction), ignoring the start when it is inside.
  double firstEntry(const Vec3& a, const Vec3& b, bool skipInitialInside, bool& startsInside) const;

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
  Field<double> d_cellSize{this,
                           "cellSize",
                           0.0,
                           {.help = "Side of the uniform grid's cells; 0 uses half the mesh's average edge length",
                            .unit = "mm",
                            .min = 0.0}};
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
  Field<double> d_contactDepth{this,
                               "contactDepth",
                               0.05,
                               {.help = "How far a swept proxy is placed into the surface so that its points register "
                                        "contact",
                                .unit = "mm",
                                .min = 0.0,
                                .minExclusive = true}};

  // The options the haptic frame branches on, read from their fields once in setMesh().
  enum class Search { kGrid, kFirstTetrahedron, kPreviousContact };
  Search m_search = Search::kGrid;
  bool m_algorithm2 = false;      // penetration="algorithm2"
  bool m_refreshEveryBox = true;  // boxRefresh="all"

  TetMesh m_mesh;  // rest shape
  TetTopology m_topology;
  const Vec3* m_nodes = nullptr;  // current node positions: the rest nodes, or the deformation's latest
  MeshReport m_report;
  size_t m_reoriented = 0;
  Box3 m_restBounds, m_bounds;            // m_bounds: the rest bounds grown by the displacement bound
  std::vector<Box3> m_restBoxes;          // per tet, at rest (the grids are built from them, grown by the margin)
  std::vector<Box3> m_tetBoxes;           // per tet, current: maintained only for the thesis's scans
  std::vector<uint8_t> m_degenerate;      // 1: zero-volume tetrahedron, never contains a point
  UniformGrid m_tetGrid, m_faceGrid;      // tetrahedra and boundary faces by cell
  std::vector<uint32_t> m_nodeFaceStart;  // node -> boundary faces holding it (compressed rows)
  std::vector<int32_t> m_nodeFaces;
  double m_averageEdge = 0;  // mm

  // Deformation (followDeformation).
  std::optional<ChannelReader<NodePositions>> m_positions;
  double m_margin = 0;             // mm, by which the grids' boxes are grown
  double m_displacementBound = 0;  // mm, the deformation's latest bound
  double m_queryGrowth = 0;        // mm, max(0, bound - margin): how far queries widen
  uint64_t m_lastStep = 0;
  std::vector<uint32_t> m_nodeTetStart;  // node -> tets (compressed rows), for boxRefresh="moved"
  std::vector<int32_t> m_nodeTets;
  std::vector<uint8_t> m_tetMarked;
  uint64_t m_deformationFrames = 0, m_framesBeyondMargin = 0, m_refreshedBoxes = 0, m_rejectedFrames = 0;
  double m_largestBound = 0;

  // Reaction forces on the nodes (computed only when a component reads them).
  Channel<NodeForces>* m_nodeForces = nullptr;
  NodeForces m_nodeForceValue;
  std::vector<int32_t> m_nodeSlot;  // per node: its entry in m_nodeForceValue, or -1
  size_t m_lastHits = 0;            // hits of the last collide(), for applyContactForce
  Eigen::Matrix3d m_lastRotation = Eigen::Matrix3d::Identity();
  Vec3 m_lastPosition = Vec3::Zero();
  const ShellPoint* m_lastShell = nullptr;

  // Per-frame working memory, sized by reserveShell().
  struct Hit {
    int32_t tet;
    int32_t point;
  };
  size_t findHitsByScan(const Eigen::Matrix3d& R, const Vec3& t, std::span<const ShellPoint> shell);
  std::vector<Hit> m_hits;
  std::vector<Vec3> m_points;        // per shell point, world
  std::vector<int32_t> m_pointTets;  // per shell point, its tet or -1
  // Scratch of the const queries (the haptic thread only).
  mutable ShellLocator m_locator;
  mutable VisitStamps m_tetVisits, m_faceVisits;  // blocks of cells: each item tested once
  mutable std::vector<Vec3> m_insetPoints;
  mutable std::vector<int32_t> m_insetTets;
  std::vector<int32_t> m_candidates;  // tets within two rings of the first colliding one
  int32_t m_lastFirstTet = 0;
  uint64_t m_scannedTets = 0;
  std::vector<double> m_depths;  // per hit, mm
  std::vector<Vec3> m_normals;   // per hit, outward unit normal of the face it measures to
  std::vector<const ShellPoint*> m_shells;
  uint64_t m_contactFrames = 0, m_maxCollidingTets = 0, m_deepFallbacks = 0, m_unreservedShellCalls = 0;
};

}  // namespace trephine::tetra
