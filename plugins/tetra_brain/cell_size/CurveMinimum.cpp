#include "plugins/tetra_brain/cell_size/CurveMinimum.h"

#include <Eigen/Dense>
#include <algorithm>

namespace trephine::tetra {

namespace {

// Least squares polynomial of degree `degree` in x (scaled to [-1, 1]).
struct Polynomial {
  Eigen::VectorXd c;
  double centre = 0, halfWidth = 1;
  double operator()(double x) const {
    const double u = (x - centre) / halfWidth;
    double y = 0;
    for (Eigen::Index k = c.size() - 1; k >= 0; --k) y = y * u + c[k];
    return y;
  }
};

Polynomial fit(const std::vector<double>& x, const std::vector<double>& y, int degree) {
  Polynomial p;
  const auto [lo, hi] = std::minmax_element(x.begin(), x.end());
  p.centre = 0.5 * (*lo + *hi);
  p.halfWidth = std::max(1e-300, 0.5 * (*hi - *lo));
  const int terms = std::min<int>(degree + 1, int(x.size()));
  Eigen::MatrixXd A(x.size(), terms);
  Eigen::VectorXd b(x.size());
  for (size_t i = 0; i < x.size(); ++i) {
    const double u = (x[i] - p.centre) / p.halfWidth;
    double power = 1;
    for (int k = 0; k < terms; ++k, power *= u) A(Eigen::Index(i), k) = power;
    b[Eigen::Index(i)] = y[i];
  }
  p.c = A.colPivHouseholderQr().solve(b);
  return p;
}

}  // namespace

CurveMinimum fitCurveMinimum(const std::vector<double>& x, const std::vector<double>& y, int degree,
                             double tolerance) {
  CurveMinimum result;
  if (x.empty()) return result;
  const Polynomial curve = fit(x, y, degree);
  for (double xi : x) result.fitted.push_back(curve(xi));
  // The minimiser and the zone, on a fine sampling of the sampled range.
  const auto [xMin, xMax] = std::minmax_element(x.begin(), x.end());
  constexpr int kFine = 4000;
  std::vector<double> fineX(kFine + 1), fineY(kFine + 1);
  size_t best = 0;
  for (int i = 0; i <= kFine; ++i) {
    fineX[i] = *xMin + (*xMax - *xMin) * i / kFine;
    fineY[i] = curve(fineX[i]);
    if (fineY[i] < fineY[best]) best = size_t(i);
  }
  const double limit = fineY[best] * (1 + tolerance);
  size_t low = best, high = best;
  while (low > 0 && fineY[low - 1] <= limit) --low;
  while (high < size_t(kFine) && fineY[high + 1] <= limit) ++high;
  result.best = fineX[best];
  result.low = fineX[low];
  result.high = fineX[high];
  return result;
}

}  // namespace trephine::tetra
