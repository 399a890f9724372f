#include "plugins/openigtlink/IgtlExportMessages.h"

#include <cstring>
#include <stdexcept>

#include "plugins/openigtlink/IgtlMessages.h"

namespace trephine::openigtlink {
namespace {

void putBig(Message& out, uint64_t v, int bytes) {
  for (int i = bytes - 1; i >= 0; --i) out.push_back(static_cast<unsigned char>((v >> (8 * i)) & 0xffu));
}
void putFloat32(Message& out, double value) {
  const float f = static_cast<float>(value);
  uint32_t bits;
  std::memcpy(&bits, &f, 4);
  putBig(out, bits, 4);
}

// Header in front of `body` (which starts kHeaderSize bytes into `message`).
void finish(Message& message, std::string_view type, std::string_view name, uint64_t timestamp) {
  MessageHeader h;
  h.version = 1;
  std::memcpy(h.type.data(), type.data(), std::min(type.size(), kTypeSize));
  std::memcpy(h.device.data(), name.data(), std::min(name.size(), kDeviceNameSize));
  h.timestamp = timestamp;
  h.bodySize = message.size() - kHeaderSize;
  h.crc = crc64({message.data() + kHeaderSize, message.size() - kHeaderSize});
  encodeHeader(h, std::span<unsigned char, kHeaderSize>(message.data(), kHeaderSize));
}

}  // namespace

Message transformMessage(std::string_view name, uint64_t timestamp, const Vec3& p, const Quat& q) {
  Message m(kHeaderSize);
  // The rotation seen from RAS axes: F R F, F = diag(-1, -1, 1).
  const Eigen::Matrix3d flip = Vec3(-1, -1, 1).asDiagonal();
  const Eigen::Matrix3d r = flip * q.normalized().toRotationMatrix() * flip;
  const Vec3 ras = lpsToRas(p);
  for (int column = 0; column < 3; ++column)
    for (int row = 0; row < 3; ++row) putFloat32(m, r(row, column));
  for (int i = 0; i < 3; ++i) putFloat32(m, ras[i]);
  finish(m, "TRANSFORM", name, timestamp);
  return m;
}

Message imageMessage(std::string_view name, uint64_t timestamp, const VoxelGrid& grid,
                     const std::array<int32_t, 3>& offset, const std::array<int32_t, 3>& size) {
  const std::array<int32_t, 3> dims{grid.nx, grid.ny, grid.nz};
  for (int a = 0; a < 3; ++a) {
    if (dims[a] > 65535) throw std::invalid_argument("a volume of more than 65535 voxels along an axis");
    if (offset[a] < 0 || size[a] < 1 || offset[a] + size[a] > dims[a])
      throw std::invalid_argument("a sub-volume outside the volume");
  }
  Message m(kHeaderSize);
  m.reserve(kHeaderSize + 72 + 2 * size_t(size[0]) * size[1] * size[2]);
  putBig(m, 1, 2);  // image header version
  m.push_back(1);   // one component
  m.push_back(4);   // int16
  m.push_back(1);   // big-endian data
  m.push_back(1);   // RAS (the scene's LPS turned into it)
  for (int a = 0; a < 3; ++a) putBig(m, static_cast<uint64_t>(dims[a]), 2);
  // Voxel axes times the spacing, then the volume's centre, in RAS: the
  // voxel axes are the scene's, so along x and y they point the other way.
  const Vec3 sign(-1, -1, 1);
  for (int a = 0; a < 3; ++a)
    for (int c = 0; c < 3; ++c) putFloat32(m, a == c ? sign[a] * grid.spacing[a] : 0.0);
  Vec3 centre;
  for (int c = 0; c < 3; ++c) centre[c] = grid.corner[c] + 0.5 * dims[c] * grid.spacing[c];
  const Vec3 ras = lpsToRas(centre);
  for (int c = 0; c < 3; ++c) putFloat32(m, ras[c]);
  for (int a = 0; a < 3; ++a) putBig(m, static_cast<uint64_t>(offset[a]), 2);
  for (int a = 0; a < 3; ++a) putBig(m, static_cast<uint64_t>(size[a]), 2);
  for (int32_t k = offset[2]; k < offset[2] + size[2]; ++k)
    for (int32_t j = offset[1]; j < offset[1] + size[1]; ++j)
      for (int32_t i = offset[0]; i < offset[0] + size[0]; ++i)
        putBig(m, static_cast<uint16_t>(grid.codes[grid.linear(i, j, k)]), 2);
  finish(m, "IMAGE", name, timestamp);
  return m;
}

Message polyDataMessage(std::string_view name, uint64_t timestamp, const std::vector<Vec3>& points,
                        const std::vector<std::array<int32_t, 3>>& triangles) {
  Message m(kHeaderSize);
  m.reserve(kHeaderSize + 40 + 12 * points.size() + 16 * triangles.size());
  // Counts: points, vertices (count, bytes), lines, polygons, triangle strips, attributes.
  putBig(m, points.size(), 4);
  putBig(m, 0, 4);
  putBig(m, 0, 4);
  putBig(m, 0, 4);
  putBig(m, 0, 4);
  putBig(m, triangles.size(), 4);
  putBig(m, 16 * triangles.size(), 4);  // each: its point count, then three indices (u32)
  putBig(m, 0, 4);
  putBig(m, 0, 4);
  putBig(m, 0, 4);
  for (const Vec3& p : points) {
    const Vec3 ras = lpsToRas(p);
    for (int c = 0; c < 3; ++c) putFloat32(m, ras[c]);
  }
  for (const auto& t : triangles) {
    putBig(m, 3, 4);
    for (const int32_t index : t) putBig(m, static_cast<uint32_t>(index), 4);
  }
  finish(m, "POLYDATA", name, timestamp);
  return m;
}

}  // namespace trephine::openigtlink
