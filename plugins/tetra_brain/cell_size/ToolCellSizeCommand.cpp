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
#include "framework/geometry/ShellSampling.h"
#include "plugins/tetra_brain/NativeTetBackend.h"
#include "plugins/tetra_brain/cell_size/ToolQueryExperiment.h"

namespace trephine::tetra {

using namespace cli;

namespace {

constexpr const char* kUsageLine =
    "usage: trephine cellsize MESH --tool RADIUS [--tool-step DEG] [--deforming] [--calibrate] [--json]\n"
    "                              [--experiment] [--depth D] [--out DIR] [--rounds N] [--poses N]\n";

std::string number(double v) { return formatDouble(v); }

}  // namespace

int toolCellSizeCommand(const Arguments& a, const PlotDrawer& drawPlot) {
  std::string error;
  const auto radius = numberOption(a, "--tool", 0, error);
  const auto step = numberOption(a, "--tool-step", 15, error);
  const auto rounds = numberOption(a, "--rounds", 3, error);
  const auto poses = numberOption(a, "--poses", 200, error);
  const auto depth = numberOption(a, "--depth", 0.05, error);
  if (error.empty() && a.positional.size() != 1) error = "one mesh expected";
  if (error.empty() && !(*radius > 0)) error = "--tool is the tool's radius in mm, above 0";
  if (error.empty() && !(*depth >= 0 && *depth <= *radius))
    error = "--depth is how far (mm) the tool is in the surface, 0 to its radius";
  if (error.empty() && !(*step >= 1 && *step <= 90)) error = "--tool-step is an angle step of 1 to 90 degrees";
  if (error.empty() && (a.has("--pnc") || a.has("--rt") || a.has("--frames")))
    error = "--pnc, --rt and --frames belong to the two-mesh model, not to --tool";
  if (error.empty() && (!(*rounds >= 1 && *rounds <= 100 && *rounds == std::floor(*rounds)) ||
                        !(*poses >= 1 && *poses <= 100000 && *poses == std::floor(*poses))))
    error = "--rounds (1 to 100) and --poses (1 to 100000) take whole counts";
  if (!error.empty()) {
    std::cerr << "trephine cellsize: " << error << "\n" << kUsageLine;
    return kUsage;
  }
  const std::string meshName = a.positional[0];
  TetMesh mesh;
  try {
    mesh = loadTetMesh(meshName);
    if (mesh.tetCount() == 0) throw std::invalid_argument("the mesh has no tetrahedra");
  } catch (const std::exception& e) {
    std::cerr << "trephine cellsize: " << meshName << ": " << e.what() << "\n";
    return kSceneError;
  }
  // The PointshellTool's angle-step shell of this radius.
  std::vector<Vec3> shell;
  for (const Vec3& d : angleStepDirections(*step)) shell.push_back(*radius * d);
  const bool deforming = a.has("--deforming"), experiment = a.has("--experiment"), calibrate = a.has("--calibrate");

  // The back-end's own figures: the average edge and margin it uses.
  const TetTopology topology(mesh);
  TetQueryOptions query;
  query.deformable = deforming;
  NativeTetBackend backend;
  backend.bind({&mesh, &topology, query});
  const double averageEdge = backend.averageEdge(), margin = backend.displacementMargin();
  const TetBoxMoments moments = measureBoxMoments(mesh, margin);
  const std::vector<std::vector<Vec3>> shells{shell};
  // TetraBrain's weights for this kind of mesh.
  const ToolQueryWeights weights =
      deforming ? kDeformingToolQueryWeights : kRigidToolQueryWeights;
  const double deltaTool = optimalToolCellSize(moments, shells, averageEdge, weights);

  std::optional<ToolQueryExperimentResult> measured;
  std::optional<double> deltaCalibrated;
  if (experiment || calibrate) {
    ToolQueryExperimentOptions options;
    options.rounds = int(*rounds);
    options.poses = int(*poses);
    options.deforming = deforming;
    options.depth = *depth;
    try {
      measured = runToolQueryExperiment(mesh, shell, options);
    } catch (const std::exception& e) {
      std::cerr << "trephine cellsize: " << meshName << ": " << e.what() << "\n";
      return kRuntimeFailure;
    }
    const ToolQueryWeights& w = measured->calibrated;
    if (w.cell + w.listed + w.overlapping > 0 && w.pointTest + w.overlapping + w.listed > 0)
      deltaCalibrated = optimalToolCellSize(moments, shells, averageEdge, w);
  }
  const double deltaHalfEdge = 0.5 * averageEdge;

  std::filesystem::path out;
  if (experiment) {
    out = a.get("--out") ? std::filesystem::path(*a.get("--out"))
                         : std::filesystem::path("runs") /
                               ("cellsize-tool-" + std::filesystem::path(meshName).stem().string());
    std::ostringstream csv;
    csv << "cell_size_mm,time_ns,fitted_ns,cells,listed,overlapping,point_tests,predicted_cells,predicted_listed,"
           "predicted_overlapping,predicted_point_tests,grid_cells,grid_entries\n";
    for (const ToolQuerySample& s : measured->samples)
      csv << number(s.cellSize) << "," << number(s.timeNs) << "," << number(s.fittedNs) << ","
          << number(s.measured.cells) << "," << number(s.measured.listed) << "," << number(s.measured.overlapping)
          << "," << number(s.measured.pointTests) << "," << number(s.predicted.cells) << ","
          << number(s.predicted.listed) << "," << number(s.predicted.overlapping) << ","
          << number(s.predicted.pointTests) << "," << s.gridCells << "," << s.gridEntries << "\n";
    if (!writeExperimentFile(out, "tool_cellsize.csv", csv.str())) return kRuntimeFailure;
  }

  std::ostringstream json;
  {
    JsonWriter w(json);
    w.beginObject();
    w.field("mesh", meshName).field("tetrahedra", mesh.tetCount()).field("nodes", mesh.nodeCount());
    w.field("tool_radius", *radius).field("shell_points", shell.size()).field("deforming", deforming);
    w.field("average_edge", averageEdge).field("displacement_margin", margin);
    w.field("delta_tool", deltaTool).field("delta_half_edge", deltaHalfEdge).field("delta_trad", averageEdge);
    if (measured) {
      const ToolQueryExperimentResult& m = *measured;
      w.key("calibrated_weights").beginObject();
      w.field("cell_ns", m.calibrated.cell).field("listed_ns", m.calibrated.listed);
      w.field("overlapping_ns", m.calibrated.overlapping).field("point_test_ns", m.calibrated.pointTest).endObject();
      if (deltaCalibrated) w.field("delta_tool_calibrated", *deltaCalibrated);
      if (experiment) {
        w.field("delta_opt", m.optimal);
        w.key("zone").beginArray().value(m.zoneLow).value(m.zoneHigh).endArray();
        w.field("epsilon_tool", toolCellSizeError(m.optimal, m.zoneLow, m.zoneHigh, deltaTool));
        w.field("epsilon_half_edge", toolCellSizeError(m.optimal, m.zoneLow, m.zoneHigh, deltaHalfEdge));
        w.field("epsilon_trad", toolCellSizeError(m.optimal, m.zoneLow, m.zoneHigh, averageEdge));
        if (deltaCalibrated)
          w.field("epsilon_tool_calibrated",
                  toolCellSizeError(m.optimal, m.zoneLow, m.zoneHigh, *deltaCalibrated));
        w.field("depth", *depth).field("inside_fraction", m.insideFraction).field("zone_tolerance", 0.1);
      }
    }
    w.endObject();
  }
  bool drawn = false;
  if (experiment) {
    if (!writeExperimentFile(out, "tool_cellsize.json", json.str())) return kRuntimeFailure;
    drawn = drawPlot({"plot_cellsize.py", {(out / "tool_cellsize.csv").string()}, "tool_cellsize.png"});
  }
  if (a.has("--json")) {
    std::cout << json.str();
    return kOk;
  }
  std::cout << std::setprecision(4);
  std::cout << "mesh             " << meshName << " (" << mesh.tetCount() << " tetrahedra), average edge "
            << averageEdge << " mm" << (deforming ? ", deforming (margin " + number(margin) + " mm)" : "") << "\n"
            << "tool             sphere of radius " << *radius << " mm, " << shell.size() << " shell points\n"
            << "delta_tool       " << deltaTool << " mm (minimises the tool query's cost model)\n"
            << "delta_half_edge  " << deltaHalfEdge << " mm (half the average edge)\n"
            << "delta_trad       " << averageEdge << " mm (average edge length)\n";
  if (measured) {
    const ToolQueryWeights& w = measured->calibrated;
    std::cout << "calibrated       cell " << w.cell << " ns, listed tetrahedron " << w.listed << " ns, kept "
              << w.overlapping << " ns, point test " << w.pointTest << " ns";
    if (deltaCalibrated) std::cout << ": delta " << *deltaCalibrated << " mm";
    std::cout << "\n";
  }
  if (experiment) {
    const ToolQueryExperimentResult& m = *measured;
    std::cout << "experiment       " << *poses << " poses " << *depth << " mm into the surface, " << m.samples.size() << " cell sizes, "
              << 100 * m.insideFraction << "% of points inside\n"
              << "delta_opt        " << m.optimal << " mm, optimal zone " << m.zoneLow << " to " << m.zoneHigh
              << " mm (fitted time within 10% of the minimum)\n"
              << "epsilon          delta_tool " << toolCellSizeError(m.optimal, m.zoneLow, m.zoneHigh, deltaTool)
              << ", half edge " << toolCellSizeError(m.optimal, m.zoneLow, m.zoneHigh, deltaHalfEdge)
              << ", delta_trad " << toolCellSizeError(m.optimal, m.zoneLow, m.zoneHigh, averageEdge)
              << " (at most 1: inside the zone)\n"
              << "outputs          " << out.string() << "/ (tool_cellsize.csv, tool_cellsize.json"
              << (drawn ? ", tool_cellsize.png)\n" : ")\n");
  }
  return kOk;
}

}  // namespace trephine::tetra
