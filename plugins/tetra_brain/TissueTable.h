#pragma once
// The tissues of a brain mesh, by label (the tetrahedra's labels, as the mesh
// file or the phantom gives them): what resection needs of each, declared by
// the scene's Tissue components. A label no tissue declares is still brain
// (it deforms and is touched) but cannot be resected.
#include <cstdint>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace trephine::tetra {

struct TissueSpec {
  std::string name;          // the tissue's name in the metrics (its component's)
  int32_t label = 0;         // the tetrahedra's label
  double removalEnergy = 0;  // J/mm^3: the work a resecting tool spends per volume removed
  double vascularity = 0;    // ml of blood per ml of tissue: the blood lost when it is removed uncoagulated
  bool critical = false;     // never removed; touching it is an event
};

// The number of tetrahedra of each label (none for a mesh without labels).
std::map<int32_t, size_t> labelCensus(std::span<const int32_t> labels);

class TissueTable {
 public:
  // Declares a tissue of a mesh whose tetrahedra have `labels`; an error
  // (what is wrong and what was expected) when the mesh has no tetrahedron
  // of its label, or another tissue already has its label or its name.
  std::optional<std::string> declare(const TissueSpec& tissue, std::span<const int32_t> labels);
  const std::vector<TissueSpec>& tissues() const { return m_tissues; }
  bool empty() const { return m_tissues.empty(); }
  // The tissue of a label, or null.
  const TissueSpec* ofLabel(int32_t label) const;
  // The labels of the mesh that no tissue declares, with their counts.
  std::map<int32_t, size_t> undeclared(std::span<const int32_t> labels) const;

 private:
  std::vector<TissueSpec> m_tissues;
};

}  // namespace trephine::tetra
