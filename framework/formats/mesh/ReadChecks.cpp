#include "framework/formats/mesh/ReadChecks.h"

#include <cmath>
#include <limits>

#include "framework/formats/mesh/TextCursor.h"

namespace trephine::formats {

std::optional<int32_t> labelFromReal(double value) {
  // The range test first: converting an out-of-range double to int is undefined.
  if (!(value >= std::numeric_limits<int32_t>::min() && value <= std::numeric_limits<int32_t>::max()))
    return std::nullopt;
  if (value != std::floor(value)) return std::nullopt;
  return static_cast<int32_t>(value);
}

std::optional<int32_t> labelFromInteger(int64_t value) {
  if (value < std::numeric_limits<int32_t>::min() || value > std::numeric_limits<int32_t>::max()) return std::nullopt;
  return static_cast<int32_t>(value);
}

bool isLabelArrayName(std::string_view name) {
  for (const std::string_view known :
       {"label", "labels", "tissue", "tissues", "tissue_label", "tissuelabel", "gmsh:physical", "medit:ref", "material",
        "materialid", "region", "cellentityids"}) {
    if (equalsIgnoreCase(name, known)) return true;
  }
  return false;
}

std::string indexRange(int64_t first, int64_t count) {
  if (count <= 0) return "none";
  return std::to_string(first) + ".." + std::to_string(first + count - 1);
}

}  // namespace trephine::formats
