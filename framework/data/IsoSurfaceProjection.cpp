#include "framework/data/IsoSurfaceProjection.h"

#include <cmath>
#include <cstring>
#include <unordered_map>
#include <vector>

namespace trephine {

double trilinearCode(const VoxelGrid& grid, const Vec3& p) {
  // Voxel centres at corner + (i + 0.5) spacing.
  const Vec3 f = (p - grid.corner).cwiseProduct(grid.inverseSpacing) - Vec3::Constant(0.5);
  const int64_t i = int64_t(std::floor(f.x())), j = int64_t(std::floor(f.y())), k = int64_t(std::floor(f.z()));
  const double u = f.x() - double(i), v = f.y() - double(j), w = f.z() - double(k);
  double value = 0;
  for (int c = 0; c < 8; ++c) {
    const int a = c & 1, b = (c >> 1) & 1, d = (c >> 2) & 1;
    const double weight = (a ? u : 1 - u) * (b ? v : 1 - v) * (d ? w : 1 - w);
    if (weight != 0) value += weight * grid.codeAtCell(i + a, j + b, k + d);
  }
  return value;
}

ProjectionCounts projectOntoIsoSurface(TriangleMesh& surface, const VoxelGrid& grid, double reach) {
  // Vertices at one position are one (blocks repeat their face vertices).
  auto key = [](const Vec3& p) {
    uint64_t words[3];
    std::memcpy(words, p.data(), sizeof words);
    return words[0] * 0x9E3779B97F4A7C15ull ^ (words[1] + 0x7F4A7C159E3779B9ull) * 31 ^ words[2];
  };
  std::unordered_map<uint64_t, std::vector<int32_t>> samePlace;
  std::vector<int32_t> leader(surface.vertices.size());
  for (size_t v = 0; v < surface.vertices.size(); ++v) {
    auto& list = samePlace[key(surface.vertices[v])];
    int32_t found = -1;
    for (int32_t other : list)
      if (surface.vertices[size_t(other)] == surface.vertices[v]) found = other;
    if (found < 0) list.push_back(int32_t(v));
    leader[v] = found < 0 ? int32_t(v) : found;
  }
  std::vector<Vec3> normals(surface.vertices.size(), Vec3::Zero());
  for (const auto& t : surface.triangles) {
    const Vec3 n = (surface.vertices[t[1]] - surface.vertices[t[0]]).cross(surface.vertices[t[2]] - surface.vertices[t[0]]);
    for (int32_t c : t) normals[size_t(leader[size_t(c)])] += n;
  }
  const double step = 0.5 * grid.spacing.minCoeff();
  const double iso = grid.isoCode;
  ProjectionCounts counts;
  std::vector<Vec3> placed(surface.vertices.size());
  std::vector<uint8_t> stayed(surface.vertices.size(), 0);
  for (size_t v = 0; v < surface.vertices.size(); ++v) {
    if (leader[v] != int32_t(v)) continue;
    const Vec3 p = surface.vertices[v];
    const double norm = normals[v].norm();
    placed[v] = p;
    if (!(norm > 0)) {
      ++counts.stayed;
      stayed[v] = 1;
      continue;
    }
    const Vec3 n = normals[v] / norm;
    const double here = trilinearCode(grid, p) - iso;
    // From air, inward (against the normal, which faces out of the bone) to
    // where the bone starts; from bone, outward to where it ends.
    const double direction = here < 0 ? -1.0 : 1.0;
    double found = here == 0 ? 0.0 : NAN;
    for (double s = step; s <= reach + 1e-12 && std::isnan(found); s += step) {
      const double a = direction * (s - step), b = direction * s;
      const double fa = trilinearCode(grid, p + a * n) - iso, fb = trilinearCode(grid, p + b * n) - iso;
      if ((fa < 0) == (fb < 0)) continue;
      double lo = a, hi = b, flo = fa;
      for (int k = 0; k < 30; ++k) {
        const double mid = 0.5 * (lo + hi);
        const double fm = trilinearCode(grid, p + mid * n) - iso;
        if ((fm < 0) == (flo < 0)) lo = mid, flo = fm;
        else hi = mid;
      }
      found = 0.5 * (lo + hi);
    }
    if (std::isnan(found)) {
      ++counts.stayed;
      stayed[v] = 1;
      continue;
    }
    placed[v] = p + found * n;
    ++counts.moved;
  }
  // A vertex that found no crossing (its normal, on a coarse staircase, misses
  // the surface within reach) would stand out of its projected neighbours as
  // a spike: it takes the mean of its neighbours instead, a few times over.
  if (counts.stayed > 0) {
    std::vector<std::vector<int32_t>> neighbours(surface.vertices.size());
    for (const auto& t : surface.triangles)
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b)
          if (a != b) neighbours[size_t(leader[size_t(t[a])])].push_back(leader[size_t(t[b])]);
    for (int round = 0; round < 10; ++round)
      for (size_t v = 0; v < surface.vertices.size(); ++v) {
        if (leader[v] != int32_t(v) || !stayed[v] || neighbours[v].empty()) continue;
        Vec3 mean = Vec3::Zero();
        for (int32_t w : neighbours[v]) mean += placed[size_t(w)];
        placed[v] = mean / double(neighbours[v].size());
      }
  }
  for (size_t v = 0; v < surface.vertices.size(); ++v) surface.vertices[v] = placed[size_t(leader[v])];
  return counts;
}

}  // namespace trephine
