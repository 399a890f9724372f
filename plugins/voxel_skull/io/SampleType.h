#pragma once
// The scalar sample types the volume readers accept (the types MetaImage,
// NRRD and NIfTI-1 have in common, minus 64-bit integers and complex types).
#include <cstddef>
#include <string>

namespace trephine::voxel {

enum class SampleType { kInt8, kUInt8, kInt16, kUInt16, kInt32, kUInt32, kFloat32, kFloat64 };

// Bytes per sample.
size_t sampleBytes(SampleType type);
// "int16", "float32", ... for messages.
std::string sampleTypeName(SampleType type);

}  // namespace trephine::voxel
