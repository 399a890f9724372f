#include "framework/formats/FileReadError.h"

#include <algorithm>

namespace trephine::formats {

namespace {

std::string withoutNul(std::string message) {
  std::replace(message.begin(), message.end(), '\0', '?');
  return message;
}

}  // namespace

FileReadError::FileReadError(const std::filesystem::path& file, const std::string& problem)
    : FileReadError(file, 0, problem) {}

FileReadError::FileReadError(const std::filesystem::path& file, size_t line, const std::string& problem)
    : std::runtime_error(
          withoutNul(file.string() + (line > 0 ? ":" + std::to_string(line) : std::string()) + ": " + problem)) {}

}  // namespace trephine::formats
