#pragma once
#include "tools/trephine/CommandLine.h"

namespace trephine::cli {

int runCommand(const Arguments& arguments);
int validateCommand(const Arguments& arguments);

}  // namespace trephine::cli
