#pragma once
// `trephine phantom SPEC --out FILE`: writes a generated phantom volume to a file.
#include "tools/trephine/CommandLine.h"

namespace trephine::cli {

int phantomCommand(const Arguments& arguments);

}  // namespace trephine::cli
