#include "plugins/tetra_brain/cell_size/ToolQueryExperiment.h"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>

#include "plugins/tetra_brain/NativeTetBackend.h"
#include "framework/data/TetTopology.h"
#include "plugins/tetra_brain/cell_size/CurveMinimum.h"

namespace trephine::tetra {

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// Poses as a haptic loop visits them: short strokes, each starting over a
// boundary face chosen at random with the tool `depth` (mm) into the surface
// (where the god-object proxy, which the queries follow, holds it), moving 0.1 mm a frame along the
// face while the tool turns 1 degree a frame. Successive queries then read
// the same cells, as at 1 kHz, instead of a cold neighbourhood each.
std::vector<Pose> contactPoses(const TetMesh& mesh, const TetTopology& topology, double radius, double depth,
                               int count) {
  constexpr int kStroke = 10;  // frames per stroke
  std::mt19937 random(5);
  std::normal_distribution<double> gauss;
  const auto& faces = topology.boundaryFaces();
  std::uniform_int_distribution<size_t> pick(0, faces.size() - 1);
  std::vector<Pose> poses;
  while (int(poses.size()) < count) {
    const BoundaryFace& face = faces[pick(random)];
    const TetIndices& tet = mesh.tets[face.tet];
    const auto v = faceNodes(tet, face.face);
    const Vec3 centre = (mesh.nodes[v[0]] + mesh.nodes[v[1]] + mesh.nodes[v[2]]) / 3.0;
    Vec3 normal = (mesh.nodes[v[1]] - mesh.nodes[v[0]]).cross(mesh.nodes[v[2]] - mesh.nodes[v[0]]).normalized();
    const Vec3 tetCentre = (mesh.nodes[tet[0]] + mesh.nodes[tet[1]] + mesh.nodes[tet[2]] + mesh.nodes[tet[3]]) / 4.0;
    if (normal.dot(centre - tetCentre) < 0) normal = -normal;  // outward
    const Vec3 along = (mesh.nodes[v[1]] - mesh.nodes[v[0]]).normalized();
    const Quat start = Quat(gauss(random), gauss(random), gauss(random), gauss(random)).normalized();
    const Quat turn(Eigen::AngleAxisd(std::numbers::pi / 180, Vec3(gauss(random), gauss(random), gauss(random)).normalized()));
    Pose pose{centre + (radius - depth) * normal, start};
    for (int frame = 0; frame < kStroke && int(poses.size()) < count; ++frame) {
      poses.push_back(pose);
      pose.position += 0.1 * along;
      pose.orientation = (turn * pose.orientation).normalized();
    }
  }
  return poses;
}

// Least squares of y on the four counts plus a constant, every count's
// coefficient at least 0: the best of the fits on each subset of the counts
// whose coefficients all come out non-negative (16 subsets; the constant is
// always in). The counts rise and fall together across a sweep, and a plain
// fit trades them against each other with negative costs.
std::array<double, 4> nonNegativeFit(const std::vector<std::array<double, 4>>& x, const std::vector<double>& y) {
  std::array<double, 4> best{0, 0, 0, 0};
  double bestResidual = INFINITY;
  for (int subset = 0; subset < 16; ++subset) {
    std::vector<int> columns;
    for (int c = 0; c < 4; ++c)
      if (subset & (1 << c)) columns.push_back(c);
    Eigen::MatrixXd A(Eigen::Index(x.size()), Eigen::Index(columns.size() + 1));
    Eigen::VectorXd b(Eigen::Index(x.size()));
    for (size_t i = 0; i < x.size(); ++i) {
      for (size_t c = 0; c < columns.size(); ++c) A(Eigen::Index(i), Eigen::Index(c)) = x[i][columns[c]];
      A(Eigen::Index(i), Eigen::Index(columns.size())) = 1.0;
      b[Eigen::Index(i)] = y[i];
    }
    const Eigen::VectorXd k = A.colPivHouseholderQr().solve(b);
    bool valid = true;
    for (size_t c = 0; c < columns.size(); ++c) valid = valid && k[Eigen::Index(c)] >= 0;
    const double residual = (A * k - b).squaredNorm();
    if (!valid || !(residual < bestResidual)) continue;
    bestResidual = residual;
    best = {0, 0, 0, 0};
    for (size_t c = 0; c < columns.size(); ++c) best[columns[c]] = k[Eigen::Index(c)];
  }
  return best;
}

ToolQueryWork perQuery(const NativeTetBackend::LocateWork& after, const NativeTetBackend::LocateWork& before) {
  const double q = double(after.queries - before.queries);
  if (!(q > 0)) return {};
  return {double(after.cells - before.cells) / q, double(after.listed - before.listed) / q,
          double(after.overlapping - before.overlapping) / q, double(after.pointTests - before.pointTests) / q};
}

}  // namespace

