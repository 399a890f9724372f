#pragma once
// One sink for every problem found in a scene: each diagnostic carries where it
// is (file:line:col, 1-based) and what was expected. The loader keeps going
// after an error so that a user sees every problem of a file at once.
#include <iosfwd>
#include <string>
#include <vector>

namespace trephine {

struct SourceLocation {
  std::string file;  // scene file, or a pseudo-file such as "--set"
  int line = 0;      // 1-based; 0 when unknown
  int column = 0;    // 1-based; 0 when unknown
  // For text read through <Include>: where it was included ("scene.xml:4:18",
  // then "<- outer.xml:2:18" for nested includes); empty otherwise.
  std::string includedFrom = {};

  bool known() const { return !file.empty(); }
  std::string str() const;  // "file:line:col"
};

enum class Severity { Error, Warning, Note };

struct Diagnostic {
  Severity severity = Severity::Error;
  SourceLocation where;
  std::string message;

  std::string str() const;  // "file:line:col: error: message"
};

class Diagnostics {
 public:
  void error(const SourceLocation& where, std::string message);
  void warning(const SourceLocation& where, std::string message);
  void note(const SourceLocation& where, std::string message);

  bool hasErrors() const { return m_errorCount > 0; }
  int errorCount() const { return m_errorCount; }
  const std::vector<Diagnostic>& all() const { return m_items; }

  // Writes every diagnostic, one per line, then "N error(s)" when there are errors.
  void print(std::ostream& out) const;
  std::string str() const;

 private:
  std::vector<Diagnostic> m_items;
  int m_errorCount = 0;
};

}  // namespace trephine
