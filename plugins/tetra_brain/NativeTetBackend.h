#pragma once
// The native back-end of TetraBrain (thesis chapter 4). Shell points are
// located in tetrahedra through a uniform grid of cells listing the
// tetrahedra whose boxes overlap them, so the cost of a frame depends on the
// tool's neighbourhood, not on the size of the mesh. Normal and penetration
// come from the boundary faces: each colliding point measures to the nearest
// one (its tetrahedron's, the ones around its nodes, else the mesh's), or, as
// the thesis's Algorithm 2, the normals of the colliding tetrahedra's boundary
// faces are averaged and the deepest point below them gives the penetration.
//
// On a deforming mesh the grids are those of a reference shape (the rest
// shape, or a deformed one a TetGridRebuild built off the haptic thread and
// adoptGrids() took), with every box grown by a displacement margin, and each
// frame reads the current node positions. While the nodes stay within the
// margin of the reference nothing is refreshed; beyond it the queries widen
// by the excess, so the results stay exact and only the cost grows. The thesis's scans instead
// refresh tetrahedron boxes every frame (all of them, or those of the moved
// nodes).
//
// Files: NativeTetBackend.cpp (grids, deformation, counters), NativeTetLocation.cpp
// (which tetrahedron holds a point, the scans, overlap), NativeTetContact.cpp
// (normal and penetration), NativeTetSweep.cpp (sweeps and ray casts).
#include <array>
#include <vector>

#include "plugins/tetra_brain/DriftBound.h"
#include "plugins/tetra_brain/LiveFaces.h"
#include "plugins/tetra_brain/ShellLocator.h"
#include "plugins/tetra_brain/TetBackend.h"
#include "plugins/tetra_brain/TetGridSet.h"
#include "plugins/tetra_brain/UniformGrid.h"
#include "plugins/tetra_brain/VisitStamps.h"
#include "plugins/tetra_brain/cell_size/ToolQueryCost.h"

namespace trephine::tetra {

// A shell point inside a tetrahedron.
struct TetHit {
  int32_t tet;
  int32_t point;  // index in the shell
};

class NativeTetBackend final : public TetBackend {
 public:
  void bind(const TetData& data) override;
  void reserveShell(std::span<const ShellPoint> shell) override;
  size_t siteCapacity() const override { return m_hits.size(); }
  void moveNodes(const NodeFrame& frame) override;
  // Grids built on a deformed shape (TetGridRebuild): used from now on, with
  // the displacement bound measured from their reference. Ignored when they
  // are not this mesh's (another node count or margin). Allocation-free.
  void adoptGrids(const TetGridSet& grids) override;
  bool adoptsGrids() const override { return true; }
  // From now on the back-end follows removals (removeTets): the boundary
  // faces now are kept by LiveFaces (flags, node rows, the cavity's faces),
  // so a removal changes no grid.
  std::optional<std::string> followRemovals() override;
  // Allocation-free: O(faces changed).
  void removeTets(const RemainingMesh::Change& change) override;
  // The faces the face grid lists (its items index this): the mesh's
  // boundary faces at first (those a removal took away fail LiveFaces's flag).
  std::span<const BoundaryFace> faces() const { return m_topology->boundaryFaces(); }
  // mm; with cellSizeRule="tool-cost", final once the tools reserved their shells (initialisation)
  double cellSize() const { return m_cellSize; }
  // mm, of the boundary faces' grid: the tetrahedra's cell, at least half an
  // average edge. The nearest-face search of a deep point (depthBelowSurface)
  // visits rings of cells out to its depth, (depth / cell)^3 of them: the
  // tool query's small cells would make it 8 to 60 times dearer.
  double faceCellSize() const { return std::max(m_cellSize, 0.5 * m_averageEdge); }
  const TetGridSet& currentGrids() const { return *m_grids; }
  TetContact collide(const Pose& X_WT, std::span<const ShellPoint> shell, bool wantSites,
                     int32_t& searchStart) override;
  // From the first tetrahedron (no tool's last contact).
  size_t broadPhase(const Pose& X_WT, std::span<const ShellPoint> shell) override {
    return findHits(X_WT, shell).size();
  }
  SweepResult sweep(const SweepQuery& query) const override;
  bool overlaps(const Pose& X_WT, std::span<const ShellPoint> shell) const override;
  std::optional<SurfaceHit> raycast(const Vec3& origin, const Vec3& direction, double maxDistance) const override;
  void reportCounters(std::vector<Counter>& counters) const override;

