#include "plugins/tetra_brain/TissueTable.h"

namespace trephine::tetra {

namespace {
// "1 (12,000 tetrahedra), 5 (3)": the labels a mesh has.
std::string describeLabels(const std::map<int32_t, size_t>& census) {
  std::string text;
  for (const auto& [label, count] : census) {
    if (!text.empty()) text += ", ";
    text += std::to_string(label) + " (" + std::to_string(count) + (count == 1 ? " tetrahedron)" : " tetrahedra)");
  }
  return text;
}
}  // namespace

std::map<int32_t, size_t> labelCensus(std::span<const int32_t> labels) {
  std::map<int32_t, size_t> census;
  for (const int32_t label : labels) ++census[label];
  return census;
}

std::optional<std::string> TissueTable::declare(const TissueSpec& tissue, std::span<const int32_t> labels) {
  const std::map<int32_t, size_t> census = labelCensus(labels);
  if (census.empty())
    return "the mesh holds no tissue labels (its file gives none): a tissue is the tetrahedra of one label "
           "(TetGen region attributes, Medit references, Gmsh physical tags, VTK cell data \"label\")";
  if (!census.contains(tissue.label))
    return "no tetrahedron of the mesh has label " + std::to_string(tissue.label) +
           "; its labels are " + describeLabels(census);
  for (const TissueSpec& other : m_tissues) {
    if (other.label == tissue.label)
      return "label " + std::to_string(tissue.label) + " is already the tissue '" + other.name + "'";
    if (other.name == tissue.name) return "another tissue of this mesh is named '" + tissue.name + "'";
  }
  m_tissues.push_back(tissue);
  return std::nullopt;
}

const TissueSpec* TissueTable::ofLabel(int32_t label) const {
  for (const TissueSpec& tissue : m_tissues)
    if (tissue.label == label) return &tissue;
  return nullptr;
}

std::map<int32_t, size_t> TissueTable::undeclared(std::span<const int32_t> labels) const {
  std::map<int32_t, size_t> census = labelCensus(labels);
  for (const TissueSpec& tissue : m_tissues) census.erase(tissue.label);
  return census;
}

}  // namespace trephine::tetra
