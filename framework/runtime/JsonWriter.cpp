#include "framework/runtime/JsonWriter.h"

#include <cmath>
#include <cstdio>

#include "framework/core/Strings.h"

namespace trephine {

void JsonWriter::newline() {
  m_out << '\n';
  for (size_t i = 0; i < m_stack.size(); ++i) m_out << "  ";
}

void JsonWriter::beforeValue() {
  if (m_afterKey) {
    m_afterKey = false;
    return;
  }
  if (!m_stack.empty()) {
    if (!m_stack.back().empty) m_out << ',';
    m_stack.back().empty = false;
    newline();
  }
}

JsonWriter& JsonWriter::beginObject() {
  beforeValue();
  m_out << '{';
  m_stack.push_back({true, true});
  return *this;
}

JsonWriter& JsonWriter::endObject() {
  const bool wasEmpty = m_stack.back().empty;
  m_stack.pop_back();
  if (!wasEmpty) newline();
  m_out << '}';
  if (m_stack.empty()) m_out << '\n';
  return *this;
}

JsonWriter& JsonWriter::beginArray() {
  beforeValue();
  m_out << '[';
  m_stack.push_back({false, true});
  return *this;
}

JsonWriter& JsonWriter::endArray() {
  const bool wasEmpty = m_stack.back().empty;
  m_stack.pop_back();
  if (!wasEmpty) newline();
  m_out << ']';
  return *this;
}

JsonWriter& JsonWriter::key(std::string_view name) {
  beforeValue();
  m_out << '"' << escape(name) << "\": ";
  m_afterKey = true;
  return *this;
}

JsonWriter& JsonWriter::value(std::string_view text) {
  beforeValue();
  m_out << '"' << escape(text) << '"';
  return *this;
}

JsonWriter& JsonWriter::value(double number) {
  beforeValue();
  if (std::isfinite(number)) {
    m_out << formatDouble(number);
  } else {
    m_out << "null";
  }
  return *this;
}

JsonWriter& JsonWriter::value(long long number) {
  beforeValue();
  m_out << number;
  return *this;
}

JsonWriter& JsonWriter::value(unsigned long long number) {
  beforeValue();
  m_out << number;
  return *this;
}

JsonWriter& JsonWriter::value(bool flag) {
  beforeValue();
  m_out << (flag ? "true" : "false");
  return *this;
}

JsonWriter& JsonWriter::null() {
  beforeValue();
  m_out << "null";
  return *this;
}

std::string JsonWriter::escape(std::string_view text) {
  std::string s;
  for (const char c : text) {
    switch (c) {
      case '"':
        s += "\\\"";
        break;
      case '\\':
        s += "\\\\";
        break;
      case '\n':
        s += "\\n";
        break;
      case '\r':
        s += "\\r";
        break;
      case '\t':
        s += "\\t";
        break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          char buffer[8];
          std::snprintf(buffer, sizeof buffer, "\\u%04x", c);
          s += buffer;
        } else {
          s += c;
        }
    }
  }
  return s;
}

}  // namespace trephine
