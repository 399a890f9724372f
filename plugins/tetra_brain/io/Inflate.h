#pragma once
// Whole gzip-wrapped mesh files (brain.ele.gz), inflated through the
// framework's capped inflater with errors that name the file. (The zlib
// blocks of VTK XML arrays use inflateExactly from the framework directly.)
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

#include "framework/compression/Inflate.h"

namespace trephine::tetra {

// Inflates a gzip (or zlib) stream, joining concatenated gzip members (pigz,
// cat a.gz b.gz). Bytes after the last member that are not gzip are ignored,
// as gunzip does. Throws TetMeshReadError naming `file` when the stream is
// corrupt, ends early (truncated file) or would exceed `maxBytes`.
std::string inflateGzip(std::string_view compressed, uint64_t maxBytes, const std::filesystem::path& file);

}  // namespace trephine::tetra
