// trephine: run, validate and document scenes.
#include <algorithm>
#include <csignal>
#include <iostream>
#include <string>
#include <string_view>
#include <vector>

#include "tools/trephine/CommandLine.h"
#include "tools/trephine/MeshCommand.h"
#include "tools/trephine/PhantomCommand.h"
#include "tools/trephine/PluginCommand.h"
#include "tools/trephine/Reference.h"
#include "tools/trephine/RunCommand.h"
#include "tools/trephine/StudyCommand.h"
#include "tools/trephine/ViewCommand.h"

namespace {

using namespace trephine::cli;

int componentsCommand(const Arguments& arguments) {
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

// A subcommand: its part of the help, its options and what runs it.
struct Command {
  std::string_view name;
  std::string_view usage;  // indented lines, as in the whole help
  std::vector<std::string> valueOptions, flags;
  int (*run)(const Arguments&);
};

const std::vector<Command>& commands() {
  static const std::vector<Command> table{
      {"run",
       R"(  trephine run SCENE [--duration S] [--out DIR] [--realtime [--view [PORT]]] [--seed N] [--set path.field=value ...] [--quiet]
                    [--strict]
      Run a scene (virtual time unless --realtime) and write summary.json,
      trace.csv and timings.csv to DIR (default runs/<scene name>).
      --view [PORT] (with --realtime): the browser viewer at
      http://127.0.0.1:PORT/ (8080 unless given; 0: any free port, printed),
      streaming what the scene's VtkExporter names as it happens.
)",
       {"--duration", "--out", "--seed", "--set", "--view"},
       {"--realtime", "--quiet", "--strict"},
       runCommand},
      {"validate",
       R"(  trephine validate SCENE [--duration S] [--seed N] [--set path.field=value ...] [--strict]
      Load and initialise a scene as run would, without running it;
      print every error, or "ok".
  Warnings (a rendering that may not be passive) are printed and the run goes
  on; --strict makes them errors (exit 1).
)",
       {"--duration", "--seed", "--set"},
       {"--strict"},
       validateCommand},
      {"study",
       R"(  trephine study SCENE --vary path.field=v1,v2[,...] [--vary ...] [--out DIR] [--jobs N]
                      [--duration S] [--seed N] [--set path.field=value ...] [--target PATH]
                      [--reference K [--coarse-reference]] [--poses N] [--repeat N]
      Run the scene once per setting of the varied fields (their cartesian
      product, the first field varying slowest) on the same device motion
      (the reference setting's, replayed by every other), and compare, for
      every tool on every target it touched (--target: that target only):
      the penetration and normal at the same tool poses (2N from the
      reference setting's frames where they touched, default N = 200)
      against a reference no setting computes (a phantom's exact shape, a
      scan's interpolated isosurface, a mesh's boundary triangles, for a
      sphere or a burr on a shaft; for another tool shape, the reference
      setting); force steps, proxy
      inside, NaN; time per frame, over --repeat runs of each setting
      (default 3, interleaved: each round runs every setting once). The reference is the setting that resolves every
      target and tool finest (voxels, tetrahedra, shell spacing), else
      setting 1; --reference K names another, refused when it is coarser
      than another setting unless --coarse-reference. Writes study.csv (the
      first pair), pairs.csv (every pair), study.md, pareto.png
      (python3-matplotlib) and settings/NNN/ to DIR (default
      runs/study-<scene name>). --jobs runs N settings at a
      time (their timings then share the cores). Under mpirun -n R each rank
      takes every R-th setting and rank 0 gathers (DIR on a shared file
      system).
)",
       {"--vary", "--out", "--jobs", "--duration", "--seed", "--set", "--target", "--reference", "--poses",
        "--repeat", "--setting", "--timing-run", "--describe", "--describe-to", "--study-id"},
       {"--coarse-reference"},
       studyCommand},
      {"components",
       R"(  trephine components [NAME] [--json | --markdown | --xsd]
      Document every component and field of every available plugin
      (--xsd: an XML Schema of scenes, for editors).
)",
       {},
       {"--json", "--markdown", "--xsd"},
       componentsCommand},
      {"phantom",
       R"(  trephine phantom SPEC --out FILE.mha|FILE.mhd [--raw]
  trephine phantom SPEC --out FILE.mesh|FILE.mesh.gz
      Write a generated phantom (the same as file="phantom:SPEC" in a scene).
      .mha/.mhd: a volume, e.g. skull?voxel=0.5 or cube?voxels=300,
      zlib-compressed unless --raw. .mesh/.mesh.gz: a tetrahedral mesh as
      Medit (gzipped for .gz), e.g. cube?cells=22 or brain?tets=22000.
      Run without arguments for the list of phantoms.
)",
       {"--out"},
       {"--raw"},
       phantomCommand},
      {"mesh",
       R"(  trephine mesh INPUT --out OUT.mesh|OUT.mesh.gz|OUT.vtu [--labels L,...] [--min-region V]
                     [--tets N | --size S]
      Mesh a closed surface (.off, .obj, .stl, .ply), phantom:sphere?radius=R
      or a labelled image into tetrahedra with CGAL Mesh_3, at about N
      tetrahedra (within 3% from a few thousand up) or at cells of
      circumradius S mm. Seeded: the same input gives the same mesh. The
      inside of a surface is its winding number, so a surface that passes
      through itself is meshed as the union of its parts. A labelled image (a
      segmentation: NRRD, NIfTI, MetaImage or a DICOM series of whole labels,
      0 outside) is meshed region by region, each tetrahedron keeping its
      label (TetraBrain's labels, LabelMaterial's label); --labels keeps only
      those listed. Each region of a label (its voxels joined across faces)
      is meshed on its own, so a segmentation's specks set a floor on the
      count that no cell size lowers (the command says so); --min-region V
      gives every region of fewer than V voxels the label most of its
      neighbours have. Needs the meshing plugin (CGAL, GPL-3.0-or-later).
)",
       {"--out", "--tets", "--size", "--labels", "--min-region"},
       {},
       meshCommand},
      {"cellsize",
       R"(  trephine cellsize MESH [--pnc P] [--rt R | --calibrate] [--json] [--experiment] [--out DIR]
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
)",
       {"--pnc", "--rt", "--out", "--frames", "--rounds", "--tool", "--tool-step", "--poses", "--depth"},
       {"--calibrate", "--json", "--experiment", "--deforming"},
       cellSizeCommand},
      {"view",
       R"(  trephine view RUN_DIR [--out DIR] [--triangles N] [--partial]
  trephine view RUN_DIR RUN_DIR... --out DIR | STUDY_DIR [--out DIR]
      Write the browser viewer of a run whose scene has a VtkExporter:
      RUN_DIR/view/index.html opens from the disk in a browser (nothing to
      install, no network) and shows the skull, the brain, the tool, the
      proxy and the force arrow in time, coloured by displacement, stress,
      density or cut with legends, with a slider marked with the run's
      events, play, standard views, a clipping plane, and the force and
      penetration plots (from trace.csv); a click on a plot goes to its
      time. Several runs (up to 6), or a study's folder (its settings'
      runs; the viewer goes to STUDY_DIR/view), are drawn side by side on
      one clock with linked cameras, their plots overlaid with the
      difference from the first. While playing or turning, the skull is
      simplified to N triangles (8000: what a browser without a graphics
      card, SwiftShader, draws 30 times a second; give 500000 or more on a
      machine with one), the blocks the drill changed kept whole while they
      fit in half of that; standing still, to 10 N. Needs the viewer built
      (Node.js and npm, see tools/setup). The viewer goes to RUN_DIR/view
      (a study's to STUDY_DIR/view), or to --out DIR; open DIR/index.html.
      --partial: view a run that is still writing, or was killed while
      writing (its files may be cut off).
)",
       {"--triangles", "--out"},
       {"--partial"},
       viewCommand},
  };
  return table;
}

