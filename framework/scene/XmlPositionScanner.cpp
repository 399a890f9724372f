#include "framework/scene/XmlPositionScanner.h"

#include <cctype>

namespace trephine {

namespace {

class Cursor {
 public:
  explicit Cursor(std::string_view text) : m_text(text) {}

  bool done() const { return m_index >= m_text.size(); }
  char peek(size_t ahead = 0) const {
    return m_index + ahead < m_text.size() ? m_text[m_index + ahead] : '\0';
  }
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
  bool skipPast(std::string_view terminator) {
    while (!done()) {
      if (startsWith(terminator)) {
        advance(terminator.size());
        return true;
      }
      advance();
    }
    return false;
  }
  void skipSpace() {
    while (!done() && std::isspace(static_cast<unsigned char>(peek()))) advance();
  }
  std::string readName() {
    std::string name;
    while (!done()) {
      const char c = peek();
      if (std::isspace(static_cast<unsigned char>(c)) || c == '/' || c == '>' || c == '=' || c == '<' ||
          c == '"' || c == '\'')
        break;
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

}  // namespace

ScanResult scanXmlPositions(std::string_view text) {
  ScanResult result;
  Cursor cursor(text);
  std::vector<OpenElement> open;
  const auto fail = [&](TextPosition at, std::string message) {
    if (!result.problem) result.problem = ScanProblem{at, std::move(message)};
  };

  while (!cursor.done() && !result.problem) {
    if (cursor.peek() != '<') {
      cursor.advance();
      continue;
    }
    const TextPosition start = cursor.position();
    if (cursor.startsWith("<!--")) {
      if (!cursor.skipPast("-->")) fail(start, "comment is not closed with '-->'");
    } else if (cursor.startsWith("<![CDATA[")) {
      if (!cursor.skipPast("]]>")) fail(start, "CDATA section is not closed with ']]>'");
    } else if (cursor.startsWith("<?")) {
      if (!cursor.skipPast("?>")) fail(start, "processing instruction is not closed with '?>'");
    } else if (cursor.startsWith("<!")) {
      // DOCTYPE, possibly with an internal subset in brackets.
      int depth = 0;
      cursor.advance(2);
      while (!cursor.done() && !(cursor.peek() == '>' && depth == 0)) {
        if (cursor.peek() == '[') ++depth;
        if (cursor.peek() == ']') --depth;
        cursor.advance();
      }
      if (cursor.done()) fail(start, "declaration is not closed with '>'");
      cursor.advance();
    } else if (cursor.startsWith("</")) {
      cursor.advance(2);
      const std::string tag = cursor.readName();
      if (open.empty()) {
        fail(start, "end tag </" + tag + "> has no matching start tag");
      } else if (open.back().tag != tag) {
        fail(start, "end tag </" + tag + "> does not match <" + open.back().tag + "> opened at line " +
                        std::to_string(open.back().at.line) + ", column " + std::to_string(open.back().at.column));
      } else {
        open.pop_back();
      }
      cursor.skipSpace();
      if (!result.problem && cursor.peek() != '>') fail(cursor.position(), "expected '>' to close </" + tag + ">");
      cursor.advance();
    } else {
      cursor.advance();
      ScannedElement element;
      element.at = start;
      element.tag = cursor.readName();
      if (element.tag.empty()) {
        fail(cursor.position(), "expected an element name after '<'");
        break;
      }
      bool closed = false;
      while (!cursor.done() && !result.problem) {
        cursor.skipSpace();
        if (cursor.startsWith("/>")) {
          cursor.advance(2);
          closed = true;
          break;
        }
        if (cursor.peek() == '>') {
          cursor.advance();
          open.push_back({element.tag, start});
          closed = true;
          break;
        }
        ScannedAttribute attribute;
        attribute.nameAt = cursor.position();
        attribute.name = cursor.readName();
        if (attribute.name.empty()) {
          fail(cursor.position(), std::string("unexpected '") + cursor.peek() + "' in <" + element.tag + ">");
          break;
        }
        cursor.skipSpace();
        if (cursor.peek() != '=') {
          fail(cursor.position(), "expected '=' after attribute '" + attribute.name + "'");
          break;
        }
        cursor.advance();
        cursor.skipSpace();
        const char quote = cursor.peek();
        if (quote != '"' && quote != '\'') {
          fail(cursor.position(), "expected a quoted value for attribute '" + attribute.name + "'");
          break;
        }
        cursor.advance();
        attribute.valueAt = cursor.position();
        while (!cursor.done() && cursor.peek() != quote) {
          if (cursor.peek() == '<') {
            fail(cursor.position(), "'<' is not allowed in the value of attribute '" + attribute.name + "'");
            break;
          }
          cursor.advance();
        }
        if (cursor.done()) {
          fail(attribute.valueAt, "value of attribute '" + attribute.name + "' is not closed");
          break;
        }
        cursor.advance();  // closing quote
        element.attributes.push_back(std::move(attribute));
      }
      if (!closed && !result.problem) fail(start, "start tag <" + element.tag + "> is not closed with '>'");
      result.elements.push_back(std::move(element));
    }
  }
  if (!result.problem && !open.empty())
    fail(open.back().at, "element <" + open.back().tag + "> is never closed");
  return result;
}

}  // namespace trephine
