#pragma once
// A small pass over XML text that records where each start tag, each
// attribute and each run of text is (1-based line and column, columns counted
// in characters, a tab counting as one), and where the first well-formedness
// problem is. The XML library reports lines only; this gives the columns. It
// also rejects what the library would accept silently or report without a
// position: text outside the root element, repeated attributes, NUL bytes.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace trephine {

struct TextPosition {
  int line = 1;
  int column = 1;
};

struct ScannedAttribute {
  std::string name;
  TextPosition nameAt;
  TextPosition valueAt;
};

struct ScannedElement {
  std::string tag;
  TextPosition at;
  std::vector<ScannedAttribute> attributes;
};

struct ScanProblem {
  TextPosition at;
  std::string message;
};

struct ScanResult {
  std::vector<ScannedElement> elements;  // in document order
  // First non-blank character of each run of character data inside an
  // element, and the '<' of each non-blank CDATA section, in document order.
  std::vector<TextPosition> texts;
  std::optional<ScanProblem> problem;  // first problem found, if any
};

ScanResult scanXmlPositions(std::string_view text);

}  // namespace trephine