double toolCellSizeError(double optimal, double zoneLow, double zoneHigh, double delta) {
  const double x = std::log(delta), best = std::log(optimal);
  if (x == best) return 0;
  if (x > best) return (x - best) / std::max(1e-12, std::log(zoneHigh) - best);
  return (best - x) / std::max(1e-12, best - std::log(zoneLow));
}

ToolQueryExperimentResult runToolQueryExperiment(const TetMesh& mesh, const std::vector<Vec3>& shell,
                                                 const ToolQueryExperimentOptions& options) {
  ToolQueryExperimentResult result;
  const TetTopology topology(mesh);
  std::vector<ShellPoint> points;
  for (const Vec3& p : shell) points.push_back({p, -p.normalized()});
  double radius = 0;  // of the shell about the tool's origin
  for (const Vec3& p : shell) radius = std::max(radius, p.norm());
  const std::vector<Pose> poses = contactPoses(mesh, topology, radius, std::min(options.depth, radius), options.poses);

  // The mesh's average edge and margin, from a back-end at the default cell.
  TetQueryOptions query;
  query.deformable = options.deforming;
  {
    NativeTetBackend probe;
    probe.bind({&mesh, &topology, query});
    result.averageEdge = probe.averageEdge();
    result.margin = probe.displacementMargin();
  }
  const TetBoxMoments moments = measureBoxMoments(mesh, result.margin);

  std::vector<double> sizes = options.cellSizes;
  if (sizes.empty())
    for (int i = 0; i <= 16; ++i) sizes.push_back(result.averageEdge * 0.1 * std::pow(20.0, i / 16.0));
  // Cells so small that the grid would list more than kMostGridEntries
  // entries (4 bytes each) are left out: a million tetrahedra at a tenth of
  // an edge would take gigabytes.
  constexpr double kMostGridEntries = 64e6;
  auto entries = [&](double delta) { return moments.overlapping(Vec3::Constant(delta)) * moments.volume / (delta * delta * delta); };
  std::erase_if(sizes, [&](double delta) { return entries(delta) > kMostGridEntries; });
  if (sizes.size() < 5) throw std::invalid_argument("fewer than 5 of the cell sizes keep the grid under 64 million entries");
  std::vector<std::vector<double>> times(sizes.size());
  result.samples.resize(sizes.size());
  size_t inside = 0, tested = 0;
  for (int round = 0; round < options.rounds; ++round)
    for (size_t s = 0; s < sizes.size(); ++s) {
      NativeTetBackend backend;
      query.cellSize = sizes[s];
      backend.bind({&mesh, &topology, query});
      backend.reserveShell(points);
      if (options.deforming) backend.moveNodes({mesh.nodes, result.margin, {}, true, INFINITY});
      const auto before = backend.locateWork();
      size_t hits = 0;
      const auto start = std::chrono::steady_clock::now();
      for (const Pose& pose : poses) hits += backend.findHits(pose, points).size();
      const double ns = std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - start).count();
      times[s].push_back(ns / double(poses.size()));
      if (round == 0) {
        ToolQuerySample& sample = result.samples[s];
        sample.cellSize = backend.currentGrids().tetGrid.cellSide();  // the grid may cap its cell count
        sample.measured = perQuery(backend.locateWork(), before);
        sample.predicted = predictToolQueryWork(moments, shell, sample.cellSize);
        sample.gridCells = backend.currentGrids().tetGrid.cellCount();
        sample.gridEntries = backend.currentGrids().tetGrid.entryCount();
        inside += hits;
        tested += poses.size() * points.size();
      }
    }
  result.insideFraction = tested ? double(inside) / double(tested) : 0;
  std::vector<double> x, t;
  for (size_t s = 0; s < sizes.size(); ++s) {
    result.samples[s].timeNs = median(times[s]);
    x.push_back(std::log(result.samples[s].cellSize));
    t.push_back(result.samples[s].timeNs);
  }
  const CurveMinimum curve = fitCurveMinimum(x, t, options.fitDegree, options.zoneTolerance);
  for (size_t s = 0; s < sizes.size(); ++s) result.samples[s].fittedNs = curve.fitted[s];
  result.optimal = std::exp(curve.best);
  result.zoneLow = std::exp(curve.low);
  result.zoneHigh = std::exp(curve.high);

  // The weights: time = w_c cells + w_l listed + w_o overlapping + w_p point
  // tests + a constant, in ns, none negative.
  std::vector<std::array<double, 4>> counts;
  std::vector<double> ns;
  for (const ToolQuerySample& sample : result.samples) {
    const ToolQueryWork& w = sample.measured;
    counts.push_back({w.cells, w.listed, w.overlapping, w.pointTests});
    ns.push_back(sample.timeNs);
  }
  const std::array<double, 4> k = nonNegativeFit(counts, ns);
  result.calibrated = {k[0], k[1], k[2], k[3]};
  return result;
}

}  // namespace trephine::tetra
