#include "framework/formats/volume/DicomReader.h"

#include <gdcmImage.h>
#include <gdcmReader.h>
#include <gdcmSequenceOfItems.h>
#include <gdcmStringFilter.h>
#include <gdcmTrace.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <set>
#include <vector>

#include "framework/core/Strings.h"
#include "framework/formats/volume/DicomStructure.h"
#include "framework/formats/volume/StoredVolume.h"
#include "framework/formats/volume/VolumeReader.h"

namespace trephine::formats {

namespace fs = std::filesystem;

namespace {

// What the reader needs of one file's header.
struct Slice {
  fs::path file;
  std::string series, description;
  std::array<uint32_t, 3> dims{0, 0, 0};  // columns, rows, frames
  Vec3 origin = Vec3::Zero();             // mm, centre of the first pixel
  Vec3 rowDirection = Vec3::UnitX();      // of increasing column index
  Vec3 columnDirection = Vec3::UnitY();   // of increasing row index
  Eigen::Vector2d pixelSpacing = Eigen::Vector2d::Ones();  // mm: between columns, between rows
  double frameStep = 0;                   // mm between frames (multi-frame files)
  double slope = 1, intercept = 0;
  double position = 0;                    // along the normal, mm
  DicomPixelAttributes pixel;             // as the structure check read them
};

std::string trimmed(std::string text) {
  while (!text.empty() && (text.back() == ' ' || text.back() == '\0')) text.pop_back();
  return text;
}

bool hasDicomMagic(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  char head[132] = {};
  in.read(head, sizeof head);
  return in.gcount() == 132 && std::string(head + 128, 4) == "DICM";
}

// The file's structure checked before GDCM reads it (DicomStructure.h).
DicomPixelAttributes checkStructure(const fs::path& file) {
  std::ifstream in(file, std::ios::binary | std::ios::ate);
  if (!in) throw VolumeReadError(file, "cannot be read");
  const std::streamoff size = in.tellg();
  std::vector<uint8_t> bytes(size_t(std::max<std::streamoff>(size, 0)));
  in.seekg(0);
  in.read(reinterpret_cast<char*>(bytes.data()), std::streamsize(bytes.size()));
  return checkDicomStructure(file, bytes);
}

// GDCM reads the file, or, after padding, only its data set (from memory:
// GDCM takes the zeros for an element and fails). `stream` keeps the bytes.
void openForGdcm(gdcm::Reader& reader, const fs::path& file, const DicomPixelAttributes& pixel,
                 std::unique_ptr<std::istringstream>& stream) {
  if (pixel.trailingZeros == 0) {
    reader.SetFileName(file.c_str());
    return;
  }
  std::ifstream in(file, std::ios::binary);
  std::string bytes(pixel.dataSetEnd, '\0');
  in.read(bytes.data(), std::streamsize(bytes.size()));
  if (uint64_t(in.gcount()) != pixel.dataSetEnd) throw VolumeReadError(file, "cannot be read again");
  stream = std::make_unique<std::istringstream>(std::move(bytes));
  reader.SetStream(*stream);
}

// The image attributes, read here from the data set rather than through
// gdcm::ImageHelper: its typed attributes assert on a value representation
// or an emptiness the standard does not allow, and which elements it reads
// depends on the SOP class and on pointers inside the file (Frame Increment
// Pointer), so no list checked beforehand covers them all. Each value is
// taken where the standard puts it: the top level, else (enhanced images)
// the Shared Functional Groups' first item, else the Per-frame Functional
// Groups' first item, inside the functional group macro that holds it.
struct ImageAttributes {
  const gdcm::DataSet& top;
  const fs::path& file;

  static std::string tagName(gdcm::Tag tag) {
    char text[16];
    std::snprintf(text, sizeof text, "(%04X,%04X)", tag.GetGroup(), tag.GetElement());
    return text;
  }

