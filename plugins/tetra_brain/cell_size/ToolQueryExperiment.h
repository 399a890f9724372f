#pragma once
// The tool query's cost measured, as section 5.4 measures the pair's: a
// shell located by the native back-end (NativeTetBackend::findHits) at poses
// pressing into the surface (strokes over boundary faces chosen at random), timed at
// each cell size of a sweep, rounds interleaved. The time per query against
// log(delta) is fitted with a polynomial: its minimiser is delta_opt, and the
// optimal zone is where the fit is within `zoneTolerance` of the minimum. The
// back-end's own counts of the work give the weights of the cost model
// (ToolQueryCost.h) on this machine.
#include <vector>

#include "framework/data/TetMesh.h"
#include "plugins/tetra_brain/cell_size/ToolQueryCost.h"

namespace trephine::tetra {

struct ToolQueryExperimentOptions {
  int poses = 200;                // per cell size and round
  double depth = 0.05;            // mm, how far the tool is in the surface (a god-object proxy's contact depth)
  int rounds = 3;                 // sweeps, interleaved; each size's time is the median of its rounds
  // mm; empty: 17 sizes from 0.1 to 2 average edges, evenly in log(delta),
  // less those whose grid would list over 64 million entries.
  std::vector<double> cellSizes;
  double zoneTolerance = 0.10;
  int fitDegree = 4;              // of the polynomial in log(delta)
  // The grids of a deforming mesh: boxes grown by the displacement margin (a
  // quarter of the average edge), nodes at the margin's bound, each kept
  // tetrahedron's current box read (as every frame of a deforming brain).
  bool deforming = false;
};

struct ToolQuerySample {
  double cellSize = 0;      // mm
  double timeNs = 0;        // per query: median over rounds of the mean over poses
  double fittedNs = 0;
  ToolQueryWork measured;   // per query, the back-end's counts
  ToolQueryWork predicted;  // per query, the model's (every cell inside the mesh)
  size_t gridCells = 0, gridEntries = 0;
};

struct ToolQueryExperimentResult {
  std::vector<ToolQuerySample> samples;
  double optimal = 0;                // delta_opt (mm)
  double zoneLow = 0, zoneHigh = 0;  // mm
  double averageEdge = 0;            // mm
  double margin = 0;                 // mm, the grids' displacement margin (0 rigid)
  double insideFraction = 0;         // of the shell's points in a tetrahedron, over all poses
  // The weights fitted to the sweep (ns, none negative): time = w_c cells +
  // w_l listed + w_o overlapping + w_p point tests + a constant.
  ToolQueryWeights calibrated;
};

// Throws std::invalid_argument when fewer than 5 cell sizes are left.
ToolQueryExperimentResult runToolQueryExperiment(const TetMesh& mesh, const std::vector<Vec3>& shell,
                                                 const ToolQueryExperimentOptions& options);

// The error of a cell size against the experiment (Eq. 5.9 in log(delta)):
// 0 at delta_opt, 1 at the edge of the zone on delta's side.
double toolCellSizeError(double optimal, double zoneLow, double zoneHigh, double delta);

}  // namespace trephine::tetra
