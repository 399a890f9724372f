#pragma once
// The experiment of thesis section 5.4, which finds the best cell size of the
// object-object collision by measuring it: two copies of a mesh placed so
// that about 1% of the first's tetrahedra hold a particle of the second,
// stepped a few frames with a penalty response at each cell size of a sweep;
// the detection time per frame against the cell size is fitted with a
// polynomial, whose minimiser is delta_opt. The optimal zone is the range of
// cell sizes whose fitted time is within `zoneTolerance` of the minimum (the
// thesis's zone, within 1 ms of it, is wider than any of these meshes'
// detection times today).
#include <cstdint>
#include <vector>

#include "framework/data/TetMesh.h"
#include "plugins/tetra_brain/cell_size/CellSizeModel.h"
#include "plugins/tetra_brain/cell_size/TetPairCollision.h"

namespace trephine::tetra {

struct CellSizeExperimentOptions {
  double collidingFraction = 0.01;  // of the first copy's tetrahedra holding a particle of the second
  int frames = 10;                  // per cell size and round (the thesis's 10)
  int rounds = 3;                   // sweeps, interleaved; each cell size's time is the median of its rounds
  std::vector<double> cellSizes;    // mm; empty: 25 sizes from 0.4 to 4 average edges, evenly in 1 / delta
  double zoneTolerance = 0.10;      // the optimal zone: fitted time within this fraction of the minimum
  int fitDegree = 4;                // of the polynomial in 1 / delta
};

struct CellSizeSample {
  double cellSize = 0;  // mm
  double timeUs = 0;    // detection per frame, median over frames and rounds
  double fittedUs = 0;  // the polynomial there
  PairCounts perFrame;  // the loops' counts of one frame (the first)
  size_t cells = 0;     // of the grid
};

struct CellSizeExperimentResult {
  Vec3 offset = Vec3::Zero();       // of the second copy (mm, along x)
  double collidingFraction = 0;     // reached: of the first copy's tetrahedra holding a particle
  std::vector<CellSizeSample> samples;
  double optimal = 0;               // delta_opt (mm)
  double zoneLow = 0, zoneHigh = 0; // the optimal zone (mm)
  // At the model's own delta_a: the fraction of tetrahedra whose cells held
  // no particle (the p_nc the model assumes).
  double measuredCollisionFree = 0;
  // t_p / t_v from the sweep: the detection time fitted as a cell visit's
  // cost times the cells visited plus a particle test's times the tests
  // (plus the grid's cells and a constant).
  double calibratedTimeRatio = 0;
};

// Throws std::invalid_argument when no offset reaches a colliding fraction
// within a factor 2 of the one asked, or a cell size needs too many cells.
CellSizeExperimentResult runCellSizeExperiment(const TetMesh& mesh, const CellSizeInputs& inputs,
                                               const CellSizeExperimentOptions& options);

// The error of a cell size against the experiment (thesis Eq. 5.9, from
// Borro et al. 2004): 0 at delta_opt, 1 at the edge of the optimal zone on
// delta's side, above 1 outside. Measured, as in the thesis's tables, in
// cells per unit length (1 / delta).
double cellSizeError(double optimal, double zoneLow, double zoneHigh, double delta);

}  // namespace trephine::tetra
