#pragma once
// The study's own CSV files (poses.csv, probe.csv, result.csv), read back by
// column name: plain cells (no quotes: the study writes none), header first.
#include <filesystem>
#include <string>
#include <vector>

namespace trephine::study {

using Table = std::vector<std::vector<std::string>>;  // header first

// Throws std::runtime_error naming the file (and the line) when it cannot be
// read, is empty, or a row has another number of cells than the header.
Table readTable(const std::filesystem::path& file);
// The index of column `name`; throws naming the file when there is none.
size_t column(const Table& table, const std::string& name, const std::filesystem::path& file);
// The cell as a number; NaN when it is not one.
double toNumber(const std::string& text);

}  // namespace trephine::study
