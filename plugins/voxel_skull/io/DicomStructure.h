#pragma once
// A check of a DICOM Part 10 file's structure, made before GDCM reads it:
// Debian's GDCM is built with assertions, and some malformed files abort the
// process inside it instead of failing the read. The check walks the file as
// the standard lays it out (PS3.5 section 7, PS3.10 section 7):
//   - the 128-byte preamble and "DICM";
//   - the File Meta Information (group 0002, explicit VR little endian),
//     with its Transfer Syntax UID;
//   - the data set in that syntax (implicit or explicit VR little endian;
//     big endian and deflated syntaxes are refused), every element's VR a
//     known one, every defined length inside its parent, sequences and items
//     nested at most 32 deep and closed by their delimiters, undefined lengths
//     only on sequences, UN and encapsulated pixel data.
// Any breach is a VolumeReadError naming the file, the byte offset and the
// problem.
#include <cstdint>
#include <filesystem>
#include <span>

namespace trephine::voxel {

void checkDicomStructure(const std::filesystem::path& file, std::span<const uint8_t> bytes);

}  // namespace trephine::voxel
