#include "framework/scene/XmlPositionScanner.h"

#include <cctype>
#include <string>
#include <unordered_map>
#include <utility>

namespace trephine {

namespace {

constexpr std::string_view kByteOrderMark = "\xEF\xBB\xBF";
// Deepest element nesting accepted. The XML library stops at about 100 with a
// line number only; scenes nest a handful of levels.
constexpr size_t kMaxDepth = 64;
// Attributes of one element at most.
constexpr size_t kMaxAttributes = 1000;

bool isSpace(char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; }

// The XML library's name rule: a letter, '_', ':' or any non-ASCII byte first,
// then also digits, '.' and '-'. Checked here so that a bad name is reported
// with its column instead of as the library's bare error code.
bool isNameStart(char c) {
  const auto u = static_cast<unsigned char>(c);
  return u >= 0x80 || std::isalpha(u) || c == '_' || c == ':';
}
bool isValidXmlName(std::string_view name) {
  if (name.empty() || !isNameStart(name.front())) return false;
  for (char c : name)
    if (!isNameStart(c) && !std::isdigit(static_cast<unsigned char>(c)) && c != '.' && c != '-') return false;
  return true;
}

std::string describe(TextPosition p) {
  return "line " + std::to_string(p.line) + ", column " + std::to_string(p.column);
}

class Cursor {
 public:
  explicit Cursor(std::string_view text) : m_text(text) {
    // An editor shows no character for a byte order mark: it takes no column.
    if (m_text.starts_with(kByteOrderMark)) m_index = kByteOrderMark.size();
  }

  bool done() const { return m_index >= m_text.size(); }
  char peek(size_t ahead = 0) const { return m_index + ahead < m_text.size() ? m_text[m_index + ahead] : '\0'; }
  bool startsWith(std::string_view s) const { return m_text.substr(m_index).starts_with(s); }
  TextPosition position() const { return m_position; }

  void advance() {
    if (done()) return;
    const unsigned char c = static_cast<unsigned char>(m_text[m_index++]);
    if (c == '\n') {
      ++m_position.line;
      m_position.column = 1;
    } else if ((c & 0xC0) != 0x80) {
      ++m_position.column;  // count characters, not UTF-8 continuation bytes
    }
  }
  void advance(size_t n) {
    for (size_t i = 0; i < n; ++i) advance();
  }
  // Moves past the next occurrence of `terminator`; false at end of text.
  // `blank` tells whether everything skipped before it was white space.
  bool skipPast(std::string_view terminator, bool* blank = nullptr) {
    if (blank) *blank = true;
    while (!done()) {
      if (startsWith(terminator)) {
        advance(terminator.size());
        return true;
      }
      if (blank && !isSpace(peek())) *blank = false;
      advance();
    }
    return false;
  }
  void skipSpace() {
    while (!done() && isSpace(peek())) advance();
  }
  std::string readName() {
    std::string name;
    while (!done()) {
      const char c = peek();
      if (isSpace(c) || c == '/' || c == '>' || c == '=' || c == '<' || c == '"' || c == '\'') break;
      name += c;
      advance();
    }
    return name;
  }

 private:
  std::string_view m_text;
  size_t m_index = 0;
  TextPosition m_position;
};

struct OpenElement {
  std::string tag;
  TextPosition at;
};

class Scanner {
 public:
  explicit Scanner(std::string_view text) : m_text(text), m_cursor(text) {}

  ScanResult run() {
    // The XML library stops reading at a NUL byte, as if the file ended there.
    if (const size_t nul = m_text.find('\0'); nul != std::string_view::npos) {
      Cursor before(m_text.substr(0, nul));
      while (!before.done()) before.advance();
      fail(before.position(), "NUL byte in the file (is it a text file?)");
      return std::move(m_result);
    }
    while (!m_cursor.done() && !m_result.problem) {
      if (m_cursor.peek() == '<') {
        markup();
      } else {
        characterData();
      }
    }
    if (!m_result.problem && !m_open.empty())
      fail(m_open.back().at, "element <" + m_open.back().tag + "> is never closed");
    if (!m_result.problem && m_result.elements.empty()) fail({}, "the file has no root element");
    return std::move(m_result);
  }

