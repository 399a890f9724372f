// Volume file input/output: MetaImage, NRRD and NIfTI-1 files written here (NIfTI-2 files written by nibabel)
// byte by byte from the format specifications (not by our writer), read back
// and compared voxel by voxel, plus the errors for corrupt files, the
// MetaImage writer round trip, resampling and the real CT data set.
#include <gtest/gtest.h>
#include <zlib.h>

#include <array>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstring>
#include <fstream>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "framework/formats/volume/NrrdDataFiles.h"
#include "framework/formats/volume/Resample.h"
#include "framework/formats/volume/VolumeReader.h"
#include "framework/formats/volume/VolumeWriter.h"
#include "tests/plugins/voxel_skull/ResampledVolumeCheck.h"
#include "tests/support/TestSupport.h"
#include "tests/support/ZlibStream.h"

namespace trephine::formats {
namespace {

using test::expectResampledLinear;
using test::TempDir;
using Bytes = std::vector<uint8_t>;

// ---------------------------------------------------------------------------
// Building files byte by byte.

template <typename T>
void put(Bytes& out, T value, bool bigEndian = false) {
  using Bits = std::conditional_t<
      sizeof(T) == 1, uint8_t,
      std::conditional_t<sizeof(T) == 2, uint16_t, std::conditional_t<sizeof(T) == 4, uint32_t, uint64_t>>>;
  const auto bits = std::bit_cast<Bits>(value);
  for (size_t b = 0; b < sizeof(T); ++b) {
    const size_t shift = 8 * (bigEndian ? sizeof(T) - 1 - b : b);
    out.push_back(uint8_t(bits >> shift));
  }
}

template <typename T>
void putAt(Bytes& out, size_t offset, T value, bool bigEndian) {
  Bytes encoded;
  put(encoded, value, bigEndian);
  std::copy(encoded.begin(), encoded.end(), out.begin() + static_cast<ptrdiff_t>(offset));
}

Bytes text(const std::string& s) { return Bytes(s.begin(), s.end()); }

Bytes operator+(Bytes a, const Bytes& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

std::filesystem::path writeFile(const std::filesystem::path& file, const Bytes& bytes) {
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  return file;
}

Bytes gzipped(const Bytes& data) { return test::zlibStream(test::asView(data), test::ZlibWrapper::kGzip); }

Bytes zlibCompressed(const Bytes& data) {
  uLongf size = compressBound(data.size());
  Bytes out(size);
  EXPECT_EQ(compress2(out.data(), &size, data.data(), data.size(), 6), Z_OK);
  out.resize(size);
  return out;
}

// ---------------------------------------------------------------------------
// Sample types: how each format names them and test values each can hold.

using Encoder = Bytes (*)(const std::vector<double>&, bool);

template <typename T>
Bytes encodeAs(const std::vector<double>& values, bool bigEndian) {
  Bytes out;
  for (double v : values) put<T>(out, static_cast<T>(v), bigEndian);
  return out;
}

struct TypeCase {
  const char* meta;
  const char* nrrd;
  int16_t niftiCode;
  int16_t bitpix;
  double first;  // values: first + step * n
  double step;
  Encoder encode;
};

const TypeCase kTypes[] = {
    {"MET_CHAR", "int8", 256, 8, -30, 1, encodeAs<int8_t>},
    {"MET_UCHAR", "uchar", 2, 8, 100, 2, encodeAs<uint8_t>},
    {"MET_SHORT", "short", 4, 16, -1000, 37, encodeAs<int16_t>},
    {"MET_USHORT", "ushort", 512, 16, 40000, 301, encodeAs<uint16_t>},  // above int16: shifted encoding
    {"MET_INT", "int", 8, 32, -100000, 999, encodeAs<int32_t>},
    {"MET_UINT", "uint", 768, 32, 3000000000.0, 7, encodeAs<uint32_t>},
    {"MET_FLOAT", "float", 16, 32, -1.25, 0.5, encodeAs<float>},  // not integers: linear fit
    {"MET_DOUBLE", "double", 64, 64, 1e-3, 0.125, encodeAs<double>},
};

// A 3 x 4 x 5 test grid (all axes different, so a swapped axis cannot go unnoticed).
constexpr std::array<int64_t, 3> kDims{3, 4, 5};
constexpr int kVoxels = 3 * 4 * 5;

std::vector<double> typeValues(const TypeCase& type) {
  std::vector<double> values;
  for (int n = 0; n < kVoxels; ++n) values.push_back(type.first + type.step * n);
  return values;
}

// Stored value of sample (i, j, k) for int16 tests: distinct, some negative.
double rampValue(int64_t i, int64_t j, int64_t k) { return 100.0 * k + 10.0 * j + double(i) - 7; }

std::vector<double> rampValues() {
  std::vector<double> values;
  for (int64_t k = 0; k < kDims[2]; ++k)
    for (int64_t j = 0; j < kDims[1]; ++j)
      for (int64_t i = 0; i < kDims[0]; ++i) values.push_back(rampValue(i, j, k));
  return values;
}

// rampValue at a fractional stored index (it is linear in the index).
double linearRamp(const Vec3& u) { return 100.0 * u.z() + 10.0 * u.y() + u.x() - 7; }

Bytes rampInt16(bool bigEndian = false) { return encodeAs<int16_t>(rampValues(), bigEndian); }

// ---------------------------------------------------------------------------
// Checks.

// Every stored sample (i, j, k), placed in the world at origin + axes * (i, j, k),
// must be found in `volume` at that world position with the expected density.
void expectWorldMapping(const DensityVolume& volume, const std::array<int64_t, 3>& storedDims,
                        const Eigen::Matrix3d& axes, const Vec3& storedOrigin,
                        const std::function<double(int64_t, int64_t, int64_t)>& expected, double tolerance = 0) {
  ASSERT_EQ(volume.voxelCount(), size_t(storedDims[0] * storedDims[1] * storedDims[2]));
  for (int64_t k = 0; k < storedDims[2]; ++k) {
    for (int64_t j = 0; j < storedDims[1]; ++j) {
      for (int64_t i = 0; i < storedDims[0]; ++i) {
        const Vec3 world = storedOrigin + axes * Vec3(double(i), double(j), double(k));
        const Vec3 index = (world - volume.origin()).cwiseQuotient(volume.spacing());
        const Eigen::Vector3i rounded = index.array().round().cast<int>();
        ASSERT_LT((index - rounded.cast<double>()).cwiseAbs().maxCoeff(), 1e-6)
            << "sample " << i << " " << j << " " << k;
        for (int a = 0; a < 3; ++a) ASSERT_TRUE(rounded[a] >= 0 && rounded[a] < volume.dims()[a]);
        EXPECT_NEAR(volume.density(rounded[0], rounded[1], rounded[2]), expected(i, j, k), tolerance)
            << "sample " << i << " " << j << " " << k;
      }
    }
  }
}

void expectExactEncoding(const DensityVolume& volume) {
  EXPECT_EQ(volume.encoding().scale, 1.0);
  EXPECT_EQ(volume.encoding().offset, std::floor(volume.encoding().offset));
}

// The VolumeReadError message of reading `file` (fails the test when it reads).
std::string readError(const std::filesystem::path& file) {
  try {
    formats::readVolume(file);
  } catch (const VolumeReadError& error) {
    return error.what();
  }
  ADD_FAILURE() << file << " was read without error";
  return "";
}

#define EXPECT_CONTAINS(haystack, needle) EXPECT_NE(std::string(haystack).find(needle), std::string::npos) << haystack

// ---------------------------------------------------------------------------
// MetaImage

std::string metaHeader(const std::string& elementType, const std::string& extra, const std::string& dataFile) {
  return "ObjectType = Image\nNDims = 3\nDimSize = 3 4 5\nElementSpacing = 0.5 0.75 2\nOffset = -10 20 30.5\n" + extra +
         "ElementType = " + elementType + "\nElementDataFile = " + dataFile + "\n";
}

TEST(MetaImageReader, LocalInt16MatchesTheHeader) {
  TempDir dir;
  const auto file =
      writeFile(dir / "head.mha", text(metaHeader("MET_SHORT", "BinaryData = True\n", "LOCAL")) + rampInt16());
  const DensityVolume volume = formats::readVolume(file);
  EXPECT_EQ(volume.dims(), (std::array<int32_t, 3>{3, 4, 5}));
  EXPECT_EQ(volume.spacing(), Vec3(0.5, 0.75, 2));
  EXPECT_EQ(volume.origin(), Vec3(-10, 20, 30.5));
  EXPECT_EQ(volume.encoding().scale, 1.0);
  EXPECT_EQ(volume.encoding().offset, 0.0);
  for (int k = 0; k < 5; ++k)
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 3; ++i) EXPECT_EQ(volume.density(i, j, k), rampValue(i, j, k));
}

TEST(MetaImageReader, DetachedBigEndianWithCrlfAndSynonyms) {
  TempDir dir;
  writeFile(dir / "head.raw", rampInt16(true));
  std::string header =
      "ObjectType = Image\r\nNDims = 3\r\nDimSize = 3 4 5\r\nElementSize = 1 2 3\r\nPosition = 1 2 3\r\n"
      "ElementByteOrderMSB = True\r\nElementType = MET_SHORT\r\nElementDataFile = head.raw\r\n";
  const DensityVolume volume = formats::readVolume(writeFile(dir / "head.mhd", text(header)));
  EXPECT_EQ(volume.spacing(), Vec3(1, 2, 3));  // ElementSize stands in for a missing ElementSpacing
  EXPECT_EQ(volume.origin(), Vec3(1, 2, 3));
  EXPECT_EQ(volume.density(2, 3, 4), rampValue(2, 3, 4));
  EXPECT_EQ(volume.density(1, 0, 2), rampValue(1, 0, 2));
}

TEST(MetaImageReader, EveryElementTypeInBothByteOrders) {
  TempDir dir;
  for (const TypeCase& type : kTypes) {
    for (bool big : {false, true}) {
      SCOPED_TRACE(std::string(type.meta) + (big ? " big-endian" : " little-endian"));
      const std::vector<double> values = typeValues(type);
      const std::string extra = std::string("BinaryDataByteOrderMSB = ") + (big ? "True" : "False") + "\n";
      const auto file =
          writeFile(dir / "typed.mha", text(metaHeader(type.meta, extra, "LOCAL")) + type.encode(values, big));
      const DensityVolume volume = formats::readVolume(file);
      const double tolerance = type.step == std::floor(type.step) && type.first == std::floor(type.first)
                                   ? 0
                                   : 0.5 * volume.encoding().scale + 1e-12;
      if (tolerance == 0) expectExactEncoding(volume);
      for (int n = 0; n < kVoxels; ++n)
        EXPECT_NEAR(volume.density(n % 3, (n / 3) % 4, n / 12), values[size_t(n)], tolerance) << n;
      EXPECT_NEAR(volume.minDensity(), values.front(), tolerance);
      EXPECT_NEAR(volume.maxDensity(), values.back(), tolerance);
    }
  }
}

TEST(MetaImageReader, ZlibCompressedLocalAndDetached) {
  TempDir dir;
  const Bytes packed = zlibCompressed(rampInt16());
  const std::string sized = "CompressedData = True\nCompressedDataSize = " + std::to_string(packed.size()) + "\n";
  const DensityVolume local =
      formats::readVolume(writeFile(dir / "z.mha", text(metaHeader("MET_SHORT", sized, "LOCAL")) + packed));
  EXPECT_EQ(local.density(2, 1, 3), rampValue(2, 1, 3));

  // Without CompressedDataSize the stream runs to the end of the file; gzip framing is accepted too.
  writeFile(dir / "z.zraw", gzipped(rampInt16()));
  const DensityVolume detached =
      formats::readVolume(writeFile(dir / "z.mhd", text(metaHeader("MET_SHORT", "CompressedData = True\n", "z.zraw"))));
  EXPECT_EQ(detached.density(0, 3, 4), rampValue(0, 3, 4));
}

TEST(MetaImageReader, HeaderSizeSkipsBytesAndMinusOneReadsTheEnd) {
  TempDir dir;
  writeFile(dir / "skip.raw", text("0123456789") + rampInt16());
  const DensityVolume skipped =
      formats::readVolume(writeFile(dir / "skip.mhd", text(metaHeader("MET_SHORT", "HeaderSize = 10\n", "skip.raw"))));
  EXPECT_EQ(skipped.density(1, 1, 1), rampValue(1, 1, 1));
  writeFile(dir / "end.raw", text("a header of unknown length") + rampInt16());
  const DensityVolume fromEnd =
      formats::readVolume(writeFile(dir / "end.mhd", text(metaHeader("MET_SHORT", "HeaderSize = -1\n", "end.raw"))));
  EXPECT_EQ(fromEnd.density(2, 3, 4), rampValue(2, 3, 4));
}

TEST(MetaImageReader, PermutedAndFlippedTransformMatrixIsApplied) {
  TempDir dir;
  // Axis 0 along +y, axis 1 along +x, axis 2 along -z (ITK lists the axis directions one after the other).
  const auto file =
      writeFile(dir / "turned.mha",
                text(metaHeader("MET_SHORT", "TransformMatrix = 0 1 0 1 0 0 0 0 -1\n", "LOCAL")) + rampInt16());
  const DensityVolume volume = formats::readVolume(file);
  EXPECT_EQ(volume.dims(), (std::array<int32_t, 3>{4, 3, 5}));
  EXPECT_EQ(volume.spacing(), Vec3(0.75, 0.5, 2));
  EXPECT_EQ(volume.origin(), Vec3(-10, 20, 30.5 - 4 * 2));
  Eigen::Matrix3d axes;
  axes.col(0) = Vec3(0, 0.5, 0);
  axes.col(1) = Vec3(0.75, 0, 0);
  axes.col(2) = Vec3(0, 0, -2);
  expectWorldMapping(volume, kDims, axes, Vec3(-10, 20, 30.5), rampValue);
}

TEST(MetaImageReader, NearlyAlignedAxesAreKeptObliqueAreResampled) {
  TempDir dir;
  const auto nearly = writeFile(
      dir / "nearly.mha",
      text(metaHeader("MET_SHORT", "TransformMatrix = 1 0.0004 0 -0.0004 1 0 0 0 1\n", "LOCAL")) + rampInt16());
  EXPECT_EQ(formats::readVolume(nearly).dims(), (std::array<int32_t, 3>{3, 4, 5}));
  const auto oblique =
      writeFile(dir / "oblique.mha",
                text(metaHeader("MET_SHORT", "TransformMatrix = 0.6 0.8 0 -0.8 0.6 0 0 0 1\n", "LOCAL")) +
                    rampInt16());
  const DensityVolume volume = formats::readVolume(oblique);
  Eigen::Matrix3d axes;
  axes.col(0) = Vec3(0.6, 0.8, 0) * 0.5;
  axes.col(1) = Vec3(-0.8, 0.6, 0) * 0.75;
  axes.col(2) = Vec3(0, 0, 2);
  // Axis 1 is the closer to x, axis 0 to y.
  EXPECT_LT((volume.spacing() - Vec3(0.8 * 0.75, 0.8 * 0.5, 2)).norm(), 1e-9) << volume.spacing().transpose();
  EXPECT_GT(expectResampledLinear(volume, kDims, axes, Vec3(-10, 20, 30.5), linearRamp, rampValue(0, 0, 0)), 20u);
}

TEST(MetaImageReader, UnsupportedFieldsAreNamed) {
  TempDir dir;
  EXPECT_EQ(readError(writeFile(dir / "head.mhd", text(metaHeader("MET_LONG_LONG", "", "LOCAL")))),
            (dir / "head.mhd").string() +
                ": ElementType 'MET_LONG_LONG' is not supported (expected MET_CHAR, MET_UCHAR, MET_SHORT, MET_USHORT, "
                "MET_INT, MET_UINT, MET_FLOAT or MET_DOUBLE)");
  EXPECT_CONTAINS(readError(writeFile(dir / "flat.mha", text("ObjectType = Image\nNDims = 2\nDimSize = 3 4\n"
                                                             "ElementType = MET_SHORT\nElementDataFile = LOCAL\n"))),
                  "NDims 2 is not supported (expected 3");
  EXPECT_CONTAINS(
      readError(writeFile(dir / "rgb.mha",
                          text(metaHeader("MET_UCHAR", "ElementNumberOfChannels = 3\n", "LOCAL")) + Bytes(180))),
      "ElementNumberOfChannels 3 is not supported");
  EXPECT_CONTAINS(readError(writeFile(dir / "list.mhd", text(metaHeader("MET_SHORT", "", "LIST")))),
                  "ElementDataFile = LIST");
  EXPECT_CONTAINS(readError(writeFile(dir / "noend.mhd", text("ObjectType = Image\nNDims = 3\n"))),
                  "no ElementDataFile line");
  EXPECT_CONTAINS(
      readError(writeFile(dir / "spacing.mha",
                          text(metaHeader("MET_SHORT", "ElementSpacing = 1 x 1\n", "LOCAL")) + rampInt16())),
      "ElementSpacing '1 x 1' is not 3 numbers");
  EXPECT_CONTAINS(readError(writeFile(dir / "missing.mhd", text(metaHeader("MET_SHORT", "", "absent.raw")))),
                  "absent.raw: cannot open");
  EXPECT_CONTAINS(readError(writeFile(dir / "control.mhd", text(metaHeader("MET_SHORT", "", std::string("a\0b", 3))))),
                  "ElementDataFile 'a\\x00b' is not a file name");
}

TEST(MetaImageReader, TruncatedDataNamesTheDataFile) {
  TempDir dir;
  writeFile(dir / "short.raw", Bytes(100));
  EXPECT_EQ(readError(writeFile(dir / "short.mhd", text(metaHeader("MET_SHORT", "", "short.raw")))),
            (dir / "short.raw").string() + ": truncated: expected 120 bytes of data, found 100");
  const Bytes packed = zlibCompressed(rampInt16());
  const Bytes cut(packed.begin(), packed.begin() + 40);
  EXPECT_CONTAINS(
      readError(writeFile(dir / "cut.mha", text(metaHeader("MET_SHORT", "CompressedData = True\n", "LOCAL")) + cut)),
      "truncated: expected 120 bytes of data, found");
  Bytes corrupt = packed;
  corrupt[5] ^= 0xff;
  corrupt[6] ^= 0xff;
  EXPECT_CONTAINS(readError(writeFile(dir / "bad.mha",
                                      text(metaHeader("MET_SHORT", "CompressedData = True\n", "LOCAL")) + corrupt)),
                  "bad.mha:");
}

TEST(MetaImageReader, AbsurdDimensionsAreRefusedBeforeAllocating) {
  TempDir dir;
  const std::string huge =
      "ObjectType = Image\nNDims = 3\nDimSize = 100000 100000 100000\nElementType = MET_SHORT\nElementDataFile = "
      "LOCAL\n";
  const auto start = std::chrono::steady_clock::now();
  EXPECT_CONTAINS(readError(writeFile(dir / "huge.mha", text(huge) + Bytes(200))), "voxels supported");
  // Within the voxel cap but far beyond the file: a size check, not a 2 GB allocation.
  const std::string large =
      "ObjectType = Image\nNDims = 3\nDimSize = 1000 1000 1000\nElementType = MET_SHORT\nElementDataFile = LOCAL\n";
  EXPECT_CONTAINS(readError(writeFile(dir / "large.mha", text(large) + Bytes(200))),
                  "truncated: expected 2000000000 bytes of data, found 200");
  // A compressed stream of a few bytes cannot hold 2 GB: refused without inflating.
  EXPECT_CONTAINS(readError(writeFile(dir / "bomb.mha", text("ObjectType = Image\nNDims = 3\nDimSize = 1000 1000 1000\n"
                                                             "CompressedData = True\nElementType = MET_SHORT\n"
                                                             "ElementDataFile = LOCAL\n") +
                                                            zlibCompressed(Bytes(1000)))),
                  "cannot hold the expected 2000000000 bytes");
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(2));
  EXPECT_CONTAINS(readError(writeFile(dir / "zero.mha", text("NDims = 3\nDimSize = 0 4 5\nElementType = MET_SHORT\n"
                                                             "ElementDataFile = LOCAL\n"))),
                  "DimSize 0 4 5 must be positive");
}

TEST(MetaImageReader, NanIsAnErrorNamingTheVoxel) {
  TempDir dir;
  std::vector<double> values(kVoxels, 1.5);
  values[size_t(1 + 3 * (2 + 4 * 3))] = std::numeric_limits<double>::quiet_NaN();
  const auto file =
      writeFile(dir / "nan.mha", text(metaHeader("MET_FLOAT", "", "LOCAL")) + encodeAs<float>(values, false));
  EXPECT_CONTAINS(readError(file), "voxel (1, 2, 3)");
  values[size_t(1 + 3 * (2 + 4 * 3))] = std::numeric_limits<double>::infinity();
  writeFile(file, text(metaHeader("MET_DOUBLE", "", "LOCAL")) + encodeAs<double>(values, false));
  EXPECT_CONTAINS(readError(file), "is NaN or infinite");
}

TEST(MetaImageReader, FloatRangeIsSpreadOverTheCodes) {
  TempDir dir;
  std::vector<double> values;
  for (int n = 0; n < kVoxels; ++n) values.push_back(0.001 * n * n - 0.5);
  const DensityVolume volume = formats::readVolume(
      writeFile(dir / "f.mha", text(metaHeader("MET_DOUBLE", "", "LOCAL")) + encodeAs<double>(values, false)));
  EXPECT_NEAR(volume.encoding().scale, (values.back() - values.front()) / 65535.0, 1e-15);
  for (int n = 0; n < kVoxels; ++n)
    EXPECT_NEAR(volume.density(n % 3, (n / 3) % 4, n / 12), values[size_t(n)], 0.5 * volume.encoding().scale + 1e-12);
}

TEST(MetaImageReader, SubnormalDensityRangesEncodeWithoutNaN) {
  // Densities that differ by subnormal amounts: range / 65535 underflows, and
  // a scale with no finite reciprocal turned every code into NaN (found by
  // fuzzing). The scale is now at least the smallest normal double: finer
  // differences are lost (the volume reads as nearly constant), coarser ones kept.
  TempDir dir;
  for (const double largest : {5e-324, 1e-312, std::numeric_limits<double>::min(), 1e-300}) {
    std::vector<double> values(kVoxels, 0.0);
    values[5] = largest;   // voxel (2, 1, 0)
    values[7] = -largest;  // voxel (1, 2, 0)
    const DensityVolume volume = formats::readVolume(
        writeFile(dir / "tiny.mha", text(metaHeader("MET_DOUBLE", "", "LOCAL")) + encodeAs<double>(values, false)));
    const double scale = volume.encoding().scale;
    ASSERT_TRUE(scale > 0 && std::isfinite(1.0 / scale)) << largest;
    for (int n = 0; n < kVoxels; ++n)
      EXPECT_NEAR(volume.density(n % 3, (n / 3) % 4, n / 12), values[size_t(n)], scale) << largest << " voxel " << n;
    if (largest >= std::numeric_limits<double>::min()) {
      EXPECT_GT(volume.density(2, 1, 0), volume.density(0, 0, 0)) << largest;
      EXPECT_LT(volume.density(1, 2, 0), volume.density(0, 0, 0)) << largest;
    }
  }
}

// ---------------------------------------------------------------------------
// NRRD

std::string nrrdHeader(const std::string& type, const std::string& extra) {
  return "NRRD0004\n# a comment\ntype: " + type + "\ndimension: 3\nsizes: 3 4 5\n" + extra;
}

TEST(NrrdReader, AttachedRawWithSpacingsCommentsAndKeyValues) {
  TempDir dir;
  const std::string header = nrrdHeader("short",
                                        "endian: little\nencoding: raw\nspacings: 0.5 0.75 2\n"
                                        "creator:=somebody\ncontent: test volume\n# more\n\n");
  const DensityVolume volume = formats::readVolume(writeFile(dir / "a.nrrd", text(header) + rampInt16()));
  EXPECT_EQ(volume.dims(), (std::array<int32_t, 3>{3, 4, 5}));
  EXPECT_EQ(volume.spacing(), Vec3(0.5, 0.75, 2));
  EXPECT_EQ(volume.origin(), Vec3::Zero());
  expectWorldMapping(volume, kDims, Vec3(0.5, 0.75, 2).asDiagonal(), Vec3::Zero(), rampValue);
}

TEST(NrrdReader, GzipBigEndianWithFlippedPermutedSpaceDirections) {
  TempDir dir;
  // Axis 0 along -x, axis 1 along +z, axis 2 along -y: a typical LPS-style flip and swap.
  const std::string header =
      nrrdHeader("short",
                 "endian: big\nencoding: gzip\nspace: left-posterior-superior\n"
                 "space directions: (-0.5,0,0) (0,0,0.75) (0,-2,0)\nspace origin: (10, 20, 30)\n\n");
  const DensityVolume volume = formats::readVolume(writeFile(dir / "g.nrrd", text(header) + gzipped(rampInt16(true))));
  EXPECT_EQ(volume.dims(), (std::array<int32_t, 3>{3, 5, 4}));
  EXPECT_EQ(volume.spacing(), Vec3(0.5, 2, 0.75));
  EXPECT_EQ(volume.origin(), Vec3(10 - 2 * 0.5, 20 - 4 * 2, 30));
  Eigen::Matrix3d axes;
  axes.col(0) = Vec3(-0.5, 0, 0);
  axes.col(1) = Vec3(0, 0, 0.75);
  axes.col(2) = Vec3(0, -2, 0);
  expectWorldMapping(volume, kDims, axes, Vec3(10, 20, 30), rampValue);
}

TEST(NrrdReader, EveryTypeSpelling) {
  TempDir dir;
  const std::pair<const char*, int> spellings[] = {{"signed char", 0},
                                                   {"int8", 0},
                                                   {"int8_t", 0},
                                                   {"uchar", 1},
                                                   {"unsigned char", 1},
                                                   {"uint8", 1},
                                                   {"uint8_t", 1},
                                                   {"short", 2},
                                                   {"short int", 2},
                                                   {"signed short", 2},
                                                   {"signed short int", 2},
                                                   {"int16", 2},
                                                   {"int16_t", 2},
                                                   {"ushort", 3},
                                                   {"unsigned short", 3},
                                                   {"unsigned short int", 3},
                                                   {"uint16", 3},
                                                   {"uint16_t", 3},
                                                   {"int", 4},
                                                   {"signed int", 4},
                                                   {"int32", 4},
                                                   {"int32_t", 4},
                                                   {"uint", 5},
                                                   {"unsigned int", 5},
                                                   {"uint32", 5},
                                                   {"uint32_t", 5},
                                                   {"float", 6},
                                                   {"double", 7}};
  for (const auto& [spelling, index] : spellings) {
    for (bool big : {false, true}) {
      SCOPED_TRACE(std::string(spelling) + (big ? " big" : " little"));
      const TypeCase& type = kTypes[index];
      const std::vector<double> values = typeValues(type);
      const std::string header =
          nrrdHeader(spelling, std::string("endian: ") + (big ? "big" : "little") + "\nencoding: raw\n\n");
      const DensityVolume volume = formats::readVolume(writeFile(dir / "t.nrrd", text(header) + type.encode(values, big)));
      const double tolerance = index >= 6 ? 0.5 * volume.encoding().scale + 1e-12 : 0;
      for (int n = 0; n < kVoxels; ++n)
        ASSERT_NEAR(volume.density(n % 3, (n / 3) % 4, n / 12), values[size_t(n)], tolerance) << n;
    }
  }
}

TEST(NrrdReader, DetachedWithLineSkipAndByteSkip) {
  TempDir dir;
  writeFile(dir / "data.pgm", text("P5\n# preamble\n3 20\n") + text("xy") + rampInt16());
  const DensityVolume volume = formats::readVolume(writeFile(
      dir / "d.nhdr",
      text(nrrdHeader("int16", "endian: little\nencoding: raw\ndata file: ./data.pgm\nline skip: 3\nbyte skip: 2\n"))));
  EXPECT_EQ(volume.density(2, 3, 4), rampValue(2, 3, 4));
  // byte skip -1: the samples are the last bytes of the file.
  writeFile(dir / "tail.raw", text("junk of any length\n") + rampInt16());
  const DensityVolume tail = formats::readVolume(
      writeFile(dir / "tail.nhdr",
                text(nrrdHeader("short", "endian: little\nencoding: raw\ndatafile: tail.raw\nbyte skip: -1\n"))));
  EXPECT_EQ(tail.density(0, 1, 2), rampValue(0, 1, 2));
  // With gzip the byte skip applies to the decompressed bytes.
  writeFile(dir / "skip.raw.gz", gzipped(text("12345") + rampInt16()));
  const DensityVolume gz = formats::readVolume(
      writeFile(dir / "skip.nhdr",
                text(nrrdHeader("short", "endian: little\nencoding: gz\ndata file: skip.raw.gz\nbyte skip: 5\n"))));
  EXPECT_EQ(gz.density(1, 2, 3), rampValue(1, 2, 3));
}

// One file per slice k of the ramp volume.
void writeSlices(const TempDir& dir, const std::function<std::string(int)>& name, bool gzip = false) {
  const Bytes all = rampInt16();
  const size_t sliceBytes = all.size() / 5;
  for (int k = 0; k < 5; ++k) {
    const Bytes slice(all.begin() + static_cast<ptrdiff_t>(k * sliceBytes),
                      all.begin() + static_cast<ptrdiff_t>((k + 1) * sliceBytes));
    writeFile(dir / name(k), gzip ? gzipped(slice) : slice);
  }
}

TEST(NrrdReader, NumberedSeriesAndListOfDataFiles) {
  TempDir dir;
  writeSlices(dir,
              [](int k) { return "slice" + std::string(k + 1 < 10 ? "00" : "0") + std::to_string(k + 1) + ".raw"; });
  const DensityVolume series = formats::readVolume(
      writeFile(dir / "series.nhdr",
                text(nrrdHeader("short", "endian: little\nencoding: raw\ndata file: slice%03d.raw 1 5 1 2\n"))));
  expectWorldMapping(series, kDims, Eigen::Matrix3d::Identity(), Vec3::Zero(), rampValue);

  // A descending series: file 5 holds slice 0.
  writeSlices(dir, [](int k) { return "down." + std::to_string(5 - k); });
  const DensityVolume down = formats::readVolume(writeFile(
      dir / "down.nhdr", text(nrrdHeader("short", "endian: little\nencoding: raw\ndata file: down.%d 5 1 -1\n"))));
  EXPECT_EQ(down.density(2, 3, 4), rampValue(2, 3, 4));

  writeSlices(
      dir, [](int k) { return "part" + std::to_string(k) + ".gz"; }, true);
  const DensityVolume list =
      formats::readVolume(writeFile(dir / "list.nhdr", text(nrrdHeader("short",
                                                              "endian: little\nencoding: gzip\ndata file: LIST\n"
                                                              "part0.gz\npart1.gz\npart2.gz\npart3.gz\npart4.gz\n"))));
  expectWorldMapping(list, kDims, Eigen::Matrix3d::Identity(), Vec3::Zero(), rampValue);

  EXPECT_CONTAINS(readError(writeFile(dir / "few.nhdr", text(nrrdHeader("short",
                                                                        "endian: little\nencoding: raw\n"
                                                                        "data file: slice%03d.raw 1 4 1\n")))),
                  "data file names 4 files");
  EXPECT_CONTAINS(readError(writeFile(dir / "many.nhdr", text(nrrdHeader("short",
                                                                         "endian: little\nencoding: raw\n"
                                                                         "data file: s%d.raw 1 2000000000000 1\n")))),
                  "more than the 60 the sizes allow");
  writeFile(dir / "slice003.raw", Bytes(10));
  EXPECT_EQ(readError(dir / "series.nhdr"),
            (dir / "slice003.raw").string() + ": truncated: expected 24 bytes of data, found 10");
}

TEST(NrrdReader, SeriesNamesFollowPrintfWithoutCallingIt) {
  EXPECT_EQ(formats::formatSeriesName("quarter.%d", 17), "quarter.17");
  EXPECT_EQ(formats::formatSeriesName("s%03d.raw", 7), "s007.raw");
  EXPECT_EQ(formats::formatSeriesName("s%-4d|", 7), "s7   |");
  EXPECT_EQ(formats::formatSeriesName("s%+d", 7), "s+7");
  EXPECT_EQ(formats::formatSeriesName("s%4i", -7), "s  -7");
  EXPECT_EQ(formats::formatSeriesName("100%%_%u", 3), "100%_3");
  EXPECT_FALSE(formats::formatSeriesName("%s", 1));
  EXPECT_FALSE(formats::formatSeriesName("%d%d", 1));
  EXPECT_FALSE(formats::formatSeriesName("plain", 1));
  EXPECT_FALSE(formats::formatSeriesName("%n", 1));
  EXPECT_FALSE(formats::formatSeriesName("%999999d", 1));
}

TEST(NrrdReader, ErrorsNameTheField) {
  TempDir dir;
  EXPECT_CONTAINS(readError(writeFile(dir / "flat.nrrd", text("NRRD0004\ntype: short\ndimension: 2\nsizes: 3 4\n"
                                                              "endian: little\nencoding: raw\n\n") +
                                                             Bytes(24))),
                  "flat.nrrd: dimension 2 is not supported (expected 3");
  EXPECT_CONTAINS(readError(writeFile(dir / "text.nrrd", text(nrrdHeader("short", "encoding: ascii\n\n1 2 3")))),
                  "encoding 'ascii' is not supported (expected raw or gzip)");
  EXPECT_CONTAINS(
      readError(writeFile(dir / "endian.nrrd", text(nrrdHeader("short", "encoding: raw\n\n")) + rampInt16())),
      "no 'endian:' field");
  EXPECT_CONTAINS(
      readError(writeFile(dir / "long.nrrd", text(nrrdHeader("long long", "endian: little\nencoding: raw\n\n")))),
      "type 'long long' is not supported");
  EXPECT_CONTAINS(readError(writeFile(dir / "v9.nrrd", text("NRRD0009\ntype: short\n"))),
                  "NRRD version 'NRRD0009' is not supported");
  EXPECT_CONTAINS(readError(writeFile(dir / "other.nrrd", text("P5\n3 4\n255\n"))), "other.nrrd: not a NRRD file");
  EXPECT_CONTAINS(readError(writeFile(dir / "twice.nrrd", text(nrrdHeader("short", "sizes: 3 4 5\n")))),
                  "field 'sizes' is given twice");
  EXPECT_CONTAINS(
      readError(writeFile(dir / "nodata.nhdr", text(nrrdHeader("short", "endian: little\nencoding: raw\n")))),
      "no data");
  EXPECT_CONTAINS(readError(writeFile(dir / "time.nrrd", text(nrrdHeader("short",
                                                                         "endian: little\nencoding: raw\n"
                                                                         "space: RAST\n\n")))),
                  "space 'RAST' is not supported");
  EXPECT_CONTAINS(
      readError(writeFile(dir / "none.nrrd", text(nrrdHeader("short",
                                                             "endian: little\nencoding: raw\n"
                                                             "space directions: none (1,0,0) (0,1,0)\n\n")))),
      "'none' for an axis");
  const Bytes packed = gzipped(rampInt16());
  EXPECT_CONTAINS(
      readError(writeFile(dir / "cut.nrrd", text(nrrdHeader("short", "endian: little\nencoding: gzip\n\n")) +
                                                Bytes(packed.begin(), packed.begin() + 30))),
      "cut.nrrd: truncated: expected 120 bytes of data, found");
  // An oblique frame is resampled.
  const std::string oblique = nrrdHeader("short",
                                         "endian: little\nencoding: raw\nspace: left-posterior-superior\n"
                                         "space directions: (0.5,0.5,0) (-0.5,0.5,0) (0,0,1)\n\n");
  const DensityVolume resampled = formats::readVolume(writeFile(dir / "oblique.nrrd", text(oblique) + rampInt16()));
  Eigen::Matrix3d axes;
  axes << 0.5, -0.5, 0, 0.5, 0.5, 0, 0, 0, 1;
  EXPECT_GT(expectResampledLinear(resampled, kDims, axes, Vec3::Zero(), linearRamp, rampValue(0, 0, 0)), 20u);
}

TEST(NrrdReader, AxisMinsGiveTheOriginWithoutSpace) {
  TempDir dir;
  const DensityVolume volume =
      formats::readVolume(writeFile(dir / "mins.nrrd", text(nrrdHeader("short",
                                                              "endian: little\nencoding: raw\nspacings: 1 2 4\n"
                                                              "axis mins: 10 20 30\ncenters: cell node cell\n\n")) +
                                                  rampInt16()));
  EXPECT_EQ(volume.origin(), Vec3(10.5, 20, 32));
}

// ---------------------------------------------------------------------------
// NIfTI-1 (headers written here, at nifti1.h's offsets)

struct NiftiFields {
  std::array<int16_t, 8> dim{3, 3, 4, 5, 1, 1, 1, 1};
  int16_t datatype = 4;
  int16_t bitpix = 16;
  std::array<float, 8> pixdim{1, 0.5f, 0.75f, 2, 0, 0, 0, 0};
  float voxOffset = 352;
  float slope = 0;
  float intercept = 0;
  uint8_t units = 2;  // mm
  int16_t qformCode = 0;
  int16_t sformCode = 0;
  std::array<float, 6> quatern{};  // b, c, d, qoffset x, y, z
  std::array<float, 12> srow{};
  std::string magic{"n+1\0", 4};
  int32_t sizeofHdr = 348;
};

// A single-file NIfTI-1: the 348-byte header (nifti1.h offsets), 4 extension bytes, the samples.
Bytes niftiFile(const NiftiFields& f, bool big, const Bytes& samples) {
  Bytes out(352, 0);
  putAt(out, 0, f.sizeofHdr, big);
  for (int n = 0; n < 8; ++n) putAt(out, 40 + 2 * n, f.dim[n], big);
  putAt(out, 70, f.datatype, big);
  putAt(out, 72, f.bitpix, big);
  for (int n = 0; n < 8; ++n) putAt(out, 76 + 4 * n, f.pixdim[n], big);
  putAt(out, 108, f.voxOffset, big);
  putAt(out, 112, f.slope, big);
  putAt(out, 116, f.intercept, big);
  out[123] = f.units;
  putAt(out, 252, f.qformCode, big);
  putAt(out, 254, f.sformCode, big);
  for (int n = 0; n < 6; ++n) putAt(out, 256 + 4 * n, f.quatern[n], big);
  for (int n = 0; n < 12; ++n) putAt(out, 280 + 4 * n, f.srow[n], big);
  std::copy(f.magic.begin(), f.magic.end(), out.begin() + 344);
  return out + samples;
}

TEST(NiftiReader, Int16WithoutOrientationInBothByteOrders) {
  TempDir dir;
  for (bool big : {false, true}) {
    const DensityVolume volume = formats::readVolume(writeFile(dir / "plain.nii", niftiFile({}, big, rampInt16(big))));
    EXPECT_EQ(volume.dims(), (std::array<int32_t, 3>{3, 4, 5}));
    EXPECT_EQ(volume.spacing(), Vec3(0.5, 0.75, 2));
    EXPECT_EQ(volume.origin(), Vec3::Zero());
    expectExactEncoding(volume);
    expectWorldMapping(volume, kDims, Vec3(0.5, 0.75, 2).asDiagonal(), Vec3::Zero(), rampValue);
  }
}

TEST(NiftiReader, EveryDatatypeInBothByteOrders) {
  TempDir dir;
  for (const TypeCase& type : kTypes) {
    for (bool big : {false, true}) {
      SCOPED_TRACE(std::string(type.meta) + (big ? " big" : " little"));
      NiftiFields fields;
      fields.datatype = type.niftiCode;
      fields.bitpix = type.bitpix;
      const std::vector<double> values = typeValues(type);
      const DensityVolume volume =
          formats::readVolume(writeFile(dir / "typed.nii", niftiFile(fields, big, type.encode(values, big))));
      const bool integral = type.step == std::floor(type.step) && type.first == std::floor(type.first);
      const double tolerance = integral ? 0 : 0.5 * volume.encoding().scale + 1e-12;
      for (int n = 0; n < kVoxels; ++n)
        ASSERT_NEAR(volume.density(n % 3, (n / 3) % 4, n / 12), values[size_t(n)], tolerance) << n;
    }
  }
}

TEST(NiftiReader, SlopeAndInterceptAreApplied) {
  TempDir dir;
  NiftiFields fields;
  fields.slope = 2;
  fields.intercept = -1024;
  const DensityVolume volume = formats::readVolume(writeFile(dir / "scaled.nii", niftiFile(fields, true, rampInt16(true))));
  expectExactEncoding(volume);  // 2 s - 1024 is still an integer
  EXPECT_EQ(volume.density(2, 3, 4), 2 * rampValue(2, 3, 4) - 1024);
  fields.slope = 0.25f;
  fields.intercept = 0.1f;
  const DensityVolume fractional = formats::readVolume(writeFile(dir / "scaled.nii", niftiFile(fields, false, rampInt16())));
  const double tolerance = 0.5 * fractional.encoding().scale + 1e-9;
  EXPECT_NEAR(fractional.density(1, 2, 3), 0.25 * rampValue(1, 2, 3) + double(0.1f), tolerance);
}

// The ramp under the sform of both sform tests: stored axis 0 along -y at
// 0.5 mm, axis 1 along +z at 0.75 mm, axis 2 along +x at 2 mm, origin
// (10, 20, -30) mm.
// NIfTI's qform and sform are RAS; the scene's world is LPS (x and y negated).
const Eigen::Matrix3d kRasToLps = Vec3(-1, -1, 1).asDiagonal();

void expectPermutedSform(const DensityVolume& volume) {
  EXPECT_EQ(volume.dims(), (std::array<int32_t, 3>{5, 3, 4}));
  EXPECT_EQ(volume.spacing(), Vec3(2, 0.5, 0.75));
  Eigen::Matrix3d axes;  // RAS, as the sform says
  axes.col(0) = Vec3(0, -0.5, 0);
  axes.col(1) = Vec3(0, 0, 0.75);
  axes.col(2) = Vec3(2, 0, 0);
  expectWorldMapping(volume, kDims, kRasToLps * axes, kRasToLps * Vec3(10, 20, -30), rampValue);
}

TEST(NiftiReader, SformPermutationAndFlipIsApplied) {
  TempDir dir;
  NiftiFields fields;
  fields.sformCode = 1;
  fields.qformCode = 1;  // ignored: the sform wins
  fields.quatern = {0.3f, 0.3f, 0.3f, 7, 7, 7};
  // Axis 0 along -y, axis 1 along +z, axis 2 along +x (RAS millimetres).
  fields.srow = {0,     0, 2, 10,  //
                 -0.5f, 0, 0, 20, 0, 0.75f, 0, -30};
  const DensityVolume volume = formats::readVolume(writeFile(dir / "sform.nii", niftiFile(fields, false, rampInt16())));
  expectPermutedSform(volume);
}

TEST(NiftiReader, QformRotationAndQfacAreApplied) {
  TempDir dir;
  NiftiFields fields;
  fields.qformCode = 1;
  fields.quatern = {0, 0, 1, 5, 6, 7};  // 180 degrees about z: x and y flipped
  fields.pixdim[0] = -1;                // qfac -1: z flipped too
  const DensityVolume volume = formats::readVolume(writeFile(dir / "qform.nii", niftiFile(fields, true, rampInt16(true))));
  EXPECT_EQ(volume.dims(), (std::array<int32_t, 3>{3, 4, 5}));
  // In LPS: x and y of the RAS mapping negated, so the lowest corner is the qform's offset there.
  EXPECT_EQ(volume.origin(), Vec3(-5, -6, 7 - 4 * 2));
  expectWorldMapping(volume, kDims, kRasToLps * Vec3(-0.5, -0.75, -2).asDiagonal(), kRasToLps * Vec3(5, 6, 7),
                     rampValue);
  fields.quatern = {0, 0, 0.3826834f, 0, 0, 0};  // 45 degrees about z: resampled
  const DensityVolume oblique = formats::readVolume(writeFile(dir / "qform.nii", niftiFile(fields, false, rampInt16())));
  const double c = std::sqrt(0.5);
  Eigen::Matrix3d rotation;
  rotation << c, -c, 0, c, c, 0, 0, 0, 1;
  const Eigen::Matrix3d axes = kRasToLps * rotation * Vec3(0.5, 0.75, -2).asDiagonal();  // qfac -1 flips z
  EXPECT_GT(expectResampledLinear(oblique, kDims, axes, Vec3::Zero(), linearRamp, rampValue(0, 0, 0)), 20u);
}

TEST(NiftiReader, GzippedAndMetres) {
  TempDir dir;
  NiftiFields fields;
  fields.units = 1;  // metres
  fields.pixdim = {1, 0.0005f, 0.00075f, 0.002f, 0, 0, 0, 0};
  const DensityVolume volume =
      formats::readVolume(writeFile(dir / "head.nii.gz", gzipped(niftiFile(fields, false, rampInt16()))));
  EXPECT_NEAR(volume.spacing().x(), 0.5, 1e-6);
  EXPECT_NEAR(volume.spacing().z(), 2, 1e-6);
  EXPECT_EQ(volume.density(2, 1, 4), rampValue(2, 1, 4));
}

TEST(NiftiReader, ErrorsNameTheField) {
  TempDir dir;
  NiftiFields fields;
  fields.voxOffset = 4000;
  EXPECT_CONTAINS(readError(writeFile(dir / "offset.nii", niftiFile(fields, false, rampInt16()))), "vox_offset 4000");
  fields = {};
  fields.datatype = 1024;
  EXPECT_CONTAINS(readError(writeFile(dir / "int64.nii", niftiFile(fields, false, Bytes(480)))),
                  "datatype 1024 (int64) is not supported");
  fields = {};
  fields.dim = {2, 3, 4, 1, 1, 1, 1, 1};
  EXPECT_CONTAINS(readError(writeFile(dir / "flat.nii", niftiFile(fields, false, Bytes(24)))),
                  "2D images are not supported");
  fields = {};
  fields.dim = {4, 3, 4, 5, 2, 1, 1, 1};
  EXPECT_CONTAINS(readError(writeFile(dir / "time.nii", niftiFile(fields, true, Bytes(240)))),
                  "dim[4] 2 is not supported");
  fields = {};
  fields.magic = std::string("ni1\0", 4);
  EXPECT_CONTAINS(readError(writeFile(dir / "pair.hdr", niftiFile(fields, false, rampInt16()))),
                  "a .hdr/.img pair (magic 'ni1' or 'ni2') whose image file " + (dir / "pair.img").string() +
                      " is missing");
  fields = {};
  fields.sizeofHdr = 540;
  EXPECT_CONTAINS(readError(writeFile(dir / "two.nii", niftiFile(fields, false, rampInt16()))), "NIfTI-2");
  fields = {};
  fields.pixdim[2] = 0;
  EXPECT_CONTAINS(readError(writeFile(dir / "pix.nii", niftiFile(fields, false, rampInt16()))), "pixdim[2] 0");
  fields = {};
  fields.dim = {3, 32767, 32767, 32767, 1, 1, 1, 1};
  EXPECT_CONTAINS(readError(writeFile(dir / "huge.nii", niftiFile(fields, false, {}))), "voxels supported");
  fields.dim = {3, 1000, 1000, 1000, 1, 1, 1, 1};
  EXPECT_EQ(readError(writeFile(dir / "large.nii", niftiFile(fields, false, Bytes(48)))),
            (dir / "large.nii").string() + ": truncated: expected 2000000000 bytes of data, found 48");
  EXPECT_CONTAINS(readError(writeFile(dir / "stub.nii", niftiFile({}, false, {}))), "truncated: expected 120 bytes");
  EXPECT_CONTAINS(readError(writeFile(dir / "tiny.nii", Bytes(100, 7))), "tiny.nii: truncated: expected a 348-byte");
  EXPECT_CONTAINS(readError(writeFile(dir / "junk.nii", Bytes(400, 7))), "sizeof_hdr is");
}

// ---------------------------------------------------------------------------
// NIfTI-2: files written by nibabel (tests/plugins/voxel_skull/data/make_nifti2.py),
// a writer independent of the reader, holding the ramp above.

Bytes nifti2File(const std::string& name) {
  const std::string bytes = test::readFile(test::sourceDir() / "tests/plugins/voxel_skull/data" / name);
  return Bytes(bytes.begin(), bytes.end());
}

TEST(NiftiReader, Nifti2SformLittleEndian) {
  TempDir dir;
  const DensityVolume volume = formats::readVolume(writeFile(dir / "sform2.nii", nifti2File("ramp_sform_le.nii")));
  expectExactEncoding(volume);
  expectPermutedSform(volume);
}

// Big endian, float32 samples scaled by the double scl_slope and scl_inter,
// a qform with qfac -1, lengths in metres.
TEST(NiftiReader, Nifti2QformBigEndianScaledInMetres) {
  TempDir dir;
  const DensityVolume volume = formats::readVolume(writeFile(dir / "qform2.nii", nifti2File("ramp_qform_be.nii")));
  EXPECT_EQ(volume.dims(), (std::array<int32_t, 3>{3, 4, 5}));
  EXPECT_LT((volume.spacing() - Vec3(0.5, 0.75, 2)).norm(), 1e-9);
  EXPECT_LT((volume.origin() - Vec3(-5, -6, 7 - 4 * 2)).norm(), 1e-9);
  expectWorldMapping(volume, kDims, kRasToLps * Vec3(-0.5, -0.75, -2).asDiagonal(), kRasToLps * Vec3(5, 6, 7),
                     rampValue);
  // The same file gzipped.
  const DensityVolume gzip = formats::readVolume(writeFile(dir / "qform2.nii.gz", gzipped(nifti2File("ramp_qform_be.nii"))));
  EXPECT_EQ(gzip.density(2, 3, 4), volume.density(2, 3, 4));
}

// .hdr/.img pairs: the header (magic "ni1" or "ni2") and the samples at
// vox_offset in NAME.img, raw or gzipped, beside it.
TEST(NiftiReader, HeaderAndImagePairsOfBothVersions) {
  TempDir dir;
  NiftiFields fields;
  fields.magic = std::string("ni1\0", 4);
  fields.voxOffset = 0;
  const Bytes header1 = niftiFile(fields, true, {});
  writeFile(dir / "head.hdr", header1);
  writeFile(dir / "head.img", rampInt16(true));
  const DensityVolume one = formats::readVolume(dir / "head.hdr");
  expectWorldMapping(one, kDims, Vec3(0.5, 0.75, 2).asDiagonal(), Vec3::Zero(), rampValue);
  // The samples gzipped, after 16 bytes the header skips.
  fields.voxOffset = 16;
  writeFile(dir / "gz.hdr", niftiFile(fields, false, {}));
  writeFile(dir / "gz.img.gz", gzipped(Bytes(16, 9) + rampInt16()));
  expectWorldMapping(formats::readVolume(dir / "gz.hdr"), kDims, Vec3(0.5, 0.75, 2).asDiagonal(), Vec3::Zero(), rampValue);
  // NIfTI-2: nibabel's single file cut in two.
  Bytes two = nifti2File("ramp_sform_le.nii");
  Bytes header2(two.begin(), two.begin() + 544);
  header2[5] = 'i';                      // "ni2"
  putAt(header2, 168, int64_t(0), false);  // vox_offset
  writeFile(dir / "two.hdr", header2);
  writeFile(dir / "two.img", Bytes(two.begin() + 544, two.end()));
  const DensityVolume pair2 = formats::readVolume(dir / "two.hdr");
  const DensityVolume single2 = formats::readVolume(writeFile(dir / "two.nii", two));
  ASSERT_EQ(pair2.dims(), single2.dims());
  EXPECT_EQ(pair2.origin(), single2.origin());
  for (int n = 0; n < kVoxels; ++n) {
    const int i = n % 5, j = (n / 5) % 3, k = n / 15;
    ASSERT_EQ(pair2.density(i, j, k), single2.density(i, j, k)) << n;
  }
  // An image file too short for the header's grid names the image file.
  writeFile(dir / "short.hdr", header1);
  writeFile(dir / "short.img", Bytes(10));
  EXPECT_CONTAINS(readError(dir / "short.hdr"), "short.img: truncated: expected 120 bytes of data, found 10");
}

TEST(NiftiReader, Nifti2ErrorsNameTheField) {
  TempDir dir;
  const Bytes good = nifti2File("ramp_sform_le.nii");  // little endian
  auto patched = [&](size_t offset, auto value) {
    Bytes bytes = good;
    putAt(bytes, offset, value, false);
    return bytes;
  };
  // A magic whose last four bytes a text-mode transfer altered.
  Bytes mangled = good;
  mangled[8] = '\n';
  mangled[9] = '\032';
  EXPECT_CONTAINS(readError(writeFile(dir / "text.nii", mangled)), "text-mode transfer");
  // 64-bit sizes: one beyond the limit, one that would overflow 32 bits.
  EXPECT_CONTAINS(readError(writeFile(dir / "huge.nii", patched(24, int64_t(1) << 40))), "voxels supported");
  EXPECT_CONTAINS(readError(writeFile(dir / "negative.nii", patched(32, int64_t(-5)))), "dim[1..3]");
  Bytes series = patched(16, int64_t(4));  // dim[0] 4: a time series of ...
  putAt(series, 48, int64_t(3), false);     // ... 3 volumes
  EXPECT_CONTAINS(readError(writeFile(dir / "time.nii", series)), "dim[4] 3 is not supported");
  EXPECT_CONTAINS(readError(writeFile(dir / "offset.nii", patched(168, int64_t(348)))),
                  "vox_offset 348 is not a byte offset between 540");
  EXPECT_CONTAINS(readError(writeFile(dir / "pixdim.nii", patched(104 + 2 * 8, 0.0))), "pixdim[2] 0");
  EXPECT_CONTAINS(readError(writeFile(dir / "type.nii", patched(12, int16_t(1280)))), "datatype 1280 (uint64)");
  EXPECT_CONTAINS(readError(writeFile(dir / "short.nii", Bytes(good.begin(), good.begin() + 500))),
                  "truncated: expected a 540-byte NIfTI-2 header, found 500 bytes");
  EXPECT_CONTAINS(readError(writeFile(dir / "cut.nii", Bytes(good.begin(), good.end() - 2))),
                  "truncated: expected 120 bytes of data, found 118");
}

// ---------------------------------------------------------------------------
// Format detection and file errors

TEST(VolumeReader, ContentDecidesAndExtensionIsTheFallback) {
  TempDir dir;
  const Bytes nrrd = text(nrrdHeader("short", "endian: little\nencoding: raw\n\n")) + rampInt16();
  EXPECT_EQ(formats::readVolume(writeFile(dir / "misnamed.mha", nrrd)).density(1, 1, 1), rampValue(1, 1, 1));
  EXPECT_EQ(formats::readVolume(writeFile(dir / "volume.dat", niftiFile({}, false, rampInt16()))).density(2, 2, 2),
            rampValue(2, 2, 2));
  EXPECT_EQ(formats::readVolume(writeFile(dir / "volume.bin", text(metaHeader("MET_SHORT", "", "LOCAL")) + rampInt16()))
                .density(0, 3, 1),
            rampValue(0, 3, 1));
  // A gzip-wrapped NRRD is looked into as well.
  EXPECT_EQ(formats::readVolume(writeFile(dir / "packed.nrrd.gz", gzipped(nrrd))).density(2, 0, 4), rampValue(2, 0, 4));

  EXPECT_CONTAINS(readError(writeFile(dir / "noise.xyz", Bytes(500, 0x5a))), "noise.xyz: not a recognised volume file");
  EXPECT_CONTAINS(readError(writeFile(dir / "noise.mhd", Bytes(500, 0x5a))),
                  "noise.mhd: line 1: expected 'Key = Value'");
  EXPECT_CONTAINS(readError(writeFile(dir / "empty.nrrd", {})), "empty.nrrd: the file is empty");
  EXPECT_CONTAINS(readError(dir / "absent.nii"), "absent.nii: cannot open");
  // A directory is read as a DICOM series; this one holds none.
  EXPECT_CONTAINS(readError(dir.path()), "a directory with no DICOM file in it");
  EXPECT_CONTAINS(readError(writeFile(dir / "broken.nii.gz", Bytes{0x1f, 0x8b, 8, 0, 0, 0, 0, 0, 0, 3, 1, 2, 3})),
                  "broken.nii.gz:");
}

// ---------------------------------------------------------------------------
// Writer

DensityVolume testVolume(DensityEncoding encoding) {
  DensityVolume volume({7, 5, 3}, Vec3(0.3, 0.7, 1.1), Vec3(-12.5, 3.25, 100), encoding);
  for (size_t n = 0; n < volume.voxelCount(); ++n) volume.codeVector()[n] = VoxelCode(int(n * 997 % 65536) - 32768);
  return volume;
}

void expectSameVolume(const DensityVolume& a, const DensityVolume& b, double tolerance) {
  ASSERT_EQ(a.dims(), b.dims());
  EXPECT_EQ(a.spacing(), b.spacing());
  EXPECT_EQ(a.origin(), b.origin());
  for (int k = 0; k < a.dims()[2]; ++k)
    for (int j = 0; j < a.dims()[1]; ++j)
      for (int i = 0; i < a.dims()[0]; ++i) ASSERT_NEAR(a.density(i, j, k), b.density(i, j, k), tolerance);
}

TEST(VolumeWriter, Int16RoundTripIsExactInEveryLayout) {
  TempDir dir;
  const DensityVolume volume = testVolume({});
  for (const char* name : {"a.mha", "b.mhd"}) {
    for (bool compress : {false, true}) {
      SCOPED_TRACE(std::string(name) + (compress ? " compressed" : " raw"));
      formats::writeMetaImage(volume, dir / name, compress);
      const DensityVolume back = formats::readVolume(dir / name);
      expectSameVolume(volume, back, 0);
      EXPECT_EQ(back.encoding().scale, 1.0);
      EXPECT_EQ(back.encoding().offset, 0.0);
      EXPECT_CONTAINS(test::readFile(dir / name), "ElementType = MET_SHORT");
    }
  }
  EXPECT_TRUE(std::filesystem::exists(dir / "b.raw"));
  EXPECT_TRUE(std::filesystem::exists(dir / "b.zraw"));
  EXPECT_CONTAINS(test::readFile(dir / "b.mhd"), "ElementDataFile = b.zraw");
}

TEST(VolumeWriter, ScaledEncodingIsWrittenAsFloatDensities) {
  TempDir dir;
  const DensityVolume volume = testVolume({-1000.25, 0.03125});
  formats::writeMetaImage(volume, dir / "f.mha", true);
  EXPECT_CONTAINS(test::readFile(dir / "f.mha"), "ElementType = MET_FLOAT");
  const DensityVolume back = formats::readVolume(dir / "f.mha");
  // Float precision of densities around 1000, and the re-encoding step.
  expectSameVolume(volume, back, 0.5 * back.encoding().scale + 2e-4);
}

TEST(VolumeWriter, FailuresNameTheFileAndLeaveNothing) {
  TempDir dir;
  const DensityVolume volume = testVolume({});
  try {
    formats::writeMetaImage(volume, dir / "missing" / "v.mha", false);
    ADD_FAILURE() << "wrote into a missing directory";
  } catch (const VolumeWriteError& error) {
    EXPECT_CONTAINS(error.what(), (dir / "missing" / "v.mha").string());
  }
  EXPECT_THROW(formats::writeMetaImage(volume, dir / "v.nrrd", false), VolumeWriteError);
  EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
}

// ---------------------------------------------------------------------------
// Resampling

TEST(Resample, TrilinearReproducesALinearRampInside) {
  // density = 2x + 3y - z + 5 (x, y, z in mm) on an anisotropic grid, in 0.01 steps.
  DensityVolume source({20, 16, 9}, Vec3(0.5, 0.8, 1.5), Vec3(-3, 4, 10), DensityEncoding{-200, 0.01});
  const auto ramp = [](const Vec3& p) { return 2 * p.x() + 3 * p.y() - p.z() + 5; };
  for (int k = 0; k < 9; ++k)
    for (int j = 0; j < 16; ++j)
      for (int i = 0; i < 20; ++i) source.setDensity(i, j, k, ramp(source.voxelCenter(i, j, k)));
  const DensityVolume result = formats::resampleToVoxelSize(source, 0.7);
  // Extents 10, 12.8, 13.5 mm -> round(extent / 0.7) voxels.
  EXPECT_EQ(result.dims(), (std::array<int32_t, 3>{14, 18, 19}));
  EXPECT_EQ(result.spacing(), Vec3::Constant(0.7));
  EXPECT_EQ(result.encoding().scale, source.encoding().scale);
  EXPECT_EQ(result.encoding().offset, source.encoding().offset);
  // Same centre of the extent.
  EXPECT_LT((result.bounds().center() - source.bounds().center()).norm(), 1e-9);
  const Box3 inside(source.voxelCenter(0, 0, 0), source.voxelCenter(19, 15, 8));
  int checked = 0;
  for (int k = 0; k < result.dims()[2]; ++k) {
    for (int j = 0; j < result.dims()[1]; ++j) {
      for (int i = 0; i < result.dims()[0]; ++i) {
        const Vec3 p = result.voxelCenter(i, j, k);
        if (!inside.contains(p)) continue;
        // Two code roundings: the source's and the result's.
        ASSERT_NEAR(result.density(i, j, k), ramp(p), 0.01 + 1e-9) << i << " " << j << " " << k;
        ++checked;
      }
    }
  }
  EXPECT_GT(checked, 2000);
}

TEST(Resample, DimensionsFollowTheExtent) {
  const DensityVolume source({10, 20, 5}, Vec3(1, 0.5, 2), Vec3::Zero());
  EXPECT_EQ(formats::resampleToVoxelSize(source, 1).dims(), (std::array<int32_t, 3>{10, 10, 10}));
  EXPECT_EQ(formats::resampleToVoxelSize(source, 3).dims(), (std::array<int32_t, 3>{3, 3, 3}));
  EXPECT_EQ(formats::resampleToVoxelSize(source, 100).dims(), (std::array<int32_t, 3>{1, 1, 1}));
  const DensityVolume flat({4, 4, 1}, Vec3(1, 1, 1), Vec3::Zero());
  EXPECT_EQ(formats::resampleToVoxelSize(flat, 0.5).dims(), (std::array<int32_t, 3>{8, 8, 2}));
  EXPECT_THROW(formats::resampleToVoxelSize(source, 0), std::invalid_argument);
  EXPECT_THROW(formats::resampleToVoxelSize(source, -1), std::invalid_argument);
  EXPECT_THROW(formats::resampleToVoxelSize(source, std::nan("")), std::invalid_argument);
  EXPECT_THROW(formats::resampleToVoxelSize(source, 1e-4), std::invalid_argument);  // 1e15 voxels
}

TEST(Resample, ConstantVolumeStaysConstant) {
  DensityVolume source({5, 6, 7}, Vec3(1, 1, 3), Vec3(1, 2, 3));
  for (auto& code : source.codeVector()) code = 1234;
  const DensityVolume result = formats::resampleToVoxelSize(source, 0.9);
  EXPECT_EQ(result.minDensity(), 1234);
  EXPECT_EQ(result.maxDensity(), 1234);
}

// ---------------------------------------------------------------------------
// Real data: the VTK headsq quarter-resolution CT (NRRD header, 93 slice files).

TEST(RealData, HeadsqQuarterLoads) {
  const std::filesystem::path file =
      std::filesystem::path(TREPHINE_SOURCE_DIR) / "../shared/data/ct_head_vtk_headsq/quarter.nhdr";
  if (!std::filesystem::exists(file)) GTEST_SKIP() << "real CT data not found at " << file << "; skipping";
  const DensityVolume volume = formats::readVolume(file);
  EXPECT_EQ(volume.dims(), (std::array<int32_t, 3>{64, 64, 93}));
  EXPECT_EQ(volume.spacing(), Vec3(3.2, 3.2, 1.5));
  EXPECT_EQ(volume.origin(), Vec3::Zero());
  expectExactEncoding(volume);
  EXPECT_EQ(volume.minDensity(), 0);
  EXPECT_EQ(volume.maxDensity(), 3926);
  // Bone (above 1150) is a minority of the head, as in the VTK examples.
  size_t bone = 0;
  for (size_t n = 0; n < volume.voxelCount(); ++n) bone += volume.encoding().density(volume.code(n)) > 1150;
  const double fraction = double(bone) / double(volume.voxelCount());
  EXPECT_GT(fraction, 0.03);
  EXPECT_LT(fraction, 0.2);
}

}  // namespace
}  // namespace trephine::formats