  // collide() in its two steps (benchmarks time them apart): the shell points
  // inside tetrahedra (empty for a shell larger than any reserved; valid until
  // the next query), then the contact those hits give.
  // `searchStart`: where the previous-contact scan starts, updated to this
  // contact's first tetrahedron (the tool's memory); without, from the first.
  std::span<TetHit> findHits(const Pose& X_WT, std::span<const ShellPoint> shell, int32_t& searchStart);
  std::span<TetHit> findHits(const Pose& X_WT, std::span<const ShellPoint> shell) {
    int32_t fromFirst = 0;
    return findHits(X_WT, shell, fromFirst);
  }
  TetContact contactOfHits(const Pose& X_WT, std::span<const ShellPoint> shell, std::span<TetHit> hits, bool wantSites);

  // The tet containing p (the lowest index when p is on a shared face), or -1.
  int32_t locate(const Vec3& p) const;
  // locate() for many points at once (tets[i] for points[i]); true if any is
  // inside. `stopAtFirst`: return at the first point found inside (the rest
  // of `tets` is then incomplete).
  bool locatePoints(std::span<const Vec3> points, std::span<int32_t> tets, bool stopAtFirst) const;
  // Depth of p below the nearest boundary face (mm, > 0 inside) and that face's outward normal.
  double depthBelowSurface(const Vec3& p, Vec3& normal) const;
  // True when a boundary face (current shape) comes within `radius` (mm) of p.
  bool surfaceWithin(const Vec3& p, double radius) const;
  // Distance of p to the nearest boundary face around the nodes of `tet`, or infinity when none.
  double depthToIncidentFaces(int32_t tet, const Vec3& p, Vec3& normal) const;
  double displacementMargin() const { return m_margin; }  // mm
  double queryWidening() const { return m_queryGrowth; }  // mm, this frame's, at most mostQueryWidening()
  double mostQueryWidening() const { return kMostWideningCells * std::max(m_grids->tetGrid.cellSide(), 0.5 * m_averageEdge); }
  double averageEdge() const { return m_averageEdge; }    // mm
  // The work of the grid's shell queries (locatePoints, cell by cell) since
  // bind(): what the tool query's cost model (cell_size/ToolQueryCost.h) predicts.
  struct LocateWork {
    uint64_t queries = 0;
    uint64_t cells = 0;        // occupied cells visited
    uint64_t listed = 0;       // tetrahedra those cells list
    uint64_t overlapping = 0;  // of those, whose (grown) box overlaps the box of the cell's points
    uint64_t pointTests = 0;   // point against such a box
    uint64_t insideTests = 0;  // point in the box, against the tetrahedron itself
  };
  const LocateWork& locateWork() const { return m_locateWork; }

 private:
  using Search = TetQueryOptions::Search;
  void buildAccelerations();
  void buildFaceSets();
  void buildRestGrids();
  // cellSizeRule="tool-cost": the cell that minimises the queries of every
  // shell reserved so far; the grids are rebuilt when it changes.
  void fitCellSizeToShell(std::span<const ShellPoint> shell);
  void refreshBoxes(std::span<const int32_t> movedNodes, bool all);
  Box3 currentBox(int32_t tet) const;
  // Calls visit(face) once for each boundary face listed in the face grid's
  // cells that `box` overlaps, until visit returns true; returns whether it did.
  template <class Visit>
  bool anyFaceInCells(const Box3& box, Visit&& visit) const {
    std::array<int32_t, 3> lo, hi;
    if (!m_grids->faceGrid.cellRange(box, lo, hi)) return false;
    m_faceVisits.begin();
    for (int32_t k = lo[2]; k <= hi[2]; ++k)
      for (int32_t j = lo[1]; j <= hi[1]; ++j)
        for (int32_t i = lo[0]; i <= hi[0]; ++i)
          for (int32_t f : m_grids->faceGrid.items(m_grids->faceGrid.cellIndex(i, j, k)))
            if (m_faceVisits.firstVisit(f) && visit(f)) return true;
    return false;
  }
  // Barycentric coordinates of p in a tet (current nodes).
  std::array<double, 4> barycentric(int32_t tet, const Vec3& p) const;
  bool inside(int32_t tet, const Vec3& p) const;
  Vec3 faceNormal(const BoundaryFace& face) const;
  size_t findHitsByScan(const Eigen::Matrix3d& R, const Vec3& t, std::span<const ShellPoint> shell,
                        int32_t& searchStart);
  ShellContact contactAlgorithm2(const Eigen::Matrix3d& R, const Vec3& t, std::span<const ShellPoint> shell,
                                 std::span<const TetHit> hits);
  ShellContact contactNearestFace(const Eigen::Matrix3d& R, const Vec3& t, std::span<const ShellPoint> shell,
                                  std::span<const TetHit> hits);
  // First entry into the mesh along a -> b (fraction), ignoring the start when it is inside.
  double firstEntry(const Vec3& a, const Vec3& b, bool skipInitialInside, bool& startsInside) const;

