#pragma once
// Base64 as VTK XML files use it for inline binary arrays. VTK encodes the
// block header and the data either as one stream or as separately padded
// streams written back to back, so padding ('=') may appear in the middle:
// decoding continues after it, which reads both layouts the same way.
#include <cstddef>
#include <string>
#include <string_view>

namespace trephine::tetra {

// Decodes `text`, skipping white space. On a character that is not base64
// (or a dangling single character) returns false with its offset in `badOffset`.
bool decodeBase64(std::string_view text, std::string& out, size_t& badOffset);

}  // namespace trephine::tetra
