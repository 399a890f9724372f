#include "framework/core/FolderInput.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace trephine {

namespace fs = std::filesystem;

namespace {

const char* describe(mode_t mode) {
  if (S_ISLNK(mode)) return "a link";
  if (S_ISDIR(mode)) return "a folder";
  if (S_ISFIFO(mode)) return "a pipe";
  if (S_ISCHR(mode) || S_ISBLK(mode)) return "a device";
  if (S_ISSOCK(mode)) return "a socket";
  return "a file";
}

}  // namespace

fs::path regularFileInside(const fs::path& folder, const fs::path& relative) {
  if (relative.is_absolute() || relative.empty())
    throw FolderInputError((folder / relative).string() + ": expected a file inside " + folder.string());
  fs::path path = folder;
  size_t parts = 0, last = 0;
  for (const fs::path& part : relative) (void)part, ++last;
  for (const fs::path& part : relative) {
    ++parts;
    const std::string name = part.string();
    if (name == "..") throw FolderInputError((folder / relative).string() + ": '..' leaves " + folder.string());
    if (name.empty() || name == ".") continue;
    path /= name;
    struct stat status {};
    if (::lstat(path.c_str(), &status) != 0)
      throw FolderInputError(path.string() + ": " + std::strerror(errno), errno == ENOENT);
    const bool wanted = parts == last ? S_ISREG(status.st_mode) : S_ISDIR(status.st_mode);
    if (!wanted)
      throw FolderInputError(path.string() + ": is " + describe(status.st_mode) + ", expected " +
                             (parts == last ? "a regular file" : "a folder") + " of " + folder.string() +
                             "'s own (links are not followed)");
  }
  return path;
}

bool isRegularFileInside(const fs::path& folder, const fs::path& relative) {
  try {
    regularFileInside(folder, relative);
    return true;
  } catch (const FolderInputError&) {
    return false;
  }
}

std::string readRegularFile(const fs::path& file, size_t maxBytes) {
  const int descriptor = ::open(file.c_str(), O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
  if (descriptor < 0) {
    if (errno == ELOOP) throw FolderInputError(file.string() + ": is a link (links are not followed)");
    throw FolderInputError(file.string() + ": cannot be read: " + std::strerror(errno));
  }
  // Closed on every way out, a failed allocation included.
  struct Closer {
    int fd;
    ~Closer() { ::close(fd); }
  } closer{descriptor};
  struct stat status {};
  std::string bytes;
  std::string problem;
  if (::fstat(descriptor, &status) != 0) {
    problem = std::string("cannot be read: ") + std::strerror(errno);
  } else if (!S_ISREG(status.st_mode)) {
    problem = std::string("is ") + describe(status.st_mode) + ", expected a regular file";
  } else if (size_t(status.st_size) > maxBytes) {
    problem = "holds " + std::to_string(status.st_size) + " bytes, more than the " + std::to_string(maxBytes) +
              " such a file can hold";
  } else {
    bytes.resize(size_t(status.st_size));
    size_t done = 0;
    while (done < bytes.size()) {
      const ssize_t n = ::read(descriptor, bytes.data() + done, bytes.size() - done);
      if (n < 0 && errno == EINTR) continue;
      if (n < 0) {
        problem = std::string("cannot be read: ") + std::strerror(errno);
        break;
      }
      if (n == 0) break;  // shortened meanwhile: what is there
      done += size_t(n);
    }
    bytes.resize(done);
  }
  if (!problem.empty()) throw FolderInputError(file.string() + ": " + problem);
  return bytes;
}

}  // namespace trephine
