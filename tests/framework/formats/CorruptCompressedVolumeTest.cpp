// Compressed volume files with bytes changed in their compressed data: each
// must either be refused or read exactly as written, never read as other
// voxels. zlib's Adler-32 and gzip's CRC-32 trailers are what tell a stream
// that still decodes from the one that was written; they are checked only at
// the end of the stream, so every reader must inflate to it.
#include <gtest/gtest.h>
#include <zlib.h>

#include <cstring>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "framework/formats/volume/VolumeReader.h"
#include "tests/support/TestSupport.h"
#include "tests/support/ZlibStream.h"

namespace trephine::formats {
namespace {

using Bytes = std::vector<uint8_t>;

constexpr int kSide = 24;  // a 24^3 int16 volume: a few kB of deflate data with Huffman blocks

// Smooth, noisy samples (as CT is): compressible, yet every block is Huffman-coded.
Bytes samples() {
  Bytes out;
  std::mt19937 noise(7);
  for (int k = 0; k < kSide; ++k)
    for (int j = 0; j < kSide; ++j)
      for (int i = 0; i < kSide; ++i) {
        const int16_t v = int16_t(40 * i + 13 * j - 20 * k + int(noise() % 9));
        out.push_back(uint8_t(v & 0xff));
        out.push_back(uint8_t(uint16_t(v) >> 8));
      }
  return out;
}

Bytes deflated(const Bytes& data, int windowBits) { return test::zlibStream(test::asView(data), test::ZlibWrapper(windowBits)); }

Bytes text(const std::string& s) { return Bytes(s.begin(), s.end()); }

void writeFile(const std::filesystem::path& file, const Bytes& bytes) {
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

// A NIfTI-1 header (nifti1.h offsets) for the int16 cube, 1 mm voxels, with
// its 4 extension bytes; magic "n+1" (one file) or "ni1" (with NAME.img).
Bytes niftiHeader(const char* magic) {
  Bytes out(352, 0);
  const auto put16 = [&](size_t at, int16_t v) { std::memcpy(&out[at], &v, 2); };
  const auto put32 = [&](size_t at, auto v) { std::memcpy(&out[at], &v, 4); };
  put32(0, int32_t(348));
  put16(40, 3);
  for (int a = 1; a <= 3; ++a) put16(40 + 2 * a, kSide);
  put16(70, 4);   // DT_INT16
  put16(72, 16);  // bitpix
  for (int a = 1; a <= 3; ++a) put32(76 + 4 * a, 1.0f);
  put32(108, std::strcmp(magic, "n+1") == 0 ? 352.0f : 0.0f);
  out[123] = 2;  // mm
  std::memcpy(&out[344], magic, 4);
  return out;
}

std::string side() { return std::to_string(kSide); }

struct Layout {
  const char* name;
  // Writes the files into `dir` with `compressed` as the stream and returns the file to read.
  std::filesystem::path (*write)(const std::filesystem::path& dir, const Bytes& compressed);
  int windowBits;  // 15 zlib, 31 gzip
};

const Layout kLayouts[] = {
    {"MetaImage, zlib stream in the file",
     [](const std::filesystem::path& dir, const Bytes& z) {
       const std::string header =
           "ObjectType = Image\nNDims = 3\nDimSize = " + side() + " " + side() + " " + side() +
           "\nElementSpacing = 1 1 1\nCompressedData = True\nCompressedDataSize = " + std::to_string(z.size()) +
           "\nElementType = MET_SHORT\nElementDataFile = LOCAL\n";
       Bytes file = text(header);
       file.insert(file.end(), z.begin(), z.end());
       writeFile(dir / "v.mha", file);
       return dir / "v.mha";
     },
     15},
    {"MetaImage, detached gzip stream",
     [](const std::filesystem::path& dir, const Bytes& z) {
       writeFile(dir / "v.zraw", z);
       writeFile(dir / "v.mhd",
                 text("ObjectType = Image\nNDims = 3\nDimSize = " + side() + " " + side() + " " + side() +
                      "\nElementSpacing = 1 1 1\nCompressedData = True\nElementType = MET_SHORT\n"
                      "ElementDataFile = v.zraw\n"));
       return dir / "v.mhd";
     },
     31},
    {"NRRD, gzip encoding",
     [](const std::filesystem::path& dir, const Bytes& z) {
       Bytes file = text("NRRD0004\ntype: short\ndimension: 3\nsizes: " + side() + " " + side() + " " + side() +
                         "\nspacings: 1 1 1\nendian: little\nencoding: gzip\n\n");
       file.insert(file.end(), z.begin(), z.end());
       writeFile(dir / "v.nrrd", file);
       return dir / "v.nrrd";
     },
     31},
    {"NIfTI-1 pair, gzipped image",
     [](const std::filesystem::path& dir, const Bytes& z) {
       writeFile(dir / "v.hdr", niftiHeader("ni1"));
       writeFile(dir / "v.img.gz", z);
       return dir / "v.hdr";
     },
     31},
};

// The stream each layout compresses (a .nii.gz compresses header and samples together).
double densityAt(const DensityVolume& v, int i, int j, int k) { return v.density(i, j, k); }

bool sameVoxels(const DensityVolume& a, const DensityVolume& b) {
  if (a.dims() != b.dims()) return false;
  for (int k = 0; k < kSide; ++k)
    for (int j = 0; j < kSide; ++j)
      for (int i = 0; i < kSide; ++i)
        if (densityAt(a, i, j, k) != densityAt(b, i, j, k)) return false;
  return true;
}

// Three bytes of the stream changed at random (never the first two, whose
// change makes the stream unrecognisable at once).
Bytes corrupted(Bytes stream, std::mt19937& random) {
  for (int n = 0; n < 3; ++n) {
    const size_t at = 2 + random() % (stream.size() - 2);
    stream[at] ^= uint8_t(1 + random() % 255);
  }
  return stream;
}

TEST(CorruptCompressedVolume, ChangedBytesAreRefusedOrReadExactly) {
  const Bytes data = samples();
  for (const Layout& layout : kLayouts) {
    SCOPED_TRACE(layout.name);
    test::TempDir dir;
    const Bytes stream = deflated(data, layout.windowBits);
    const DensityVolume original = formats::readVolume(layout.write(dir.path(), stream));
    std::mt19937 random(2026);
    int refused = 0, readExactly = 0;
    for (int trial = 0; trial < 60; ++trial) {
      test::TempDir trialDir;
      const std::filesystem::path file = layout.write(trialDir.path(), corrupted(stream, random));
      try {
        const DensityVolume read = formats::readVolume(file);
        ASSERT_TRUE(sameVoxels(read, original)) << "trial " << trial << ": corrupt data read as other voxels";
        ++readExactly;
      } catch (const VolumeReadError&) {
        ++refused;
      }
    }
    // Nearly every change is caught: only a change in the gzip header's
    // unchecked fields (time stamp, flags of no consequence) reads the same.
    EXPECT_GE(refused, 50) << readExactly << " read exactly";
    RecordProperty(std::string(layout.name) + ": refused of 60", refused);
  }
}

TEST(CorruptCompressedVolume, GzippedNiftiFileIsRefusedOrReadExactly) {
  Bytes file = niftiHeader("n+1");
  const Bytes data = samples();
  file.insert(file.end(), data.begin(), data.end());
  const Bytes stream = deflated(file, 31);
  test::TempDir dir;
  writeFile(dir.path() / "v.nii.gz", stream);
  const DensityVolume original = formats::readVolume(dir.path() / "v.nii.gz");
  std::mt19937 random(11);
  int refused = 0;
  for (int trial = 0; trial < 60; ++trial) {
    writeFile(dir.path() / "c.nii.gz", corrupted(stream, random));
    try {
      ASSERT_TRUE(sameVoxels(formats::readVolume(dir.path() / "c.nii.gz"), original)) << "trial " << trial;
    } catch (const VolumeReadError&) {
      ++refused;
    }
  }
  EXPECT_GE(refused, 50);
  RecordProperty("NIfTI-1 .nii.gz: refused of 60", refused);
}

TEST(CorruptCompressedVolume, MissingChecksumIsTruncation) {
  const Bytes data = samples();
  for (const Layout& layout : kLayouts) {
    SCOPED_TRACE(layout.name);
    test::TempDir dir;
    Bytes stream = deflated(data, layout.windowBits);
    stream.resize(stream.size() - (layout.windowBits == 31 ? 8 : 4));  // the trailer cut off, the data whole
    try {
      formats::readVolume(layout.write(dir.path(), stream));
      ADD_FAILURE() << "a stream without its trailer was read";
    } catch (const VolumeReadError& e) {
      EXPECT_NE(std::string(e.what()).find("truncated"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace trephine::formats
