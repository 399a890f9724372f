#include "framework/core/TextTable.h"

#include <algorithm>

namespace trephine {

std::string formatColumns(const std::vector<std::vector<std::string>>& rows, const std::string& indent) {
  std::vector<size_t> width;
  for (const auto& row : rows)
    for (size_t c = 0; c < row.size(); ++c) {
      if (width.size() <= c) width.push_back(0);
      width[c] = std::max(width[c], row[c].size());
    }
  std::string out;
  for (const auto& row : rows) {
    std::string line = indent;
    for (size_t c = 0; c < row.size(); ++c) {
      if (c > 0) line += "  ";
      line.append(width[c] - row[c].size(), ' ');
      line += row[c];
    }
    out += line + "\n";
  }
  return out;
}

}  // namespace trephine
