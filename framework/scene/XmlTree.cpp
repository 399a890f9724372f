#include "framework/scene/XmlTree.h"

#include <tinyxml2.h>

#include <algorithm>
#include <array>
#include <fstream>

#include "framework/core/Strings.h"
#include "framework/scene/XmlPositionScanner.h"

namespace trephine {

const XmlAttribute* XmlElement::attribute(std::string_view name) const {
  for (const XmlAttribute& a : attributes)
    if (a.name == name) return &a;
  return nullptr;
}

namespace {

SourceLocation at(const std::string& file, TextPosition p) { return {file, p.line, p.column}; }

struct Converter {
  const std::string& fileName;
  const std::filesystem::path& baseDirectory;
  const std::vector<ScannedElement>& scanned;
  const std::vector<TextPosition>& texts;
  Diagnostics& diagnostics;
  size_t next = 0;      // index of the next scanned element, in document order
  size_t nextText = 0;  // index of the next scanned text run

  // The scanned run of text the library reports on `line` (it gives the line
  // of the first non-blank character). Runs that decode to blanks ("&#32;")
  // have no text node, so unmatched runs are skipped.
  SourceLocation textAt(int line) {
    for (size_t i = nextText; i < texts.size(); ++i) {
      if (texts[i].line == line) {
        nextText = i + 1;
        return at(fileName, texts[i]);
      }
    }
    return {fileName, line, 1};
  }

  XmlElement convert(const tinyxml2::XMLElement& source) {
    XmlElement element;
    element.tag = source.Name();
    element.baseDirectory = baseDirectory;
    const ScannedElement* positions =
        next < scanned.size() && scanned[next].tag == element.tag ? &scanned[next] : nullptr;
    ++next;
    element.at = positions ? at(fileName, positions->at) : SourceLocation{fileName, source.GetLineNum(), 1};
    size_t index = 0;  // the library keeps the attributes in the document's order, as the scanner does
    for (const tinyxml2::XMLAttribute* a = source.FirstAttribute(); a; a = a->Next(), ++index) {
      XmlAttribute attribute{a->Name(), a->Value(), element.at, element.at};
      const ScannedAttribute* s = positions && index < positions->attributes.size() &&
                                          positions->attributes[index].name == attribute.name
                                      ? &positions->attributes[index]
                                      : nullptr;
      if (s) {
        attribute.nameAt = at(fileName, s->nameAt);
        attribute.valueAt = at(fileName, s->valueAt);
      }
      element.attributes.push_back(std::move(attribute));
    }
    for (const tinyxml2::XMLNode* child = source.FirstChild(); child; child = child->NextSibling()) {
      if (const auto* childElement = child->ToElement()) {
        element.children.push_back(convert(*childElement));
      } else if (const auto* text = child->ToText()) {
        if (!trim(text->Value() ? text->Value() : "").empty())
          diagnostics.error(textAt(text->GetLineNum()),
                            "unexpected text inside <" + element.tag + ">; scene content goes in attributes");
      }
    }
    return element;
  }
};

}  // namespace

std::optional<XmlElement> parseXml(std::string_view text, const std::string& fileName,
                                   const std::filesystem::path& baseDirectory, Diagnostics& diagnostics) {
  const ScanResult scan = scanXmlPositions(text);
  tinyxml2::XMLDocument document;
  // What the scanner refuses the library never parses (its cost grows with
  // the square of an element's attributes).
  const tinyxml2::XMLError status =
      scan.problem ? tinyxml2::XML_ERROR_PARSING : document.Parse(text.data(), text.size());
  if (status != tinyxml2::XML_SUCCESS || scan.problem) {
    if (scan.problem) {
      diagnostics.error(at(fileName, scan.problem->at), "malformed XML: " + scan.problem->message);
    } else {
      // Only what the scanner does not check ends here; the library knows the line only.
      diagnostics.error(
          {fileName, std::max(1, document.ErrorLineNum()), 1},
          std::string("malformed XML on this line (") + tinyxml2::XMLDocument::ErrorIDToName(status) + ")");
    }
    return std::nullopt;
  }
  const tinyxml2::XMLElement* root = document.RootElement();
  if (!root) {
    diagnostics.error({fileName, 1, 1}, "malformed XML: the file has no root element");
    return std::nullopt;
  }
  if (const tinyxml2::XMLElement* second = root->NextSiblingElement()) {
    size_t index = 0;
    for (const tinyxml2::XMLElement* e = root; e != second; e = e->NextSiblingElement()) {
      // count elements of the first root's subtree to find the second root's scanned position
      std::vector<const tinyxml2::XMLElement*> stack{e};
      while (!stack.empty()) {
        const auto* top = stack.back();
        stack.pop_back();
        ++index;
        for (const auto* c = top->LastChildElement(); c; c = c->PreviousSiblingElement()) stack.push_back(c);
      }
    }
    const SourceLocation where = index < scan.elements.size() ? at(fileName, scan.elements[index].at)
                                                              : SourceLocation{fileName, second->GetLineNum(), 1};
    diagnostics.error(where,
                      "a scene file has one root element; found a second one <" + std::string(second->Name()) + ">");
    return std::nullopt;
  }
  Converter converter{fileName, baseDirectory, scan.elements, scan.texts, diagnostics};
  return converter.convert(*root);
}

std::optional<XmlElement> readXmlFile(const std::filesystem::path& file, const SourceLocation& from,
                                      Diagnostics& diagnostics) {
  std::error_code ec;
  if (!std::filesystem::exists(file, ec)) {
    diagnostics.error(from, "scene file not found: " + file.string());
    return std::nullopt;
  }
  if (!std::filesystem::is_regular_file(file, ec)) {
    diagnostics.error(from, "not a regular file: " + file.string());
    return std::nullopt;
  }
  const std::string tooLarge =
      "scene file " + file.string() + " is larger than " + std::to_string(kMaxSceneFileBytes >> 20) + " MiB";
  const auto size = std::filesystem::file_size(file, ec);
  if (!ec && size > kMaxSceneFileBytes) {
    diagnostics.error(from, tooLarge);
    return std::nullopt;
  }
  std::ifstream in(file, std::ios::binary);
  if (ec || !in) {
    diagnostics.error(from, "cannot read " + file.string());
    return std::nullopt;
  }
  // The size is read as it goes too: files such as /proc/self/pagemap say 0
  // bytes and never end.
  std::string content;
  std::array<char, 64 * 1024> buffer;
  while (in.read(buffer.data(), buffer.size()) || in.gcount() > 0) {
    content.append(buffer.data(), static_cast<size_t>(in.gcount()));
    if (content.size() > kMaxSceneFileBytes) {
      diagnostics.error(from, tooLarge);
      return std::nullopt;
    }
  }
  if (in.bad()) {
    diagnostics.error(from, "cannot read " + file.string());
    return std::nullopt;
  }
  return parseXml(content, file.string(), file.parent_path(), diagnostics);
}

}  // namespace trephine
