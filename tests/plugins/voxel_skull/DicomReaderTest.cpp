// DICOM series read as volumes: series written here with GDCM's writer
// (sorted and shuffled files, slices stacked downwards, rescale to
// Hounsfield units, two series, a missing slice, a tilted gantry, a
// truncated file), each read back against the values and geometry written.
#include <gdcmAttribute.h>
#include <gdcmImageWriter.h>
#include <gdcmTrace.h>
#include <gdcmUIDGenerator.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <functional>
#include <fstream>
#include <numeric>

#include "plugins/voxel_skull/io/VolumeReader.h"
#include "tests/support/TestSupport.h"

namespace trephine {
namespace {

using voxel::DensityVolume;
using voxel::VolumeReadError;

struct SliceSpec {
  int columns = 6, rows = 4;
  Vec3 origin = Vec3::Zero();
  Vec3 rowDirection = Vec3::UnitX(), columnDirection = Vec3::UnitY();
  double columnSpacing = 0.5, rowSpacing = 0.75;  // mm
  double slope = 1, intercept = -1024;
  std::string series = "1.2.826.0.1.3680043.2.1125.1", description = "head CT";
  std::function<int16_t(int, int)> value;  // stored value at (column, row)
};

void writeSlice(const std::filesystem::path& file, const SliceSpec& s) {
  gdcm::Trace::SetWarning(false);  // GDCM's writer fills in what these slices leave out
  gdcm::ImageWriter writer;
  gdcm::Image& image = writer.GetImage();
  image.SetNumberOfDimensions(2);
  image.SetDimension(0, s.columns);
  image.SetDimension(1, s.rows);
  image.SetPixelFormat(gdcm::PixelFormat::INT16);
  image.SetPhotometricInterpretation(gdcm::PhotometricInterpretation::MONOCHROME2);
  image.SetSpacing(0, s.columnSpacing);
  image.SetSpacing(1, s.rowSpacing);
  for (int a = 0; a < 3; ++a) image.SetOrigin(a, s.origin[a]);
  const double cosines[6] = {s.rowDirection.x(),    s.rowDirection.y(),    s.rowDirection.z(),
                             s.columnDirection.x(), s.columnDirection.y(), s.columnDirection.z()};
  image.SetDirectionCosines(cosines);
  image.SetSlope(s.slope);
  image.SetIntercept(s.intercept);
  std::vector<int16_t> pixels(size_t(s.columns) * s.rows);
  for (int r = 0; r < s.rows; ++r)
    for (int c = 0; c < s.columns; ++c) pixels[size_t(r) * s.columns + c] = s.value(c, r);
  gdcm::DataElement data(gdcm::Tag(0x7fe0, 0x0010));
  data.SetByteValue(reinterpret_cast<const char*>(pixels.data()), uint32_t(pixels.size() * 2));
  image.SetDataElement(data);
  gdcm::DataSet& ds = writer.GetFile().GetDataSet();
  gdcm::Attribute<0x0008, 0x0016> sopClass = {"1.2.840.10008.5.1.4.1.1.2"};  // CT Image Storage
  ds.Replace(sopClass.GetAsDataElement());
  gdcm::Attribute<0x0008, 0x0060> modality = {"CT"};
  ds.Replace(modality.GetAsDataElement());
  gdcm::Attribute<0x0020, 0x000e> series = {s.series.c_str()};
  ds.Replace(series.GetAsDataElement());
  gdcm::Attribute<0x0008, 0x103e> description = {s.description.c_str()};
  ds.Replace(description.GetAsDataElement());
  writer.SetFileName(file.c_str());
  ASSERT_TRUE(writer.Write()) << file;
}

// A series of `slices` slices stepping `step` mm along the normal (z), the
// stored value of (c, r, k) 100 c + 10 r + k.
void writeSeries(const std::filesystem::path& dir, int slices, double step, SliceSpec spec = {},
                 const std::vector<int>& skip = {}) {
  std::filesystem::create_directories(dir);
  for (int k = 0; k < slices; ++k) {
    if (std::find(skip.begin(), skip.end(), k) != skip.end()) continue;
    SliceSpec s = spec;
    s.origin = spec.origin + Vec3(0, 0, k * step);
    s.value = [k](int c, int r) { return int16_t(100 * c + 10 * r + k); };
    // Files named against their order (z9, z8, ...): sorting is by position.
    writeSlice(dir / ("img" + std::to_string(97 - k) + ".dcm"), s);
  }
}

TEST(DicomReaderTest, ASeriesIsSortedByPositionAndRescaledToHounsfieldUnits) {
  test::TempDir dir;
  writeSeries(dir.path() / "ct", 5, 1.25, SliceSpec{.origin = Vec3(-10, 20, 30)});
  const DensityVolume v = voxel::readVolume(dir.path() / "ct");
  ASSERT_EQ(v.dims(), (std::array<int32_t, 3>{6, 4, 5}));
  EXPECT_NEAR(v.spacing().x(), 0.5, 1e-9);
  EXPECT_NEAR(v.spacing().y(), 0.75, 1e-9);
  EXPECT_NEAR(v.spacing().z(), 1.25, 1e-9) << "the step between positions";
  EXPECT_NEAR((v.origin() - Vec3(-10, 20, 30)).norm(), 0, 1e-6);
  for (int k = 0; k < 5; ++k)
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 6; ++c) ASSERT_NEAR(v.density(c, r, k), 100 * c + 10 * r + k - 1024, 1e-9) << c << r << k;
}

TEST(DicomReaderTest, SlicesSteppingDownwardsAreFlippedOntoAPositiveGrid) {
  test::TempDir dir;
  writeSeries(dir.path() / "down", 4, -2.0, SliceSpec{.slope = 2, .intercept = 5});
  const DensityVolume v = voxel::readVolume(dir.path() / "down");
  ASSERT_EQ(v.dims()[2], 4);
  EXPECT_NEAR(v.spacing().z(), 2.0, 1e-9);
  EXPECT_NEAR(v.origin().z(), -6.0, 1e-9) << "the lowest slice first";
  // The lowest slice (k = 3 as written) is now the first.
  EXPECT_NEAR(v.density(1, 2, 0), 2 * (100 + 20 + 3) + 5, 1e-9);
  EXPECT_NEAR(v.density(1, 2, 3), 2 * (100 + 20 + 0) + 5, 1e-9);
}

TEST(DicomReaderTest, TwoSeriesAreListedAndOneIsPickedByItsUid) {
  test::TempDir dir;
  writeSeries(dir.path() / "both", 3, 1.0);
  SliceSpec other{.series = "1.2.826.0.1.3680043.2.1125.2", .description = "scout"};
  for (int k = 0; k < 2; ++k) {
    SliceSpec s = other;
    s.origin = Vec3(0, 0, 5 * k);
    s.value = [](int, int) { return int16_t(7); };
    writeSlice(dir.path() / "both" / ("scout" + std::to_string(k) + ".dcm"), s);
  }
  try {
    voxel::readVolume(dir.path() / "both");
    ADD_FAILURE() << "two series read as one";
  } catch (const VolumeReadError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("2 series in one directory"), std::string::npos) << message;
    EXPECT_NE(message.find("1.2.826.0.1.3680043.2.1125.2 (\"scout\", 2 files)"), std::string::npos) << message;
    EXPECT_NE(message.find("?series=UID"), std::string::npos) << message;
  }
  const DensityVolume scout = voxel::readVolume((dir.path() / "both").string() + "?series=1.2.826.0.1.3680043.2.1125.2");
  EXPECT_EQ(scout.dims()[2], 2);
  EXPECT_NEAR(scout.density(0, 0, 1), 7 - 1024, 1e-9);
  EXPECT_THROW(voxel::readVolume((dir.path() / "both").string() + "?series=9.9"), VolumeReadError);
}

