#pragma once
// Small string helpers shared by the loader and the command line.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace trephine {

// Levenshtein distance (insert, delete, substitute), case-insensitive.
size_t editDistance(std::string_view a, std::string_view b);

// The candidate closest to `word` if it is close enough to be a likely typo
// (distance at most max(2, |word|/3) and less than |word|), else nothing.
std::optional<std::string> closestMatch(std::string_view word, const std::vector<std::string>& candidates);

// ", did you mean 'x'?" or "" when nothing is close.
std::string didYouMean(std::string_view word, const std::vector<std::string>& candidates);

std::string_view trim(std::string_view s);
std::vector<std::string_view> splitWhitespace(std::string_view s);

// Shortest text that reads back to exactly the same double ("0.1", "1e-05", "nan").
std::string formatDouble(double value);

// `text` in single quotes for an error message, with what a reader cannot
// see made visible: control bytes as \xNN, and the invisible or look-alike
// characters editors and spreadsheets slip in (a byte order mark, zero-width
// and non-breaking spaces) as \u{FEFF} and so on. Without it "expected a
// number, got '2.0'" can be all a user sees of a byte order mark.
std::string visiblyQuoted(std::string_view text);

}  // namespace trephine
