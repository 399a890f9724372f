#pragma once
// The reader fuzz targets hand their input to the readers as files: in a
// directory of this process's own (relative data file names in fuzzed headers
// resolve inside it), removed at exit.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

namespace trephine::fuzz {

// <temp>/<prefix>_<pid>, created on first use and removed at exit (never
// destroyed before that: the exit handler needs it). One prefix per program.
inline const std::filesystem::path& inputDirectory(const char* prefix) {
  static std::filesystem::path* directory = nullptr;  // libFuzzer runs inputs on one thread
  if (!directory) {
    directory = new std::filesystem::path(std::filesystem::temp_directory_path() /
                                          (std::string(prefix) + "_" + std::to_string(::getpid())));
    std::filesystem::create_directories(*directory);
    std::atexit([] {
      std::error_code ignored;
      std::filesystem::remove_all(*directory, ignored);
    });
  }
  return *directory;
}

inline void writeInputFile(const std::filesystem::path& file, const uint8_t* data, size_t size) {
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
}

}  // namespace trephine::fuzz
