#include "framework/formats/volume/NiftiReader.h"

#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <string>

#include "framework/core/Strings.h"
#include "framework/formats/volume/HeaderText.h"
#include "framework/formats/volume/SampleBlocks.h"
#include "framework/formats/volume/StoredVolume.h"
#include "framework/formats/volume/VolumeReader.h"

namespace trephine::formats {

namespace {

// Where the fields read here sit in each version's header (nifti1.h,
// nifti2.h), and how wide they are. NIfTI-2 widens dim to int64, the reals
// to double, vox_offset to int64 and the codes to int32, and moves them.
struct HeaderLayout {
  int version;
  size_t headerBytes;
  size_t magic, magicBytes;
  size_t dim, dimBytes;  // dim[8]
  size_t datatype;       // int16 in both
  size_t pixdim;         // real[8]
  size_t voxOffset;      // float (NIfTI-1) or int64 (NIfTI-2)
  size_t sclSlope, sclInter;
  size_t realBytes;  // float or double
  size_t qformCode, sformCode, codeBytes;
  size_t quaternB;  // then c, d, qoffset x, y, z: six reals
  size_t srowX;     // then srow_y, srow_z: three real[4]
  size_t xyztUnits, unitsBytes;
};

constexpr HeaderLayout kNifti1{.version = 1, .headerBytes = 348, .magic = 344, .magicBytes = 4,
                               .dim = 40, .dimBytes = 2, .datatype = 70, .pixdim = 76, .voxOffset = 108,
                               .sclSlope = 112, .sclInter = 116, .realBytes = 4, .qformCode = 252,
                               .sformCode = 254, .codeBytes = 2, .quaternB = 256, .srowX = 280,
                               .xyztUnits = 123, .unitsBytes = 1};
constexpr HeaderLayout kNifti2{.version = 2, .headerBytes = 540, .magic = 4, .magicBytes = 8,
                               .dim = 16, .dimBytes = 8, .datatype = 12, .pixdim = 104, .voxOffset = 168,
                               .sclSlope = 176, .sclInter = 184, .realBytes = 8, .qformCode = 344,
                               .sformCode = 348, .codeBytes = 4, .quaternB = 352, .srowX = 400,
                               .xyztUnits = 500, .unitsBytes = 4};
constexpr size_t kLargestHeaderBytes = 540;

template <typename Bits>
Bits swappedBytes(Bits bits) {
  if constexpr (sizeof bits == 2) return Bits(__builtin_bswap16(uint16_t(bits)));
  else if constexpr (sizeof bits == 4) return Bits(__builtin_bswap32(uint32_t(bits)));
  else return Bits(__builtin_bswap64(uint64_t(bits)));
}

// Reads header fields of either version in the header's byte order.
class HeaderFields {
 public:
  HeaderFields(const std::array<uint8_t, kLargestHeaderBytes>& bytes, const HeaderLayout& layout, bool bigEndian)
      : m_bytes(bytes), m_layout(layout), m_swap(bigEndian != (std::endian::native == std::endian::big)) {}

  // A signed integer of `bytes` bytes.
  int64_t integer(size_t offset, size_t bytes) const {
    switch (bytes) {
      case 1: return int8_t(m_bytes[offset]);
      case 2: return std::bit_cast<int16_t>(load<uint16_t>(offset));
      case 4: return std::bit_cast<int32_t>(load<uint32_t>(offset));
      default: return std::bit_cast<int64_t>(load<uint64_t>(offset));
    }
  }
  // A float (NIfTI-1) or double (NIfTI-2) field.
  double real(size_t offset) const {
    return m_layout.realBytes == 4 ? double(std::bit_cast<float>(load<uint32_t>(offset)))
                                   : std::bit_cast<double>(load<uint64_t>(offset));
  }
  double realAt(size_t first, int index) const { return real(first + m_layout.realBytes * size_t(index)); }
  int64_t dim(int index) const { return integer(m_layout.dim + m_layout.dimBytes * size_t(index), m_layout.dimBytes); }
  int64_t code(size_t offset) const { return integer(offset, m_layout.codeBytes); }
  uint8_t units() const { return uint8_t(integer(m_layout.xyztUnits, m_layout.unitsBytes) & 0xFF); }
  double voxOffset() const {
    return m_layout.version == 1 ? real(m_layout.voxOffset) : double(integer(m_layout.voxOffset, 8));
  }
  std::string_view magic() const {
    return {reinterpret_cast<const char*>(m_bytes.data()) + m_layout.magic, m_layout.magicBytes};
  }

