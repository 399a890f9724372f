#pragma once
// `trephine phantom SPEC --out FILE`: writes a generated phantom (a volume or a
// tetrahedral mesh, chosen by the extension of FILE) to a file.
#include "tools/trephine/CommandLine.h"

namespace trephine::cli {

int phantomCommand(const Arguments& arguments);

}  // namespace trephine::cli
