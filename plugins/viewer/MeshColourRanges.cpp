#include "plugins/viewer/MeshColourRanges.h"

#include <tinyxml2.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "framework/formats/vtk/VtkXmlFile.h"
#include "framework/runtime/RunViewer.h"

namespace trephine::viewer {

namespace {

using formats::VtkXmlFile;

// The largest norm of `components`-tuples of the arrays named `names` under
// `section` (PointData or CellData) of `piece`, into `ranges`.
void largest(const VtkXmlFile& vtk, const VtkXmlFile::Element& piece, const char* section, int64_t tuples,
             std::map<std::string, double>& ranges) {
  const auto* data = piece.FirstChildElement(section);
  if (!data) return;
  for (const auto* array = data->FirstChildElement("DataArray"); array; array = array->NextSiblingElement("DataArray")) {
    const std::string name(formats::vtkXmlAttribute(*array, "Name"));
    const bool point = std::string(section) == "PointData";
    if (!(point ? name == "displacement" || name == "force" : name == "von_mises")) continue;
    const int64_t components = vtk.components(*array);
    const std::vector<double> values = vtk.reals(*array, components * tuples);
    double most = 0;
    for (int64_t i = 0; i < tuples; ++i) {
      double squared = 0;
      for (int64_t c = 0; c < components; ++c) squared += values[size_t(i * components + c)] * values[size_t(i * components + c)];
      if (std::isfinite(squared)) most = std::max(most, squared);
    }
    double& range = ranges[name];
    range = std::max(range, std::sqrt(most));
  }
}

}  // namespace

std::map<std::string, double> meshColourRanges(const std::vector<std::filesystem::path>& files) {
  std::map<std::string, double> ranges;
  for (const auto& file : files) {
    std::ifstream in(file, std::ios::binary);
    if (!in) throw ViewerDataError(file.string() + ": cannot be read");
    std::ostringstream text;
    text << in.rdbuf();
    const std::string content = text.str();
    try {
      const VtkXmlFile vtk(file, content, "UnstructuredGrid");
      for (const auto* piece = vtk.dataSet().FirstChildElement("Piece"); piece;
           piece = piece->NextSiblingElement("Piece")) {
        largest(vtk, *piece, "PointData", vtk.count(*piece, "NumberOfPoints", int64_t(1) << 31), ranges);
        largest(vtk, *piece, "CellData", vtk.count(*piece, "NumberOfCells", int64_t(1) << 31), ranges);
      }
    } catch (const ViewerDataError&) {
      throw;
    } catch (const std::exception& e) {
      throw ViewerDataError(e.what());
    }
  }
  return ranges;
}

}  // namespace trephine::viewer
