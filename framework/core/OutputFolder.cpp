#include "framework/core/OutputFolder.h"

#include <dirent.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <system_error>
#include <vector>

namespace trephine {

namespace fs = std::filesystem;

namespace {

std::string errorText() { return std::strerror(errno); }

std::shared_ptr<const int> own(int descriptor) {
  return std::shared_ptr<const int>(new int(descriptor), [](const int* fd) {
    ::close(*fd);
    delete fd;
  });
}

EntryKind kindOf(const struct stat& status) {
  if (S_ISLNK(status.st_mode)) return EntryKind::kLink;
  if (S_ISDIR(status.st_mode)) return EntryKind::kFolder;
  if (S_ISREG(status.st_mode)) return EntryKind::kFile;
  return EntryKind::kSpecial;
}

const char* describe(EntryKind kind) {
  switch (kind) {
    case EntryKind::kLink:
      return "a link";
    case EntryKind::kFile:
      return "a file";
    case EntryKind::kSpecial:
      return "a special file (a device, a pipe or a socket)";
    default:
      return "not a folder";
  }
}

// Removes everything in the folder open at `descriptor`, links as links.
void emptyFolder(int descriptor, const fs::path& path) {
  // A descriptor of its own (not a dup: that would share the read position,
  // and a second listing would find nothing).
  const int listing = ::openat(descriptor, ".", O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (listing < 0) throw FileWriteError(path, "cannot list it: " + errorText());
  DIR* dir = ::fdopendir(listing);
  if (!dir) {
    ::close(listing);
    throw FileWriteError(path, "cannot list it: " + errorText());
  }
  std::vector<std::string> names;
  while (const dirent* entry = ::readdir(dir)) {
    const std::string name = entry->d_name;
    if (name != "." && name != "..") names.push_back(name);
  }
  ::closedir(dir);
  for (const std::string& name : names) {
    struct stat status {};
    if (::fstatat(descriptor, name.c_str(), &status, AT_SYMLINK_NOFOLLOW) != 0) continue;
    if (S_ISDIR(status.st_mode)) {
      const int inner = ::openat(descriptor, name.c_str(), O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
      if (inner < 0) throw FileWriteError(path / name, "cannot open it to remove it: " + errorText());
      const auto owned = own(inner);
      emptyFolder(inner, path / name);
      if (::unlinkat(descriptor, name.c_str(), AT_REMOVEDIR) != 0)
        throw FileWriteError(path / name, "cannot remove it: " + errorText());
    } else if (::unlinkat(descriptor, name.c_str(), 0) != 0 && errno != ENOENT) {
      throw FileWriteError(path / name, "cannot remove it: " + errorText());
    }
  }
}

}  // namespace

OutputFolder::OutputFolder(std::shared_ptr<const int> descriptor, fs::path path)
    : m_descriptor(std::move(descriptor)), m_path(std::move(path)) {}

OutputFolder OutputFolder::create(const fs::path& path) {
  std::error_code ec, isFolder;
  fs::create_directories(path.empty() ? fs::path(".") : path, ec);
  if (ec && !fs::is_directory(path, isFolder)) throw FileWriteError(path, "cannot create the folder: " + ec.message());
  return open(path);
}

OutputFolder OutputFolder::open(const fs::path& path) {
  const fs::path named = path.empty() ? fs::path(".") : path;
  const int descriptor = ::open(named.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (descriptor < 0) throw FileWriteError(path, "cannot open the folder: " + errorText());
  return OutputFolder(own(descriptor), path);
}

OutputFolder OutputFolder::subfolder(const fs::path& relative) const {
  if (relative.is_absolute()) throw FileWriteError(relative, "expected a folder inside " + m_path.string());
  OutputFolder folder = *this;
  for (const fs::path& part : relative) {
    const std::string name = part.string();
    if (name.empty() || name == ".") continue;
    if (name == "..") throw FileWriteError(m_path / relative, "'..' leaves the output folder");
    const fs::path inside = folder.m_path / name;
    int descriptor = ::openat(folder.descriptor(), name.c_str(), O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
    if (descriptor < 0 && errno == ENOENT) {
      if (::mkdirat(folder.descriptor(), name.c_str(), 0777) != 0 && errno != EEXIST)
        throw FileWriteError(inside, "cannot create the folder: " + errorText());
      descriptor = ::openat(folder.descriptor(), name.c_str(), O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
    }
    if (descriptor < 0) {
      const EntryKind found = folder.kind(name);
      if (found != EntryKind::kMissing && found != EntryKind::kFolder)
        throw FileWriteError(inside, std::string("is ") + describe(found) +
                                         ", not a folder of the output's own: refusing to write through it");
      throw FileWriteError(inside, "cannot open the folder: " + errorText());
    }
    folder = OutputFolder(own(descriptor), inside);
  }
  return folder;
}

EntryKind OutputFolder::kind(const std::string& name) const {
  struct stat status {};
  if (::fstatat(descriptor(), name.c_str(), &status, AT_SYMLINK_NOFOLLOW) != 0) return EntryKind::kMissing;
  return kindOf(status);
}

void OutputFolder::remove(const std::string& name) const {
  if (name.empty() || name == "." || name == ".." || name.find('/') != std::string::npos)
    throw FileWriteError(m_path / name, "expected one name in the folder");
  const EntryKind found = kind(name);
  if (found == EntryKind::kMissing) return;
  if (found == EntryKind::kFolder) {
    const int inner = ::openat(descriptor(), name.c_str(), O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
    if (inner < 0) throw FileWriteError(m_path / name, "cannot open it to remove it: " + errorText());
    const auto owned = own(inner);
    emptyFolder(inner, m_path / name);
    if (::unlinkat(descriptor(), name.c_str(), AT_REMOVEDIR) != 0)
      throw FileWriteError(m_path / name, "cannot remove it: " + errorText());
    return;
  }
  if (::unlinkat(descriptor(), name.c_str(), 0) != 0 && errno != ENOENT)
    throw FileWriteError(m_path / name, "cannot remove it: " + errorText());
}

void OutputFolder::clear() const { emptyFolder(descriptor(), m_path); }

OutputPath OutputPath::beside(const std::string& name) const {
  const std::filesystem::path relative = m_relative.has_parent_path() ? m_relative.parent_path() / name : std::filesystem::path(name);
  return m_folder ? OutputPath(*m_folder, relative) : OutputPath(relative);
}

}  // namespace trephine
