#pragma once
// What the program reads back from a folder it or another run wrote (a run's
// outputs, a study's settings): only regular files reached without links, of
// a bounded size. A link to /etc/passwd, a device such as /dev/zero or a pipe
// planted there is refused with a message saying what it is, never read,
// copied or waited on.
#include <cstddef>
#include <filesystem>
#include <stdexcept>
#include <string>

namespace trephine {

class FolderInputError : public std::runtime_error {
 public:
  explicit FolderInputError(const std::string& message, bool missing = false)
      : std::runtime_error(message), m_missing(missing) {}
  // Nothing is there (as opposed to something that is not the folder's own file).
  bool missing() const { return m_missing; }

 private:
  bool m_missing;
};

// `folder / relative` when every part of `relative` is a folder (not a link)
// and its last part a regular file (not a link, device, pipe or socket).
// `folder` itself is taken as named. Throws FolderInputError naming the part.
std::filesystem::path regularFileInside(const std::filesystem::path& folder, const std::filesystem::path& relative);

// Whether `folder / relative` is such a file (false when missing or anything else).
bool isRegularFileInside(const std::filesystem::path& folder, const std::filesystem::path& relative);

// The bytes of `file`, opened without following a final link and without
// waiting on a pipe, when it is a regular file of at most `maxBytes`. Throws
// FolderInputError.
std::string readRegularFile(const std::filesystem::path& file, size_t maxBytes);

}  // namespace trephine
