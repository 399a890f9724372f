#include "framework/meshing/LabelRegions.h"

#include <map>
#include <vector>

namespace trephine {

namespace {

// Every voxel's region (-1 outside, label 0), regions numbered from 0, and
// each region's voxel count.
struct Regions {
  std::vector<int32_t> of;
  std::vector<size_t> sizes;
};

Regions findRegions(const LabelledImage& image) {
  const int64_t nx = image.dims[0], ny = image.dims[1], nz = image.dims[2];
  Regions r;
  r.of.assign(image.labels.size(), -1);
  std::vector<int64_t> stack;
  for (int64_t start = 0; start < int64_t(image.labels.size()); ++start) {
    if (image.labels[size_t(start)] == 0 || r.of[size_t(start)] >= 0) continue;
    const int32_t region = int32_t(r.sizes.size()), label = image.labels[size_t(start)];
    size_t count = 0;
    r.of[size_t(start)] = region;
    stack.push_back(start);
    while (!stack.empty()) {
      const int64_t v = stack.back();
      stack.pop_back();
      ++count;
      const int64_t i = v % nx, j = (v / nx) % ny, k = v / (nx * ny);
      const int64_t neighbours[6][2] = {{i > 0, v - 1},           {i + 1 < nx, v + 1},
                                        {j > 0, v - nx},          {j + 1 < ny, v + nx},
                                        {k > 0, v - nx * ny},     {k + 1 < nz, v + nx * ny}};
      for (const auto& [inside, w] : neighbours)
        if (inside && r.of[size_t(w)] < 0 && image.labels[size_t(w)] == label) {
          r.of[size_t(w)] = region;
          stack.push_back(w);
        }
    }
    r.sizes.push_back(count);
  }
  return r;
}

}  // namespace

LabelRegionCount countLabelRegions(const LabelledImage& image, size_t smallVoxels) {
  const Regions r = findRegions(image);
  LabelRegionCount count;
  count.regions = r.sizes.size();
  for (const size_t size : r.sizes)
    if (size < smallVoxels) ++count.small, count.smallVoxels += size;
  return count;
}

LabelRegionCount mergeSmallLabelRegions(LabelledImage& image, size_t minVoxels) {
  const Regions r = findRegions(image);
  const int64_t nx = image.dims[0], ny = image.dims[1], nz = image.dims[2];
  LabelRegionCount merged;
  merged.regions = r.sizes.size();
  // Per small region, the labels across its faces (the original labels).
  std::vector<std::map<int32_t, size_t>> across(r.sizes.size());
  for (int64_t v = 0; v < int64_t(image.labels.size()); ++v) {
    const int32_t region = r.of[size_t(v)];
    if (region < 0 || r.sizes[size_t(region)] >= minVoxels) continue;
    const int64_t i = v % nx, j = (v / nx) % ny, k = v / (nx * ny);
    const int64_t neighbours[6][2] = {{i > 0, v - 1},       {i + 1 < nx, v + 1},      {j > 0, v - nx},
                                      {j + 1 < ny, v + nx}, {k > 0, v - nx * ny}, {k + 1 < nz, v + nx * ny}};
    for (const auto& [inside, w] : neighbours) {
      if (inside && r.of[size_t(w)] == region) continue;
      ++across[size_t(region)][inside ? image.labels[size_t(w)] : 0];
    }
  }
  std::vector<int32_t> to(r.sizes.size(), -1);
  for (size_t region = 0; region < r.sizes.size(); ++region) {
    if (r.sizes[region] >= minVoxels) continue;
    size_t most = 0;
    for (const auto& [label, faces] : across[region])
      if (faces > most) most = faces, to[region] = label;  // ties: the smaller label, as the map is ordered
    ++merged.small;
    merged.smallVoxels += r.sizes[region];
  }
  for (size_t v = 0; v < image.labels.size(); ++v)
    if (r.of[v] >= 0 && to[size_t(r.of[v])] >= 0) image.labels[v] = to[size_t(r.of[v])];
  return merged;
}

}  // namespace trephine
