#pragma once
// The NRRD "data file:" field of detached headers, in its three forms:
//   data file: head.raw                          one file
//   data file: quarter.%d 1 93 1 [2]             a numbered series (printf-style
//                                                format, first, last, step, [slab dimension])
//   data file: LIST [2]                          the names follow, one per line
// Names are relative to the header's directory unless absolute.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace trephine::formats {

struct NrrdDataFiles {
  std::vector<std::filesystem::path> files;
  std::optional<int64_t> slabDimension;  // dimension of the block in each file, when given
};

// Expands the value of "data file:" (not LIST). At most `maxFiles` files are
// generated; a series longer than that is reported, not expanded.
NrrdDataFiles expandNrrdDataFile(std::string_view value, const std::filesystem::path& header, uint64_t maxFiles);

// The file number `number` formatted with a printf-style `format` holding
// exactly one %d/%i/%u conversion (flags 0, -, + or space, optional width);
// formatted here rather than by printf so a hostile format cannot misbehave.
// Nothing when the format is not of that form.
std::optional<std::string> formatSeriesName(std::string_view format, int64_t number);

}  // namespace trephine::formats
