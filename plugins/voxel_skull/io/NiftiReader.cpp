#include "plugins/voxel_skull/io/NiftiReader.h"

#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <string>

#include "framework/core/Strings.h"
#include "plugins/voxel_skull/io/HeaderText.h"
#include "plugins/voxel_skull/io/SampleBlocks.h"
#include "plugins/voxel_skull/io/StoredVolume.h"
#include "plugins/voxel_skull/io/VolumeReader.h"

namespace trephine::voxel {

namespace {

constexpr size_t kHeaderBytes = 348;
constexpr int32_t kNifti2HeaderBytes = 540;

// Byte offsets of the NIfTI-1 header fields used here (nifti1.h).
enum Offset : size_t {
  kDim = 40,  // int16[8]
  kDatatype = 70,
  kPixdim = 76,  // float[8]
  kVoxOffset = 108,
  kSclSlope = 112,
  kSclInter = 116,
  kXyztUnits = 123,
  kQformCode = 252,
  kSformCode = 254,
  kQuaternB = 256,  // then c, d, qoffset x, y, z: six floats
  kSrowX = 280,     // then srow_y, srow_z: three float[4]
  kMagic = 344,
};

// Reads header fields in the header's byte order.
class HeaderBytes {
 public:
  HeaderBytes(const std::array<uint8_t, kHeaderBytes>& bytes, bool bigEndian)
      : m_bytes(bytes), m_swap(bigEndian != (std::endian::native == std::endian::big)) {}
  int16_t int16(size_t offset) const { return std::bit_cast<int16_t>(load<uint16_t>(offset)); }
  double real(size_t offset) const { return std::bit_cast<float>(load<uint32_t>(offset)); }
  uint8_t byte(size_t offset) const { return m_bytes[offset]; }

