#pragma once
// The messages the exporter streams to 3D Slicer, packed by hand like the
// device's (IgtlMessages.h), version 1 headers: TRANSFORM (a pose), IMAGE
// (the skull's codes, whole or a sub-volume: the protocol's partial update)
// and POLYDATA (a triangle surface). They run off the haptic loop and
// allocate. Each takes the scene's world coordinates (LPS, mm) and writes
// RAS, the frame 3D Slicer reads OpenIGTLink in (x and y negated).
#include <array>
#include <cstdint>
#include <string_view>
#include <vector>

#include "framework/data/VoxelGrid.h"
#include "framework/math/Math.h"

namespace trephine::openigtlink {

using Message = std::vector<unsigned char>;

// The scene's LPS to RAS (and back: it is its own inverse).
inline Vec3 lpsToRas(const Vec3& p) { return Vec3(-p.x(), -p.y(), p.z()); }

Message transformMessage(std::string_view name, uint64_t timestamp, const Vec3& position_mm, const Quat& orientation);

// The block [offset, offset + size) of the grid's voxels (their int16 codes,
// as the volume stores them), placed in the whole volume: the image's size is
// the grid's, its matrix the voxel axes times the spacing, its origin the
// volume's centre (as the protocol puts it). Throws std::invalid_argument
// when the grid is larger than 65535 voxels along an axis (the protocol's limit).
Message imageMessage(std::string_view name, uint64_t timestamp, const VoxelGrid& grid,
                     const std::array<int32_t, 3>& offset, const std::array<int32_t, 3>& size);

// Points (mm) and triangles (indices into them) as POLYDATA polygons.
Message polyDataMessage(std::string_view name, uint64_t timestamp, const std::vector<Vec3>& points,
                        const std::vector<std::array<int32_t, 3>>& triangles);

}  // namespace trephine::openigtlink
