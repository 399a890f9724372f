#include "framework/core/Diagnostics.h"

#include <ostream>
#include <sstream>

namespace trephine {

std::string SourceLocation::str() const {
  std::string s = file.empty() ? std::string("<unknown>") : file;
  if (line > 0) {
    s += ":" + std::to_string(line);
    if (column > 0) s += ":" + std::to_string(column);
  }
  return s;
}

std::string Diagnostic::str() const {
  const char* label = severity == Severity::Error ? "error" : severity == Severity::Warning ? "warning" : "note";
  return where.str() + ": " + label + ": " + message;
}

void Diagnostics::error(const SourceLocation& where, std::string message) {
  m_items.push_back({Severity::Error, where, std::move(message)});
  ++m_errorCount;
}
void Diagnostics::warning(const SourceLocation& where, std::string message) {
  m_items.push_back({Severity::Warning, where, std::move(message)});
}
void Diagnostics::note(const SourceLocation& where, std::string message) {
  m_items.push_back({Severity::Note, where, std::move(message)});
}

void Diagnostics::print(std::ostream& out) const {
  for (const Diagnostic& d : m_items) out << d.str() << "\n";
  if (m_errorCount > 0) out << m_errorCount << (m_errorCount == 1 ? " error" : " errors") << "\n";
}

std::string Diagnostics::str() const {
  std::ostringstream out;
  print(out);
  return out.str();
}

}  // namespace trephine
