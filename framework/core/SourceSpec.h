#pragma once
// The text after a generated-source scheme in a file field, such as
// "skull?voxel=0.5" in file="phantom:skull?voxel=0.5": a name and numeric
// keys, each with a default. Errors say which key and what was expected.
#include <map>
#include <string>

namespace trephine {

class SourceSpec {
 public:
  // Splits "name?k=v&k=v"; throws std::invalid_argument for a key not in
  // `defaults` (listing the known ones), a key without a value or a value that
  // is not a finite number.
  SourceSpec(const std::string& name, const std::string& query, std::map<std::string, double> defaults);
  // "name?query" split into its name and query.
  static std::pair<std::string, std::string> split(const std::string& specification);

  const std::string& name() const { return m_name; }
  double number(const std::string& key) const { return m_values.at(key); }
  double positive(const std::string& key) const;                    // throws unless > 0
  int wholeNumber(const std::string& key, int min, int max) const;  // throws unless an integer in [min, max]

 private:
  std::string m_name;
  std::map<std::string, double> m_values;
};

}  // namespace trephine