 private:
  void fail(TextPosition at, std::string message) {
    if (!m_result.problem) m_result.problem = ScanProblem{at, std::move(message)};
  }

  // Text between markup: only white space is allowed outside the root element.
  void characterData() {
    if (isSpace(m_cursor.peek())) {
      m_cursor.advance();
      return;
    }
    if (m_open.empty()) {
      fail(m_cursor.position(), "text outside the root element");
      return;
    }
    m_result.texts.push_back(m_cursor.position());
    while (!m_cursor.done() && m_cursor.peek() != '<') m_cursor.advance();
  }

  // After "<!--": to the comment's end. XML allows "--" nowhere in a
  // comment but in its end "-->" (a comment ending in "--->" included); the
  // XML library would take such a comment, which other readers of the scene
  // (a schema check, an editor) refuse.
  void comment(TextPosition start) {
    while (!m_cursor.done()) {
      if (m_cursor.startsWith("-->")) {
        m_cursor.advance(3);
        return;
      }
      if (m_cursor.startsWith("--"))
        fail(m_cursor.position(), "'--' inside a comment: XML allows it only in the comment's end '-->' (write "
                                  "a single '-', or '- -')");
      m_cursor.advance();
    }
    fail(start, "comment is not closed with '-->'");
  }

  void markup() {
    const TextPosition start = m_cursor.position();
    const bool pastProlog = std::exchange(m_pastProlog, true);
    // The terminator is searched after the opener, as the XML library does: "<!-->" is not a comment.
    const auto opens = [&](std::string_view opener) {
      if (!m_cursor.startsWith(opener)) return false;
      m_cursor.advance(opener.size());
      return true;
    };
    if (opens("<!--")) {
      comment(start);
    } else if (opens("<![CDATA[")) {
      bool blank = true;
      if (!m_cursor.skipPast("]]>", &blank)) fail(start, "CDATA section is not closed with ']]>'");
      if (m_open.empty()) fail(start, "CDATA section outside the root element");
      if (!blank) m_result.texts.push_back(start);
    } else if (opens("<?")) {
      if (!m_cursor.skipPast("?>")) fail(start, "processing instruction is not closed with '?>'");
      // The XML library takes every <?...?> for an XML declaration and accepts those only first.
      if (pastProlog) fail(start, "'<?...?>' is only allowed at the start of the file, before any other markup");
      m_pastProlog = pastProlog;
    } else if (m_cursor.startsWith("<!")) {
      declaration(start);
      // The XML library ends a declaration at its first '>', so an internal
      // subset's "]>" would become text: a declaration belongs before the root.
      if (!m_result.elements.empty()) fail(start, "'<!...>' declarations are only allowed before the root element");
    } else if (m_cursor.startsWith("</")) {
      endTag(start);
    } else {
      startTag(start);
    }
  }

  // DOCTYPE, possibly with an internal subset in brackets.
  void declaration(TextPosition start) {
    int depth = 0;
    m_cursor.advance(2);
    while (!m_cursor.done() && !(m_cursor.peek() == '>' && depth == 0)) {
      if (m_cursor.peek() == '[') ++depth;
      if (m_cursor.peek() == ']' && depth > 0) --depth;
      m_cursor.advance();
    }
    if (m_cursor.done()) fail(start, "declaration is not closed with '>'");
    m_cursor.advance();
  }

  void endTag(TextPosition start) {
    m_cursor.advance(2);
    const std::string tag = m_cursor.readName();
    if (tag.empty()) {
      fail(m_cursor.position(), "expected an element name right after '</'");
    } else if (m_open.empty()) {
      fail(start, "end tag </" + tag + "> has no matching start tag");
    } else if (m_open.back().tag != tag) {
      fail(start,
           "end tag </" + tag + "> does not match <" + m_open.back().tag + "> opened at " + describe(m_open.back().at));
    } else {
      m_open.pop_back();
    }
    m_cursor.skipSpace();
    if (!m_result.problem && m_cursor.peek() != '>') fail(m_cursor.position(), "expected '>' to close </" + tag + ">");
    m_cursor.advance();
  }

