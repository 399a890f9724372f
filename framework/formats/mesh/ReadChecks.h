#pragma once
// Limits and checks shared by every mesh format reader, so that they refuse
// the same things in the same words: counts beyond what the simulation could
// ever hold (checked before anything is reserved), labels that are not
// 32-bit integers, node indices outside the mesh.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace trephine::formats {

// At most 2^28 nodes and 2^28 tetrahedra (about 10 GB as a TetMesh): far
// above any surgical mesh, and node indices stay well inside int32_t.
constexpr int64_t kMaxNodes = int64_t(1) << 28;
constexpr int64_t kMaxTets = int64_t(1) << 28;
// Raw records of a file (all its elements or cells, of any type), and the
// values of one array (a VTK connectivity array holds several per cell).
constexpr int64_t kMaxRecords = int64_t(1) << 30;
constexpr int64_t kMaxArrayValues = int64_t(1) << 32;

// `value` as a label when it is an integer in int32_t range (TetGen writes
// attributes as reals: "5" and "5.0" are both label 5).
std::optional<int32_t> labelFromReal(double value);
std::optional<int32_t> labelFromInteger(int64_t value);

// True for the names of per-cell arrays that hold a tissue label: "label",
// "labels", "tissue", "gmsh:physical", "medit:ref", "CellEntityIds", ...
// (case-insensitive).
bool isLabelArrayName(std::string_view name);

// "1..30871" for 30871 nodes numbered from 1; "none" for no nodes.
std::string indexRange(int64_t first, int64_t count);

}  // namespace trephine::formats
