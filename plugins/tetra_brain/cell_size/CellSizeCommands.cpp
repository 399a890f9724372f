#include "plugins/tetra_brain/cell_size/CellSizeCommands.h"

#include <iostream>

#include "framework/core/AtomicFile.h"
#include "framework/core/FileWriteError.h"
#include "framework/core/OutputFolder.h"

#include "framework/formats/mesh/TetMeshReader.h"
#include "plugins/tetra_brain/TetPhantoms.h"

namespace trephine::tetra {

TetMesh loadTetMesh(const std::string& name) {
  constexpr std::string_view kPhantom = "phantom:";
  if (name.rfind(kPhantom, 0) == 0) return makeTetPhantom(name.substr(kPhantom.size()));
  return formats::readTetMesh(name);
}

bool writeExperimentFile(const std::filesystem::path& out, const std::string& name, const std::string& text) {
  try {
    writeFileAtomically(OutputFolder::create(out), name, [&](std::ostream& file) { file << text; });
    return true;
  } catch (const FileWriteError& e) {
    std::cerr << "trephine cellsize: " << e.what() << "\n";
    return false;
  }
}

namespace {

class CellSizeCommands final : public PluginCommands {
 public:
  int run(const cli::Arguments& arguments, const PlotDrawer& drawPlot) const override {
    if (arguments.command == "cellsize") return cellSizeCommand(arguments, drawPlot);
    std::cerr << "trephine: the tetra_brain plugin has no command '" << arguments.command << "'\n";
    return cli::kUsage;
  }
};

}  // namespace

std::shared_ptr<PluginCommands> makeCellSizeCommands() { return std::make_shared<CellSizeCommands>(); }

}  // namespace trephine::tetra
