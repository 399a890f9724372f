#include "framework/formats/volume/VolumeReader.h"

#include <algorithm>
#include <new>
#include <string>

#include "framework/formats/volume/ByteSource.h"
#include "framework/formats/volume/Decompress.h"
#include "framework/formats/volume/DicomReader.h"
#include "framework/formats/volume/HeaderText.h"
#include "framework/formats/volume/MetaImageReader.h"
#include "framework/formats/volume/NiftiReader.h"
#include "framework/formats/volume/NrrdReader.h"
#include "framework/formats/volume/StoredVolume.h"

namespace trephine::formats {

namespace {

enum class Format { kUnknown, kMetaImage, kNrrd, kNifti };

// Enough of the start of a file to recognise every supported format.
constexpr uint64_t kDetectionBytes = 4096;

bool isGzip(std::span<const uint8_t> head) { return head.size() >= 2 && head[0] == 0x1f && head[1] == 0x8b; }

Format formatFromContent(std::span<const uint8_t> head) {
  if (looksLikeNrrd(head)) return Format::kNrrd;
  if (looksLikeNifti(head)) return Format::kNifti;
  if (looksLikeMetaImage(head)) return Format::kMetaImage;
  return Format::kUnknown;
}

// The format the extension promises (".nii.gz" counts as ".nii").
Format formatFromExtension(std::filesystem::path file) {
  std::string extension = file.extension().string();
  if (equalsIgnoreCase(extension, ".gz")) extension = file.stem().extension().string();
  if (equalsIgnoreCase(extension, ".mha") || equalsIgnoreCase(extension, ".mhd")) return Format::kMetaImage;
  if (equalsIgnoreCase(extension, ".nrrd") || equalsIgnoreCase(extension, ".nhdr")) return Format::kNrrd;
  if (equalsIgnoreCase(extension, ".nii")) return Format::kNifti;
  return Format::kUnknown;
}

DensityVolume readFormat(Format format, const ByteSource& source) {
  switch (format) {
    case Format::kMetaImage:
      return readMetaImage(source);
    case Format::kNrrd:
      return readNrrd(source);
    case Format::kNifti:
      return readNifti(source);
    case Format::kUnknown:
      break;
  }
  throw VolumeReadError(source.path(),
                        "not a recognised volume file (expected MetaImage .mha/.mhd, NRRD .nrrd/.nhdr "
                        "or NIfTI .nii/.nii.gz)");
}

DensityVolume readVolumeFile(const std::filesystem::path& file, VolumeReadNotes* notes);

}  // namespace

DensityVolume readVolume(const std::filesystem::path& file, VolumeReadNotes* notes) {
  // A volume whose data is all there but more than this machine holds (a
  // header declaring 1100^3 voxels with a gzip of zeros behind it): said,
  // with the file and what it takes, instead of a bare std::bad_alloc.
  try {
    return readVolumeFile(file, notes);
  } catch (const std::bad_alloc&) {
    std::error_code ec;
    const uintmax_t bytes = std::filesystem::is_regular_file(file, ec) ? std::filesystem::file_size(file, ec) : 0;
    throw VolumeReadError(file, "the volume it declares does not fit in this machine's memory (its " +
                                    std::to_string(bytes) + " bytes of file hold more samples than can be kept)");
  }
}

namespace {

DensityVolume readVolumeFile(const std::filesystem::path& file, VolumeReadNotes* notes) {
  // A DICOM series: a directory (of one series, or DIR?series=UID to pick one).
  const std::string text = file.string();
  if (const size_t query = text.find("?series="); query != std::string::npos)
    return readDicom(text.substr(0, query), text.substr(query + 8), notes);
  std::error_code ec;
  if (std::filesystem::is_directory(file, ec)) return readDicom(file, "", notes);
  const FileByteSource source(file);
  if (source.size() == 0)
    throw VolumeReadError(file, "the file is empty (expected a MetaImage, NRRD or NIfTI volume)");
  const std::vector<uint8_t> head = source.readClipped(0, kDetectionBytes);
  if (looksLikeDicom(head)) return readDicom(file, "", notes);  // one slice, or a multi-frame image
  if (!isGzip(head)) {
    const Format format = formatFromContent(head);
    return readFormat(format != Format::kUnknown ? format : formatFromExtension(file), source);
  }
  // A gzip-wrapped file (.nii.gz): decompress it whole, then look inside. The
  // output is capped at the largest volume a header could describe.
  const std::vector<uint8_t> compressed = source.readClipped(0, source.size());
  std::vector<uint8_t> inflated =
      inflateVolumeData(compressed, kMaxHeaderBytes + kMaxVoxels * 8, file, "the largest volume a header can describe");
  if (inflated.empty()) throw VolumeReadError(file, "the gzip stream holds no data");
  const MemoryByteSource content(file, std::move(inflated));
  const std::vector<uint8_t> innerHead = content.readClipped(0, kDetectionBytes);
  if (isGzip(innerHead)) throw VolumeReadError(file, "gzip inside gzip is not supported (expected one gzip layer)");
  const Format format = formatFromContent(innerHead);
  return readFormat(format != Format::kUnknown ? format : formatFromExtension(file), content);
}

}  // namespace

}  // namespace trephine::formats
