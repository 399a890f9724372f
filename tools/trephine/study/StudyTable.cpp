#include "tools/trephine/study/StudyTable.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace trephine::study {

namespace {

std::vector<std::string> splitRow(const std::string& line) {
  std::vector<std::string> cells;
  std::istringstream row(line);
  std::string cell;
  while (std::getline(row, cell, ',')) cells.push_back(cell);
  if (!line.empty() && line.back() == ',') cells.emplace_back();
  return cells;
}

}  // namespace

Table readTable(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw std::runtime_error(file.string() + ": cannot read");
  Table table;
  std::string line;
  while (std::getline(in, line))
    if (!line.empty()) table.push_back(splitRow(line));
  if (table.empty()) throw std::runtime_error(file.string() + ": empty");
  for (size_t r = 1; r < table.size(); ++r)
    if (table[r].size() != table[0].size())
      throw std::runtime_error(file.string() + ":" + std::to_string(r + 1) + ": expected " +
                               std::to_string(table[0].size()) + " columns");
  return table;
}

size_t column(const Table& table, const std::string& name, const std::filesystem::path& file) {
  const auto it = std::find(table[0].begin(), table[0].end(), name);
  if (it == table[0].end()) throw std::runtime_error(file.string() + ": no column '" + name + "'");
  return static_cast<size_t>(it - table[0].begin());
}

double toNumber(const std::string& text) {
  try {
    size_t used = 0;
    const double value = std::stod(text, &used);
    return used == text.size() ? value : std::nan("");
  } catch (const std::exception&) {
    return std::nan("");
  }
}

}  // namespace trephine::study