  const TetMesh* m_mesh = nullptr;  // rest shape
  const TetTopology* m_topology = nullptr;
  TetQueryOptions m_options;
  const Vec3* m_nodes = nullptr;          // current node positions: the rest nodes, or the deformation's latest
  Box3 m_bounds;                          // the grids' reference bounds grown by the displacement bound
  TetGridSet m_restGrids;                 // built on the rest shape at bind()
  const TetGridSet* m_grids = &m_restGrids;  // in use: the rest ones or adopted ones (read in place)
  double m_cellSize = 0;                  // mm
  TetBoxMoments m_boxMoments;             // the tool query's cost model's view of the mesh
  std::vector<std::vector<Vec3>> m_modelShells;  // tool frame, mm: the shells the cell is fitted to
  std::vector<std::pair<const void*, size_t>> m_modelShellKeys;
  uint64_t m_adoptedGrids = 0;
  std::vector<Box3> m_tetBoxes;           // per tet, current: maintained only for the thesis's scans
  // Per tet: 0, or why it never contains a point (zero volume, removed).
  static constexpr uint8_t kDegenerateTet = 1, kRemovedTet = 2;
  std::vector<uint8_t> m_holdsNoPoint;
  bool m_followsRemovals = false;
  LiveFaces m_live;  // the boundary faces now
  double m_averageEdge = 0;  // mm

  // Deformation.
  double m_margin = 0;                   // mm, by which the grids' boxes are grown
  double m_displacementBound = 0;        // mm, the latest frame's bound
  double m_queryGrowth = 0;              // mm, max(0, bound - margin) up to the cap: how far queries widen
  // The most the queries widen, in cells of half an average edge or the grid's, the larger.
  static constexpr double kMostWideningCells = 1.0;
  uint64_t m_framesWideningCapped = 0;
  std::vector<uint32_t> m_nodeTetStart;  // node -> tets (compressed rows), for boxRefresh="moved"
  std::vector<int32_t> m_nodeTets;
  std::vector<uint8_t> m_tetMarked;
  uint64_t m_framesBeyondMargin = 0, m_refreshedBoxes = 0;
  DriftBound m_drift;  // from adopted grids' reference shape

  // Per-query working memory, sized by reserveShell().
  std::vector<TetHit> m_hits;
  std::vector<Vec3> m_points;        // per shell point, world
  std::vector<int32_t> m_pointTets;  // per shell point, its tet or -1
  std::vector<double> m_depths;      // per hit, mm
  std::vector<Vec3> m_normals;       // per hit, outward unit normal of the face it measures to
  std::vector<ContactSite> m_sites;  // per hit
  std::vector<int32_t> m_hitTets;    // the contact's tetrahedra, each once (TetContact::tets)
  // Scratch of the const queries (the haptic thread only).
  mutable ShellLocator m_locator;
  mutable VisitStamps m_tetVisits, m_faceVisits;  // blocks of cells: each item tested once
  mutable std::vector<Vec3> m_insetPoints;
  mutable std::vector<int32_t> m_insetTets;
  std::vector<int32_t> m_candidates;  // tets within two rings of the first colliding one
  // The previous-contact scan starts at the last frame's first colliding
  // tetrahedron: the one state kept between queries, as the thesis's method is.
  uint64_t m_scannedTets = 0;
  mutable LocateWork m_locateWork;
  uint64_t m_maxCollidingTets = 0, m_deepFallbacks = 0;
};

}  // namespace trephine::tetra
