#include "framework/formats/mesh/TetGenFiles.h"

#include <system_error>

#include "framework/formats/mesh/TetMeshReader.h"
#include "framework/formats/mesh/TextCursor.h"

namespace trephine::formats {

namespace {

bool endsWithIgnoreCase(std::string_view text, std::string_view suffix) {
  return text.size() >= suffix.size() && equalsIgnoreCase(text.substr(text.size() - suffix.size()), suffix);
}

// The file name without ".gz" and without its TetGen (or other) extension.
std::string baseName(const std::filesystem::path& file) {
  std::string name = file.filename().string();
  if (endsWithIgnoreCase(name, ".gz")) name.resize(name.size() - 3);
  for (const std::string_view extension : {".node", ".ele"}) {
    if (endsWithIgnoreCase(name, extension)) return name.substr(0, name.size() - extension.size());
  }
  const size_t dot = name.rfind('.');
  return dot == std::string::npos || dot == 0 ? name : name.substr(0, dot);
}

bool isFile(const std::filesystem::path& path) {
  std::error_code ignored;
  return std::filesystem::is_regular_file(path, ignored);
}

std::optional<std::filesystem::path> firstExisting(const std::filesystem::path& directory, const std::string& base,
                                                   const std::string& extension) {
  for (const std::string& name : {base + extension, base + extension + ".gz"}) {
    if (isFile(directory / name)) return directory / name;
  }
  return std::nullopt;
}

}  // namespace

std::filesystem::path findTetGenPartner(const std::filesystem::path& file, TetGenPart fileIs) {
  const std::string base = baseName(file);
  const std::string extension = fileIs == TetGenPart::kNode ? ".ele" : ".node";
  if (const auto partner = firstExisting(file.parent_path(), base, extension)) return *partner;
  const std::string what =
      fileIs == TetGenPart::kNode ? "TetGen node file: its element file" : "TetGen element file: its node file";
  throw TetMeshReadError(file, "a " + what + " is missing (looked for " + base + extension + " and " + base +
                                   extension + ".gz next to it)");
}

std::optional<std::filesystem::path> findTetGenNodeForBase(const std::filesystem::path& base) {
  if (base.filename().empty()) return std::nullopt;
  return firstExisting(base.parent_path(), base.filename().string(), ".node");
}

}  // namespace trephine::formats
