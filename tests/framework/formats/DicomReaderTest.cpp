// DICOM series read as volumes: series written here with GDCM's writer
// (sorted and shuffled files, slices stacked downwards, rescale to
// Hounsfield units, two series, a missing slice, a tilted gantry, an oblique
// plane, a truncated file, malformed meta information), each read back
// against the values and geometry written.
#include <gdcmAttribute.h>
#include <gdcmImageWriter.h>
#include <gdcmSequenceOfFragments.h>
#include <gdcmTrace.h>
#include <gdcmUIDGenerator.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <functional>
#include <fstream>
#include <numeric>

#include "framework/formats/volume/DicomWriter.h"
#include "framework/formats/volume/VolumeReader.h"
#include "tests/plugins/voxel_skull/ResampledVolumeCheck.h"
#include "tests/support/TestSupport.h"

namespace trephine {
namespace {

using formats::VolumeReadError;

struct SliceSpec {
  int columns = 6, rows = 4;
  Vec3 origin = Vec3::Zero();
  Vec3 rowDirection = Vec3::UnitX(), columnDirection = Vec3::UnitY();
  double columnSpacing = 0.5, rowSpacing = 0.75;  // mm
  double slope = 1, intercept = -1024;
  std::string series = "1.2.826.0.1.3680043.2.1125.1", description = "head CT";
  std::function<int16_t(int, int)> value;  // stored value at (column, row), plus 1000 per frame
  int frames = 1;                           // several: one multi-frame file
  double frameSpacing = 1;                  // mm between frames
  std::string sopClass = "1.2.840.10008.5.1.4.1.1.2";  // CT Image Storage
  // Encapsulated pixel data written as these fragments, under this syntax.
  gdcm::TransferSyntax::TSType transferSyntax = gdcm::TransferSyntax::ExplicitVRLittleEndian;
  std::vector<std::string> fragments;
};

void writeSlice(const std::filesystem::path& file, const SliceSpec& s) {
  gdcm::Trace::SetWarning(false);  // GDCM's writer fills in what these slices leave out
  gdcm::ImageWriter writer;
  gdcm::Image& image = writer.GetImage();
  image.SetNumberOfDimensions(s.frames > 1 ? 3 : 2);
  image.SetDimension(0, s.columns);
  image.SetDimension(1, s.rows);
  if (s.frames > 1) image.SetDimension(2, s.frames), image.SetSpacing(2, s.frameSpacing);
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
  std::vector<int16_t> pixels(size_t(s.columns) * s.rows * s.frames);
  for (int f = 0; f < s.frames; ++f)
    for (int r = 0; r < s.rows; ++r)
      for (int c = 0; c < s.columns; ++c)
        pixels[(size_t(f) * s.rows + r) * s.columns + c] = int16_t(s.value(c, r) + 1000 * f);
  gdcm::DataElement data(gdcm::Tag(0x7fe0, 0x0010));
  if (s.fragments.empty()) {
    data.SetByteValue(reinterpret_cast<const char*>(pixels.data()), uint32_t(pixels.size() * 2));
  } else {
    gdcm::SmartPointer<gdcm::SequenceOfFragments> sequence = new gdcm::SequenceOfFragments;
    for (const std::string& bytes : s.fragments) {
      gdcm::Fragment fragment;
      fragment.SetByteValue(bytes.data(), uint32_t(bytes.size()));
      sequence->AddFragment(fragment);
    }
    data.SetValue(*sequence);
    data.SetVLToUndefined();
    data.SetVR(gdcm::VR::OB);
  }
  image.SetTransferSyntax(s.transferSyntax);
  image.SetDataElement(data);
  gdcm::DataSet& ds = writer.GetFile().GetDataSet();
  gdcm::Attribute<0x0008, 0x0016> sopClass = {s.sopClass.c_str()};
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

// The error of reading `path` as a volume, or "no error".
std::string readError(const std::filesystem::path& path) {
  try {
    formats::readVolume(path);
  } catch (const VolumeReadError& e) {
    return e.what();
  }
  return "no error";
}

// The same after writing `bytes` to `file`.
std::string readErrorOf(const std::filesystem::path& file, const std::string& bytes) {
  std::ofstream(file, std::ios::binary) << bytes;
  return readError(file);
}

TEST(DicomReaderTest, ASeriesIsSortedByPositionAndRescaledToHounsfieldUnits) {
  test::TempDir dir;
  SliceSpec spec;
  spec.origin = Vec3(-10, 20, 30);
  writeSeries(dir.path() / "ct", 5, 1.25, spec);
  const DensityVolume v = formats::readVolume(dir.path() / "ct");
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
  SliceSpec spec;
  spec.slope = 2;
  spec.intercept = 5;
  writeSeries(dir.path() / "down", 4, -2.0, spec);
  const DensityVolume v = formats::readVolume(dir.path() / "down");
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
  SliceSpec other;
  other.series = "1.2.826.0.1.3680043.2.1125.2";
  other.description = "scout";
  for (int k = 0; k < 2; ++k) {
    SliceSpec s = other;
    s.origin = Vec3(0, 0, 5 * k);
    s.value = [](int, int) { return int16_t(7); };
    writeSlice(dir.path() / "both" / ("scout" + std::to_string(k) + ".dcm"), s);
  }
  try {
    formats::readVolume(dir.path() / "both");
    ADD_FAILURE() << "two series read as one";
  } catch (const VolumeReadError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("2 series in one directory"), std::string::npos) << message;
    EXPECT_NE(message.find("1.2.826.0.1.3680043.2.1125.2 (\"scout\", 2 files)"), std::string::npos) << message;
    EXPECT_NE(message.find("?series=UID"), std::string::npos) << message;
  }
  const DensityVolume scout = formats::readVolume((dir.path() / "both").string() + "?series=1.2.826.0.1.3680043.2.1125.2");
  EXPECT_EQ(scout.dims()[2], 2);
  EXPECT_NEAR(scout.density(0, 0, 1), 7 - 1024, 1e-9);
  EXPECT_THROW(formats::readVolume((dir.path() / "both").string() + "?series=9.9"), VolumeReadError);
}

TEST(DicomReaderTest, BrokenSeriesAreClearErrorsNamingTheFiles) {
  test::TempDir dir;
  const auto message = readError;
  writeSeries(dir.path() / "gap", 6, 1.0, {}, {3});
  EXPECT_NE(message(dir.path() / "gap").find("a slice is missing between img95.dcm and img93.dcm"), std::string::npos)
      << message(dir.path() / "gap");
  std::filesystem::create_directories(dir.path() / "empty");
  EXPECT_NE(message(dir.path() / "empty").find("no DICOM file"), std::string::npos);
  // A file cut short in its pixel data.
  writeSeries(dir.path() / "cut", 3, 1.0);
  const auto victim = dir.path() / "cut" / "img96.dcm";
  const auto size = std::filesystem::file_size(victim);
  std::filesystem::resize_file(victim, size - 20);
  EXPECT_NE(message(dir.path() / "cut").find("img96.dcm"), std::string::npos) << message(dir.path() / "cut");
}

// A gantry-tilted CT (each slice shifted across the plane as it steps) and
// an oblique plane are resampled onto an axis-aligned grid: where the stored
// slices are, the density is the stored one interpolated (exact for this
// ramp, linear in the stored index); outside them, the lowest density.
TEST(DicomReaderTest, TiltedAndObliqueSeriesAreResampledOntoAnAxisAlignedGrid) {
  test::TempDir dir;
  struct Case {
    std::string name;
    Vec3 rowDirection, columnDirection, step;
  };
  const double c30 = std::cos(M_PI / 6), s30 = std::sin(M_PI / 6);
  const std::vector<Case> cases = {
      {"tilted", Vec3::UnitX(), Vec3::UnitY(), Vec3(0, 0.5, 1.0)},  // tilt of 26.6 degrees about x
      {"oblique", Vec3(c30, s30, 0), Vec3(-s30, c30, 0), Vec3(0, 0, 1.5)},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const int slices = 5;
    std::filesystem::create_directories(dir.path() / c.name);
    SliceSpec spec;
    spec.rowDirection = c.rowDirection;
    spec.columnDirection = c.columnDirection;
    for (int k = 0; k < slices; ++k) {
      SliceSpec s = spec;
      s.origin = Vec3(3, -2, 10) + k * c.step;
      s.value = [k](int col, int row) { return int16_t(100 * col + 10 * row + 3 * k); };
      writeSlice(dir.path() / c.name / ("s" + std::to_string(k) + ".dcm"), s);
    }
    const DensityVolume volume = formats::readVolume(dir.path() / c.name);
    Eigen::Matrix3d axes;
    axes.col(0) = c.rowDirection * spec.columnSpacing;
    axes.col(1) = c.columnDirection * spec.rowSpacing;
    axes.col(2) = c.step;
    const size_t inside = test::expectResampledLinear(
        volume, {spec.columns, spec.rows, slices}, axes, Vec3(3, -2, 10),
        [](const Vec3& u) { return 100 * u[0] + 10 * u[1] + 3 * u[2] - 1024; }, -1024);
    EXPECT_GT(inside, size_t(spec.columns * spec.rows * slices / 2));
    // Spacing: the stored steps' components along the world axes.
    EXPECT_NEAR(volume.spacing().z(), c.step.z(), 1e-9);
    if (c.name == "tilted") {
      EXPECT_NEAR(volume.spacing().x(), spec.columnSpacing, 1e-9);
      EXPECT_NEAR(volume.spacing().y(), spec.rowSpacing, 1e-9);
    }
  }
}

// One multi-frame file: frames stacked along the normal at the spacing the
// file gives.
TEST(DicomReaderTest, AMultiFrameFileIsAVolume) {
  test::TempDir dir;
  SliceSpec spec;
  spec.frames = 4;
  spec.frameSpacing = 2.5;
  spec.origin = Vec3(1, 2, 3);
  spec.sopClass = "1.2.840.10008.5.1.4.1.1.2.1";  // Enhanced CT Image Storage
  spec.value = [](int c, int r) { return int16_t(100 * c + 10 * r); };
  writeSlice(dir.path() / "frames.dcm", spec);
  const DensityVolume volume = formats::readVolume(dir.path() / "frames.dcm");
  ASSERT_EQ(volume.dims(), (std::array<int32_t, 3>{spec.columns, spec.rows, 4}));
  EXPECT_EQ(volume.spacing(), Vec3(spec.columnSpacing, spec.rowSpacing, 2.5));
  EXPECT_EQ(volume.origin(), Vec3(1, 2, 3));
  for (int f = 0; f < 4; ++f)
    for (int r = 0; r < spec.rows; ++r)
      for (int c = 0; c < spec.columns; ++c)
        ASSERT_EQ(volume.density(c, r, f), 100 * c + 10 * r + 1000 * f - 1024) << c << " " << r << " " << f;
}

// Files whose meta information GDCM's lenient fallback reader asserts on
// (found by fuzzing): each is one clear error naming the file.
TEST(DicomReaderTest, MalformedMetaInformationIsAnErrorNotAnAbort) {
  test::TempDir dir;
  SliceSpec spec;
  spec.value = [](int c, int r) { return int16_t(c + r); };
  writeSlice(dir.path() / "good.dcm", spec);
  std::ifstream in(dir.path() / "good.dcm", std::ios::binary);
  const std::string good((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  // (0002,0000) UL at byte 132: its value at 140, the group after it at 144.
  ASSERT_EQ(good.compare(132, 6, std::string("\x02\x00\x00\x00UL", 6)), 0);
  const uint32_t groupLength = uint8_t(good[140]) | uint8_t(good[141]) << 8 | uint8_t(good[142]) << 16;
  const size_t metaEnd = 144 + groupLength;
  const size_t syntaxAt = good.find("1.2.840.10008.1.2.1");
  ASSERT_LT(syntaxAt, metaEnd);
  auto read = [&](const std::string& name) { return readError(dir.path() / name); };
  auto message = [&](const std::string& name, const std::string& bytes) { return readErrorOf(dir.path() / name, bytes); };
  auto expect = [&](const std::string& name, const std::string& bytes, const std::string& problem) {
    const std::string text = message(name, bytes);
    EXPECT_NE(text.find(name), std::string::npos) << text;
    EXPECT_NE(text.find(problem), std::string::npos) << text;
  };
  expect("meta_only.dcm", good.substr(0, metaEnd), "ends after its meta information");
  std::string unknownSyntax = good;
  unknownSyntax.replace(syntaxAt, 19, "1.2.840.10008.9.9.9");
  expect("unknown_syntax.dcm", unknownSyntax, "transfer syntax 1.2.840.10008.9.9.9 (expected");
  expect("no_group_length.dcm", good.substr(0, 132) + good.substr(144), "does not start with its Group Length");
  std::string sequenceInMeta = good;
  sequenceInMeta.replace(syntaxAt - 4, 2, "SQ");
  expect("sequence_in_meta.dcm", sequenceInMeta, "value representation SQ");
  // JPEG baseline pixel data that are no JPEG stream.
  spec.transferSyntax = gdcm::TransferSyntax::JPEGBaselineProcess1;
  spec.fragments = {std::string(48, '\x5a')};
  writeSlice(dir.path() / "bad_jpeg.dcm", spec);
  const std::string text = read("bad_jpeg.dcm");
  EXPECT_NE(text.find("bad_jpeg.dcm"), std::string::npos) << text;
  EXPECT_NE(text.find("cannot be decoded (transfer syntax 1.2.840.10008.1.2.4.50"), std::string::npos) << text;
  // A DICOM Segmentation object is named as such, with what to do instead.
  SliceSpec seg;
  seg.sopClass = "1.2.840.10008.5.1.4.1.1.66.4";
  seg.value = [](int c, int r) { return int16_t(c * r & 1); };
  writeSlice(dir.path() / "labels_seg.dcm", seg);
  const std::string segText = read("labels_seg.dcm");
  EXPECT_NE(segText.find("labels_seg.dcm"), std::string::npos) << segText;
  EXPECT_NE(segText.find("a DICOM Segmentation (SEG"), std::string::npos) << segText;
  EXPECT_NE(segText.find("segimage2itkimage"), std::string::npos) << segText;
}

// What GDCM asserts on rather than refuses, refused first, naming the file
// and the element: a palette colour image (its pixel reader asserts when the
// palette's tables are missing), an image attribute stored with another VR
// than the standard's (its typed attributes assert), colour samples.
TEST(DicomReaderTest, ImageAttributesGdcmWouldAssertOnAreErrors) {
  test::TempDir dir;
  SliceSpec spec;
  spec.value = [](int c, int r) { return int16_t(c - r); };
  writeSlice(dir.path() / "good.dcm", spec);
  const std::string good = test::readFile(dir.path() / "good.dcm");
  auto message = [&](const std::string& name, const std::string& bytes) { return readErrorOf(dir.path() / name, bytes); };
  auto patched = [&](const std::string& from, const std::string& to) {
    std::string bytes = good;
    const size_t at = bytes.find(from);
    EXPECT_NE(at, std::string::npos) << "no " << from;
    if (at != std::string::npos) bytes.replace(at, from.size(), to);
    return bytes;
  };
  std::string text = message("palette.dcm", patched("MONOCHROME2", "PALETTE COL"));
  EXPECT_NE(text.find("palette.dcm"), std::string::npos) << text;
  EXPECT_NE(text.find("PhotometricInterpretation (0028,0004) is \"PALETTE COL\" (expected MONOCHROME2"),
            std::string::npos)
      << text;
  // Rows (0028,0010) stored as SS.
  text = message("rows_ss.dcm", patched(std::string("\x28\x00\x10\x00US", 6), std::string("\x28\x00\x10\x00SS", 6)));
  EXPECT_NE(text.find("(0028,0010) has value representation SS (expected US)"), std::string::npos) << text;
  // Three samples a pixel.
  text = message("rgb.dcm", patched(std::string("\x28\x00\x02\x00US\x02\x00\x01\x00", 10),
                                    std::string("\x28\x00\x02\x00US\x02\x00\x03\x00", 10)));
  EXPECT_NE(text.find("(0028,0002) is 3 (expected SamplesPerPixel 1: a grey-level image)"), std::string::npos) << text;
  // Elements GDCM's image helper read through typed attributes, depending on
  // the SOP class and on pointers in the file (found by fuzzing: a Frame
  // Increment Pointer (0028,0009) stored as US aborted the process). The
  // reader takes the image's attributes itself and ignores what it does not use.
  const std::string rows(std::string("\x28\x00\x10\x00US", 6));
  for (const std::string& vr : {std::string("US"), std::string("DS"), std::string("SQ")}) {
    const std::string pointer = std::string("\x28\x00\x09\x00", 4) + vr + std::string("\x02\x00\x54\x00", 4);
    const std::string bytes = patched(rows, pointer + rows);
    text = message("frame_pointer_" + vr + ".dcm", bytes);
    EXPECT_TRUE(text == "no error" || text.find("frame_pointer_" + vr + ".dcm") != std::string::npos) << vr << ": " << text;
  }
  // Attributes the reader takes, with values that are not numbers: named.
  {
    std::string bytes = good;
    const size_t at = bytes.find(std::string("\x28\x00\x30\x00" "DS", 6));
    ASSERT_NE(at, std::string::npos);
    const size_t length = uint8_t(bytes[at + 6]) | uint8_t(bytes[at + 7]) << 8;
    ASSERT_GE(length, 6u);
    bytes.replace(at + 8, length, "1\\abc" + std::string(length - 5, ' '));
    text = message("spacing_text.dcm", bytes);
    EXPECT_NE(text.find("spacing_text.dcm"), std::string::npos) << text;
    EXPECT_NE(text.find("PixelSpacing (0028,0030) holds \"1\\abc"), std::string::npos) << text;
  }
  // The unpatched file still reads, MONOCHROME1 too (the stored values, not inverted).
  EXPECT_EQ(message("good_again.dcm", good), "no error");
  EXPECT_EQ(message("mono1.dcm", patched("MONOCHROME2", "MONOCHROME1")), "no error");
  const DensityVolume mono1 = formats::readVolume(dir.path() / "mono1.dcm");
  EXPECT_EQ(mono1.density(3, 1, 0), spec.slope * (3 - 1) + spec.intercept);
}

// The real CT of ../shared/data (a raw NRRD) written as a DICOM series by
// the project's writer and read back: the same grid and the same densities,
// voxel for voxel. Writing into a directory that holds files is refused and
// leaves them.
TEST(DicomReaderTest, TheRealCtHeadSurvivesADicomRoundTrip) {
  const auto nhdr = test::sourceDir() / "../shared/data/ct_head_vtk_headsq/quarter.nhdr";
  if (!std::filesystem::exists(nhdr)) GTEST_SKIP() << nhdr << " is absent (../shared/data)";
  const DensityVolume ct = formats::readVolume(nhdr);
  test::TempDir dir;
  formats::writeDicomSeries(ct, dir.path() / "ct", "VTK head");
  const DensityVolume back = formats::readVolume(dir.path() / "ct");
  ASSERT_EQ(back.dims(), ct.dims());
  EXPECT_LT((back.spacing() - ct.spacing()).norm(), 1e-6);
  EXPECT_LT((back.origin() - ct.origin()).norm(), 1e-6);
  size_t differing = 0;
  for (int32_t k = 0; k < ct.dims()[2]; ++k)
    for (int32_t j = 0; j < ct.dims()[1]; ++j)
      for (int32_t i = 0; i < ct.dims()[0]; ++i) differing += back.density(i, j, k) != ct.density(i, j, k);
  EXPECT_EQ(differing, 0u);
  std::filesystem::create_directories(dir.path() / "full");
  std::ofstream(dir.path() / "full" / "notes.txt") << "kept";
  try {
    formats::writeDicomSeries(ct, dir.path() / "full/", "again");
    ADD_FAILURE() << "no error for a directory that holds a file";
  } catch (const formats::VolumeWriteError& e) {
    EXPECT_NE(std::string(e.what()).find("full: exists and is not an empty directory"), std::string::npos) << e.what();
  }
  EXPECT_EQ(test::readFile(dir.path() / "full" / "notes.txt"), "kept");
  EXPECT_FALSE(std::filesystem::exists(dir.path() / "full.writing"));
}

// In a scene: VoxelSkull's file is the series' directory, or the directory
// and a series among several.
TEST(DicomReaderTest, AVoxelSkullLoadsASeriesFromItsDirectory) {
  test::TempDir dir;
  SliceSpec spec;
  spec.columns = spec.rows = 8;
  writeSeries(dir.path() / "ct", 8, 1.0, spec);
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

// Slices whose positions a scanner rounded (steps within 10% of the series'
// step): resampled onto even steps, each even slice interpolated linearly
// between the stored slices around it, with a warning giving the spread;
// beyond 10%, refused. Written here with GDCM at positions 0, 7.07, 14.04,
// 21.16, 28.06, 35.11 mm; the value of slice k is 100 c + 10 r + k.
TEST(DicomReaderTest, UnevenStepsWithinTenPercentAreResampledWithAWarningAndRefusedBeyond) {
  test::TempDir dir;
  const std::vector<double> positions{0, 7.07, 14.04, 21.16, 28.06, 35.11};
  const auto write = [&](const std::filesystem::path& folder, const std::vector<double>& at) {
    std::filesystem::create_directories(folder);
    for (size_t k = 0; k < at.size(); ++k) {
      SliceSpec s;
      s.origin = Vec3(0, 0, at[k]);
      s.value = [k](int c, int r) { return int16_t(100 * c + 10 * r + int(k)); };
      writeSlice(folder / ("img" + std::to_string(k) + ".dcm"), s);
    }
  };
  write(dir.path() / "uneven", positions);
  formats::VolumeReadNotes notes;
  const DensityVolume v = formats::readVolume(dir.path() / "uneven", &notes);
  ASSERT_EQ(notes.warnings.size(), 1u);
  EXPECT_NE(notes.warnings[0].find("uneven slice steps, 6.9 mm to 7.12 mm (the series' median step 7.05 mm): "
                                   "resampled onto an even 7.022 mm grid"),
            std::string::npos)
      << notes.warnings[0];
  ASSERT_EQ(v.dims()[2], 6);
  EXPECT_NEAR(v.spacing().z(), 35.11 / 5, 1e-9);
  // At even position z_j = j 35.11 / 5, between stored slices k and k + 1,
  // the value is k + (z_j - z_k) / (z_k+1 - z_k) (linear in the position).
  for (int j = 0; j < 6; ++j) {
    const double z = j * 35.11 / 5;
    size_t k = 0;
    while (k + 2 < positions.size() && positions[k + 1] < z) ++k;
    const double expected = double(k) + (z - positions[k]) / (positions[k + 1] - positions[k]);
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 6; ++c)
        ASSERT_NEAR(v.density(c, r, j), 100 * c + 10 * r + expected - 1024, v.encoding().scale / 2 + 1e-9)
            << c << " " << r << " " << j << " (interpolated values are coded on 16 bits)";
  }
  // Even to 1%: read as it is, no warning.
  write(dir.path() / "rounded", {0, 7.02, 14.01, 21.03, 28.0});
  formats::VolumeReadNotes none;
  EXPECT_EQ(formats::readVolume(dir.path() / "rounded", &none).dims()[2], 5);
  EXPECT_TRUE(none.warnings.empty());
  EXPECT_TRUE(none.notes.empty());
  // A step 12% off the series' step is not a rounding: refused, naming the pair.
  write(dir.path() / "far", {0, 7, 14, 21.84, 28.84, 35.84});
  EXPECT_NE(readError(dir.path() / "far").find("uneven slice steps: img2.dcm and img3.dcm are 7.84"),
            std::string::npos)
      << readError(dir.path() / "far");
}

// Zeros after a file's data set (padding some scanners write) are ignored
// with a note: the volume is the one without them. Anything else there is an
// error at its byte.
TEST(DicomReaderTest, ZerosAfterTheDataSetArePaddingAndAnythingElseThereIsAnError) {
  test::TempDir dir;
  writeSeries(dir.path() / "plain", 3, 1.0);
  writeSeries(dir.path() / "padded", 3, 1.0);
  const auto padded = dir.path() / "padded" / "img96.dcm";
  const auto size = std::filesystem::file_size(padded);
  std::ofstream(padded, std::ios::binary | std::ios::app) << std::string(2'500'000, '\0');
  formats::VolumeReadNotes notes;
  const DensityVolume v = formats::readVolume(dir.path() / "padded", &notes);
  const DensityVolume plain = formats::readVolume(dir.path() / "plain");
  ASSERT_EQ(v.dims(), plain.dims());
  for (size_t n = 0; n < v.voxelCount(); ++n) ASSERT_EQ(v.code(n), plain.code(n)) << n;
  ASSERT_EQ(notes.notes.size(), 1u);
  EXPECT_EQ(notes.notes[0], "1 of 3 files carry zeros after their data set, padding that is ignored (img96.dcm: "
                            "2500000 bytes)");
  EXPECT_TRUE(notes.warnings.empty());
  // One byte that is not zero among them: not padding.
  std::filesystem::resize_file(padded, size);
  std::ofstream(padded, std::ios::binary | std::ios::app) << std::string(1000, '\0') + "\x01" + std::string(99, '\0');
  EXPECT_NE(readError(dir.path() / "padded").find("img96.dcm: not a well-formed DICOM file at byte " +
                                                  std::to_string(size)),
            std::string::npos)
      << readError(dir.path() / "padded");
}

// A series as a scanner writes it, from an independent writer (pydicom,
// Debian's python3-pydicom: tests/framework/formats/data/write_scanner_dicom.py):
// a padded file and rounded positions, read with a note and a warning, and
// touched by a skull that loads it.
TEST(DicomReaderTest, ASeriesWrittenByPydicomWithPaddingAndUnevenStepsLoads) {
  if (std::system("/usr/bin/python3 -c 'import pydicom' 2>/dev/null") != 0)
    GTEST_SKIP() << "pydicom is not installed (Debian: python3-pydicom; tools/setup installs it)";
  test::TempDir dir;
  const std::string command = "/usr/bin/python3 " +
                              (test::sourceDir() / "tests/framework/formats/data/write_scanner_dicom.py").string() +
                              " " + (dir.path() / "mr").string();
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
  formats::VolumeReadNotes notes;
  const DensityVolume v = formats::readVolume(dir.path() / "mr", &notes);
  EXPECT_EQ(v.dims(), (std::array<int32_t, 3>{8, 5, 6}));
  EXPECT_NEAR(v.spacing().x(), 0.8, 1e-9) << "PixelSpacing is rows then columns";
  EXPECT_NEAR(v.spacing().y(), 0.9, 1e-9);
  EXPECT_NEAR(v.spacing().z(), 35.11 / 5, 1e-9);
  EXPECT_NEAR((v.origin() - Vec3(-5, 12, 0)).norm(), 0, 1e-6);
  // Interpolated densities are coded on 16 bits over their range: to half a step.
  EXPECT_NEAR(v.density(3, 2, 0), 320, v.encoding().scale / 2 + 1e-9);
  EXPECT_NEAR(v.density(3, 2, 5), 325, v.encoding().scale / 2 + 1e-9) << "the first and last slices stay";
  ASSERT_EQ(notes.notes.size(), 1u);
  EXPECT_NE(notes.notes[0].find("IM0004: 65536 bytes"), std::string::npos) << notes.notes[0];
  ASSERT_EQ(notes.warnings.size(), 1u);
  // A skull on it: a note and a warning at its file attribute; it loads, and
  // a 0.4 mm probe pushed along -x into its face at x = 0.6 mm is stopped there.
  Diagnostics d;
  auto simulation = test::loadScene(R"(<Node name="root">
  <RequiredPlugin name="voxel_skull"/>
  <RequiredPlugin name="haptics"/>
  <VoxelSkull name="skull" file=")" + (dir.path() / "mr").string() + R"(" isovalue="250"/>
  <ScriptedDevice name="device" record="false" path="waypoints" waypoints="0 4 13.8 17  0.4 -1 13.8 17  0.6 -1 13.8 17"/>
  <PointshellTool name="probe" radius="0.4" angleStep="15" device="@device"/>
  <GodObjectProxy name="proxy" tool="@probe" target="@skull"/>
  <ForceFeedback name="force" proxy="@proxy" stiffness="1" damping="0" maxForce="3"/>
</Node>)", d);
  ASSERT_TRUE(simulation) << test::messages(d);
  simulation->run();
  EXPECT_GT(simulation->hapticLog().stats().contactFrames, 100u);
  EXPECT_GT(simulation->hapticLog().stats().forceMax, 1.0) << "pressed 1.4 mm past the face at 1 N/mm";
  EXPECT_EQ(simulation->hapticLog().stats().proxyInsideFrames, 0u);
  EXPECT_NE(test::messages(d).find("inline.xml:4:"), std::string::npos) << test::messages(d);
  EXPECT_NE(test::messages(d).find("note: file of VoxelSkull 'skull': 1 of 6 files carry zeros"), std::string::npos)
      << test::messages(d);
  EXPECT_NE(test::messages(d).find("warning: file of VoxelSkull 'skull': uneven slice steps"), std::string::npos)
      << test::messages(d);
}

// One head written three ways by each format's own rules (pydicom for the
// DICOM series in LPS, NIfTI-1 packed from nifti1.h with its sform in RAS,
// an NRRD in right-anterior-superior: data/write_head_both_ways.py): each
// lands on the same voxels of the scene's LPS world, the dense lump on the
// patient's left and front (+x, -y). Before, the NIfTI's and the NRRD's RAS
// were taken as the world as they were: the lump on the right, at the back.
TEST(DicomReaderTest, TheSameHeadAsDicomNiftiAndNrrdLandsOnTheSameVoxels) {
  if (std::system("/usr/bin/python3 -c 'import pydicom' 2>/dev/null") != 0)
    GTEST_SKIP() << "pydicom is not installed (Debian: python3-pydicom; tools/setup installs it)";
  test::TempDir dir;
  const std::string command = "/usr/bin/python3 " +
                              (test::sourceDir() / "tests/framework/formats/data/write_head_both_ways.py").string() +
                              " " + dir.path().string();
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
  const DensityVolume dicom = formats::readVolume(dir.path() / "dicom");
  const DensityVolume nifti = formats::readVolume(dir.path() / "head.nii");
  const DensityVolume nrrd = formats::readVolume(dir.path() / "head.nrrd");
  const Vec3 first(-11.5, -9.0, 40.0), spacing(1.0, 1.25, 2.0);  // LPS, as the script writes it
  for (const DensityVolume* v : {&dicom, &nifti, &nrrd}) {
    ASSERT_EQ(v->dims(), (std::array<int32_t, 3>{24, 20, 16}));
    EXPECT_LT((v->origin() - first).norm(), 1e-5);
    EXPECT_LT((v->spacing() - spacing).norm(), 1e-6);
  }
  // Every voxel: the same density in each, the lump where the script put it.
  size_t lump = 0;
  for (int k = 0; k < 16; ++k)
    for (int j = 0; j < 20; ++j)
      for (int i = 0; i < 24; ++i) {
        const double expected = (i >= 16 && j < 6 && k >= 10) ? 1000 : 100;
        lump += expected > 500;
        for (const DensityVolume* v : {&dicom, &nifti, &nrrd})
          ASSERT_NEAR(v->density(i, j, k), expected, v->encoding().scale) << i << " " << j << " " << k;
      }
  EXPECT_EQ(lump, 8u * 6u * 6u);
  // The lump is at LPS x > 0 (left), y < 0 (front): its first voxel's centre.
  const Vec3 lumpCorner = dicom.origin() + Vec3(16, 0, 10).cwiseProduct(spacing);
  EXPECT_GT(lumpCorner.x(), 0);
  EXPECT_LT(lumpCorner.y(), 0);
}

}  // namespace
}  // namespace trephine
