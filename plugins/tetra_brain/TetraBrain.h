#pragma once
// A brain as a tetrahedral mesh, touched by a pointshell tool (thesis chapter
// 4). Shell points are located in tetrahedra through a uniform grid of cells
// listing the tetrahedra whose boxes overlap them, so the cost of a frame
// depends on the tool's neighbourhood, not on the size of the mesh. The
// contact normal averages the outward normals of the boundary faces of the
// colliding tetrahedra; the penetration is the deepest colliding point below
// those faces (Algorithm 2), or below the nearest boundary face when its
// tetrahedra have none (the tool deep in the mesh).
#include <vector>

#include "framework/core/Component.h"
#include "framework/geometry/ShellContactTarget.h"
#include "plugins/tetra_brain/TetMesh.h"
#include "plugins/tetra_brain/TetTopology.h"
#include "plugins/tetra_brain/UniformGrid.h"

namespace trephine::tetra {

class TetraBrain final : public Component, public ShellContactTarget {
 public:
  static constexpr std::string_view kTypeName = "TetraBrain";

  void init(InitContext& context) override;
  void reportCounters(std::vector<Counter>& counters) const override;

  // SurfaceTarget
  Box3 bounds() const override { return m_bounds; }
  std::optional<SurfaceHit> raycast(const Vec3& origin, const Vec3& direction, double maxDistance) const override;
  // ShellContactTarget
  void reserveShell(std::span<const ShellPoint> shell) override;
  SweepResult sweep(const SweepQuery& query) const override;
  ShellContact collide(const Pose& X_WT, std::span<const ShellPoint> shell, bool removeMaterial) override;
  bool overlaps(const Pose& X_WT, std::span<const ShellPoint> shell) const override;
  double contactDepth() const override { return d_contactDepth.value(); }

  // Replaces the mesh (tests and tools): validates, reorients and rebuilds the grids.
  void setMesh(TetMesh mesh);
  const TetMesh& mesh() const { return m_mesh; }
  const TetTopology& topology() const { return m_topology; }
  const MeshReport& report() const { return m_report; }
  // The tet containing p (the lowest index when p is on a shared face), or -1.
  int32_t locate(const Vec3& p) const;
  // Depth of p below the nearest boundary face (mm, > 0 inside) and that face's outward normal.
  double depthBelowSurface(const Vec3& p, Vec3& normal) const;

 private:
  void buildAccelerations();
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
                       {.help = "Tetrahedral mesh: TetGen .node/.ele, Medit .mesh, Gmsh .msh (v1, v2 ASCII), VTK .vtk "
                                "or .vtu (format read from the content, gzip allowed); or a phantom: "
                                "phantom:cube?cells=22, phantom:brain?tets=22000",
                        .required = true},
                       FilePathField::Role::Input,
                       {"phantom"}};
  EnumField d_inverted{this,
                       "inverted",
                       {"reorient", "refuse"},
                       "reorient",
                       {.help = "Tetrahedra with negative volume: swap two nodes (and report how many), or refuse "
                                "the mesh"}};
  Field<Vec3> d_translation{this, "translation", Vec3::Zero(), {.help = "Moves the mesh after loading", .unit = "mm"}};
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
  Field<double> d_contactDepth{this,
                               "contactDepth",
                               0.05,
                               {.help = "How far a swept proxy is placed into the surface so that its points register "
                                        "contact",
                                .unit = "mm",
                                .min = 0.0,
                                .minExclusive = true}};

  TetMesh m_mesh;
  TetTopology m_topology;
  MeshReport m_report;
  size_t m_reoriented = 0;
  Box3 m_bounds;
  std::vector<Box3> m_tetBoxes;
  std::vector<uint8_t> m_degenerate;  // 1: zero-volume tetrahedron, never contains a point
  UniformGrid m_tetGrid, m_faceGrid;  // tetrahedra and boundary faces by cell
  double m_averageEdge = 0;           // mm

  // Per-frame working memory, sized by reserveShell().
  struct Hit {
    int32_t tet;
    int32_t point;
  };
  size_t findHitsByScan(const Eigen::Matrix3d& R, const Vec3& t, std::span<const ShellPoint> shell);
  std::vector<Hit> m_hits;
  std::vector<Vec3> m_points;         // per shell point, world (scan searches)
  std::vector<int32_t> m_candidates;  // tets within two rings of the first colliding one
  int32_t m_lastFirstTet = 0;
  uint64_t m_scannedTets = 0;
  std::vector<double> m_depths;  // per hit, mm
  std::vector<Vec3> m_normals;   // per hit, outward unit normal of the face it measures to
  std::vector<const ShellPoint*> m_shells;
  uint64_t m_contactFrames = 0, m_maxCollidingTets = 0, m_deepFallbacks = 0, m_unreservedShellCalls = 0;
};

}  // namespace trephine::tetra
