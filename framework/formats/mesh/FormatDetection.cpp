#include "framework/formats/mesh/FormatDetection.h"

#include "framework/formats/mesh/MeditReader.h"
#include "framework/formats/mesh/VtkLegacyReader.h"

namespace trephine::formats {

namespace {

bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f'; }

// The content after white space and whole '#' comment lines.
std::string_view afterComments(std::string_view text) {
  while (true) {
    size_t start = 0;
    while (start < text.size() && isSpace(text[start])) ++start;
    text.remove_prefix(start);
    if (text.empty() || text[0] != '#') return text;
    const size_t newline = text.find('\n');
    text = newline == std::string_view::npos ? std::string_view() : text.substr(newline + 1);
  }
}

}  // namespace

MeshFormat detectMeshFormat(std::string_view content) {
  if (content.size() >= 4) {
    const std::string_view head = content.substr(0, 4);
    if (head == std::string_view("\1\0\0\0", 4) || head == std::string_view("\0\0\0\1", 4))
      return MeshFormat::kMeditBinary;
  }
  if (content.starts_with("\xEF\xBB\xBF")) content.remove_prefix(3);  // UTF-8 byte order mark
  // "# vtk DataFile Version" is a comment line to the other formats: test it first.
  if (looksLikeVtkLegacy(content)) return MeshFormat::kVtkLegacy;
  const std::string_view text = afterComments(content);
  if (text.empty()) return MeshFormat::kUnknown;
  const char first = text[0];
  if (first == '<') return MeshFormat::kVtu;
  if (first == '$') return MeshFormat::kGmsh;
  if (first >= '0' && first <= '9') return MeshFormat::kTetGen;
  if (looksLikeMedit(content)) return MeshFormat::kMedit;
  return MeshFormat::kUnknown;
}

}  // namespace trephine::formats
