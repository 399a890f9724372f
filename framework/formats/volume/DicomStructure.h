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
// problem. The elements GDCM reads through its typed attributes (the image's
// size, pixel format, position, orientation, spacing and rescale, at any
// depth) must have their standard value representation: GDCM asserts on
// another. The Image Pixel attributes come back, so that the pixels are
// decoded from them (GDCM's image reader also parses palettes, icons,
// overlays and curves, and asserts on malformed ones).
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>

namespace trephine::formats {

// What decoding the pixels needs of the Image Pixel module (PS3.3
// C.7.6.3), at the data set's top level; one sample a pixel (the check
// refuses more). BitsAllocated is 0 where absent; an absent BitsStored is
// BitsAllocated, an absent HighBit BitsStored - 1.
struct DicomPixelAttributes {
  uint16_t bitsAllocated = 0, bitsStored = 0, highBit = 0, pixelRepresentation = 0;
  std::string photometricInterpretation;  // trimmed: MONOCHROME1, MONOCHROME2, or empty (absent)
  // Where the data set ends, and the zero bytes after it: some scanners pad
  // a file to a block size (a GE MR series carries megabytes). Only zeros
  // pass; anything else after the data set is a breach like any other.
  uint64_t dataSetEnd = 0;
  uint64_t trailingZeros = 0;
};

DicomPixelAttributes checkDicomStructure(const std::filesystem::path& file, std::span<const uint8_t> bytes);

}  // namespace trephine::formats
