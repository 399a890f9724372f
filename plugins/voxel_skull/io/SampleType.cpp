#include "plugins/voxel_skull/io/SampleType.h"

namespace trephine::voxel {

size_t sampleBytes(SampleType type) {
  switch (type) {
    case SampleType::kInt8:
    case SampleType::kUInt8:
      return 1;
    case SampleType::kInt16:
    case SampleType::kUInt16:
      return 2;
    case SampleType::kInt32:
    case SampleType::kUInt32:
    case SampleType::kFloat32:
      return 4;
    case SampleType::kFloat64:
      return 8;
  }
  return 1;
}

std::string sampleTypeName(SampleType type) {
  switch (type) {
    case SampleType::kInt8:
      return "int8";
    case SampleType::kUInt8:
      return "uint8";
    case SampleType::kInt16:
      return "int16";
    case SampleType::kUInt16:
      return "uint16";
    case SampleType::kInt32:
      return "int32";
    case SampleType::kUInt32:
      return "uint32";
    case SampleType::kFloat32:
      return "float32";
    case SampleType::kFloat64:
      return "float64";
  }
  return "unknown";
}

}  // namespace trephine::voxel
