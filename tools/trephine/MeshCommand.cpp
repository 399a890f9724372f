#include "tools/trephine/MeshCommand.h"

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <iostream>
#include <map>

#include "framework/core/SourceSpec.h"
#include "framework/meshing/LabelRegions.h"
#include "framework/meshing/TetMeshing.h"
#include "framework/meshing/SurfaceSolid.h"
#include "framework/formats/surface/SurfaceReader.h"
#include "framework/formats/mesh/VtuWriter.h"
#include "tools/trephine/LabelledImageInput.h"

namespace trephine::cli {

namespace {

constexpr const char* kUsageLine =
    "usage: trephine mesh INPUT --out OUT.mesh|OUT.mesh.gz|OUT.vtu [--labels L,L,...] [--min-region V]\n"
    "                     [--tets N | --size S]\n"
    "  INPUT: a closed surface (.off, .obj, .stl, .ply), phantom:sphere?radius=R (a ball, mm), or a labelled\n"
    "  image (a segmentation: .nrrd, .nhdr, .nii, .nii.gz, .mha, .mhd or a DICOM series' directory)\n";

bool isSurfaceName(const std::string& name) {
  for (const char* ext : {".off", ".obj", ".stl", ".ply"}) {
    std::string lower = name;
    std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    if (lower.size() >= 4 && lower.compare(lower.size() - 4, 4, ext) == 0) return true;
  }
  return false;
}

// The solid and what to say of it.
struct Solid {
  ImplicitSolid implicit;
  std::string description;
};

Solid solidOf(const std::string& name) {
  constexpr std::string_view kPhantom = "phantom:";
  if (name.rfind(kPhantom, 0) == 0) {
    const auto [kind, query] = SourceSpec::split(name.substr(kPhantom.size()));
    if (kind != "sphere") throw std::invalid_argument("the mesh command's phantom is sphere?radius=R, not '" + kind + "'");
    const SourceSpec spec(kind, query, {{"radius", 50}});
    const double r = spec.positive("radius");
    const ImplicitSolid s = ballSolid(r);
    return {s, "a ball of radius " + std::to_string(r) + " mm"};
  }
  SurfaceSolid surface(formats::readSurface(name));
  return {surface.solid(), std::to_string(surface.triangleCount()) + " triangles, enclosing " +
                               std::to_string(std::abs(surface.volume())) + " mm^3 (inside: the winding number)"};
}

// Regions smaller than this (voxels; a cube of 3) are meshed on their own
// with a few dozen tetrahedra whatever the cell size.
constexpr size_t kSmallRegion = 27;

int meshLabelledImageFile(const std::string& input, const std::string& out, const std::vector<int32_t>& keep, int tets,
                          double size, size_t minRegion) {
  try {
    LabelledImageInput labelled = readLabelledImage(input, keep);
    if (minRegion > 0) {
      const LabelRegionCount merged = mergeSmallLabelRegions(labelled.image, minRegion);
      labelled.labelledVoxels = 0;
      for (const int32_t label : labelled.image.labels) labelled.labelledVoxels += label != 0;
      std::cout << input << ": " << merged.small << " of its " << merged.regions << " regions had fewer than "
                << minRegion << " voxels (" << merged.smallVoxels
                << " voxels in all): each took the label most of its neighbours have\n";
    }
    const auto start = std::chrono::steady_clock::now();
    const TetMesh mesh = tets > 0 ? meshLabelledImage(labelled.image, tets)
                                         : meshLabelledImageAtSize(labelled.image, size);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    formats::writeTetMeshFile(mesh, out);
    std::map<int32_t, size_t> perLabel;
    for (int32_t label : mesh.labels) ++perLabel[label];
    std::cout << out << ": " << mesh.tetCount() << " tetrahedra, " << mesh.nodeCount() << " nodes";
    if (tets > 0)
      std::cout << " (" << std::showpos << 100.0 * (double(mesh.tetCount()) / double(tets) - 1) << std::noshowpos
                << "% from " << tets << ")";
    std::cout << " in " << seconds << " s from " << input << ": " << labelled.labelledVoxels
              << " labelled voxels of " << labelled.image.labels.size() << "\n  tetrahedra per label:";
    for (const auto& [label, count] : perLabel) std::cout << " " << label << ": " << count;
    std::cout << "\n";
    if (tets > 0 && double(mesh.tetCount()) > 1.1 * tets) {
      // Above the count asked for: small regions are a floor no cell size lowers.
      const LabelRegionCount regions = countLabelRegions(labelled.image, kSmallRegion);
      if (regions.small > 0)
        std::cout << "  note: " << regions.small << " of the image's " << regions.regions << " regions have fewer than "
                  << kSmallRegion << " voxels (" << regions.smallVoxels
                  << " voxels in all); each is meshed on its own, whatever the cell size, which keeps the count "
                     "above "
                  << tets << ". --min-region " << kSmallRegion
                  << " gives them the label around them (or --labels keeps only the regions wanted).\n";
    }
  } catch (const std::exception& e) {
    std::cerr << "trephine mesh: " << e.what() << "\n";
    return kSceneError;
  }
  return kOk;
}

}  // namespace

int meshCommand(const Arguments& a) {
  std::string error;
  if (a.positional.size() != 1) error = "one input expected";
  else if (!a.get("--out")) error = "--out OUT is required";
  else if (a.has("--tets") == a.has("--size")) error = "give --tets N or --size S (one of them)";
  else if (!formats::isWritableTetMeshName(*a.get("--out"))) error = "--out must end in .mesh, .mesh.gz or .vtu";
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
  long minRegion = 0;
  if (error.empty() && a.has("--min-region")) {
    const std::string t = *a.get("--min-region");
    const auto r = std::from_chars(t.data(), t.data() + t.size(), minRegion);
    if (r.ec != std::errc() || r.ptr != t.data() + t.size() || minRegion < 1 || minRegion > 1000000)
      error = "--min-region takes a voxel count from 1 to 1000000, not '" + t + "'";
  }
  std::vector<int32_t> keep;
  if (error.empty() && a.has("--labels")) {
    try {
      keep = parseLabelList(*a.get("--labels"));
    } catch (const std::invalid_argument& e) {
      error = e.what();
    }
  }
  const bool isImage = error.empty() && !isSurfaceName(a.positional[0]) && a.positional[0].rfind("phantom:", 0) != 0;
  if (error.empty() && a.has("--labels") && !isImage) error = "--labels is for a labelled image, not a surface";
  if (error.empty() && a.has("--min-region") && !isImage)
    error = "--min-region is for a labelled image, not a surface";
  if (!error.empty()) {
    std::cerr << "trephine mesh: " << error << "\n" << kUsageLine;
    return kUsage;
  }
  const std::string input = a.positional[0], out = *a.get("--out");
  if (isImage) return meshLabelledImageFile(input, out, keep, int(tets), size, size_t(minRegion));
  try {
    const Solid solid = solidOf(input);
    const TetMesh mesh =
        tets > 0 ? meshImplicitSolid(solid.implicit, int(tets)) : meshImplicitSolidAtSize(solid.implicit, size);
    formats::writeTetMeshFile(mesh, out);
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