  void startTag(TextPosition start) {
    m_cursor.advance();
    ScannedElement element;
    element.at = start;
    const TextPosition nameAt = m_cursor.position();
    element.tag = m_cursor.readName();
    if (element.tag.empty()) {
      fail(nameAt, "expected an element name after '<'");
      return;
    }
    if (!isValidXmlName(element.tag)) {
      fail(nameAt, "'" + element.tag + "' is not a valid element name (names start with a letter or '_')");
      return;
    }
    if (m_open.size() >= kMaxDepth) {
      fail(start, "elements nested more than " + std::to_string(kMaxDepth) + " deep");
      return;
    }
    bool closed = false;
    m_names.clear();
    while (!m_cursor.done() && !m_result.problem) {
      m_cursor.skipSpace();
      if (m_cursor.startsWith("/>")) {
        m_cursor.advance(2);
        closed = true;
        break;
      }
      if (m_cursor.peek() == '>') {
        m_cursor.advance();
        m_open.push_back({element.tag, start});
        closed = true;
        break;
      }
      if (element.attributes.size() >= kMaxAttributes) {
        // Before the XML library sees it: it compares each attribute with
        // every one before it, so a hundred thousand would take minutes.
        fail(m_cursor.position(), "<" + element.tag + "> has more than " + std::to_string(kMaxAttributes) +
                                      " attributes (a component has a few dozen fields)");
        break;
      }
      if (auto attribute = readAttribute(element)) {
        m_names.emplace(attribute->name, element.attributes.size());
        element.attributes.push_back(std::move(*attribute));
      }
    }
    if (!closed && !m_result.problem) fail(start, "start tag <" + element.tag + "> is not closed with '>'");
    m_result.elements.push_back(std::move(element));
  }

  std::optional<ScannedAttribute> readAttribute(const ScannedElement& element) {
    ScannedAttribute attribute;
    attribute.nameAt = m_cursor.position();
    attribute.name = m_cursor.readName();
    if (attribute.name.empty()) {
      fail(m_cursor.position(), std::string("unexpected '") + m_cursor.peek() + "' in <" + element.tag + ">");
      return std::nullopt;
    }
    if (!isValidXmlName(attribute.name)) {
      fail(attribute.nameAt,
           "'" + attribute.name + "' is not a valid attribute name (names start with a letter or '_')");
      return std::nullopt;
    }
    if (const auto earlier = m_names.find(attribute.name); earlier != m_names.end()) {
      fail(attribute.nameAt, "attribute '" + attribute.name + "' is given twice in <" + element.tag + "> (first at " +
                                 describe(element.attributes[earlier->second].nameAt) + ")");
      return std::nullopt;
    }
    m_cursor.skipSpace();
    if (m_cursor.peek() != '=') {
      fail(m_cursor.position(), "expected '=' after attribute '" + attribute.name + "'");
      return std::nullopt;
    }
    m_cursor.advance();
    m_cursor.skipSpace();
    const char quote = m_cursor.peek();
    if (quote != '"' && quote != '\'') {
      fail(m_cursor.position(), "expected a quoted value for attribute '" + attribute.name + "'");
      return std::nullopt;
    }
    m_cursor.advance();
    attribute.valueAt = m_cursor.position();
    while (!m_cursor.done() && m_cursor.peek() != quote) {
      if (m_cursor.peek() == '<') {
        // Most often the closing quote is missing, so the value runs into the next tag.
        fail(attribute.valueAt, "value of attribute '" + attribute.name + "' is not closed before the '<' at " +
                                    describe(m_cursor.position()) + " (a value cannot contain '<'; write &lt;)");
        return std::nullopt;
      }
      m_cursor.advance();
    }
    if (m_cursor.done()) {
      fail(attribute.valueAt, "value of attribute '" + attribute.name + "' is not closed");
      return std::nullopt;
    }
    m_cursor.advance();  // closing quote
    return attribute;
  }

  std::string_view m_text;
  Cursor m_cursor;
  ScanResult m_result;
  std::vector<OpenElement> m_open;
  std::unordered_map<std::string, size_t> m_names;  // the element's attributes so far, by name: their index
  bool m_pastProlog = false;  // seen anything but white space and <?...?>
};

}  // namespace

ScanResult scanXmlPositions(std::string_view text) { return Scanner(text).run(); }

}  // namespace trephine
