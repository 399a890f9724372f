#pragma once
// A scene file read into plain elements that carry their positions: every
// element knows the line and column of its '<', every attribute those of its
// name and of its value. The XML library stays inside XmlTree.cpp.
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "framework/core/Diagnostics.h"

namespace trephine {

struct XmlAttribute {
  std::string name;
  std::string value;  // entities decoded
  SourceLocation nameAt;
  SourceLocation valueAt;  // first character inside the quotes
};

struct XmlElement {
  std::string tag;
  SourceLocation at;  // the '<'
  std::vector<XmlAttribute> attributes;
  std::vector<XmlElement> children;
  std::filesystem::path baseDirectory;  // directory of the file it came from

  const XmlAttribute* attribute(std::string_view name) const;
};

// Largest scene file read, to fail clearly on /dev/zero and the like (bytes).
inline constexpr size_t kMaxSceneFileBytes = 16u << 20;

// Parses `text` (named `fileName` in messages). Reports malformed XML with its
// position and returns nothing on failure.
std::optional<XmlElement> parseXml(std::string_view text, const std::string& fileName,
                                   const std::filesystem::path& baseDirectory, Diagnostics& diagnostics);

// Reads and parses a file; a missing, unreadable, oversized or non-regular file is an error at `from`.
std::optional<XmlElement> readXmlFile(const std::filesystem::path& file, const SourceLocation& from,
                                      Diagnostics& diagnostics);

}  // namespace trephine
