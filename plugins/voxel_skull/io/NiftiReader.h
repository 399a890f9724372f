#pragma once
// NIfTI-1 single-file volumes (.nii; .nii.gz arrive here decompressed): the
// 348-byte binary header, in either byte order, and the samples at vox_offset.
#include <span>

#include "plugins/voxel_skull/DensityVolume.h"
#include "plugins/voxel_skull/io/ByteSource.h"

namespace trephine::voxel {

DensityVolume readNifti(const ByteSource& source);

// True when `head` starts with sizeof_hdr 348 (NIfTI-1) or 540 (NIfTI-2, refused by readNifti) in either byte order.
bool looksLikeNifti(std::span<const uint8_t> head);

}  // namespace trephine::voxel
