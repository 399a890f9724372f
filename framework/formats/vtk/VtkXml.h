#pragma once
// Writing VTK XML datasets that ParaView opens: poly data (.vtp: points,
// vertices, lines, triangles), unstructured grids of tetrahedra (.vtu) and the
// collection that orders a run's files in time (.pvd). Arrays are appended as
// raw little-endian bytes in zlib blocks of 32 KiB (header_type UInt64,
// vtkZLibDataCompressor), coordinates and values in Float32: a frame of a
// 20,000-tetrahedron brain is a fifth of its ASCII size, and a viewer needs no
// more than 7 digits of millimetres. Files are written whole through a
// temporary name (AtomicFile).
#include <array>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "framework/core/OutputFolder.h"
#include "framework/math/Math.h"

namespace trephine::formats {

// `components` values per point (or per cell), point after point.
struct VtkDataArray {
  std::string name;
  int components = 1;
  std::vector<float> values;
};

struct VtkPolyData {
  std::vector<Vec3> points;                       // mm
  std::vector<int32_t> vertices;                  // one vertex cell per listed point
  std::vector<std::array<int32_t, 2>> lines;
  std::vector<std::array<int32_t, 3>> triangles;
  std::vector<VtkDataArray> pointData;
};

// Float32 coordinates are a viewer's (7 digits of mm); Float64 a mesh file's,
// read back exactly.
enum class PointPrecision { kFloat32, kFloat64 };

struct VtkTetGrid {
  std::span<const Vec3> points;                   // mm
  std::span<const std::array<int32_t, 4>> tets;   // VTK_TETRA, positively oriented
  std::vector<VtkDataArray> pointData;
  std::vector<VtkDataArray> cellData;                // one tuple per tetrahedron
  std::span<const int32_t> labels;                // tissue labels (Int32 cell array "label"), or none
  PointPrecision precision = PointPrecision::kFloat32;
};

// The cells (and labels) of a tetrahedral grid, compressed once: a series of
// files of one mesh whose nodes move (a deforming brain) then compresses only
// the points and point data of each frame, a fifth of the bytes.
class VtkTetCells {
 public:
  // Throws std::invalid_argument for an index outside [0, points) or labels
  // of another count than the tetrahedra.
  VtkTetCells(std::span<const std::array<int32_t, 4>> tets, std::span<const int32_t> labels, size_t points);
  size_t tetCount() const { return m_tets; }
  size_t pointCount() const { return m_points; }

 private:
  friend void writeTetGrid(std::span<const Vec3>, const VtkTetCells&, const std::vector<VtkDataArray>&,
                           const std::vector<VtkDataArray>&, const OutputPath&, PointPrecision);
  size_t m_tets = 0, m_points = 0;
  std::string m_connectivity, m_offsets, m_types, m_labels;  // header and zlib blocks each
};

// Throws FileWriteError (the file and what failed: an index out of range, an
// array of the wrong length, a non-finite coordinate, the disk).
void writePolyData(const VtkPolyData& data, const OutputPath& file);
void writeTetGrid(const VtkTetGrid& grid, const OutputPath& file);
void writeTetGrid(std::span<const Vec3> points, const VtkTetCells& cells, const std::vector<VtkDataArray>& pointData,
                  const std::vector<VtkDataArray>& cellData, const OutputPath& file,
                  PointPrecision precision = PointPrecision::kFloat32);

// A .vtm multiblock index: one dataset made of the files listed (relative to
// the .vtm's directory), each at its block's index (an index not listed is
// an empty block), for a surface written block by block where only the
// changed blocks get new files: a block keeps its index while others empty
// or fill.
void writeMultiBlock(const std::vector<std::pair<size_t, std::string>>& blocks, const OutputPath& file);

// A .pvd collection: ParaView plays its datasets in time order, parts drawn together.
class PvdCollection {
 public:
  // `file` relative to the .pvd's directory; `time` in s.
  void add(double time, const std::string& file, int part = 0);
  size_t size() const { return m_entries.size(); }
  void write(const OutputPath& file) const;

 private:
  struct Entry {
    double time;
    std::string file;
    int part;
  };
  std::vector<Entry> m_entries;
};

}  // namespace trephine::formats
