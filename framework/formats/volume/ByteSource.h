#pragma once
// Random access to the bytes of a volume file: either the file on disk or,
// for gzip-wrapped files, its decompressed content in memory. Readers ask for
// ranges they have checked against size() first, so a corrupt header never
// leads to reading past the end or allocating more than the file holds.
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <span>
#include <utility>
#include <vector>

namespace trephine::formats {

class ByteSource {
 public:
  virtual ~ByteSource() = default;
  // The file named in error messages (also the base of relative data file names).
  const std::filesystem::path& path() const { return m_path; }
  virtual uint64_t size() const = 0;
  // Copies bytes [offset, offset + out.size()) into `out`; the range must lie inside size().
  virtual void read(uint64_t offset, std::span<uint8_t> out) const = 0;
  // The bytes [offset, offset + count), clipped to the end of the source.
  std::vector<uint8_t> readClipped(uint64_t offset, uint64_t count) const;

 protected:
  explicit ByteSource(std::filesystem::path path) : m_path(std::move(path)) {}

 private:
  std::filesystem::path m_path;
};

// A regular file on disk (devices, pipes and directories are refused: they
// could block or have no size).
class FileByteSource : public ByteSource {
 public:
  explicit FileByteSource(const std::filesystem::path& path);
  uint64_t size() const override { return m_size; }
  void read(uint64_t offset, std::span<uint8_t> out) const override;

 private:
  mutable std::ifstream m_stream;
  uint64_t m_size = 0;
};

// Bytes already in memory (a decompressed file), named after the file they came from.
class MemoryByteSource : public ByteSource {
 public:
  MemoryByteSource(const std::filesystem::path& path, std::vector<uint8_t> bytes)
      : ByteSource(path), m_bytes(std::move(bytes)) {}
  uint64_t size() const override { return m_bytes.size(); }
  void read(uint64_t offset, std::span<uint8_t> out) const override;

 private:
  std::vector<uint8_t> m_bytes;
};

}  // namespace trephine::formats
