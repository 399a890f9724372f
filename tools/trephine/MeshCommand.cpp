#include "tools/trephine/MeshCommand.h"

#include <charconv>
#include <cmath>
#include <iostream>

#include "framework/core/SourceSpec.h"
#include "plugins/tetra_brain/ImplicitMesher.h"
#include "plugins/tetra_brain/SurfaceSolid.h"
#include "plugins/tetra_brain/io/SurfaceReader.h"
#include "plugins/tetra_brain/io/VtuWriter.h"

namespace trephine::cli {

namespace {

constexpr const char* kUsageLine =
    "usage: trephine mesh SURFACE --out OUT.mesh|OUT.mesh.gz|OUT.vtu [--tets N | --size S]\n"
    "  SURFACE: a closed surface (.off, .obj, .stl, .ply) or phantom:sphere?radius=R (a ball, mm)\n";

// The solid and what to say of it.
struct Solid {
  tetra::ImplicitSolid implicit;
  std::string description;
};

Solid solidOf(const std::string& name) {
  constexpr std::string_view kPhantom = "phantom:";
  if (name.rfind(kPhantom, 0) == 0) {
    const auto [kind, query] = SourceSpec::split(name.substr(kPhantom.size()));
    if (kind != "sphere") throw std::invalid_argument("the mesh command's phantom is sphere?radius=R, not '" + kind + "'");
    const SourceSpec spec(kind, query, {{"radius", 50}});
    const double r = spec.positive("radius");
    const tetra::ImplicitSolid s = tetra::ballSolid(r);
    return {s, "a ball of radius " + std::to_string(r) + " mm"};
  }
  tetra::SurfaceSolid surface(tetra::readSurface(name));
  return {surface.solid(), std::to_string(surface.triangleCount()) + " triangles, enclosing " +
                               std::to_string(std::abs(surface.volume())) + " mm^3 (inside: the winding number)"};
}

}  // namespace

int meshCommand(const Arguments& a) {
  std::string error;
  if (a.positional.size() != 1) error = "one surface expected";
  else if (!a.get("--out")) error = "--out OUT is required";
  else if (a.has("--tets") == a.has("--size")) error = "give --tets N or --size S (one of them)";
  else if (!tetra::isWritableTetMeshName(*a.get("--out"))) error = "--out must end in .mesh, .mesh.gz or .vtu";
  long tets = 0;
  double size = 0;
  if (error.empty() && a.has("--tets")) {
    const std::string t = *a.get("--tets");
    const auto r = std::from_chars(t.data(), t.data() + t.size(), tets);
    if (r.ec != std::errc() || r.ptr != t.data() + t.size() || tets < 100 || tets > 2000000)
      error = "--tets takes a count from 100 to 2000000, not '" + t + "'";
  }
  if (error.empty() && a.has("--size")) {
    const std::string t = *a.get("--size");
    const auto r = std::from_chars(t.data(), t.data() + t.size(), size);
    if (r.ec != std::errc() || r.ptr != t.data() + t.size() || !(size > 0) || !std::isfinite(size))
      error = "--size takes a positive length in mm, not '" + t + "'";
  }
  if (!error.empty()) {
    std::cerr << "trephine mesh: " << error << "\n" << kUsageLine;
    return kUsage;
  }
  const std::string input = a.positional[0], out = *a.get("--out");
  try {
    const Solid solid = solidOf(input);
    const tetra::TetMesh mesh =
        tets > 0 ? tetra::meshImplicitSolid(solid.implicit, int(tets)) : tetra::meshImplicitSolidAtSize(solid.implicit, size);
    tetra::writeTetMeshFile(mesh, out);
    std::cout << out << ": " << mesh.tetCount() << " tetrahedra, " << mesh.nodeCount() << " nodes";
    if (tets > 0)
      std::cout << " (" << std::showpos << 100.0 * (double(mesh.tetCount()) / double(tets) - 1) << std::noshowpos
                << "% from " << tets << ")";
    std::cout << " from " << input << ": " << solid.description << "\n";
  } catch (const std::exception& e) {
    std::cerr << "trephine mesh: " << e.what() << "\n";
    return kSceneError;
  }
  return kOk;
}

}  // namespace trephine::cli
