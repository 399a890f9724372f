#pragma once
// TetGen meshes: a .node file ("N 3 A M" then "i x y z [attributes] [marker]")
// and an .ele file ("T 4 A" then "i n1 n2 n3 n4 [attributes]"). Indices are
// 0- or 1-based, as the smallest index in the .node file says; '#' starts a
// comment. Node attributes and boundary markers are ignored; the first
// element attribute (TetGen's region attribute) becomes the tetrahedron's
// label. Ten-node (quadratic) tetrahedra keep their four corners, which
// TetGen lists first.
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include "framework/data/TetMesh.h"
#include "framework/formats/mesh/TetGenFiles.h"

namespace trephine::formats {

// Which file of a TetGen pair `content` is, judged from its first line
// (a dimension of 3 after the count: nodes; 4 or 10 nodes per element: elements).
std::optional<TetGenPart> tetGenPartOf(std::string_view content);

// Reads the mesh given one file of the pair and its content; the other file
// is found with findTetGenPartner and read too.
TetMesh readTetGen(const std::filesystem::path& file, std::string content);

}  // namespace trephine::formats
