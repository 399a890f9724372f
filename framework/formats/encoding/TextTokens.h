#pragma once
// Words and numbers of text file formats (volume headers, mesh and surface
// files), read the same way by every reader: ASCII case folding, whole-token
// numbers and tokens quoted for error messages.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace trephine::formats {

bool equalsIgnoreCase(std::string_view a, std::string_view b);
bool startsWithIgnoreCase(std::string_view text, std::string_view prefix);
// ASCII lower case (keywords are ASCII; other bytes are kept).
std::string toLower(std::string_view text);

// Whole-token numbers ("+5" and "5" both read; "5x" and "+-5" do not). "nan"
// and "inf" read, and a real that overflows a double reads as infinity:
// callers check finiteness and report it.
std::optional<int64_t> parseInteger(std::string_view token);
std::optional<double> parseReal(std::string_view token);

// `text` for an error message: quoted, non-printable bytes and backslashes
// escaped as \xNN, text longer than 80 bytes cut.
std::string quoteForMessage(std::string_view text);

}  // namespace trephine::formats
