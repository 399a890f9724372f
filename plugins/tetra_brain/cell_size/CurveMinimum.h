#pragma once
// The minimum of a measured cost curve: a least-squares polynomial through
// the samples, its minimiser on the sampled range, and the zone around it
// where the polynomial stays within a tolerance of the minimum.
#include <vector>

namespace trephine::tetra {

struct CurveMinimum {
  double best = 0;               // the minimiser (in x)
  double low = 0, high = 0;      // the zone (in x, low <= best <= high)
  std::vector<double> fitted;    // the polynomial at each sample
};

// `degree` is capped by the sample count; `tolerance` is a fraction of the minimum.
CurveMinimum fitCurveMinimum(const std::vector<double>& x, const std::vector<double>& y, int degree,
                             double tolerance);

}  // namespace trephine::tetra
