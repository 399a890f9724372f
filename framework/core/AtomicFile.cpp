#include "framework/core/AtomicFile.h"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <system_error>

namespace trephine {

FileWriteError::FileWriteError(const std::filesystem::path& file, const std::string& problem)
    : std::runtime_error(file.string() + ": " + problem) {}

AtomicFile::AtomicFile(const std::filesystem::path& file)
    : m_file(file), m_temporary(file.string() + ".partial-" + std::to_string(::getpid())) {
  m_stream.open(m_temporary, std::ios::binary | std::ios::trunc);
  if (!m_stream)
    throw FileWriteError(m_file, "cannot create " + m_temporary.string() + ": " + std::strerror(errno));
}

AtomicFile::~AtomicFile() {
  if (m_committed) return;
  m_stream.close();
  std::error_code ignored;
  std::filesystem::remove(m_temporary, ignored);
}

void AtomicFile::write(const char* bytes, size_t size) {
  m_stream.write(bytes, static_cast<std::streamsize>(size));
  if (!m_stream) throw FileWriteError(m_file, std::string("write failed: ") + std::strerror(errno));
}

void AtomicFile::commit() {
  // A stream that failed while it was written keeps its failbit (errno is
  // still the failed write's: formatting sets none); one whose buffered bytes
  // cannot be written fails at the flush.
  if (m_stream) {
    errno = 0;
    m_stream.flush();
    if (m_stream) m_stream.close();
  }
  if (!m_stream) {
    const int error = errno;
    throw FileWriteError(m_file, std::string("write failed: ") +
                                     (error ? std::strerror(error) : "the stream reports an error"));
  }
  std::error_code error;
  std::filesystem::rename(m_temporary, m_file, error);
  if (error) throw FileWriteError(m_file, "cannot rename the written file into place: " + error.message());
  m_committed = true;
}

void writeFileAtomically(const std::filesystem::path& file, const std::function<void(std::ostream&)>& writer) {
  AtomicFile out(file);
  writer(out.stream());
  out.commit();
}

}  // namespace trephine
