#include "framework/formats/volume/ByteSource.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <system_error>

#include "framework/formats/volume/VolumeReader.h"

namespace trephine::formats {

std::vector<uint8_t> ByteSource::readClipped(uint64_t offset, uint64_t count) const {
  const uint64_t available = offset < size() ? size() - offset : 0;
  std::vector<uint8_t> bytes(static_cast<size_t>(std::min(count, available)));
  if (!bytes.empty()) read(offset, bytes);
  return bytes;
}

FileByteSource::FileByteSource(const std::filesystem::path& path) : ByteSource(path) {
  std::error_code error;
  const std::filesystem::file_status status = std::filesystem::status(path, error);
  if (error || !std::filesystem::exists(status))
    throw VolumeReadError(path, "cannot open: " + (error ? error.message() : std::string("no such file")));
  if (!std::filesystem::is_regular_file(status)) throw VolumeReadError(path, "cannot open: not a regular file");
  m_size = std::filesystem::file_size(path, error);
  if (error) throw VolumeReadError(path, "cannot read the file size: " + error.message());
  m_stream.open(path, std::ios::binary);
  if (!m_stream) throw VolumeReadError(path, std::string("cannot open: ") + std::strerror(errno));
}

void FileByteSource::read(uint64_t offset, std::span<uint8_t> out) const {
  if (offset > m_size || out.size() > m_size - offset)
    throw VolumeReadError(path(), "internal error: read past the end of the file");
  m_stream.clear();
  m_stream.seekg(static_cast<std::streamoff>(offset));
  m_stream.read(reinterpret_cast<char*>(out.data()), static_cast<std::streamsize>(out.size()));
  if (!m_stream || static_cast<size_t>(m_stream.gcount()) != out.size())
    throw VolumeReadError(path(),
                          "read error at byte " + std::to_string(offset) + " (the file changed or the disk failed)");
}

void MemoryByteSource::read(uint64_t offset, std::span<uint8_t> out) const {
  if (offset > m_bytes.size() || out.size() > m_bytes.size() - offset)
    throw VolumeReadError(path(), "internal error: read past the end of the data");
  std::copy_n(m_bytes.begin() + static_cast<ptrdiff_t>(offset), out.size(), out.begin());
}

}  // namespace trephine::formats
