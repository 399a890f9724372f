// Reading a CT series: a 512 x 512 x N series of int16 slices (rescale to
// Hounsfield units), written once per size with GDCM's writer into a
// temporary directory, in shuffled file order, then read as a volume
// (structure check, headers, sort, pixels, int16 codes); and a series from a
// gantry tilted by 15 degrees, whose sheared grid is also resampled onto an
// axis-aligned one. Bytes processed are the voxels' 2 bytes each. The smoke
// test reads 8 slices of 64 x 64 of each kind (TREPHINE_BENCH_DICOM_SMOKE=1).
#include <benchmark/benchmark.h>
#include <gdcmAttribute.h>
#include <gdcmImageWriter.h>
#include <gdcmTrace.h>

#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <tuple>
#include <string>
#include <vector>

#include "framework/formats/volume/VolumeReader.h"

namespace {

namespace fs = std::filesystem;

bool smoke() { return std::getenv("TREPHINE_BENCH_DICOM_SMOKE") != nullptr; }

// The series' directory for `slices` slices of `side` x `side`, written on
// first use; `tiltDegrees` shifts each slice along y as a gantry tilted about
// x does (the reader then resamples the sheared grid).
fs::path series(int side, int slices, double tiltDegrees = 0) {
  static std::map<std::tuple<int, int, double>, fs::path> written;
  auto& dir = written[{side, slices, tiltDegrees}];
  if (!dir.empty()) return dir;
  dir = fs::temp_directory_path() / ("trephine-dicom-bench-" + std::to_string(side) + "-" + std::to_string(slices) +
                                     "-" + std::to_string(int(tiltDegrees)) + "-" + std::to_string(getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  gdcm::Trace::SetWarning(false);
  std::vector<int16_t> pixels(size_t(side) * side);
  for (int k = 0; k < slices; ++k) {
    for (size_t i = 0; i < pixels.size(); ++i) pixels[i] = int16_t((i * 7 + size_t(k) * 13) % 3000);
    gdcm::ImageWriter writer;
    gdcm::Image& image = writer.GetImage();
    image.SetNumberOfDimensions(2);
    image.SetDimension(0, side);
    image.SetDimension(1, side);
    image.SetPixelFormat(gdcm::PixelFormat::INT16);
    image.SetPhotometricInterpretation(gdcm::PhotometricInterpretation::MONOCHROME2);
    image.SetSpacing(0, 0.45);
    image.SetSpacing(1, 0.45);
    image.SetOrigin(1, 0.625 * k * std::tan(tiltDegrees * M_PI / 180));
    image.SetOrigin(2, 0.625 * k);  // mm: a 0.625 mm CT
    const double cosines[6] = {1, 0, 0, 0, 1, 0};
    image.SetDirectionCosines(cosines);
    image.SetIntercept(-1024);
    image.SetSlope(1);
    gdcm::DataElement data(gdcm::Tag(0x7fe0, 0x0010));
    data.SetByteValue(reinterpret_cast<const char*>(pixels.data()), uint32_t(pixels.size() * 2));
    image.SetDataElement(data);
    gdcm::DataSet& ds = writer.GetFile().GetDataSet();
    gdcm::Attribute<0x0008, 0x0016> sopClass = {"1.2.840.10008.5.1.4.1.1.2"};
    ds.Replace(sopClass.GetAsDataElement());
    gdcm::Attribute<0x0020, 0x000e> uid = {"1.2.826.0.1.3680043.2.1125.9"};
    ds.Replace(uid.GetAsDataElement());
    // Names out of the slices' order: the reader sorts by position.
    writer.SetFileName((dir / ("s" + std::to_string((k * 37) % slices + 1000) + "_" + std::to_string(k) + ".dcm")).c_str());
    if (!writer.Write()) std::abort();
  }
  return dir;
}

void BM_ReadCtSeries(benchmark::State& state) {
  const int side = smoke() ? 64 : 512, slices = smoke() ? 8 : int(state.range(0));
  const fs::path dir = series(side, slices);
  for (auto _ : state) {
    const trephine::DensityVolume volume = trephine::formats::readVolume(dir);
    benchmark::DoNotOptimize(volume.codes());
  }
  state.SetBytesProcessed(int64_t(state.iterations()) * side * side * slices * 2);
  state.counters["slices"] = slices;
}
BENCHMARK(BM_ReadCtSeries)->Arg(100)->Arg(300)->Unit(benchmark::kMillisecond)->UseRealTime();

// A 300-slice series from a gantry tilted by 15 degrees: read, then
// resampled trilinearly onto an axis-aligned grid.
void BM_ReadTiltedCtSeries(benchmark::State& state) {
  const int side = smoke() ? 64 : 512, slices = smoke() ? 8 : 300;
  const fs::path dir = series(side, slices, 15);
  std::array<int32_t, 3> dims{};
  for (auto _ : state) {
    const trephine::DensityVolume volume = trephine::formats::readVolume(dir);
    dims = volume.dims();
    benchmark::DoNotOptimize(volume.codes());
  }
  state.SetBytesProcessed(int64_t(state.iterations()) * side * side * slices * 2);
  state.counters["resampled_voxels"] = double(dims[0]) * dims[1] * dims[2];
}
BENCHMARK(BM_ReadTiltedCtSeries)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  // The series written are left in the temporary directory's care no longer.
  for (const auto& entry : fs::directory_iterator(fs::temp_directory_path()))
    if (entry.path().filename().string().starts_with("trephine-dicom-bench-") &&
        entry.path().filename().string().ends_with("-" + std::to_string(getpid())))
      fs::remove_all(entry.path());
  return 0;
}
