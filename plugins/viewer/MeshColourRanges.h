#pragma once
// The range of each quantity the browser viewer colours a tetrahedral mesh
// (a brain) by, over all its files, so that a colour means the same value at
// every time of a run: the largest node displacement |u| (mm) and node force
// |f| (N) of the point arrays "displacement" and "force", and the largest
// element von Mises stress (kPa) of the cell array "von_mises". A quantity
// none of the files has is left out.
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace trephine::viewer {

// Keys "displacement", "force", "von_mises". Throws ViewerDataError for a file
// that cannot be read.
std::map<std::string, double> meshColourRanges(const std::vector<std::filesystem::path>& files);

}  // namespace trephine::viewer
