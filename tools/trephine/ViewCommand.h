#pragma once
// `trephine view RUN_DIR`: writes the browser viewer of a run next to its
// outputs (RUN_DIR/view/index.html, the bundled viewer and the run's VTK
// files repacked as scripts), so that it opens from the disk with nothing
// installed and no network.
#include "tools/trephine/CommandLine.h"

namespace trephine::cli {

int viewCommand(const Arguments& arguments);

}  // namespace trephine::cli
