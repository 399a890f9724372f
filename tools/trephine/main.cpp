// trephine: run, validate and document scenes.
#include <iostream>
#include <vector>
#include <string>

#include "tools/trephine/CellSizeCommand.h"
#include "tools/trephine/CommandLine.h"
#include "tools/trephine/MeshCommand.h"
#include "tools/trephine/PhantomCommand.h"
#include "tools/trephine/Reference.h"
#include "tools/trephine/RunCommand.h"
#include "tools/trephine/StudyCommand.h"
#include "tools/trephine/ViewCommand.h"

namespace {

constexpr const char* kHelp = R"(trephine - haptic neurosurgery simulation framework

usage:
  trephine run SCENE [--duration S] [--out DIR] [--realtime [--view [PORT]]] [--seed N] [--set path.field=value ...] [--quiet]
                    [--strict]
      Run a scene (virtual time unless --realtime) and write summary.json,
      trace.csv and timings.csv to DIR (default runs/<scene name>).
      --view [PORT] (with --realtime): the browser viewer at
      http://127.0.0.1:PORT/ (8080 unless given; 0: any free port, printed),
      streaming what the scene's VtkExporter names as it happens.
  trephine validate SCENE [--duration S] [--seed N] [--set path.field=value ...] [--strict]
      Load and initialise a scene as run would, without running it;
      print every error, or "ok".
  Warnings (a rendering that may not be passive) are printed and the run goes
  on; --strict makes them errors (exit 1).
  trephine study SCENE --vary path.field=v1,v2[,...] [--vary ...] [--out DIR] [--jobs N]
                      [--duration S] [--seed N] [--set path.field=value ...] [--target PATH]
                      [--reference K] [--poses N]
      Run the scene once per setting of the varied fields (their cartesian
      product, the first field varying slowest) on the same device motion, and
      compare: the target's penetration and normal at the same tool poses (the
      contact frames of setting K, default 1; 2N poses, default N = 200)
      against the exact shape of a phantom, or against setting K when the
      target has none; force steps, proxy inside, NaN; time per frame. Writes
      study.csv, study.md, pareto.png (python3-matplotlib) and settings/NNN/
      to DIR (default runs/study-<scene name>). --jobs runs N settings at a
      time (their timings then share the cores). Under mpirun -n R each rank
      takes every R-th setting and rank 0 gathers (DIR on a shared file
      system).
  trephine components [NAME] [--json | --markdown | --xsd]
      Document every component and field of every available plugin
      (--xsd: an XML Schema of scenes, for editors).
  trephine phantom SPEC --out FILE.mha|FILE.mhd [--raw]
  trephine phantom SPEC --out FILE.mesh|FILE.mesh.gz
      Write a generated phantom (the same as file="phantom:SPEC" in a scene).
      .mha/.mhd: a volume, e.g. skull?voxel=0.5 or cube?voxels=300,
      zlib-compressed unless --raw. .mesh/.mesh.gz: a tetrahedral mesh as
      Medit (gzipped for .gz), e.g. cube?cells=22 or brain?tets=22000.
      Run without arguments for the list of phantoms.
  trephine mesh INPUT --out OUT.mesh|OUT.mesh.gz|OUT.vtu [--labels L,...] [--tets N | --size S]
      Mesh a closed surface (.off, .obj, .stl, .ply), phantom:sphere?radius=R
      or a labelled image into tetrahedra with CGAL Mesh_3, at about N
      tetrahedra (within 3% from a few thousand up) or at cells of
      circumradius S mm. Seeded: the same input gives the same mesh. The
      inside of a surface is its winding number, so a surface that passes
      through itself is meshed as the union of its parts. A labelled image (a
      segmentation: NRRD, NIfTI, MetaImage or a DICOM series of whole labels,
      0 outside) is meshed region by region, each tetrahedron keeping its
      label (TetraBrain's labels, LabelMaterial's label); --labels keeps only
      those listed. Needs the meshing plugin (CGAL, GPL-3.0-or-later).
  trephine cellsize MESH [--pnc P] [--rt R | --calibrate] [--json] [--experiment] [--out DIR]
                        [--frames N] [--rounds N]
      The grid cell size for collision between two copies of a tetrahedral
      mesh (a file, or phantom:SPEC): delta_a, the minimiser of the thesis's
      cost model (p_nc 0.99 and r_t 5 unless given; --calibrate measures r_t
      here), and delta_trad, the average edge length. --experiment measures
      the optimum: two copies with 1% of tetrahedra colliding, timed at 25
      cell sizes, a polynomial fit; prints delta_opt, the optimal zone (within
      10% of the least time) and each prediction's error (Eq. 5.9), and
      writes cellsize.csv, cellsize.json and cellsize.png to DIR (default
      runs/cellsize-<mesh name>). --json prints one JSON object.
  trephine cellsize MESH --tool RADIUS [--tool-step DEG] [--deforming] [--calibrate] [--json]
                        [--experiment] [--depth D] [--out DIR] [--rounds N] [--poses N]
      The cell size of TetraBrain's grid for a spherical tool's pointshell
      (the angle-step shell, 15 degrees unless given): delta_tool, the
      minimiser of the tool query's cost model (TetraBrain's default), half
      the average edge and the average edge. --experiment times the query at
      17 cell sizes on strokes D mm into the surface (0.05: where a god-object
      proxy holds the tool), fits a polynomial in log(delta), and writes tool_cellsize.csv, .json and .png; --calibrate
      fits the model's weights to those times. --deforming: the grids of a
      deforming mesh (boxes grown by the displacement margin).
  trephine view RUN_DIR [--triangles N] [--partial]
      Write the browser viewer of a run whose scene has a VtkExporter:
      RUN_DIR/view/index.html opens from the disk in a browser (nothing to
      install, no network) and shows the skull, the brain, the tool, the
      proxy and the force arrow in time, with a slider, play, and the force
      and penetration plots (from trace.csv); a click on a plot goes to its
      time. While playing or turning, the skull is simplified to N
      triangles (8000: what a browser without a graphics card, SwiftShader,
      draws 30 times a second; give 500000 or more on a machine with one),
      the blocks the drill changed kept whole while they fit in half of
      that; standing still, to 10 N. Needs the viewer built (Node.js and
      npm, see tools/setup).
  trephine --version | --help

