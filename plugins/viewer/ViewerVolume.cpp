#include "plugins/viewer/ViewerVolume.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>

#include "framework/formats/volume/VolumeReader.h"
#include "framework/runtime/RunViewer.h"

namespace trephine::viewer {

namespace fs = std::filesystem;

namespace {

template <class T>
void put(std::string& out, T value) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  out.append(bytes, sizeof(T));
}

// i,j,k,t rows of skull_removed.csv: the earliest t of each packed voxel.
std::map<uint32_t, float> readRemoved(const fs::path& file, const DensityVolume& volume, int factor,
                                      const std::array<int32_t, 3>& packed, size_t& count) {
  std::map<uint32_t, float> first;
  std::ifstream in(file);
  if (!in) return first;  // a run that ended before the exporter's end
  std::string line;
  std::getline(in, line);
  if (line != "i,j,k,t") throw ViewerDataError(file.string() + ":1: expected the header i,j,k,t, not '" + line + "'");
  for (size_t number = 2; std::getline(in, line); ++number) {
    long long i = -1, j = -1, k = -1;
    double t = NAN;
    char tail = 0;
    if (std::sscanf(line.c_str(), "%lld,%lld,%lld,%lf%c", &i, &j, &k, &t, &tail) != 4 || !std::isfinite(t) ||
        i < 0 || j < 0 || k < 0 || i >= volume.dims()[0] || j >= volume.dims()[1] || k >= volume.dims()[2])
      throw ViewerDataError(file.string() + ":" + std::to_string(number) + ": expected i,j,k inside the " +
                            std::to_string(volume.dims()[0]) + " x " + std::to_string(volume.dims()[1]) + " x " +
                            std::to_string(volume.dims()[2]) + " volume and a finite t, not '" + line + "'");
    const uint32_t voxel = uint32_t(i / factor + packed[0] * (j / factor + packed[1] * size_t(k / factor)));
    auto [at, added] = first.try_emplace(voxel, float(t));
    if (!added) at->second = std::min(at->second, float(t));
    ++count;
  }
  return first;
}

}  // namespace

double readSkullIsovalue(const fs::path& file) {
  std::ifstream in(file);
  if (!in) return NAN;
  std::stringstream text;
  text << in.rdbuf();
  const std::string json = text.str();
  const size_t key = json.find("\"isovalue\"");
  const size_t colon = key == std::string::npos ? key : json.find(':', key);
  if (colon == std::string::npos) throw ViewerDataError(file.string() + ": expected an \"isovalue\": number");
  char* end = nullptr;
  const double value = std::strtod(json.c_str() + colon + 1, &end);
  if (end == json.c_str() + colon + 1 || !std::isfinite(value))
    throw ViewerDataError(file.string() + ": the isovalue is not a finite number");
  return value;
}

std::optional<PackedSkullVolume> packSkullVolume(const fs::path& directory, size_t maxVoxels) {
  const fs::path densityFile = directory / "skull_density.mhd";
  if (!fs::is_regular_file(densityFile)) return std::nullopt;
  DensityVolume volume;
  try {
    volume = formats::readVolume(densityFile);
  } catch (const std::exception& e) {
    throw ViewerDataError(e.what());
  }
  const auto& dims = volume.dims();
  int factor = 1;
  auto packedDims = [&](int f) {
    return std::array<int32_t, 3>{(dims[0] + f - 1) / f, (dims[1] + f - 1) / f, (dims[2] + f - 1) / f};
  };
  auto countOf = [](const std::array<int32_t, 3>& d) { return size_t(d[0]) * size_t(d[1]) * size_t(d[2]); };
  while (countOf(packedDims(factor)) > std::max<size_t>(maxVoxels, 1)) ++factor;
  const std::array<int32_t, 3> packed = packedDims(factor);

  PackedSkullVolume out;
  out.factor = factor;
  std::string& bytes = out.density;
  bytes = "VOL1";
  for (int32_t n : packed) put<uint32_t>(bytes, uint32_t(n));
  // A packed voxel's centre: the mean of the centres of the voxels it averages
  // (a partial block at the far edge is averaged over the voxels it has).
  const Vec3 origin = volume.origin() + 0.5 * (factor - 1) * volume.spacing();
  for (int a = 0; a < 3; ++a) put<float>(bytes, float(origin[a]));
  for (int a = 0; a < 3; ++a) put<float>(bytes, float(volume.spacing()[a] * factor));
  put<float>(bytes, float(readSkullIsovalue(directory / "skull_volume.json")));
  put<float>(bytes, float(volume.encoding().offset));
  put<float>(bytes, float(volume.encoding().scale));
  for (int32_t k = 0; k < packed[2]; ++k)
    for (int32_t j = 0; j < packed[1]; ++j)
      for (int32_t i = 0; i < packed[0]; ++i) {
        double sum = 0;
        int n = 0;
        for (int32_t c = k * factor; c < std::min(dims[2], (k + 1) * factor); ++c)
          for (int32_t b = j * factor; b < std::min(dims[1], (j + 1) * factor); ++b)
            for (int32_t a = i * factor; a < std::min(dims[0], (i + 1) * factor); ++a, ++n)
              sum += volume.code(volume.index(a, b, c));
        put<int16_t>(bytes, int16_t(std::lround(sum / n)));
      }
  const std::map<uint32_t, float> removed =
      readRemoved(directory / "skull_removed.csv", volume, factor, packed, out.removedVoxels);
  std::vector<std::pair<float, uint32_t>> byTime;
  for (const auto& [voxel, t] : removed) byTime.push_back({t, voxel});
  std::sort(byTime.begin(), byTime.end());
  out.removed = "RMV1";
  put<uint32_t>(out.removed, uint32_t(byTime.size()));
  for (const auto& [t, voxel] : byTime) {
    put<uint32_t>(out.removed, voxel);
    put<float>(out.removed, t);
  }
  return out;
}

}  // namespace trephine::viewer