  // The first item's data set of the sequence `tag` in `ds`, if there is
  // one. Only sequences GDCM parsed while reading (explicit SQ, or of
  // undefined length), whose structure the check before it walked.
  static const gdcm::SequenceOfItems* sequence(const gdcm::DataSet& ds, gdcm::Tag tag) {
    if (!ds.FindDataElement(tag)) return nullptr;
    const gdcm::DataElement& de = ds.GetDataElement(tag);
    if (de.IsEmpty()) return nullptr;
    return dynamic_cast<const gdcm::SequenceOfItems*>(&de.GetValue());
  }
  static const gdcm::DataSet* firstItem(const gdcm::DataSet& ds, gdcm::Tag tag) {
    const gdcm::SequenceOfItems* items = sequence(ds, tag);
    if (!items || items->GetNumberOfItems() == 0) return nullptr;
    return &items->GetItem(1).GetNestedDataSet();
  }

  // The element `tag`, at the top level or in the functional group macro
  // `macro` of an enhanced image's functional groups; null where absent or empty.
  const gdcm::DataElement* find(gdcm::Tag tag, gdcm::Tag macro = gdcm::Tag(0, 0)) const {
    auto nonEmpty = [&](const gdcm::DataSet& ds) -> const gdcm::DataElement* {
      if (!ds.FindDataElement(tag)) return nullptr;
      const gdcm::DataElement& de = ds.GetDataElement(tag);
      return de.IsEmpty() || !de.GetByteValue() ? nullptr : &de;
    };
    if (const gdcm::DataElement* de = nonEmpty(top)) return de;
    if (macro == gdcm::Tag(0, 0)) return nullptr;
    for (const gdcm::Tag& groups : {gdcm::Tag(0x5200, 0x9229), gdcm::Tag(0x5200, 0x9230)})
      if (const gdcm::DataSet* group = firstItem(top, groups))
        if (const gdcm::DataSet* inMacro = firstItem(*group, macro))
          if (const gdcm::DataElement* de = nonEmpty(*inMacro)) return de;
    return nullptr;
  }

  // A decimal (DS) or integer (IS) string's values: every one a finite number.
  std::vector<double> numbers(const gdcm::DataElement& de, const char* name) const {
    const gdcm::ByteValue* bytes = de.GetByteValue();
    const std::string text(bytes->GetPointer(), bytes->GetLength());
    std::vector<double> values;
    size_t from = 0;
    while (from <= text.size()) {
      const size_t to = std::min(text.find('\\', from), text.size());
      std::string item = trimmed(text.substr(from, to - from));
      item.erase(0, std::min(item.find_first_not_of(' '), item.size()));
      char* end = nullptr;
      const double value = std::strtod(item.c_str(), &end);
      if (item.empty() || end != item.c_str() + item.size() || !std::isfinite(value))
        throw VolumeReadError(file, std::string(name) + " " + tagName(de.GetTag()) + " holds \"" +
                                        text.substr(0, 64) + "\" (expected numbers separated by \\)");
      values.push_back(value);
      from = to + 1;
    }
    return values;
  }

  // Numbers of `tag` (empty where absent), exactly `count` of them where present.
  std::vector<double> numbers(gdcm::Tag tag, size_t count, const char* name, gdcm::Tag macro = gdcm::Tag(0, 0)) const {
    const gdcm::DataElement* de = find(tag, macro);
    if (!de) return {};
    std::vector<double> values = numbers(*de, name);
    if (values.size() != count)
      throw VolumeReadError(file, std::string(name) + " " + tagName(tag) + " holds " + std::to_string(values.size()) +
                                      " values (expected " + std::to_string(count) + ")");
    return values;
  }

