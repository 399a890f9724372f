#pragma once
// Shapes shared by the tetrahedral brain tests: an even spherical shell and the
// cube phantom as a TetraBrain.
#include <cmath>
#include <numbers>
#include <vector>

#include "plugins/tetra_brain/CubePhantom.h"
#include "plugins/tetra_brain/NativeTetBackend.h"
#include "plugins/tetra_brain/TetraBrain.h"

namespace trephine::tetra::shapes {

// `count` points evenly spread (Fibonacci) on a sphere of `radius` mm, inward normals.
// The native back-end of a brain built by setMesh() (its location and depth queries).
inline const NativeTetBackend& native(const TetraBrain& brain) {
  return dynamic_cast<const NativeTetBackend&>(*brain.backend());
}

inline std::vector<ShellPoint> sphereShell(double radius, int count) {
  std::vector<ShellPoint> shell;
  const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < count; ++i) {
    const double z = 1.0 - (2.0 * i + 1.0) / count, r = std::sqrt(1 - z * z);
    const Vec3 d(r * std::cos(golden * i), r * std::sin(golden * i), z);
    shell.push_back({radius * d, -d});
  }
  return shell;
}

// A 200 mm cube of cells^3 cells, its top face at z = 100 (plus `shift`).
inline TetraBrain& cubeBrain(TetraBrain& brain, int cells, const Vec3& shift = Vec3::Zero()) {
  TetMesh mesh = makeCubeMesh(cells);
  for (Vec3& p : mesh.nodes) p += shift;
  brain.setMesh(std::move(mesh));
  return brain;
}

// A tool's response that presses the mesh with `force` (N, on the mesh) at
// the sites its collide() returned, at time t (s).
inline ContactResponse pressing(double t, const Vec3& force, std::span<const ContactSite> sites) {
  ContactResponse response;
  response.t = t;
  response.forceOnTarget_N = force;
  response.sites = sites;
  return response;
}

// One tool's response as the whole of its frame's (as the contact frame
// hands a target the responses of a frame).
inline void respondAlone(ShellContactTarget& target, const ContactResponse& response) {
  target.respond(response.t, {&response, 1});
}

}  // namespace trephine::tetra::shapes
