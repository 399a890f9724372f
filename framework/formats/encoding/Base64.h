#pragma once
// Base64 (RFC 4648): decoding as VTK XML files use it for inline binary
// arrays, encoding for the viewer's data files. VTK encodes the block header
// and the data either as one stream or as separately padded streams written
// back to back, so padding ('=') may appear in the middle: decoding continues
// after it, which reads both layouts the same way.
#include <cstddef>
#include <string>
#include <string_view>

namespace trephine::formats {

// Decodes `text`, skipping white space. On a character that is not base64
// (or a dangling single character) returns false with its offset in `badOffset`.
bool decodeBase64(std::string_view text, std::string& out, size_t& badOffset);

// Standard padded base64 of `bytes`.
std::string encodeBase64(std::string_view bytes);

}  // namespace trephine::formats