  // An unsigned short (US) at the top level; 0 where absent.
  uint32_t unsignedShort(gdcm::Tag tag) const {
    const gdcm::DataElement* de = find(tag);
    if (!de) return 0;
    const gdcm::ByteValue* bytes = de->GetByteValue();
    if (bytes->GetLength() != 2) throw VolumeReadError(file, tagName(tag) + " is not one US value");
    const auto* b = reinterpret_cast<const uint8_t*>(bytes->GetPointer());
    return uint32_t(b[0]) | uint32_t(b[1]) << 8;
  }
};

Slice readHeader(const fs::path& file) {
  const DicomPixelAttributes pixel = checkStructure(file);
  gdcm::Reader reader;
  std::unique_ptr<std::istringstream> stream;
  openForGdcm(reader, file, pixel, stream);
  if (!reader.ReadUpToTag(gdcm::Tag(0x7fe0, 0x0010), std::set<gdcm::Tag>{}))
    throw VolumeReadError(file, "GDCM cannot read it as DICOM (truncated, or not Part 10)");
  const gdcm::File& f = reader.GetFile();
  Slice s;
  s.pixel = pixel;
  gdcm::StringFilter strings;
  strings.SetFile(f);
  s.file = file;
  s.series = trimmed(strings.ToString(gdcm::Tag(0x0020, 0x000e)));
  s.description = trimmed(strings.ToString(gdcm::Tag(0x0008, 0x103e)));
  const ImageAttributes image{f.GetDataSet(), file};
  const uint32_t columns = image.unsignedShort(gdcm::Tag(0x0028, 0x0011));
  const uint32_t rows = image.unsignedShort(gdcm::Tag(0x0028, 0x0010));
  if (columns == 0 || rows == 0)
    throw VolumeReadError(file, "no image: Rows (0028,0010) or Columns (0028,0011) missing or zero");
  const std::vector<double> frames = image.numbers(gdcm::Tag(0x0028, 0x0008), 1, "NumberOfFrames");
  if (!frames.empty() && !(frames[0] >= 1 && frames[0] <= 1e6 && frames[0] == std::floor(frames[0])))
    throw VolumeReadError(file, "NumberOfFrames (0028,0008) is " + formatDouble(frames[0]) +
                                    " (expected a whole number from 1 to 1000000)");
  s.dims = {columns, rows, frames.empty() ? 1u : uint32_t(frames[0])};
  const gdcm::Tag planePosition(0x0020, 0x9113), planeOrientation(0x0020, 0x9116), pixelMeasures(0x0028, 0x9110),
      valueTransformation(0x0028, 0x9145);
  std::vector<double> origin = image.numbers(gdcm::Tag(0x0020, 0x0032), 3, "ImagePositionPatient", planePosition);
  std::vector<double> cosines = image.numbers(gdcm::Tag(0x0020, 0x0037), 6, "ImageOrientationPatient", planeOrientation);
  std::vector<double> spacing = image.numbers(gdcm::Tag(0x0028, 0x0030), 2, "PixelSpacing", pixelMeasures);
  if (origin.empty() || cosines.empty() || spacing.empty())
    throw VolumeReadError(file, "ImagePositionPatient (0020,0032), ImageOrientationPatient (0020,0037) or "
                                "PixelSpacing (0028,0030) missing");
  // PixelSpacing is (between rows, between columns): y first.
  std::swap(spacing[0], spacing[1]);
  // Frames of one file: their step from the first two frames' positions
  // (an enhanced image), else the spacing between slices, else the slice
  // thickness; 0 where none is given.
  double frameStep = 0;
  if (s.dims[2] > 1) {
    const gdcm::DataSet* perFrame = ImageAttributes::firstItem(f.GetDataSet(), gdcm::Tag(0x5200, 0x9230));
    const gdcm::SequenceOfItems* framesSequence = ImageAttributes::sequence(f.GetDataSet(), gdcm::Tag(0x5200, 0x9230));
    if (perFrame && framesSequence && framesSequence->GetNumberOfItems() >= 2) {
      const ImageAttributes frame0{*perFrame, file};
      const ImageAttributes frame1{framesSequence->GetItem(2).GetNestedDataSet(), file};
      const gdcm::DataSet* position0 = ImageAttributes::firstItem(frame0.top, planePosition);
      const gdcm::DataSet* position1 = ImageAttributes::firstItem(frame1.top, planePosition);
      if (position0 && position1) {
        const std::vector<double> p0 =
            ImageAttributes{*position0, file}.numbers(gdcm::Tag(0x0020, 0x0032), 3, "ImagePositionPatient");
        const std::vector<double> p1 =
            ImageAttributes{*position1, file}.numbers(gdcm::Tag(0x0020, 0x0032), 3, "ImagePositionPatient");
        if (p0.size() == 3 && p1.size() == 3) frameStep = (Vec3(p1[0], p1[1], p1[2]) - Vec3(p0[0], p0[1], p0[2])).norm();
      }
    }
    for (const gdcm::Tag& step : {gdcm::Tag(0x0018, 0x0088), gdcm::Tag(0x0018, 0x0050)}) {
      if (frameStep > 0) break;
      const std::vector<double> value = image.numbers(step, 1, "a slice spacing", pixelMeasures);
      if (!value.empty()) frameStep = std::abs(value[0]);
    }
  }
  std::vector<double> rescale;
  const std::vector<double> intercept = image.numbers(gdcm::Tag(0x0028, 0x1052), 1, "RescaleIntercept", valueTransformation);
  const std::vector<double> slope = image.numbers(gdcm::Tag(0x0028, 0x1053), 1, "RescaleSlope", valueTransformation);
  if (!intercept.empty() || !slope.empty())
    rescale = {intercept.empty() ? 0.0 : intercept[0], slope.empty() ? 1.0 : slope[0]};
  s.origin = Vec3(origin[0], origin[1], origin[2]);
  s.rowDirection = Vec3(cosines[0], cosines[1], cosines[2]);
  s.columnDirection = Vec3(cosines[3], cosines[4], cosines[5]);
  if (std::abs(s.rowDirection.norm() - 1) > 1e-3 || std::abs(s.columnDirection.norm() - 1) > 1e-3 ||
      std::abs(s.rowDirection.dot(s.columnDirection)) > 1e-3)
    throw VolumeReadError(file, "ImageOrientationPatient (0020,0037) is not two orthogonal unit vectors");
  s.pixelSpacing = Eigen::Vector2d(spacing[0], spacing[1]);
  if (!(s.pixelSpacing.minCoeff() > 0) || !s.pixelSpacing.allFinite())
    throw VolumeReadError(file, "PixelSpacing (0028,0030) is not positive");
  s.frameStep = frameStep;
  if (rescale.size() == 2) s.intercept = rescale[0], s.slope = rescale[1];
  if (!(s.slope != 0) || !std::isfinite(s.slope) || !std::isfinite(s.intercept))
    throw VolumeReadError(file, "RescaleSlope (0028,1053) is zero or not finite");
  return s;
}

// That the file holds the `expected` bytes of its (uncompressed, little
// endian) Pixel Data: the element is the last (7FE0,0010) tag in the last
// expected + 4 KiB of the file, its value starting 8 (implicit VR) or 12
// (explicit VR) bytes after the tag.
void checkPixelDataLength(const fs::path& file, uint64_t dataSetEnd, uint64_t expected) {
  std::ifstream in(file, std::ios::binary);
  const uint64_t size = dataSetEnd;  // the file less any padding after its data set
  const uint64_t tail = std::min<uint64_t>(size, expected + 4096);
  std::string bytes(tail, '\0');
  in.seekg(std::streamoff(size - tail));
  in.read(bytes.data(), std::streamsize(tail));
  const size_t tag = bytes.rfind(std::string("\xE0\x7F\x10\x00", 4));
  if (tag == std::string::npos) throw VolumeReadError(file, "no Pixel Data (7FE0,0010) near the end of the file");
  const bool explicitVr = tag + 6 <= bytes.size() && (bytes.compare(tag + 4, 2, "OW") == 0 || bytes.compare(tag + 4, 2, "OB") == 0);
  const uint64_t start = (size - tail) + tag + (explicitVr ? 12 : 8);
  if (size < start + expected)
    throw VolumeReadError(file, "its pixel data are cut short: " + std::to_string(size > start ? size - start : 0) +
                                    " bytes of the image's " + std::to_string(expected));
}

// The stored samples of a file, and their type. Decoded from the pixel
// attributes the structure check read, through a gdcm::Image built here:
// GDCM's own image reader would also parse the file's palettes, icons,
// overlays and curves, none of which a density volume needs, and asserts on
// malformed ones.
std::vector<uint8_t> readPixels(const Slice& slice, NumberType& type) {
  const DicomPixelAttributes& a = slice.pixel;
  const bool isSigned = a.pixelRepresentation == 1;
  switch (a.bitsAllocated) {
    case 8: type = isSigned ? NumberType::kInt8 : NumberType::kUInt8; break;
    case 16: type = isSigned ? NumberType::kInt16 : NumberType::kUInt16; break;
    case 32: type = isSigned ? NumberType::kInt32 : NumberType::kUInt32; break;
    default:
      throw VolumeReadError(slice.file, "BitsAllocated (0028,0100) is " + std::to_string(a.bitsAllocated) +
                                            " (expected 8, 16 or 32)");
  }
  gdcm::Reader reader;
  std::unique_ptr<std::istringstream> stream;
  openForGdcm(reader, slice.file, a, stream);
  if (!reader.Read()) throw VolumeReadError(slice.file, "GDCM cannot read its data set");
  const gdcm::DataSet& ds = reader.GetFile().GetDataSet();
  const gdcm::Tag pixelTag(0x7fe0, 0x0010);
  if (!ds.FindDataElement(pixelTag)) throw VolumeReadError(slice.file, "no Pixel Data (7FE0,0010)");
  gdcm::PixelFormat format;
  format.SetSamplesPerPixel(1);
  format.SetBitsAllocated(a.bitsAllocated);
  format.SetBitsStored(a.bitsStored);
  format.SetHighBit(a.highBit);
  format.SetPixelRepresentation(a.pixelRepresentation);
  gdcm::Image image;
  image.SetNumberOfDimensions(slice.dims[2] > 1 ? 3 : 2);
  for (unsigned d = 0; d < image.GetNumberOfDimensions(); ++d) image.SetDimension(d, slice.dims[d]);
  image.SetPixelFormat(format);
  image.SetPhotometricInterpretation(a.photometricInterpretation == "MONOCHROME1"
                                         ? gdcm::PhotometricInterpretation::MONOCHROME1
                                         : gdcm::PhotometricInterpretation::MONOCHROME2);
  const gdcm::TransferSyntax syntax = reader.GetFile().GetHeader().GetDataSetTransferSyntax();
  image.SetTransferSyntax(syntax);
  image.SetDataElement(ds.GetDataElement(pixelTag));
  const size_t expected = size_t(slice.dims[0]) * slice.dims[1] * slice.dims[2] * byteSize(type);
  // Uncompressed data cut short: GDCM reads what is there, warns and pads.
  if (!ds.GetDataElement(pixelTag).GetSequenceOfFragments()) checkPixelDataLength(slice.file, a.dataSetEnd, expected);
  std::vector<uint8_t> bytes(expected);
  if (!image.GetBuffer(reinterpret_cast<char*>(bytes.data()))) {
    const char* name = syntax.GetString();
    throw VolumeReadError(slice.file, std::string("its pixel data cannot be decoded (transfer syntax ") +
                                          (name ? name : "unknown") + ": not supported by this build)");
  }
  return bytes;
}

// "7.02 mm": a slice position or step, to the micrometre.
std::string millimetres(double mm) { return formatDouble(std::round(mm * 1000) / 1000) + " mm"; }

// Steps closer to the series' step than this fraction are even (rounding of
// the positions); up to kMostUnevenStep they are resampled; beyond, refused.
constexpr double kEvenStep = 0.01, kMostUnevenStep = 0.1;

// The samples of `slices` (stored order, slices sorted by position, `type`)
// at `positions` along the normal: each interpolated linearly between the
// stored slices around it, as 32-bit floats.
std::vector<uint8_t> resampleEvenly(const std::vector<Slice>& slices, const std::vector<double>& positions,
                                    const std::vector<uint8_t>& samples, NumberType type) {
  const size_t perSlice = size_t(slices.front().dims[0]) * slices.front().dims[1];
  const size_t bytesPerSlice = perSlice * byteSize(type);
  std::vector<double> below, above;
  std::vector<uint8_t> out(positions.size() * perSlice * sizeof(float));
  size_t k = 0;
  for (size_t j = 0; j < positions.size(); ++j) {
    while (k + 2 < slices.size() && slices[k + 1].position < positions[j]) ++k;
    const double span = slices[k + 1].position - slices[k].position;
    const double w = std::clamp((positions[j] - slices[k].position) / span, 0.0, 1.0);
    const auto sliceBytes = [&](size_t index) {
      return std::string_view(reinterpret_cast<const char*>(samples.data()) + index * bytesPerSlice, bytesPerSlice);
    };
    below.clear();
    above.clear();
    decodeNumbers(sliceBytes(k), type, false, below);
    decodeNumbers(sliceBytes(k + 1), type, false, above);
    float* target = reinterpret_cast<float*>(out.data()) + j * perSlice;
    for (size_t i = 0; i < perSlice; ++i) target[i] = float((1 - w) * below[i] + w * above[i]);
  }
  return out;
}

}  // namespace

bool looksLikeDicom(std::span<const uint8_t> head) {
  return head.size() >= 132 && std::equal(head.begin() + 128, head.begin() + 132, "DICM");
}

DensityVolume readDicom(const fs::path& path, const std::string& seriesUid, VolumeReadNotes* notes) {
  // GDCM's own warnings go to stderr; what matters comes back as errors here.
  gdcm::Trace::SetWarning(false);
  gdcm::Trace::SetDebug(false);
  gdcm::Trace::SetError(false);  // the reader reports its own errors, naming the file
  // The files: the one given, or the directory's DICOM files.
  std::vector<fs::path> files;
  std::error_code ec;
  if (fs::is_directory(path, ec)) {
    for (const auto& entry : fs::directory_iterator(path, ec))
      if (entry.is_regular_file() && hasDicomMagic(entry.path())) files.push_back(entry.path());
    if (files.empty()) throw VolumeReadError(path, "a directory with no DICOM file in it (expected one series)");
  } else {
    files.push_back(path);
  }
  std::sort(files.begin(), files.end());
  std::vector<Slice> slices;
  for (const fs::path& file : files) slices.push_back(readHeader(file));

  // One series: the only one, or the one asked for.
  std::map<std::string, std::pair<std::string, size_t>> series;  // uid -> description, files
  for (const Slice& s : slices) {
    auto& entry = series[s.series];
    entry.first = s.description;
    ++entry.second;
  }
  if (!seriesUid.empty()) {
    if (!series.count(seriesUid)) {
      std::string known;
      for (const auto& [uid, info] : series) known += (known.empty() ? "" : ", ") + uid;
      throw VolumeReadError(path, "no series " + seriesUid + " here (its series: " + known + ")");
    }
    std::erase_if(slices, [&](const Slice& s) { return s.series != seriesUid; });
  } else if (series.size() > 1) {
    std::string list;
    for (const auto& [uid, info] : series)
      list += "\n  " + uid + " (" + (info.first.empty() ? "no description" : "\"" + info.first + "\"") + ", " +
              std::to_string(info.second) + " files)";
    throw VolumeReadError(path, std::to_string(series.size()) + " series in one directory; pick one with " +
                                    "file=\"" + path.string() + "?series=UID\":" + list);
  }

  // One grid: same size and orientation; sorted along the normal.
  const Slice& first = slices.front();
  const Vec3 normal = first.rowDirection.cross(first.columnDirection);
  for (Slice& s : slices) {
    if (s.dims[0] != first.dims[0] || s.dims[1] != first.dims[1])
      throw VolumeReadError(s.file, "an image of " + std::to_string(s.dims[0]) + " x " + std::to_string(s.dims[1]) +
                                        " in a series of " + std::to_string(first.dims[0]) + " x " +
                                        std::to_string(first.dims[1]));
    if ((s.rowDirection - first.rowDirection).norm() > 1e-4 || (s.columnDirection - first.columnDirection).norm() > 1e-4)
      throw VolumeReadError(s.file, "an orientation unlike the series' first file's " + first.file.filename().string());
    if ((s.pixelSpacing - first.pixelSpacing).norm() > 1e-4)
      throw VolumeReadError(s.file, "a PixelSpacing unlike the series' first file's " + first.file.filename().string());
    if (s.slope != first.slope || s.intercept != first.intercept)
      throw VolumeReadError(s.file, "a rescale unlike the series' first file's (one slope and intercept per series "
                                    "is read)");
    s.position = s.origin.dot(normal);
  }
  std::sort(slices.begin(), slices.end(), [](const Slice& a, const Slice& b) { return a.position < b.position; });

  StoredVolume stored;
  Vec3 sliceStep = normal;  // mm from one slice to the next
  std::vector<double> evenPositions;  // mm along the normal: the even grid, when the stored slices are not
  if (slices.size() == 1) {
    stored.dims = {first.dims[0], first.dims[1], first.dims[2]};
    sliceStep = normal * (first.frameStep > 0 ? first.frameStep : 1.0);
  } else {
    if (first.dims[2] != 1) throw VolumeReadError(path, "multi-frame files in a series of several files");
    std::vector<double> steps;
    for (size_t k = 1; k < slices.size(); ++k) steps.push_back(slices[k].position - slices[k - 1].position);
    std::vector<double> sorted = steps;
    std::sort(sorted.begin(), sorted.end());
    const double step = sorted[sorted.size() / 2];
    double farthest = 0;  // mm, the step farthest from the series' step
    for (size_t k = 0; k < steps.size(); ++k) {
      const std::string pair = slices[k].file.filename().string() + " and " + slices[k + 1].file.filename().string();
      if (steps[k] < 1e-3 * step || steps[k] < 1e-6)
        throw VolumeReadError(path, "two slices at one position: " + pair);
      if (steps[k] > 1.5 * step)
        throw VolumeReadError(path, "a slice is missing between " + pair + " (" + std::to_string(steps[k]) +
                                        " mm apart, the series' step is " + std::to_string(step) + " mm)");
      if (std::abs(steps[k] - step) > kMostUnevenStep * step)
        throw VolumeReadError(path, "uneven slice steps: " + pair + " are " + std::to_string(steps[k]) +
                                        " mm apart, the series' step is " + std::to_string(step) +
                                        " mm (steps within " + std::to_string(int(kMostUnevenStep * 100)) +
                                        "% of it are resampled onto an even grid)");
      farthest = std::max(farthest, std::abs(steps[k] - step));
    }
    stored.dims = {first.dims[0], first.dims[1], int64_t(slices.size())};
    // From the first slice to the last, the mean step. A tilted gantry makes
    // it leave the normal: the grid is sheared, and assembleVolume resamples
    // it onto an axis-aligned one (as it does an oblique plane).
    sliceStep = (slices.back().origin - slices.front().origin) / double(slices.size() - 1);
    if (farthest > kEvenStep * step) {
      // Uneven within the tolerance (positions rounded by the scanner): each
      // slice of the even grid interpolated between the two stored slices
      // around it, as 3D Slicer regularises such series.
      evenPositions.resize(slices.size());
      for (size_t k = 0; k < slices.size(); ++k)
        evenPositions[k] = slices.front().position +
                           double(k) * (slices.back().position - slices.front().position) / double(slices.size() - 1);
      if (notes)
        notes->warnings.push_back(
            "uneven slice steps, " + millimetres(sorted.front()) + " to " + millimetres(sorted.back()) +
            " (the series' median step " + millimetres(step) + "): resampled onto an even " +
            millimetres((slices.back().position - slices.front().position) / double(slices.size() - 1)) +
            " grid by linear interpolation between the stored slices");
    }
  }
  checkDimensions(stored.dims, "the series' Rows, Columns and slices", path);
  stored.axes.col(0) = first.rowDirection * first.pixelSpacing.x();
  stored.axes.col(1) = first.columnDirection * first.pixelSpacing.y();
  stored.axes.col(2) = sliceStep;
  stored.origin = slices.front().origin;
  stored.scaling = {first.slope, first.intercept};

  std::vector<uint8_t> samples;
  samples.reserve(stored.voxelCount() * 4);
  NumberType type = NumberType::kInt16;
  for (size_t k = 0; k < slices.size(); ++k) {
    NumberType sliceType = NumberType::kInt16;
    const std::vector<uint8_t> pixels = readPixels(slices[k], sliceType);
    if (k > 0 && sliceType != type)
      throw VolumeReadError(slices[k].file, "samples of " + numberTypeName(sliceType) + " in a series of " +
                                                numberTypeName(type));
    type = sliceType;
    samples.insert(samples.end(), pixels.begin(), pixels.end());
  }
  stored.layout = {type, false};
  if (!evenPositions.empty()) {
    samples = resampleEvenly(slices, evenPositions, samples, type);
    stored.layout = {NumberType::kFloat32, false};
  }
  size_t padded = 0;
  const Slice* example = nullptr;
  for (const Slice& slice : slices)
    if (slice.pixel.trailingZeros > 0) ++padded, example = example ? example : &slice;
  if (padded > 0 && notes)
    notes->notes.push_back(std::to_string(padded) + " of " + std::to_string(slices.size()) +
                           " files carry zeros after their data set, padding that is ignored (" +
                           example->file.filename().string() + ": " + std::to_string(example->pixel.trailingZeros) +
                           " bytes)");
  return assembleVolume(stored, samples, path);
}

}  // namespace trephine::formats