constexpr std::string_view kTitle = "trephine - haptic neurosurgery simulation framework\n";
constexpr std::string_view kFooter = R"(
Plugins are searched in TREPHINE_PLUGIN_PATH (colon-separated), then
<prefix>/lib/trephine/plugins, then the build's plugin directory.

exit codes: 0 ok, 1 scene or input error, 2 usage, 3 run-time failure
)";

void writeHelp(std::ostream& out) {
  out << kTitle << "\nusage:\n";
  for (const Command& command : commands()) out << command.usage;
  out << "  trephine --version | --help\n  trephine COMMAND --help\n      One command's part of this help.\n"
      << kFooter;
}

void writeCommandHelp(std::ostream& out, const Command& command) { out << "usage:\n" << command.usage << kFooter; }

bool asksForHelp(int argc, char** argv) {
  for (int i = 2; i < argc; ++i) {
    const std::string_view word = argv[i];
    if (word == "--help" || word == "-h") return true;
  }
  return false;
}

}  // namespace

int main(int argc, char** argv) {
  // A file-size limit (ulimit -f) is a write that fails, as a full disk's
  // does: the write returns EFBIG and the output that could not be written
  // is named, instead of the process being killed with nothing said.
  std::signal(SIGXFSZ, SIG_IGN);
  if (argc < 2) {
    writeHelp(std::cerr);
    return kUsage;
  }
  std::string name = argv[1];
  // `trephine help` is `trephine --help`; `trephine help run` is `trephine run --help`.
  const bool helpFor = name == "help" && argc > 2;
  if ((name == "--help" || name == "-h" || name == "help") && !helpFor) {
    writeHelp(std::cout);
    return kOk;
  }
  if (name == "--version") {
    std::cout << "trephine " << TREPHINE_VERSION << "\n";
    return kOk;
  }
  if (helpFor) name = argv[2];
  const auto found =
      std::find_if(commands().begin(), commands().end(), [&](const Command& command) { return command.name == name; });
  if (found == commands().end()) {
    std::string names;
    for (const Command& command : commands()) names += std::string(command.name) + ", ";
    std::cerr << "trephine: unknown command '" << name << "' (" << names << "--help, --version)\n";
    return kUsage;
  }
  const Command& command = *found;
  if (helpFor || asksForHelp(argc, argv)) {
    writeCommandHelp(std::cout, command);
    return kOk;
  }
  Arguments arguments;
  arguments.command = name;
  std::vector<std::string> words(argv, argv + argc);
  if (command.name == "run") {
    // --view takes an optional port: "--view" alone is "--view 8080".
    for (size_t i = 2; i < words.size(); ++i)
      if (words[i] == "--view" &&
          (i + 1 == words.size() || words[i + 1].empty() || words[i + 1][0] < '0' || words[i + 1][0] > '9'))
        words[i] = "--view=8080";
  }
  std::vector<char*> pointers;
  for (std::string& w : words) pointers.push_back(w.data());
  if (const auto error =
          parseArguments(int(pointers.size()), pointers.data(), command.valueOptions, command.flags, arguments)) {
    std::cerr << "trephine " << name << ": " << *error << " (trephine " << name << " --help)\n";
    return kUsage;
  }
  return command.run(arguments);
}
