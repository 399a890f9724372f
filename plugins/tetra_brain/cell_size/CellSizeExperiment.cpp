#include "plugins/tetra_brain/cell_size/CellSizeExperiment.h"

#include "plugins/tetra_brain/cell_size/CurveMinimum.h"

#include <Eigen/Dense>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>

namespace trephine::tetra {

namespace {

constexpr double kFrameTime = 1e-3;  // s, the response's step

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// The second copy: the mesh turned by 10 degrees about a skew axis through
// its centre. Copies face to face with no turn meet a whole layer at once on
// a mesh with flat faces (a cube's), and no offset gives 1%.
TetMesh turnedCopy(const TetMesh& mesh) {
  TetMesh copy = mesh;
  Vec3 centre = Vec3::Zero();
  for (const Vec3& p : mesh.nodes) centre += p;
  centre /= double(mesh.nodes.size());
  const Eigen::Matrix3d turn =
      Eigen::AngleAxisd(10 * 3.14159265358979323846 / 180, Vec3(0.3, 0.5, 0.8).normalized()).toRotationMatrix();
  for (Vec3& p : copy.nodes) p = centre + turn * (p - centre);
  return copy;
}

// The fraction of the first copy's tetrahedra holding a particle of the
// second, shifted by `offset` along x.
double collidingFractionAt(const TetMesh& mesh, const TetMesh& second, double offset, double cellSize) {
  TetPairScene scene(mesh, second, Vec3(offset, 0, 0));
  const PairCounts counts = scene.detect(cellSize);
  return double(counts.collidingTets) / double(mesh.tetCount());
}

// Bisection on the offset: the fraction falls as the copies part.
double placeSecondCopy(const TetMesh& mesh, const TetMesh& second, double target, double cellSize,
                       double& reached) {
  Box3 bounds;
  for (const Vec3& p : mesh.nodes) bounds.extend(p);
  for (const Vec3& p : second.nodes) bounds.extend(p);
  double overlapping = 0, apart = bounds.sizes().x();  // offsets
  for (int i = 0; i < 40; ++i) {
    const double mid = 0.5 * (overlapping + apart);
    (collidingFractionAt(mesh, second, mid, cellSize) > target ? overlapping : apart) = mid;
  }
  reached = collidingFractionAt(mesh, second, overlapping, cellSize);
  if (!(reached >= 0.5 * target && reached <= 2 * target))
    throw std::invalid_argument("no offset of the second copy makes " + std::to_string(100 * target) +
                                "% of the tetrahedra collide (reached " + std::to_string(100 * reached) + "%)");
  return overlapping;
}

}  // namespace

double cellSizeError(double optimal, double zoneLow, double zoneHigh, double delta) {
  // In cells per unit length n = 1 / delta, as the thesis's tables (voxels
  // per axis of its scene): a small cell is a large n.
  const double nOpt = 1 / optimal, n = 1 / delta;
  if (n == nOpt) return 0;
  // The zone's width on each side of the optimum. An optimum at an end of the
  // sampled range (timings a loaded machine bends) leaves the zone no width
  // on that side: it is taken as wide as on the other (the error was
  // infinite, written as null).
  double larger = nOpt - 1 / zoneHigh, smaller = 1 / zoneLow - nOpt;
  if (!(larger > 0)) larger = smaller;
  if (!(smaller > 0)) smaller = larger;
  // n below the optimum (a larger cell): against the zone's larger cell.
  if (n < nOpt) return (nOpt - n) / larger;
  return (n - nOpt) / smaller;
}

CellSizeExperimentResult runCellSizeExperiment(const TetMesh& mesh, const CellSizeInputs& inputs,
                                               const CellSizeExperimentOptions& options) {
  CellSizeExperimentResult result;
  const TetMesh second = turnedCopy(mesh);
  const double offset =
      placeSecondCopy(mesh, second, options.collidingFraction, inputs.averageEdge, result.collidingFraction);
  result.offset = Vec3(offset, 0, 0);

  std::vector<double> sizes = options.cellSizes;
  if (sizes.empty()) {
    const double nLow = 1 / (4 * inputs.averageEdge), nHigh = 1 / (0.4 * inputs.averageEdge);
    for (int i = 0; i < 25; ++i) sizes.push_back(1 / (nLow + (nHigh - nLow) * i / 24.0));
  }
  std::vector<std::vector<double>> times(sizes.size());
  result.samples.resize(sizes.size());
  // Rounds interleaved: each cell size meets the machine in each of its states.
  for (int round = 0; round < options.rounds; ++round)
    for (size_t s = 0; s < sizes.size(); ++s) {
      // The same motion at every cell size: the detection is exact, so the
      // contacts, the response and the path are the same.
      TetPairScene scene(mesh, second, result.offset);
      // Towards the first copy by a hundredth of an edge a frame; the
      // response holds it.
      scene.setVelocityOfB(Vec3(-0.01 * inputs.averageEdge / kFrameTime, 0, 0));
      for (int frame = 0; frame < options.frames; ++frame) {
        const auto start = std::chrono::steady_clock::now();
        const PairCounts counts = scene.detect(sizes[s]);
        const double us = std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count();
        times[s].push_back(us);
        if (round == 0 && frame == 0) result.samples[s].perFrame = counts;
        scene.step(sizes[s], kFrameTime);  // the response (its own detection is not timed)
      }
    }
  std::vector<double> n, t;
  for (size_t s = 0; s < sizes.size(); ++s) {
    CellSizeSample& sample = result.samples[s];
    sample.cellSize = sizes[s];
    sample.timeUs = median(times[s]);
    ParticleGrid grid;  // its size, for the calibration
    Box3 bounds;
    for (const Vec3& p : mesh.nodes) bounds.extend(p);
    for (const Vec3& p : second.nodes) bounds.extend(p + result.offset);
    grid.build({}, bounds, sizes[s]);
    sample.cells = grid.cellCount();
    n.push_back(1 / sizes[s]);
    t.push_back(sample.timeUs);
  }
  const CurveMinimum curve = fitCurveMinimum(n, t, options.fitDegree, options.zoneTolerance);
  for (size_t s = 0; s < sizes.size(); ++s) result.samples[s].fittedUs = curve.fitted[s];
  result.optimal = 1 / curve.best;
  result.zoneLow = 1 / curve.high;  // the smaller cell: the larger n
  result.zoneHigh = 1 / curve.low;

  // p_nc at the model's delta_a.
  {
    TetPairScene scene(mesh, second, result.offset);
    const PairCounts counts = scene.detect(optimalCellSize(inputs, {}));
    result.measuredCollisionFree = 1 - double(counts.tetsWithParticles) / double(mesh.tetCount());
  }
  // r_t: time = a cellVisits + b boxTests + c cells + d.
  Eigen::MatrixXd A(result.samples.size(), 4);
  Eigen::VectorXd b(result.samples.size());
  for (size_t s = 0; s < result.samples.size(); ++s) {
    const CellSizeSample& sample = result.samples[s];
    A.row(Eigen::Index(s)) << double(sample.perFrame.cellVisits), double(sample.perFrame.boxTests),
        double(sample.cells), 1.0;
    b[Eigen::Index(s)] = sample.timeUs;
  }
  const Eigen::VectorXd k = A.colPivHouseholderQr().solve(b);
  result.calibratedTimeRatio = k[0] > 0 ? k[1] / k[0] : 0;
  return result;
}

}  // namespace trephine::tetra
