// Columns of text: whatever the lengths of the values, every line splits back
// into its cells, and each column is right-aligned.
#include <gtest/gtest.h>

#include <random>

#include "framework/core/Strings.h"
#include "framework/core/TextTable.h"

namespace trephine {
namespace {

TEST(TextTableTest, ValuesOfAnyLengthNeverRunTogether) {
  std::mt19937 random(11);
  std::uniform_int_distribution<int> length(1, 12), columns(1, 8), rowsOf(1, 10), digit(0, 9);
  for (int table = 0; table < 500; ++table) {
    const int width = columns(random);
    std::vector<std::vector<std::string>> rows;
    const int count = rowsOf(random);
    for (int r = 0; r < count; ++r) {
      std::vector<std::string> row;
      for (int c = 0; c < width; ++c) {
        std::string cell;
        for (int k = length(random); k > 0; --k) cell += char('0' + digit(random));
        row.push_back(cell);
      }
      rows.push_back(row);
    }
    const std::string text = formatColumns(rows, "    ");
    std::vector<std::string> lines;
    for (size_t start = 0, end; (end = text.find('\n', start)) != std::string::npos; start = end + 1)
      lines.push_back(text.substr(start, end - start));
    ASSERT_EQ(lines.size(), rows.size());
    for (size_t r = 0; r < rows.size(); ++r) {
      ASSERT_TRUE(lines[r].starts_with("    "));
      const std::vector<std::string_view> cells = splitWhitespace(lines[r]);
      ASSERT_EQ(cells.size(), rows[r].size()) << lines[r];
      for (size_t c = 0; c < cells.size(); ++c) EXPECT_EQ(cells[c], rows[r][c]);
      // Right-aligned: every line of the table ends at the same column.
      EXPECT_EQ(lines[r].size(), lines[0].size());
    }
  }
}

TEST(TextTableTest, AColumnIsAsWideAsItsWidestCell) {
  EXPECT_EQ(formatColumns({{"p50_us", "max_us"}, {"3.39", "120586.25"}, {"2.10", "7.94"}}, "  "),
            "  p50_us     max_us\n"
            "    3.39  120586.25\n"
            "    2.10       7.94\n");
}

}  // namespace
}  // namespace trephine
