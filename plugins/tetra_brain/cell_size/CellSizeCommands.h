#pragma once
// `trephine cellsize MESH`, which the brain plugin provides to the program
// (PluginCommands): the grid cell size the thesis's cost model predicts for
// collision between two copies of a tetrahedral mesh (chapter 5), the
// edge-length rule, and with --experiment the measured optimum; with --tool
// RADIUS, the cell size of TetraBrain's grid for a spherical tool's
// pointshell (the tool query's cost model).
#include <filesystem>
#include <memory>
#include <string>

#include "framework/data/TetMesh.h"
#include "framework/runtime/PluginCommands.h"

namespace trephine::tetra {

int cellSizeCommand(const cli::Arguments& arguments, const PlotDrawer& drawPlot);
int toolCellSizeCommand(const cli::Arguments& arguments, const PlotDrawer& drawPlot);

// Writes `text` as `out`/`name` (the folder created when missing), whole or
// not at all and never through a link (AtomicFile): on a failure (a full
// disk, a link in the way) prints why and returns false.
bool writeExperimentFile(const std::filesystem::path& out, const std::string& name, const std::string& text);

// A tetrahedral mesh file (.mesh, .vtu, .vtk, .msh, .node/.ele) or phantom:SPEC. Throws with the reason.
TetMesh loadTetMesh(const std::string& name);

// The registry service: runs `cellsize`.
std::shared_ptr<PluginCommands> makeCellSizeCommands();

}  // namespace trephine::tetra
