#pragma once
// NRRD volumes (teem's Nearly Raw Raster Data, 3D Slicer's native format):
// a "field: value" text header after the NRRD000X magic, with the samples
// after a blank line (.nrrd) or in data files the header names (.nhdr);
// raw or gzip encoded.
#include <span>

#include "framework/data/DensityVolume.h"
#include "framework/formats/volume/ByteSource.h"

namespace trephine::formats {

DensityVolume readNrrd(const ByteSource& header);

// True when `head` (the first bytes of a file) starts with a NRRD magic.
bool looksLikeNrrd(std::span<const uint8_t> head);

}  // namespace trephine::formats
