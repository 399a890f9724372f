
#include "plugins/tetra_brain/cell_size/CellSizeCommands.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <optional>
#include <sstream>

#include "framework/core/Strings.h"
#include "framework/runtime/JsonWriter.h"
#include "plugins/tetra_brain/cell_size/CellSizeExperiment.h"
#include "plugins/tetra_brain/cell_size/CellSizeModel.h"

namespace trephine::tetra {

using namespace cli;

namespace {

constexpr const char* kUsageLine =
    "usage: trephine cellsize MESH [--pnc P] [--rt R | --calibrate] [--json] [--experiment] [--out DIR]\n"
    "                              [--frames N] [--rounds N]\n"
    "       trephine cellsize MESH --tool RADIUS ...   (the tool query's cell: see trephine --help)\n"
    "  MESH: a tetrahedral mesh file (.mesh, .vtu, .vtk, .msh, .node/.ele) or phantom:SPEC\n";

std::string number(double v) { return formatDouble(v); }

}  // namespace

int cellSizeCommand(const Arguments& a, const PlotDrawer& drawPlot) {
  if (a.has("--tool")) return toolCellSizeCommand(a, drawPlot);
  std::string error;
  const auto pnc = numberOption(a, "--pnc", 0.99, error);
  const auto rt = numberOption(a, "--rt", 5.0, error);
  const auto frames = numberOption(a, "--frames", 10, error);
  const auto rounds = numberOption(a, "--rounds", 3, error);
  if (error.empty() && a.positional.size() != 1) error = "one mesh expected";
  if (error.empty() && a.has("--rt") && a.has("--calibrate")) error = "--rt and --calibrate exclude each other";
  if (error.empty() && !(*pnc > 0 && *pnc < 1)) error = "--pnc is a probability in (0, 1)";
  if (error.empty() && !(*rt > 0)) error = "--rt is a positive time ratio";
  if (error.empty() && (!(*frames >= 1 && *frames <= 1000 && *frames == std::floor(*frames)) ||
                         !(*rounds >= 1 && *rounds <= 100 && *rounds == std::floor(*rounds))))
    error = "--frames (1 to 1000) and --rounds (1 to 100) take whole counts";
  if (!error.empty()) {
    std::cerr << "trephine cellsize: " << error << "\n" << kUsageLine;
    return kUsage;
  }
  const std::string meshName = a.positional[0];
  TetMesh mesh;
  CellSizeInputs inputs;
  try {
    mesh = loadTetMesh(meshName);
    inputs = measureCellSizeInputs(mesh);
  } catch (const std::exception& e) {
    std::cerr << "trephine cellsize: " << meshName << ": " << e.what() << "\n";
    return kSceneError;
  }
  CostParameters parameters{*pnc, *rt};
  const bool experiment = a.has("--experiment"), calibrate = a.has("--calibrate");
  std::optional<CellSizeExperimentResult> measured;
  if (experiment || calibrate) {
    CellSizeExperimentOptions options;
    options.frames = int(*frames);
    options.rounds = int(*rounds);
    try {
      measured = runCellSizeExperiment(mesh, inputs, options);
    } catch (const std::exception& e) {
      std::cerr << "trephine cellsize: " << meshName << ": " << e.what() << "\n";
      return kRuntimeFailure;
    }
    if (calibrate) parameters.testTimeRatio = measured->calibratedTimeRatio;
  }
  const double deltaA = optimalCellSize(inputs, parameters);
  const double deltaTrad = inputs.averageEdge;
  // The model with both constants measured (p_nc at delta_a, r_t from the sweep).
  std::optional<double> deltaMeasured;
  if (measured && measured->calibratedTimeRatio > 0 && measured->measuredCollisionFree > 0 &&
      measured->measuredCollisionFree < 1)
    deltaMeasured = optimalCellSize(inputs, {measured->measuredCollisionFree, measured->calibratedTimeRatio});

  std::filesystem::path out;
  if (experiment) {
    out = a.get("--out") ? std::filesystem::path(*a.get("--out"))
                         : std::filesystem::path("runs") / ("cellsize-" + std::filesystem::path(meshName).stem().string());
    std::ostringstream csv;
    csv << "cell_size_mm,cells_per_mm,time_us,fitted_us,cell_visits,box_tests,barycentric_tests,contacts,grid_cells\n";
    for (const CellSizeSample& s : measured->samples)
      csv << number(s.cellSize) << "," << number(1 / s.cellSize) << "," << number(s.timeUs) << ","
          << number(s.fittedUs) << "," << s.perFrame.cellVisits << "," << s.perFrame.boxTests << ","
          << s.perFrame.barycentricTests << "," << s.perFrame.contacts << "," << s.cells << "\n";
    if (!writeExperimentFile(out, "cellsize.csv", csv.str())) return kRuntimeFailure;
  }

  std::ostringstream json;
  {
    JsonWriter w(json);
    w.beginObject();
    w.field("mesh", meshName).field("tetrahedra", inputs.tetrahedra).field("nodes", mesh.nodeCount());
    w.field("delta_a", deltaA).field("delta_trad", deltaTrad);
    w.key("inputs").beginObject();
    w.field("mean_longest_edge", inputs.longestEdge).field("largest_edge", inputs.largestEdge);
    w.field("mean_facet_area", inputs.facetArea).field("facets", inputs.facets);
    w.field("average_edge", inputs.averageEdge).field("edges", inputs.edges);
    w.endObject();
    w.field("pnc", parameters.collisionFreeProbability).field("rt", parameters.testTimeRatio);
    if (measured) {
      const CellSizeExperimentResult& m = *measured;
      w.field("calibrated_rt", m.calibratedTimeRatio).field("measured_pnc", m.measuredCollisionFree);
      if (deltaMeasured) w.field("delta_measured_constants", *deltaMeasured);
      if (experiment) {
        w.field("delta_opt", m.optimal);
        w.key("zone").beginArray().value(m.zoneLow).value(m.zoneHigh).endArray();
        w.field("epsilon_a", cellSizeError(m.optimal, m.zoneLow, m.zoneHigh, deltaA));
        w.field("epsilon_trad", cellSizeError(m.optimal, m.zoneLow, m.zoneHigh, deltaTrad));
        if (deltaMeasured)
          w.field("epsilon_measured_constants", cellSizeError(m.optimal, m.zoneLow, m.zoneHigh, *deltaMeasured));
        w.field("colliding_fraction", m.collidingFraction).field("offset_mm", m.offset.x());
        w.field("zone_tolerance", 0.1);
      }
    }
    w.endObject();
  }
  bool drawn = false;
  if (experiment) {
    if (!writeExperimentFile(out, "cellsize.json", json.str())) return kRuntimeFailure;
    drawn = drawPlot({"plot_cellsize.py", {(out / "cellsize.csv").string()}, "cellsize.png"});
  }

  if (a.has("--json")) {
    std::cout << json.str();
  } else {
    std::cout << std::setprecision(4);
    std::cout << "mesh        " << meshName << " (" << inputs.tetrahedra << " tetrahedra, " << mesh.nodeCount()
              << " nodes)\n"
              << "inputs      mean longest edge " << inputs.longestEdge << " mm (largest " << inputs.largestEdge
              << "), mean facet area " << inputs.facetArea << " mm^2 (" << inputs.facets << " facets), average edge "
              << inputs.averageEdge << " mm (" << inputs.edges << " edges)\n"
              << "model       p_nc " << parameters.collisionFreeProbability << ", r_t " << parameters.testTimeRatio
              << (calibrate ? " (calibrated on this machine)" : "") << "\n"
              << "delta_a     " << deltaA << " mm (minimises the cost model)\n"
              << "delta_trad  " << deltaTrad << " mm (average edge length)\n";
    if (measured) {
      const CellSizeExperimentResult& m = *measured;
      std::cout << "measured    r_t " << m.calibratedTimeRatio << ", p_nc " << m.measuredCollisionFree
                << " (at delta_a)";
      if (deltaMeasured) std::cout << ": delta " << *deltaMeasured << " mm";
      std::cout << "\n";
    }
    if (experiment) {
      const CellSizeExperimentResult& m = *measured;
      std::cout << "experiment  two copies " << m.offset.x() << " mm apart, " << 100 * m.collidingFraction
                << "% of tetrahedra colliding; " << m.samples.size() << " cell sizes\n"
                << "delta_opt   " << m.optimal << " mm, optimal zone " << m.zoneLow << " to " << m.zoneHigh
                << " mm (fitted time within 10% of the minimum)\n"
                << "epsilon     delta_a " << cellSizeError(m.optimal, m.zoneLow, m.zoneHigh, deltaA)
                << ", delta_trad " << cellSizeError(m.optimal, m.zoneLow, m.zoneHigh, deltaTrad)
                << " (at most 1: inside the zone)\n"
                << "outputs     " << out.string() << "/ (cellsize.csv, cellsize.json";
      std::cout << (drawn ? ", cellsize.png)\n" : ")\n");
    }
  }
  return kOk;
}

}  // namespace trephine::tetra
