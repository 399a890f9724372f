#include "framework/geometry/ShellSampling.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace trephine {

std::vector<Vec3> angleStepDirections(double stepDegrees) {
  const double step = stepDegrees * std::numbers::pi / 180.0;
  std::vector<Vec3> out;
  // Counting in integers keeps the grid exact (no accumulated rounding).
  const int alphaSteps = static_cast<int>(std::ceil(360.0 / stepDegrees - 1e-9));
  const int betaSteps = static_cast<int>(std::floor(180.0 / stepDegrees + 1e-9));
  for (int j = 0; j <= betaSteps; ++j) {
    const double beta = j * step;
    const bool pole = std::abs(std::sin(beta)) < 1e-12;
    for (int i = 0; i < alphaSteps; ++i) {
      const double alpha = i * step;
      out.emplace_back(std::cos(alpha) * std::sin(beta), std::sin(alpha) * std::sin(beta), std::cos(beta));
      if (pole) break;  // every alpha gives the same pole point
    }
  }
  return out;
}

std::vector<Vec3> evenDirections(int count) {
  std::vector<Vec3> out;
  out.reserve(count);
  const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));  // rad between consecutive points
  for (int i = 0; i < count; ++i) {
    const double z = 1.0 - (2.0 * i + 1.0) / count;  // equal-area bands
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    const double phi = golden * i;
    out.emplace_back(r * std::cos(phi), r * std::sin(phi), z);
  }
  return out;
}

double largestGapAngle(const std::vector<Vec3>& directions) {
  if (directions.empty()) return std::numbers::pi;
  double worst = 0;
  for (const Vec3& probe : evenDirections(20000)) {
    double best = -1;
    for (const Vec3& d : directions) best = std::max(best, probe.dot(d));
    worst = std::max(worst, std::acos(std::clamp(best, -1.0, 1.0)));
  }
  return worst;
}

double shellSag(std::span<const ShellPoint> shell, double radius) {
  if (shell.empty()) return 0;
  double sag = 0;
  for (const Vec3& d : evenDirections(4096)) {
    double support = -INFINITY;
    for (const ShellPoint& p : shell) support = std::max(support, p.position.dot(d));
    sag = std::max(sag, radius - support);
  }
  return sag;
}

}  // namespace trephine
