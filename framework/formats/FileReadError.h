#pragma once
// The one error of every reader: a file that cannot be read as what was
// asked for. The message starts with the file, then the line when there is
// one ("liver.msh:1234: "), or names the field or byte offset, then says what
// was wrong and what was expected. NUL bytes of the file's text are shown as
// '?', so the message stays one C string. (Writers throw FileWriteError.)
#include <filesystem>
#include <stdexcept>
#include <string>

namespace trephine::formats {

class FileReadError : public std::runtime_error {
 public:
  FileReadError(const std::filesystem::path& file, const std::string& problem);
  // line: 1-based line of the file (of its decompressed text for a .gz file); 0: none.
  FileReadError(const std::filesystem::path& file, size_t line, const std::string& problem);
};

}  // namespace trephine::formats
