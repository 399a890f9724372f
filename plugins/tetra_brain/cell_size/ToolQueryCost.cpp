#include "plugins/tetra_brain/cell_size/ToolQueryCost.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <tuple>

namespace trephine::tetra {

namespace {

double expectedOverlaps(const BoxProductSums& s, double tetrahedra, double volume, const Vec3& e) {
  if (!(volume > 0)) return 0;
  const double sum = s.xyz + s.pairs.dot(e) + s.singles.x() * e.y() * e.z() + s.singles.y() * e.x() * e.z() +
                     s.singles.z() * e.x() * e.y() + tetrahedra * e.x() * e.y() * e.z();
  return sum / volume;
}

void addBox(BoxProductSums& s, const Vec3& A) {
  s.xyz += A.x() * A.y() * A.z();
  s.pairs += Vec3(A.y() * A.z(), A.x() * A.z(), A.x() * A.y());
  s.singles += A;
}

}  // namespace

double TetBoxMoments::overlapping(const Vec3& e) const { return expectedOverlaps(grown, tetrahedra, volume, e); }

double TetBoxMoments::tightOverlapping(const Vec3& e) const {
  return expectedOverlaps(tight, tetrahedra, volume, e);
}

TetBoxMoments measureBoxMoments(const TetMesh& mesh, double margin) {
  TetBoxMoments m;
  for (const TetIndices& k : mesh.tets) {
    const Vec3 &a = mesh.nodes[k[0]], &b = mesh.nodes[k[1]], &c = mesh.nodes[k[2]], &d = mesh.nodes[k[3]];
    m.volume += std::abs(signedVolume(a, b, c, d));
    const Vec3 lo = a.cwiseMin(b).cwiseMin(c).cwiseMin(d), hi = a.cwiseMax(b).cwiseMax(c).cwiseMax(d);
    addBox(m.grown, (hi - lo).array() + 2 * margin);
    addBox(m.tight, hi - lo);
    m.tetrahedra += 1;
  }
  return m;
}

ToolQueryWork predictToolQueryWork(const TetBoxMoments& moments, std::span<const Vec3> shell, double delta,
                                   int samples) {
  ToolQueryWork work;
  if (shell.empty() || !(delta > 0) || samples < 1) return work;
  // The same turns and shifts (in cells) at every delta: z is then a smooth
  // function of delta, whose minimum a search can find.
  std::mt19937 random(20261124);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> gauss;
  struct Cell {
    std::array<int64_t, 3> key;
    Vec3 point;
    bool operator<(const Cell& o) const { return key < o.key; }
  };
  std::vector<Cell> cells(shell.size());
  const double inside = moments.overlapping(Vec3::Constant(delta));
  for (int s = 0; s < samples; ++s) {
    const Eigen::Quaterniond turn =
        Eigen::Quaterniond(gauss(random), gauss(random), gauss(random), gauss(random)).normalized();
    const Vec3 shift(unit(random), unit(random), unit(random));
    for (size_t i = 0; i < shell.size(); ++i) {
      const Vec3 p = turn * shell[i];
      const Vec3 g = p / delta + shift;
      cells[i] = {{int64_t(std::floor(g.x())), int64_t(std::floor(g.y())), int64_t(std::floor(g.z()))}, p};
    }
    std::sort(cells.begin(), cells.end());
    for (size_t first = 0; first < cells.size();) {
      size_t last = first;
      Box3 box(cells[first].point, cells[first].point);
      while (last + 1 < cells.size() && cells[last + 1].key == cells[first].key) box.extend(cells[++last].point);
      const double k = double(last - first + 1);
      work.cells += 1;
      work.listed += inside;
      work.overlapping += moments.overlapping(box.sizes());
      work.pointTests += k * moments.tightOverlapping(box.sizes());
      first = last + 1;
    }
  }
  const double n = double(samples);
  work.cells /= n;
  work.listed /= n;
  work.overlapping /= n;
  work.pointTests /= n;
  return work;
}

double toolQueryCost(const ToolQueryWork& work, const ToolQueryWeights& weights) {
  return weights.cell * work.cells + weights.listed * work.listed + weights.overlapping * work.overlapping +
         weights.pointTest * work.pointTests;
}

double optimalToolCellSize(const TetBoxMoments& moments, std::span<const std::vector<Vec3>> shells,
                           double averageEdge, const ToolQueryWeights& weights) {
  auto cost = [&](double delta) {
    double z = 0;
    for (const auto& shell : shells) {
    // Turns and shifts: about 16k points a delta, at most 64 samples (a few
    // hundred points occupy a few cells of a large delta, whose count one
    // sample gives to within a cell), at least 2 for shells of thousands.
    const int samples = int(std::clamp<size_t>(16384 / std::max<size_t>(1, shell.size()), 2, 64));
    z += toolQueryCost(predictToolQueryWork(moments, shell, delta, samples), weights);
  }
    return z;
  };
  // A scan in log delta, then golden sections around its best.
  const double lo = kSmallestCellInEdges * averageEdge, hi = 4 * averageEdge;
  constexpr int kScan = 40;
  auto at = [&](int i) { return lo * std::pow(hi / lo, double(i) / kScan); };
  int best = 0;
  double bestCost = INFINITY;
  for (int i = 0; i <= kScan; ++i)
    if (const double z = cost(at(i)); z < bestCost) bestCost = z, best = i;
  double a = std::log(at(std::max(0, best - 1))), b = std::log(at(std::min(kScan, best + 1)));
  constexpr double kGolden = 0.6180339887498949;
  double x1 = b - kGolden * (b - a), x2 = a + kGolden * (b - a);
  double f1 = cost(std::exp(x1)), f2 = cost(std::exp(x2));
  for (int i = 0; i < 30; ++i) {
    if (f1 < f2) {
      b = x2, x2 = x1, f2 = f1;
      x1 = b - kGolden * (b - a), f1 = cost(std::exp(x1));
    } else {
      a = x1, x1 = x2, f1 = f2;
      x2 = a + kGolden * (b - a), f2 = cost(std::exp(x2));
    }
  }
  const double golden = std::exp(0.5 * (a + b));
  return cost(golden) <= bestCost ? golden : at(best);
}

}  // namespace trephine::tetra