 private:
  template <typename Bits>
  Bits load(size_t offset) const {
    Bits bits;
    std::memcpy(&bits, m_bytes.data() + offset, sizeof bits);
    if (m_swap) bits = swappedBytes(bits);
    return bits;
  }
  const std::array<uint8_t, kLargestHeaderBytes>& m_bytes;
  const HeaderLayout& m_layout;
  bool m_swap;
};

int32_t sizeofHdr(std::span<const uint8_t> head, bool bigEndian) {
  uint32_t bits = 0;
  std::memcpy(&bits, head.data(), 4);
  if (bigEndian != (std::endian::native == std::endian::big)) bits = swappedBytes(bits);
  return std::bit_cast<int32_t>(bits);
}

NumberType datatype(int64_t code, const std::filesystem::path& file) {
  // nifti1.h DT_* codes (the same in nifti2.h); `supported` marks the ones read here.
  struct Datatype {
    int16_t code;
    const char* name;
    bool supported;
    NumberType type;
  };
  static const Datatype kDatatypes[] = {{2, "uint8", true, NumberType::kUInt8},
                                        {256, "int8", true, NumberType::kInt8},
                                        {4, "int16", true, NumberType::kInt16},
                                        {512, "uint16", true, NumberType::kUInt16},
                                        {8, "int32", true, NumberType::kInt32},
                                        {768, "uint32", true, NumberType::kUInt32},
                                        {16, "float32", true, NumberType::kFloat32},
                                        {64, "float64", true, NumberType::kFloat64},
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

// The version's magic: "n+1\0" or "n+2\0" and the four bytes that catch a
// file mangled by a text-mode transfer (a single .nii), or "ni1\0" / "ni2\0"
// (a .hdr whose samples are in the .img beside it). True for a pair.
bool checkMagic(const HeaderFields& header, const HeaderLayout& layout, const std::filesystem::path& file) {
  const std::string_view magic = header.magic();
  const std::string version = std::to_string(layout.version);
  const std::string tail = layout.version == 1 ? std::string() : std::string("\r\n\032\n", 4);
  const std::string single = "n+" + version + std::string(1, '\0') + tail;
  const std::string pair = "ni" + version + std::string(1, '\0') + tail;
  if (magic == single) return false;
  if (magic == pair) return true;
  if (layout.version == 2 && (magic.substr(0, 4) == std::string_view(single).substr(0, 4) ||
                              magic.substr(0, 4) == std::string_view(pair).substr(0, 4)))
    throw VolumeReadError(file, "magic '" + std::string(magic.substr(0, 3)) + "' is followed by " +
                                    quoteForMessage(magic.substr(4)) +
                                    " instead of \\r\\n\\032\\n (the file was altered, perhaps by a text-mode "
                                    "transfer)");
  throw VolumeReadError(file, "magic " + quoteForMessage(magic.substr(0, 4)) + " is not 'n+" + version + "' or 'ni" +
                                  version + "' (expected a NIfTI-" + version +
                                  " .nii, or a .hdr and its .img; Analyze 7.5 is not supported)");
}

// The image file of a .hdr/.img pair: NAME.img or NAME.img.gz beside
// NAME.hdr (or NAME.hdr.gz).
std::filesystem::path pairedImage(const std::filesystem::path& header) {
  std::filesystem::path stem = header;
  if (equalsIgnoreCase(stem.extension().string(), ".gz")) stem.replace_extension();
  stem.replace_extension();
  std::error_code ec;
  for (const char* extension : {".img", ".IMG", ".img.gz"}) {
    const std::filesystem::path image = stem.string() + extension;
    if (std::filesystem::is_regular_file(image, ec)) return image;
  }
  throw VolumeReadError(header, "a .hdr/.img pair (magic 'ni1' or 'ni2') whose image file " +
                                    (stem.string() + ".img") + " is missing");
}

}  // namespace

bool looksLikeNifti(std::span<const uint8_t> head) {
  if (head.size() < 4) return false;
  for (bool big : {false, true}) {
    const int32_t size = sizeofHdr(head, big);
    if (size == int32_t(kNifti1.headerBytes) || size == int32_t(kNifti2.headerBytes)) return true;
  }
  return false;
}

DensityVolume readNifti(const ByteSource& source) {
  const std::filesystem::path& file = source.path();
  std::array<uint8_t, kLargestHeaderBytes> raw{};
  source.read(0, std::span(raw).first(std::min<size_t>(4, source.size())));
  // The version and the byte order from sizeof_hdr (348 or 540).
  const HeaderLayout* layout = &kNifti1;
  bool bigEndian = false;
  bool known = false;
  if (source.size() >= 4) {
    for (const HeaderLayout* candidate : {&kNifti1, &kNifti2})
      for (bool big : {false, true})
        if (!known && sizeofHdr(raw, big) == int32_t(candidate->headerBytes))
          layout = candidate, bigEndian = big, known = true;
  }
  const std::string name = "NIfTI-" + std::to_string(layout->version);
  if (source.size() < layout->headerBytes)
    throw VolumeReadError(file, "truncated: expected a " + std::to_string(layout->headerBytes) + "-byte " + name +
                                    " header, found " + std::to_string(source.size()) + " bytes");
  if (!known)
    throw VolumeReadError(file, "sizeof_hdr is " + std::to_string(sizeofHdr(raw, false)) +
                                    " (expected 348, NIfTI-1, or 540, NIfTI-2: not a NIfTI file)");
  source.read(0, std::span(raw).first(layout->headerBytes));
  const HeaderFields header(raw, *layout, bigEndian);
  const bool pair = checkMagic(header, *layout, file);

  const int64_t rank = header.dim(0);
  if (rank < 1 || rank > 7) throw VolumeReadError(file, "dim[0] " + std::to_string(rank) + " is not 1 to 7");
  if (rank < 3)
    throw VolumeReadError(file, "dim[0] " + std::to_string(rank) + ": " + std::to_string(rank) +
                                    "D images are not supported (expected a 3D volume)");
  StoredVolume stored;
  for (int a = 0; a < 3; ++a) stored.dims[a] = header.dim(a + 1);
  for (int a = 4; a <= rank; ++a) {
    if (header.dim(a) != 1)
      throw VolumeReadError(file, "dim[" + std::to_string(a) + "] " + std::to_string(header.dim(a)) +
                                      " is not supported (expected 1: only 3D volumes, no time series)");
  }
  checkDimensions(stored.dims, "dim[1..3]", file);
  stored.layout = {datatype(header.integer(layout->datatype, 2), file), bigEndian};

  const double unit = millimetresPerUnit(header.units());
  Vec3 spacing;
  for (int a = 0; a < 3; ++a) {
    const double pixdim = header.realAt(layout->pixdim, a + 1);
    if (!std::isfinite(pixdim) || pixdim == 0)
      throw VolumeReadError(file, "pixdim[" + std::to_string(a + 1) + "] " + formatDouble(pixdim) +
                                      " is not a voxel size (expected a finite, non-zero number)");
    spacing[a] = std::abs(pixdim) * unit;
  }

  // Orientation and origin: sform, else qform, else none (NIfTI "method 1").
  Eigen::Matrix3d direction = Eigen::Matrix3d::Identity();
  if (header.code(layout->sformCode) > 0) {
    for (int row = 0; row < 3; ++row) {
      for (int column = 0; column < 3; ++column) direction(row, column) = header.realAt(layout->srowX, 4 * row + column);
      stored.origin[row] = header.realAt(layout->srowX, 4 * row + 3) * unit;
    }
    for (int a = 0; a < 3; ++a) {
      const double length = direction.col(a).norm();
      if (length > 0 && std::isfinite(length)) direction.col(a) /= length;
    }
  } else if (header.code(layout->qformCode) > 0) {
    direction = quaternionRotation(header.realAt(layout->quaternB, 0), header.realAt(layout->quaternB, 1),
                                   header.realAt(layout->quaternB, 2), header.realAt(layout->pixdim, 0), file);
    for (int a = 0; a < 3; ++a) stored.origin[a] = header.realAt(layout->quaternB, 3 + a) * unit;
  }
  for (int a = 0; a < 3; ++a) stored.axes.col(a) = direction.col(a) * spacing[a];
  // The qform and the sform map voxels to RAS (nifti1.h); the scene's world is LPS.
  if (header.code(layout->sformCode) > 0 || header.code(layout->qformCode) > 0)
    convertToLps(stored, PatientFrame::kRas);

  const double slope = header.real(layout->sclSlope);
  const double intercept = header.real(layout->sclInter);
  if (slope != 0 && std::isfinite(slope)) stored.scaling = {slope, std::isfinite(intercept) ? intercept : 0.0};

  const double voxOffset = header.voxOffset();
  std::vector<uint8_t> samples;
  if (pair) {
    // The samples at vox_offset (usually 0) in the .img, raw or gzipped.
    const std::filesystem::path imageFile = pairedImage(file);
    const FileByteSource image(imageFile);
    if (!std::isfinite(voxOffset) || voxOffset < 0 || voxOffset != std::floor(voxOffset) ||
        voxOffset > double(image.size()))
      throw VolumeReadError(file, "vox_offset " + formatDouble(voxOffset) + " is not a byte offset in the " +
                                      std::to_string(image.size()) + "-byte " + imageFile.filename().string());
    const std::vector<uint8_t> head = image.readClipped(0, 2);
    if (head.size() == 2 && head[0] == 0x1f && head[1] == 0x8b)
      appendCompressedSamples(image, 0, std::nullopt, BlockStart{uint64_t(voxOffset)}, stored.byteCount(), samples);
    else
      appendRawSamples(image, BlockStart{uint64_t(voxOffset)}, stored.byteCount(), samples);
    return assembleVolume(stored, samples, imageFile);
  }
  if (!std::isfinite(voxOffset) || voxOffset < double(layout->headerBytes) || voxOffset != std::floor(voxOffset) ||
      voxOffset > double(source.size()))
    throw VolumeReadError(file, "vox_offset " + formatDouble(voxOffset) + " is not a byte offset between " +
                                    std::to_string(layout->headerBytes) + " and the " +
                                    std::to_string(source.size()) + "-byte file size");
  appendRawSamples(source, BlockStart{uint64_t(voxOffset)}, stored.byteCount(), samples);
  return assembleVolume(stored, samples, file);
}

}  // namespace trephine::formats