Plugins are searched in TREPHINE_PLUGIN_PATH (colon-separated), then
<prefix>/lib/trephine/plugins, then the build's plugin directory.

exit codes: 0 ok, 1 scene or input error, 2 usage, 3 run-time failure
)";

}  // namespace

int main(int argc, char** argv) {
  using namespace trephine::cli;
  if (argc < 2) {
    std::cerr << kHelp;
    return kUsage;
  }
  const std::string command = argv[1];
  if (command == "--help" || command == "-h" || command == "help") {
    std::cout << kHelp;
    return kOk;
  }
  if (command == "--version") {
    std::cout << "trephine " << TREPHINE_VERSION << "\n";
    return kOk;
  }
  Arguments arguments;
  arguments.command = command;
  std::optional<std::string> error;
  if (command == "run") {
    // --view takes an optional port: "--view" alone is "--view 8080".
    std::vector<std::string> words(argv, argv + argc);
    for (size_t i = 2; i < words.size(); ++i)
      if (words[i] == "--view" && (i + 1 == words.size() || words[i + 1].empty() || words[i + 1][0] < '0' ||
                                   words[i + 1][0] > '9'))
        words[i] = "--view=8080";
    std::vector<char*> pointers;
    for (std::string& w : words) pointers.push_back(w.data());
    error = parseArguments(int(pointers.size()), pointers.data(), {"--duration", "--out", "--seed", "--set", "--view"},
                           {"--realtime", "--quiet", "--strict"}, arguments);
    if (!error) return runCommand(arguments);
  } else if (command == "study") {
    error = parseArguments(argc, argv,
                           {"--vary", "--out", "--jobs", "--duration", "--seed", "--set", "--target", "--reference",
                            "--poses", "--setting"},
                           {}, arguments);
    if (!error) return studyCommand(arguments);
  } else if (command == "mesh") {
    error = parseArguments(argc, argv, {"--out", "--tets", "--size", "--labels"}, {}, arguments);
    if (!error) return meshCommand(arguments);
  } else if (command == "cellsize") {
    error = parseArguments(argc, argv, {"--pnc", "--rt", "--out", "--frames", "--rounds", "--tool", "--tool-step", "--poses", "--depth"},
                           {"--calibrate", "--json", "--experiment", "--deforming"}, arguments);
    if (!error) return cellSizeCommand(arguments);
  } else if (command == "validate") {
    error = parseArguments(argc, argv, {"--duration", "--seed", "--set"}, {"--strict"}, arguments);
    if (!error) return validateCommand(arguments);
  } else if (command == "components") {
    error = parseArguments(argc, argv, {}, {"--json", "--markdown", "--xsd"}, arguments);
    if (!error) {
      if (arguments.positional.size() > 1) {
        std::cerr << "usage: trephine components [NAME] [--json | --markdown | --xsd]\n";
        return kUsage;
      }
      const ReferenceFormat format = arguments.has("--json")       ? ReferenceFormat::Json
                                     : arguments.has("--markdown") ? ReferenceFormat::Markdown
                                     : arguments.has("--xsd")      ? ReferenceFormat::XmlSchema
                                                                   : ReferenceFormat::Text;
      std::string problem;
      const bool ok =
          writeReference(std::cout, format, arguments.positional.empty() ? "" : arguments.positional[0], problem);
      if (!problem.empty()) std::cerr << "trephine: " << problem << "\n";
      return ok ? kOk : kSceneError;
    }
  } else if (command == "view") {
    error = parseArguments(argc, argv, {"--triangles"}, {"--partial"}, arguments);
    if (!error) return viewCommand(arguments);
  } else if (command == "phantom") {
    error = parseArguments(argc, argv, {"--out"}, {"--raw"}, arguments);
    if (!error) return phantomCommand(arguments);
  } else {
    std::cerr << "trephine: unknown command '" << command
              << "' (run, validate, study, components, phantom, mesh, cellsize, view, --help, --version)\n";
    return kUsage;
  }
  std::cerr << "trephine " << command << ": " << *error << "\n";
  return kUsage;
}