TEST(DicomReaderTest, BrokenSeriesAreClearErrorsNamingTheFiles) {
  test::TempDir dir;
  auto message = [](const std::filesystem::path& path) {
    try {
      voxel::readVolume(path);
    } catch (const VolumeReadError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  writeSeries(dir.path() / "gap", 6, 1.0, {}, {3});
  EXPECT_NE(message(dir.path() / "gap").find("a slice is missing between img95.dcm and img93.dcm"), std::string::npos)
      << message(dir.path() / "gap");
  std::filesystem::create_directories(dir.path() / "empty");
  EXPECT_NE(message(dir.path() / "empty").find("no DICOM file"), std::string::npos);
  // A tilted gantry: each slice shifted along y as it steps in z.
  std::filesystem::create_directories(dir.path() / "sheared");
  for (int k = 0; k < 3; ++k) {
    SliceSpec s;
    s.origin = Vec3(0, 0.5 * k, 1.0 * k);
    s.value = [](int, int) { return int16_t(1); };
    writeSlice(dir.path() / "sheared" / ("t" + std::to_string(k) + ".dcm"), s);
  }
  EXPECT_NE(message(dir.path() / "sheared").find("gantry-tilted series: each slice is shifted 0.5"),
            std::string::npos)
      << message(dir.path() / "sheared");
  // An oblique plane (rotated 30 degrees about z).
  std::filesystem::create_directories(dir.path() / "turned");
  for (int k = 0; k < 2; ++k) {
    SliceSpec s;
    s.rowDirection = Vec3(std::cos(M_PI / 6), std::sin(M_PI / 6), 0);
    s.columnDirection = Vec3(-std::sin(M_PI / 6), std::cos(M_PI / 6), 0);
    s.origin = Vec3(0, 0, 1.0 * k);
    s.value = [](int, int) { return int16_t(1); };
    writeSlice(dir.path() / "turned" / ("o" + std::to_string(k) + ".dcm"), s);
  }
  EXPECT_NE(message(dir.path() / "turned").find("oblique"), std::string::npos) << message(dir.path() / "turned");
  // A file cut short in its pixel data.
  writeSeries(dir.path() / "cut", 3, 1.0);
  const auto victim = dir.path() / "cut" / "img96.dcm";
  const auto size = std::filesystem::file_size(victim);
  std::filesystem::resize_file(victim, size - 20);
  EXPECT_NE(message(dir.path() / "cut").find("img96.dcm"), std::string::npos) << message(dir.path() / "cut");
}

// In a scene: VoxelSkull's file is the series' directory, or the directory
// and a series among several.
TEST(DicomReaderTest, AVoxelSkullLoadsASeriesFromItsDirectory) {
  test::TempDir dir;
  writeSeries(dir.path() / "ct", 8, 1.0, SliceSpec{.columns = 8, .rows = 8});
  auto scene = [&](const std::string& file) {
    return R"(<Node name="root">
  <RequiredPlugin name="voxel_skull"/>
  <VoxelSkull name="skull" file=")" + file + R"(" isovalue="-900"/>
</Node>)";
  };
  Diagnostics d;
  EXPECT_TRUE(test::loadScene(scene((dir.path() / "ct").string() + "/"), d)) << test::messages(d);
  Diagnostics unknown;
  EXPECT_FALSE(test::loadScene(scene((dir.path() / "ct").string() + "/?series=9.9"), unknown));
  EXPECT_NE(test::messages(unknown).find("no series 9.9 here"), std::string::npos) << test::messages(unknown);
}

}  // namespace
}  // namespace trephine
