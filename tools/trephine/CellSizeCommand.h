#pragma once
// `trephine cellsize MESH`: the grid cell size the thesis's cost model
// predicts for collision between two copies of a tetrahedral mesh (chapter
// 5), the edge-length rule, and with --experiment the measured optimum.
#include "tools/trephine/CommandLine.h"

namespace trephine::cli {

int cellSizeCommand(const Arguments& arguments);

}  // namespace trephine::cli
