#pragma once
#include <filesystem>
#include <stdexcept>
#include <string>

namespace trephine {

// A file that cannot be written: the message starts with the file, then says
// what failed ("out/brain.mesh: cannot create ...: No such file or directory").
class FileWriteError : public std::runtime_error {
 public:
  FileWriteError(const std::filesystem::path& file, const std::string& problem)
      : std::runtime_error(file.string() + ": " + problem) {}
};

}  // namespace trephine
