#pragma once
// MetaImage (ITK MetaIO) volumes: a "Key = Value" text header ending with
// ElementDataFile, and the samples either after it in the same file
// (ElementDataFile = LOCAL, .mha) or in a separate file (.mhd + .raw/.zraw),
// raw or zlib-compressed (CompressedData = True). TransformMatrix places the
// samples; AnatomicalOrientation is only a label and is ignored.
#include "framework/data/DensityVolume.h"
#include "framework/formats/volume/ByteSource.h"

namespace trephine::formats {

DensityVolume readMetaImage(const ByteSource& header);

// True when `head` (the first bytes of a file) starts like a MetaImage header.
bool looksLikeMetaImage(std::span<const uint8_t> head);

}  // namespace trephine::formats
