#pragma once
// The VTK cell types the readers keep: linear tetrahedra, and quadratic ones
// (10 points: the 4 corners first, then the 6 edge midpoints), of which only
// the corners are kept: collision works on the straight-sided tetrahedra.
#include <cstdint>
#include <string>

namespace trephine::formats {

inline constexpr int64_t kVtkTetra = 10;
inline constexpr int64_t kVtkQuadraticTetra = 24;

// Points a cell of `type` lists when it is a tetrahedron (4 or 10), else 0.
inline int64_t vtkTetraPointCount(int64_t type) { return type == kVtkTetra ? 4 : type == kVtkQuadraticTetra ? 10 : 0; }

// "type 10 (VTK_TETRA)", for messages.
inline std::string vtkTetraTypeName(int64_t type) {
  return "type " + std::to_string(type) + (type == kVtkTetra ? " (VTK_TETRA)" : " (VTK_QUADRATIC_TETRA)");
}

}  // namespace trephine::formats
