#include "plugins/tetra_brain/io/FileContent.h"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <system_error>

#include "plugins/tetra_brain/io/Inflate.h"
#include "plugins/tetra_brain/io/TetMeshReader.h"

namespace trephine::tetra {

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
  std::string content = inflateGzip(bytes, kMaxContentBytes, file);
  if (content.empty()) throw TetMeshReadError(file, "the gzip file holds no data (expected a tetrahedral mesh)");
  if (startsWithGzipMagic(content))
    throw TetMeshReadError(file, "gzip inside gzip is not supported (expected one gzip layer)");
  return content;
}

}  // namespace trephine::tetra
