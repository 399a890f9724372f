#pragma once
// A file written through a temporary name in the same folder (so the rename
// cannot cross file systems) and renamed into place only once all of it is
// written and closed: a failed write leaves neither a partial file nor the
// temporary one. The temporary file is made new (O_EXCL) under a name no one
// can guess and never through a link, and the rename replaces a link at the
// final name instead of writing through it: whatever was planted in the
// folder, nothing outside it is written.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <ostream>
#include <span>
#include <string>

#include "framework/core/FileWriteError.h"
#include "framework/core/OutputFolder.h"

namespace trephine {

class AtomicFile {
 public:
  // `file` as named: its folder is opened as given (links in a path a user
  // names are the user's). Throws FileWriteError when it cannot be created.
  explicit AtomicFile(const std::filesystem::path& file);
  // `relative` inside `folder`: the folders on the way are made when missing
  // and never followed through a link (OutputFolder::subfolder).
  AtomicFile(const OutputFolder& folder, const std::filesystem::path& relative);
  // Either of the above, as `file` says.
  explicit AtomicFile(const OutputPath& file);
  ~AtomicFile();  // removes the temporary file unless committed
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  void write(const char* bytes, size_t size);
  void write(std::span<const uint8_t> bytes) { write(reinterpret_cast<const char*>(bytes.data()), bytes.size()); }
  void write(const std::string& text) { write(text.data(), text.size()); }
  // For writers that stream text: a failure shows at commit(), which flushes
  // and checks the stream before the file takes its name.
  std::ostream& stream();
  // Closes the temporary file and renames it to the final name.
  void commit();
  const std::filesystem::path& path() const { return m_file; }

 private:
  class Buffer;
  void open();
  std::filesystem::path m_file;  // for messages
  OutputFolder m_folder;
  std::string m_name;       // in m_folder
  std::string m_temporary;  // in m_folder
  std::unique_ptr<Buffer> m_buffer;
  std::unique_ptr<std::ostream> m_stream;
  bool m_committed = false;
};

// Writes `file` through an AtomicFile: `writer` streams the contents. Throws
// FileWriteError (no space left, no permission) and leaves no partial file.
void writeFileAtomically(const OutputPath& file, const std::function<void(std::ostream&)>& writer);
void writeFileAtomically(const OutputFolder& folder, const std::filesystem::path& relative,
                         const std::function<void(std::ostream&)>& writer);

}  // namespace trephine
