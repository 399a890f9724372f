#pragma once
// A file written through a temporary name in the same directory (so the
// rename cannot cross file systems) and renamed into place only once all of
// it is written and closed: a failed write leaves neither a partial file nor
// the temporary one. For outputs other tools read (volumes, meshes).
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <ostream>
#include <span>
#include <stdexcept>
#include <string>

namespace trephine {

// A file that cannot be written: the message starts with the file, then says
// what failed ("out/brain.mesh: cannot create ...: No such file or directory").
class FileWriteError : public std::runtime_error {
 public:
  FileWriteError(const std::filesystem::path& file, const std::string& problem);
};

class AtomicFile {
 public:
  // Opens the temporary file; throws FileWriteError when it cannot.
  explicit AtomicFile(const std::filesystem::path& file);
  ~AtomicFile();  // removes the temporary file unless committed
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  void write(const char* bytes, size_t size);
  void write(std::span<const uint8_t> bytes) { write(reinterpret_cast<const char*>(bytes.data()), bytes.size()); }
  void write(const std::string& text) { write(text.data(), text.size()); }
  // For writers that stream text: a failure shows at commit(), which flushes
  // and checks the stream before the file takes its name.
  std::ostream& stream() { return m_stream; }
  // Closes the temporary file and renames it to the final name.
  void commit();
  const std::filesystem::path& path() const { return m_file; }

 private:
  std::filesystem::path m_file;
  std::filesystem::path m_temporary;
  std::ofstream m_stream;
  bool m_committed = false;
};

// Writes `file` through an AtomicFile: `writer` streams the contents. Throws
// FileWriteError (no space left, no permission) and leaves no partial file.
void writeFileAtomically(const std::filesystem::path& file, const std::function<void(std::ostream&)>& writer);

}  // namespace trephine
