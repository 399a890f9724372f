#include "tools/trephine/CommandValues.h"

#include <charconv>
#include <cmath>

#include "plugins/tetra_brain/TetPhantoms.h"
#include "framework/formats/mesh/TetMeshReader.h"

namespace trephine::cli {

std::optional<double> numberOption(const Arguments& a, const std::string& name, double fallback, std::string& error) {
  const auto text = a.get(name);
  if (!text) return fallback;
  double value = 0;
  const auto r = std::from_chars(text->data(), text->data() + text->size(), value);
  if (r.ec != std::errc() || r.ptr != text->data() + text->size() || !std::isfinite(value)) {
    error = name + " takes a number, not '" + *text + "'";
    return std::nullopt;
  }
  return value;
}

TetMesh loadTetMesh(const std::string& name) {
  constexpr std::string_view kPhantom = "phantom:";
  if (name.rfind(kPhantom, 0) == 0) return tetra::makeTetPhantom(name.substr(kPhantom.size()));
  return formats::readTetMesh(name);
}

}  // namespace trephine::cli
