#pragma once
#include "tools/trephine/CommandLine.h"

namespace trephine::cli {

// trephine study SCENE --vary path.field=v1,v2 [...] --out DIR [--jobs N] ...
int studyCommand(const Arguments& arguments);

}  // namespace trephine::cli
