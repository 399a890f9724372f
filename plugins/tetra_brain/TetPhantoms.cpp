#include "plugins/tetra_brain/TetPhantoms.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <stdexcept>

#include "framework/core/MadeOnce.h"
#include "framework/core/SourceSpec.h"
#include "plugins/tetra_brain/BrainPhantom.h"
#include "plugins/tetra_brain/CubePhantom.h"
#include "framework/meshing/TetMeshing.h"

namespace trephine::tetra {

namespace {

// A phantom named by its specification, parsed once: how to mesh it, and
// the solid it approximates.
struct TetPhantomDefinition {
  std::function<TetMesh()> mesh;
  LevelSet shape;
};

TetPhantomDefinition defineTetPhantom(const std::string& specification) {
  const auto [name, query] = SourceSpec::split(specification);
  if (name == "cube") {
    const SourceSpec k(name, query, {{"cells", 22}, {"size", 200}});
    const int cells = k.wholeNumber("cells", 1, 200);
    const double size = k.positive("size");
    return {[=] { return makeCubeMesh(cells, size); },
            [half = 0.5 * size](const Vec3& p) { return (p.cwiseAbs() - Vec3::Constant(half)).maxCoeff(); }};
  }
  if (name == "bar") {
    // A bar of square section along x, from x = 0 to the length, centred on
    // the x axis: the cantilever of the FEM's tests and scenes.
    const SourceSpec k(name, query, {{"length", 100}, {"width", 10}, {"cells", 4}});
    const double length = k.positive("length"), width = k.positive("width");
    const int cells = k.wholeNumber("cells", 1, 200);
    const int along = std::max(1, int(std::lround(cells * length / width)));
    const Vec3 low(0, -width / 2, -width / 2), high(length, width / 2, width / 2);
    return {[=] { return makeBoxMesh({along, cells, cells}, low, high); },
            [=](const Vec3& p) {
              const Vec3 centre = 0.5 * (low + high), half = 0.5 * (high - low);
              return ((p - centre).cwiseAbs() - half).maxCoeff();
            }};
  }
  if (name == "brain") {
    const SourceSpec k(name, query,
                       {{"tets", 22000},
                        {"tumour", 0},
                        {"tumourX", 25},
                        {"tumourY", 10},
                        {"tumourZ", 30},
                        {"vessel", 0},
                        {"vesselX", 0},
                        {"vesselZ", 30},
                        {"detail", 3}});
    const int tets = k.wholeNumber("tets", 100, 2000000);
    BrainPhantomRegions regions;
    regions.tumourRadius = k.number("tumour");
    regions.tumourCentre = Vec3(k.number("tumourX"), k.number("tumourY"), k.number("tumourZ"));
    regions.vesselRadius = k.number("vessel");
    regions.vesselX = k.number("vesselX");
    regions.vesselZ = k.number("vesselZ");
    regions.detail = k.number("detail");
    if (!(regions.detail >= 1 && regions.detail <= 10))
      throw std::invalid_argument("phantom:brain: detail (how many times finer the tumour and vessel are meshed "
                                  "than the brain) must be within [1, 10]; got " + std::to_string(regions.detail));
    if (regions.tumourRadius < 0 || regions.vesselRadius < 0)
      throw std::invalid_argument("phantom:brain: tumour and vessel are radii (mm), 0 for none; got " +
                                  std::to_string(regions.tumourRadius) + " and " + std::to_string(regions.vesselRadius));
    // A tumour may break the cortex (its part outside the brain is not
    // meshed), but its centre is in the brain.
    if (regions.tumourRadius > 0 && !(brainPhantomDistance(regions.tumourCentre) < 0))
      throw std::invalid_argument("phantom:brain: the tumour's centre (tumourX, tumourY, tumourZ) lies outside the "
                                  "brain; a tumour may break the cortex, but its centre must be inside");
    return {[=] { return makeBrainPhantom(tets, regions); }, brainPhantomDistance};
  }
  if (name == "sphere") {
    // A ball at the origin (the thesis's Table 5.1 meshes: 41937, 52326,
    // 60688, 72631 and 80927 tetrahedra).
    const SourceSpec k(name, query, {{"tets", 41937}, {"radius", 50}});
    const int tets = k.wholeNumber("tets", 100, 2000000);
    const double r = k.positive("radius");
    const ImplicitSolid solid = ballSolid(r);
    return {[=] { return meshImplicitSolid(solid, tets); }, solid.distance};
  }
  throw std::invalid_argument("unknown phantom '" + name + "' (cube, bar, brain, sphere)");
}

}  // namespace

TetMesh makeTetPhantom(const std::string& specification) {
  // Meshing the brain or the sphere takes seconds: kept for the process's next
  // load of the same phantom (the last four, each up to 64 MB).
  static MadeOnce<TetMesh> made(4, size_t(64) << 20, [](const TetMesh& mesh) {
    return mesh.nodes.size() * sizeof(Vec3) + mesh.tets.size() * sizeof(TetIndices) +
           mesh.labels.size() * sizeof(int32_t);
  });
  const TetPhantomDefinition definition = defineTetPhantom(specification);  // refuses a bad one every time
  return made.get(specification, definition.mesh);
}

LevelSet tetPhantomShape(const std::string& specification) { return defineTetPhantom(specification).shape; }

std::string tetPhantomHelp() {
  return "  cube?cells=22&size=200   cube of cells^3 cells, 5 tetrahedra each (Table 4.1: 7, 13, 22, 30, 40, 50, 60)\n"
         "  bar?length=100&width=10&cells=4   bar of square section along x from x = 0, cells across its width\n"
         "  brain?tets=22000         brain-shaped mesh (CGAL Mesh_3; Table 4.2: 3500, 12500, 22000, 40500, 50000)\n"
         "    &tumour=10             with a tumour of this radius (mm, label 2; the brain is label 1), centred at\n"
         "    &tumourX=25&tumourY=10&tumourZ=30   (mm; the default 25 mm below the right hemisphere's top)\n"
         "    &vessel=1.5            with a vessel of this radius (mm, label 3), a tube along y at vesselZ=30 and\n"
         "                           vesselX (0: 3 mm beside the tumour)\n"
         "  sphere?tets=41937&radius=50   ball (CGAL Mesh_3; Table 5.1: 41937, 52326, 60688, 72631, 80927)\n";
}

}  // namespace trephine::tetra
