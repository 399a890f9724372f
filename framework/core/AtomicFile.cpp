#include "framework/core/AtomicFile.h"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <random>
#include <streambuf>
#include <vector>

namespace trephine {

namespace fs = std::filesystem;

// The temporary file's bytes, buffered and written to its descriptor; the
// first failed write's errno is kept for the message.
class AtomicFile::Buffer : public std::streambuf {
 public:
  explicit Buffer(int descriptor) : m_descriptor(descriptor), m_bytes(1 << 16) {
    setp(m_bytes.data(), m_bytes.data() + m_bytes.size());
  }
  ~Buffer() override { close(); }
  int error() const { return m_error; }
  // Writes what is buffered and closes; false when any write failed.
  bool close() {
    if (m_descriptor < 0) return m_error == 0;
    flushBytes();
    if (::close(m_descriptor) != 0 && !m_error) m_error = errno;
    m_descriptor = -1;
    return m_error == 0;
  }

 protected:
  int_type overflow(int_type c) override {
    if (!flushBytes()) return traits_type::eof();
    if (!traits_type::eq_int_type(c, traits_type::eof())) {
      *pptr() = traits_type::to_char_type(c);
      pbump(1);
    }
    return traits_type::not_eof(c);
  }
  int sync() override { return flushBytes() ? 0 : -1; }

 private:
  bool flushBytes() {
    const char* from = pbase();
    while (!m_error && from < pptr()) {
      const ssize_t n = ::write(m_descriptor, from, size_t(pptr() - from));
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) m_error = n < 0 ? errno : EIO;
      else from += n;
    }
    setp(m_bytes.data(), m_bytes.data() + m_bytes.size());
    return m_error == 0;
  }
  int m_descriptor;
  int m_error = 0;
  std::vector<char> m_bytes;
};

namespace {

// A suffix no one can guess, so a name planted beforehand is never the one opened.
std::string unguessableSuffix() {
  static std::atomic<uint64_t> counter{std::random_device{}()};
  static const uint64_t salt = (uint64_t(std::random_device{}()) << 32) ^ std::random_device{}();
  const uint64_t value = (counter.fetch_add(0x9E3779B97F4A7C15ull) ^ salt) * 0xBF58476D1CE4E5B9ull;
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(value));
  return text;
}

// The folder of a file as named, the message naming the file.
OutputFolder folderOf(const fs::path& file) {
  const fs::path folder = file.has_parent_path() ? file.parent_path() : fs::path(".");
  try {
    return OutputFolder::open(folder);
  } catch (const FileWriteError& e) {
    throw FileWriteError(file, std::string("cannot create it: ") + e.what());
  }
}

}  // namespace

AtomicFile::AtomicFile(const fs::path& file)
    : m_file(file),
      m_folder(folderOf(file)),
      m_name(file.filename().string()) {
  open();
}

AtomicFile::AtomicFile(const OutputFolder& folder, const fs::path& relative)
    : m_file(folder.path() / relative),
      m_folder(relative.has_parent_path() ? folder.subfolder(relative.parent_path()) : folder),
      m_name(relative.filename().string()) {
  open();
}

AtomicFile::AtomicFile(const OutputPath& file)
    : m_file(file.path()),
      m_folder(file.folder() ? (file.relative().has_parent_path() ? file.folder()->subfolder(file.relative().parent_path())
                                                                   : *file.folder())
                             : folderOf(file.relative())),
      m_name(file.relative().filename().string()) {
  open();
}

void AtomicFile::open() {
  if (m_name.empty() || m_name == "." || m_name == "..") throw FileWriteError(m_file, "expected a file name");
  // Tried again under another name only when one is taken (a file left by a
  // killed process, or something planted there).
  for (int attempt = 0; attempt < 100; ++attempt) {
    m_temporary = m_name + ".partial-" + std::to_string(::getpid()) + "-" + unguessableSuffix();
    const int descriptor = ::openat(m_folder.descriptor(), m_temporary.c_str(),
                                    O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
    if (descriptor >= 0) {
      try {
        m_buffer = std::make_unique<Buffer>(descriptor);  // owns the descriptor from here
        m_stream = std::make_unique<std::ostream>(m_buffer.get());
      } catch (...) {
        if (!m_buffer) ::close(descriptor);
        m_buffer.reset();
        ::unlinkat(m_folder.descriptor(), m_temporary.c_str(), 0);
        throw;
      }
      return;
    }
    if (errno != EEXIST)
      throw FileWriteError(m_file, "cannot create " + (m_folder.path() / m_temporary).string() + ": " +
                                       std::strerror(errno));
  }
  throw FileWriteError(m_file, "cannot create a temporary file beside it: every name tried is taken");
}

AtomicFile::~AtomicFile() {
  if (m_committed || !m_buffer) return;
  m_stream.reset();
  m_buffer->close();
  ::unlinkat(m_folder.descriptor(), m_temporary.c_str(), 0);
}

std::ostream& AtomicFile::stream() { return *m_stream; }

void AtomicFile::write(const char* bytes, size_t size) {
  m_stream->write(bytes, static_cast<std::streamsize>(size));
  if (!*m_stream)
    throw FileWriteError(m_file, std::string("write failed: ") + std::strerror(m_buffer->error() ? m_buffer->error() : EIO));
}

void AtomicFile::commit() {
  // A stream that failed while it was written keeps its failbit; one whose
  // buffered bytes cannot be written fails at the close.
  const bool streamed = bool(*m_stream);
  const bool closed = m_buffer->close();
  if (!streamed || !closed) {
    const int error = m_buffer->error();
    throw FileWriteError(m_file, std::string("write failed: ") +
                                     (error ? std::strerror(error) : "the stream reports an error"));
  }
  // renameat replaces whatever has the final name, a link included, and
  // never writes through it; a folder there is not replaced.
  if (::renameat(m_folder.descriptor(), m_temporary.c_str(), m_folder.descriptor(), m_name.c_str()) != 0)
    throw FileWriteError(m_file, std::string("cannot rename the written file into place: ") + std::strerror(errno));
  m_committed = true;
}

void writeFileAtomically(const OutputPath& file, const std::function<void(std::ostream&)>& writer) {
  AtomicFile out(file);
  writer(out.stream());
  out.commit();
}

void writeFileAtomically(const OutputFolder& folder, const fs::path& relative,
                         const std::function<void(std::ostream&)>& writer) {
  AtomicFile out(folder, relative);
  writer(out.stream());
  out.commit();
}

}  // namespace trephine
