#include "tools/trephine/study/ScanIsosurface.h"

#include <algorithm>
#include <cmath>

namespace trephine::study {

LevelSet scanIsosurface(const ScanAsRead& scan) {
  return [volume = scan.volume, isovalue = scan.isovalue](const Vec3& p) {
    const DensityVolume& v = *volume;
    if (!v.bounds().contains(p)) return 1.0;
    const auto& dims = v.dims();
    // Continuous index of p among the voxel centres, held at the outer centres.
    const Vec3 u = (p - v.origin()).cwiseQuotient(v.spacing());
    int32_t lo[3];
    double f[3];
    for (int a = 0; a < 3; ++a) {
      const double x = std::clamp(u[a], 0.0, double(dims[a] - 1));
      lo[a] = std::min<int32_t>(int32_t(std::floor(x)), std::max(dims[a] - 2, 0));
      f[a] = dims[a] > 1 ? x - lo[a] : 0.0;
    }
    const auto at = [&](int a, int b, int c) {
      return v.density(std::min(lo[0] + a, dims[0] - 1), std::min(lo[1] + b, dims[1] - 1),
                       std::min(lo[2] + c, dims[2] - 1));
    };
    double density = 0;
    for (int c = 0; c < 2; ++c)
      for (int b = 0; b < 2; ++b)
        for (int a = 0; a < 2; ++a)
          density += (a ? f[0] : 1 - f[0]) * (b ? f[1] : 1 - f[1]) * (c ? f[2] : 1 - f[2]) * at(a, b, c);
    return isovalue - density;
  };
}

}  // namespace trephine::study
