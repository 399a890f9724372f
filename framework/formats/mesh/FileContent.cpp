#include "framework/formats/mesh/FileContent.h"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <system_error>

#include "framework/formats/encoding/Inflate.h"
#include "framework/formats/mesh/TetMeshReader.h"

namespace trephine::formats {

bool startsWithGzipMagic(std::string_view bytes) {
  return bytes.size() >= 2 && uint8_t(bytes[0]) == 0x1f && uint8_t(bytes[1]) == 0x8b;
}

std::string readFileContent(const std::filesystem::path& file) {
  std::error_code error;
  const std::filesystem::file_status status = std::filesystem::status(file, error);
  if (error || !std::filesystem::exists(status))
    throw TetMeshReadError(file, "cannot open: " + (error ? error.message() : std::string("no such file")));
  // Devices, pipes and directories could block or have no size.
  if (!std::filesystem::is_regular_file(status)) throw TetMeshReadError(file, "cannot open: not a regular file");
  const uint64_t size = std::filesystem::file_size(file, error);
  if (error) throw TetMeshReadError(file, "cannot read the file size: " + error.message());
  if (size == 0) throw TetMeshReadError(file, "the file is empty (expected a tetrahedral mesh)");
  if (size > kMaxContentBytes)
    throw TetMeshReadError(file, "the file has " + std::to_string(size) + " bytes, more than the " +
                                     std::to_string(kMaxContentBytes) + " a mesh reader accepts");
  std::ifstream stream(file, std::ios::binary);
  if (!stream) throw TetMeshReadError(file, std::string("cannot open: ") + std::strerror(errno));
  std::string bytes(static_cast<size_t>(size), '\0');
  stream.read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (static_cast<uint64_t>(stream.gcount()) != size)
    throw TetMeshReadError(file, "read error after " + std::to_string(stream.gcount()) + " of " + std::to_string(size) +
                                     " bytes (the file changed or the disk failed)");
  if (!startsWithGzipMagic(bytes)) return bytes;
  const WholeStream whole =
      inflateWhole({reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size()}, kMaxContentBytes);
  switch (whole.problem) {
    case WholeStream::Problem::kNone:
      break;
    case WholeStream::Problem::kCorrupt:
      throw TetMeshReadError(file, "corrupt gzip data (zlib: " + whole.zlibReason + ")");
    case WholeStream::Problem::kTooLarge:
      throw TetMeshReadError(file, "the gzip content is larger than " + std::to_string(kMaxContentBytes) +
                                       " bytes (expected a mesh of at most 2^28 nodes and tetrahedra)");
    case WholeStream::Problem::kTruncated:
      throw TetMeshReadError(file, "the gzip data ends before the end of the compressed stream (truncated file)");
  }
  std::string content(whole.bytes.begin(), whole.bytes.end());
  if (content.empty()) throw TetMeshReadError(file, "the gzip file holds no data (expected a tetrahedral mesh)");
  if (startsWithGzipMagic(content))
    throw TetMeshReadError(file, "gzip inside gzip is not supported (expected one gzip layer)");
  return content;
}

}  // namespace trephine::formats