 private:
  template <typename Bits>
  Bits load(size_t offset) const {
    Bits bits;
    std::memcpy(&bits, m_bytes.data() + offset, sizeof bits);
    if (m_swap)
      bits = sizeof bits == 2 ? Bits(__builtin_bswap16(uint16_t(bits))) : Bits(__builtin_bswap32(uint32_t(bits)));
    return bits;
  }
  const std::array<uint8_t, kHeaderBytes>& m_bytes;
  bool m_swap;
};

int32_t sizeofHdr(std::span<const uint8_t> head, bool bigEndian) {
  uint32_t bits = 0;
  std::memcpy(&bits, head.data(), 4);
  if (bigEndian != (std::endian::native == std::endian::big)) bits = __builtin_bswap32(bits);
  return std::bit_cast<int32_t>(bits);
}

SampleType datatype(int16_t code, const std::filesystem::path& file) {
  // nifti1.h DT_* codes; `supported` marks the ones read here.
  struct Datatype {
    int16_t code;
    const char* name;
    bool supported;
    SampleType type;
  };
  static const Datatype kDatatypes[] = {{2, "uint8", true, SampleType::kUInt8},
                                        {256, "int8", true, SampleType::kInt8},
                                        {4, "int16", true, SampleType::kInt16},
                                        {512, "uint16", true, SampleType::kUInt16},
                                        {8, "int32", true, SampleType::kInt32},
                                        {768, "uint32", true, SampleType::kUInt32},
                                        {16, "float32", true, SampleType::kFloat32},
                                        {64, "float64", true, SampleType::kFloat64},
                                        {1, "binary", false, {}},
                                        {32, "complex64", false, {}},
                                        {128, "rgb24", false, {}},
                                        {1024, "int64", false, {}},
                                        {1280, "uint64", false, {}},
                                        {1536, "float128", false, {}},
                                        {1792, "complex128", false, {}},
                                        {2048, "complex256", false, {}},
                                        {2304, "rgba32", false, {}}};
  const char* name = "unknown";
  for (const Datatype& datatype : kDatatypes) {
    if (datatype.code != code) continue;
    if (datatype.supported) return datatype.type;
    name = datatype.name;
  }
  throw VolumeReadError(file, "datatype " + std::to_string(code) + " (" + name +
                                  ") is not supported (expected uint8 (2), int8 (256), int16 (4), uint16 (512), "
                                  "int32 (8), uint32 (768), float32 (16) or float64 (64))");
}

// Millimetres per spatial unit of xyzt_units (unknown units are taken as mm).
double millimetresPerUnit(uint8_t xyztUnits) {
  switch (xyztUnits & 0x07) {
    case 1:
      return 1000.0;  // metre
    case 3:
      return 0.001;  // micrometre
    default:
      return 1.0;  // mm or unknown
  }
}

// Rotation of the qform (nifti1.h, "METHOD 2"); its third column is flipped by qfac.
Eigen::Matrix3d quaternionRotation(double b, double c, double d, double qfac, const std::filesystem::path& file) {
  if (!std::isfinite(b) || !std::isfinite(c) || !std::isfinite(d))
    throw VolumeReadError(file, "quatern_b/c/d are not finite (expected the qform rotation)");
  double a = 1.0 - (b * b + c * c + d * d);
  if (a < 1e-7) {
    // A 180 degree rotation: (b, c, d) is the axis; renormalise it.
    const double norm = std::sqrt(b * b + c * c + d * d);
    a = 0;
    b /= norm;
    c /= norm;
    d /= norm;
  } else {
    a = std::sqrt(a);
  }
  Eigen::Matrix3d r;
  r << a * a + b * b - c * c - d * d, 2 * (b * c - a * d), 2 * (b * d + a * c),  //
      2 * (b * c + a * d), a * a + c * c - b * b - d * d, 2 * (c * d - a * b),   //
      2 * (b * d - a * c), 2 * (c * d + a * b), a * a + d * d - c * c - b * b;
  r.col(2) *= qfac < 0 ? -1.0 : 1.0;
  return r;
}

}  // namespace

bool looksLikeNifti(std::span<const uint8_t> head) {
  if (head.size() < 4) return false;
  for (bool big : {false, true}) {
    const int32_t size = sizeofHdr(head, big);
    if (size == int32_t(kHeaderBytes) || size == kNifti2HeaderBytes) return true;
  }
  return false;
}

DensityVolume readNifti(const ByteSource& source) {
  const std::filesystem::path& file = source.path();
  if (source.size() < kHeaderBytes)
    throw VolumeReadError(file, "truncated: expected a " + std::to_string(kHeaderBytes) +
                                    "-byte NIfTI-1 header, found " + std::to_string(source.size()) + " bytes");
  std::array<uint8_t, kHeaderBytes> raw{};
  source.read(0, raw);
  bool bigEndian = false;
  if (sizeofHdr(raw, false) == int32_t(kHeaderBytes)) {
    bigEndian = false;
  } else if (sizeofHdr(raw, true) == int32_t(kHeaderBytes)) {
    bigEndian = true;
  } else if (sizeofHdr(raw, false) == kNifti2HeaderBytes || sizeofHdr(raw, true) == kNifti2HeaderBytes) {
    throw VolumeReadError(file, "NIfTI-2 (sizeof_hdr 540) is not supported (expected NIfTI-1, sizeof_hdr 348)");
  } else {
    throw VolumeReadError(
        file, "sizeof_hdr is " + std::to_string(sizeofHdr(raw, false)) + " (expected 348: not a NIfTI-1 file)");
  }
  const HeaderBytes header(raw, bigEndian);

  const std::string_view magic(reinterpret_cast<const char*>(raw.data()) + kMagic, 4);
  if (magic == std::string_view("ni1\0", 4))
    throw VolumeReadError(file,
                          "magic 'ni1' marks a .hdr/.img pair, which is not supported (expected a single-file "
                          "NIfTI-1 .nii, magic 'n+1')");
  if (magic != std::string_view("n+1\0", 4))
    throw VolumeReadError(file,
                          "magic " + quoteForMessage(magic) +
                              " is not 'n+1' (expected a single-file NIfTI-1 .nii; Analyze 7.5 is not supported)");

  const int16_t rank = header.int16(kDim);
  if (rank < 1 || rank > 7) throw VolumeReadError(file, "dim[0] " + std::to_string(rank) + " is not 1 to 7");
  if (rank < 3)
    throw VolumeReadError(file, "dim[0] " + std::to_string(rank) + ": " + std::to_string(rank) +
                                    "D images are not supported (expected a 3D volume)");
  StoredVolume stored;
  for (int a = 0; a < 3; ++a) stored.dims[a] = header.int16(kDim + 2 * (a + 1));
  for (int a = 4; a <= rank; ++a) {
    if (header.int16(kDim + 2 * a) != 1)
      throw VolumeReadError(file, "dim[" + std::to_string(a) + "] " + std::to_string(header.int16(kDim + 2 * a)) +
                                      " is not supported (expected 1: only 3D volumes, no time series)");
  }
  checkDimensions(stored.dims, "dim[1..3]", file);
  stored.layout = {datatype(header.int16(kDatatype), file), bigEndian};

  const double unit = millimetresPerUnit(header.byte(kXyztUnits));
  Vec3 spacing;
  for (int a = 0; a < 3; ++a) {
    const double pixdim = header.real(kPixdim + 4 * (a + 1));
    if (!std::isfinite(pixdim) || pixdim == 0)
      throw VolumeReadError(file, "pixdim[" + std::to_string(a + 1) + "] " + formatDouble(pixdim) +
                                      " is not a voxel size (expected a finite, non-zero number)");
    spacing[a] = std::abs(pixdim) * unit;
  }

  // Orientation and origin: sform, else qform, else none (NIfTI "method 1").
  Eigen::Matrix3d direction = Eigen::Matrix3d::Identity();
  if (header.int16(kSformCode) > 0) {
    for (int row = 0; row < 3; ++row) {
      for (int column = 0; column < 3; ++column) direction(row, column) = header.real(kSrowX + 16 * row + 4 * column);
      stored.origin[row] = header.real(kSrowX + 16 * row + 12) * unit;
    }
    for (int a = 0; a < 3; ++a) {
      const double length = direction.col(a).norm();
      if (length > 0 && std::isfinite(length)) direction.col(a) /= length;
    }
  } else if (header.int16(kQformCode) > 0) {
    direction = quaternionRotation(header.real(kQuaternB), header.real(kQuaternB + 4), header.real(kQuaternB + 8),
                                   header.real(kPixdim), file);
    for (int a = 0; a < 3; ++a) stored.origin[a] = header.real(kQuaternB + 12 + 4 * a) * unit;
  }
  for (int a = 0; a < 3; ++a) stored.axes.col(a) = direction.col(a) * spacing[a];

  const double slope = header.real(kSclSlope);
  const double intercept = header.real(kSclInter);
  if (slope != 0 && std::isfinite(slope)) stored.scaling = {slope, std::isfinite(intercept) ? intercept : 0.0};

  const double voxOffset = header.real(kVoxOffset);
  if (!std::isfinite(voxOffset) || voxOffset < double(kHeaderBytes) || voxOffset != std::floor(voxOffset) ||
      voxOffset > double(source.size()))
    throw VolumeReadError(file, "vox_offset " + formatDouble(voxOffset) + " is not a byte offset between 348 and the " +
                                    std::to_string(source.size()) + "-byte file size");
  std::vector<uint8_t> samples;
  appendRawSamples(source, BlockStart{uint64_t(voxOffset)}, stored.byteCount(), samples);
  return assembleVolume(stored, samples, file);
}

}  // namespace trephine::voxel
