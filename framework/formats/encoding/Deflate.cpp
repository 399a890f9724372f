#include "framework/formats/encoding/Deflate.h"

#include <zlib.h>

#include <stdexcept>

namespace trephine::formats {

std::string deflateBytes(std::span<const uint8_t> bytes, int level) {
  uLongf size = compressBound(uLong(bytes.size()));
  std::string out(size, '\0');
  const int status = compress2(reinterpret_cast<Bytef*>(out.data()), &size, bytes.data(), uLong(bytes.size()), level);
  // Only memory can fail here: the bound is zlib's own for these bytes.
  if (status != Z_OK) throw std::runtime_error("zlib could not deflate " + std::to_string(bytes.size()) + " bytes");
  out.resize(size);
  return out;
}

}  // namespace trephine::formats
