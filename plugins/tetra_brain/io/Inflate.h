#pragma once
// zlib inflation for mesh files: whole gzip-wrapped files (brain.ele.gz) and
// the zlib blocks of compressed VTK XML arrays. Output is always capped by
// the caller, so a corrupt or malicious stream cannot make the reader
// allocate more than the file could honestly hold.
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>

namespace trephine::tetra {

// deflate never compresses better than about 1032:1, so n compressed bytes
// cannot hold more than this: lets callers refuse impossible sizes up front.
uint64_t maxInflatedSize(uint64_t compressedBytes);

// Inflates a gzip (or zlib) stream, joining concatenated gzip members (pigz,
// cat a.gz b.gz). Bytes after the last member that are not gzip are ignored,
// as gunzip does. Throws TetMeshReadError naming `file` when the stream is
// corrupt, ends early (truncated file) or would exceed `maxBytes`.
std::string inflateGzip(std::string_view compressed, uint64_t maxBytes, const std::filesystem::path& file);

// Inflates one zlib stream that must produce exactly out.size() bytes. On
// failure returns false and says why in `problem`.
bool inflateExactly(std::string_view compressed, std::span<char> out, std::string& problem);

}  // namespace trephine::tetra
