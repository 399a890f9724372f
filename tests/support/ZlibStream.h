#pragma once
// Compressed streams written by zlib itself (an independent writer, not the
// project's Deflate.cpp), for the readers' tests. Link ZLIB::ZLIB.
#include <zlib.h>

#include <cstdint>
#include <stdexcept>
#include <string_view>
#include <vector>

namespace trephine::test {

enum class ZlibWrapper { kZlib = 15, kGzip = 15 + 16, kRawDeflate = -15 };

// `bytes` deflated at level 6 in one stream with the given wrapper.
inline std::vector<uint8_t> zlibStream(std::string_view bytes, ZlibWrapper wrapper = ZlibWrapper::kZlib) {
  z_stream z{};
  if (deflateInit2(&z, 6, Z_DEFLATED, int(wrapper), 8, Z_DEFAULT_STRATEGY) != Z_OK)
    throw std::runtime_error("deflateInit2 failed");
  std::vector<uint8_t> out(deflateBound(&z, uLong(bytes.size())) + 64);
  z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(bytes.data()));
  z.avail_in = uInt(bytes.size());
  z.next_out = out.data();
  z.avail_out = uInt(out.size());
  const int result = deflate(&z, Z_FINISH);
  deflateEnd(&z);
  if (result != Z_STREAM_END) throw std::runtime_error("deflate did not finish the stream");
  out.resize(z.total_out);
  return out;
}

template <class Bytes>
std::string_view asView(const Bytes& bytes) {
  return {reinterpret_cast<const char*>(bytes.data()), bytes.size()};
}

}  // namespace trephine::test
