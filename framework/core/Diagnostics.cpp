#include "framework/core/Diagnostics.h"

#include <algorithm>
#include <ostream>
#include <sstream>
#include <tuple>

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
  return where.str() + ": " + label + ": " + message +
         (where.includedFrom.empty() ? std::string() : " [included from " + where.includedFrom + "]");
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
  // In file order, as a reader goes through the scene; the order found is kept for equal places.
  std::vector<const Diagnostic*> sorted;
  for (const Diagnostic& d : m_items) sorted.push_back(&d);
  std::stable_sort(sorted.begin(), sorted.end(), [](const Diagnostic* a, const Diagnostic* b) {
    return std::tie(a->where.file, a->where.line, a->where.column) <
           std::tie(b->where.file, b->where.line, b->where.column);
  });
  for (const Diagnostic* d : sorted) out << d->str() << "\n";
  if (m_errorCount > 0) out << m_errorCount << (m_errorCount == 1 ? " error" : " errors") << "\n";
}

std::string Diagnostics::str() const {
  std::ostringstream out;
  print(out);
  return out.str();
}

}  // namespace trephine
