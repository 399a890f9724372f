#pragma once
// NIfTI-1 and NIfTI-2 volumes: single files (.nii; .nii.gz arrive here
// decompressed) and .hdr/.img pairs (the samples in NAME.img or NAME.img.gz
// beside NAME.hdr): the 348-byte (NIfTI-1) or 540-byte (NIfTI-2: 64-bit
// sizes, double reals) binary header, in either byte order, and the samples
// at vox_offset. Written here rather than taken from nifticlib, whose reader
// prints its errors and opens files itself: this one reads through the
// ByteSource of the other formats (gzip, the fuzzer's memory files) and
// says which field is wrong.
#include <span>

#include "framework/data/DensityVolume.h"
#include "framework/formats/volume/ByteSource.h"

namespace trephine::formats {

DensityVolume readNifti(const ByteSource& source);

// True when `head` starts with sizeof_hdr 348 (NIfTI-1) or 540 (NIfTI-2) in either byte order.
bool looksLikeNifti(std::span<const uint8_t> head);

}  // namespace trephine::formats
