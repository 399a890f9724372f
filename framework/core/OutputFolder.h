#pragma once
// A folder the program writes into, opened once. Everything it makes,
// replaces or removes inside is reached from the folder's descriptor
// (openat, mkdirat, renameat, unlinkat) one name at a time and never through
// a link: a link or special file planted in an output folder (a `view` that
// points at another folder, a `vtk` that points at /etc, a temporary name
// that points at a file elsewhere) is refused or replaced, never written
// through, emptied or followed. The folder itself is opened as named: links
// in the path a user gives are the user's own.
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include "framework/core/FileWriteError.h"

namespace trephine {

// What a name in a folder is, without following a link.
enum class EntryKind { kMissing, kFile, kFolder, kLink, kSpecial };

class OutputFolder {
 public:
  // Opens `path`, creating it and its parents when missing. Throws
  // FileWriteError when it cannot, or when it is not a folder.
  static OutputFolder create(const std::filesystem::path& path);
  // Opens the existing folder `path`. Throws FileWriteError.
  static OutputFolder open(const std::filesystem::path& path);

  // The folder `relative` inside this one (names separated by '/', no '..'),
  // each made when missing. A link, a file or a special file on the way is
  // refused: throws FileWriteError naming it.
  OutputFolder subfolder(const std::filesystem::path& relative) const;

  // What `name` (one name in this folder) is, without following it.
  EntryKind kind(const std::string& name) const;
  // Removes `name` from this folder: a file or a link itself; a folder with
  // everything in it, never following a link inside. Nothing when missing.
  // Throws FileWriteError when something cannot be removed.
  void remove(const std::string& name) const;

  // Removes everything in this folder, as remove() does.
  void clear() const;

  const std::filesystem::path& path() const { return m_path; }
  int descriptor() const { return *m_descriptor; }

 private:
  OutputFolder(std::shared_ptr<const int> descriptor, std::filesystem::path path);
  std::shared_ptr<const int> m_descriptor;  // shared by copies; closed with the last
  std::filesystem::path m_path;             // for messages
};

// Where a writer puts a file: a path as a user named it (its folder opened as
// given), or a name inside an opened OutputFolder (reached without links).
class OutputPath {
 public:
  OutputPath(std::filesystem::path file) : m_relative(std::move(file)) {}  // NOLINT: a path is one
  OutputPath(const std::string& file) : m_relative(file) {}               // NOLINT
  OutputPath(const char* file) : m_relative(file) {}                      // NOLINT
  OutputPath(OutputFolder folder, std::filesystem::path relative)
      : m_folder(std::move(folder)), m_relative(std::move(relative)) {}

  // Another file in the same folder (a MetaImage's data file beside its header).
  OutputPath beside(const std::string& name) const;
  // The whole path, for messages and for names a format records.
  std::filesystem::path path() const { return m_folder ? m_folder->path() / m_relative : m_relative; }
  const std::optional<OutputFolder>& folder() const { return m_folder; }
  const std::filesystem::path& relative() const { return m_relative; }

 private:
  std::optional<OutputFolder> m_folder;
  std::filesystem::path m_relative;  // inside m_folder; without one, the path as named
};

}  // namespace trephine
