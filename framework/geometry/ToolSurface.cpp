#include "framework/geometry/ToolSurface.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace trephine {

namespace {

// A latitude-longitude sphere of `radius` at the origin: `rings` rings of
// `segments` points between two poles, appended to `mesh`.
void appendSphere(TriangleMesh& mesh, double radius, int segments, int rings) {
  const int32_t base = int32_t(mesh.vertices.size());
  mesh.vertices.push_back(radius * Vec3::UnitZ());
  for (int r = 1; r <= rings; ++r) {
    const double polar = std::numbers::pi * r / (rings + 1);
    for (int s = 0; s < segments; ++s) {
      const double azimuth = 2 * std::numbers::pi * s / segments;
      mesh.vertices.push_back(radius * Vec3(std::sin(polar) * std::cos(azimuth), std::sin(polar) * std::sin(azimuth),
                                            std::cos(polar)));
    }
  }
  mesh.vertices.push_back(-radius * Vec3::UnitZ());
  const int32_t south = int32_t(mesh.vertices.size()) - 1;
  const auto at = [&](int ring, int s) { return base + 1 + (ring - 1) * segments + (s % segments); };
  for (int s = 0; s < segments; ++s) mesh.triangles.push_back({base, at(1, s), at(1, s + 1)});
  for (int r = 1; r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      mesh.triangles.push_back({at(r, s), at(r + 1, s), at(r + 1, s + 1)});
      mesh.triangles.push_back({at(r, s), at(r + 1, s + 1), at(r, s + 1)});
    }
  for (int s = 0; s < segments; ++s) mesh.triangles.push_back({south, at(rings, s + 1), at(rings, s)});
}

}  // namespace

TriangleMesh solidSurface(const ToolSolid& solid, int segments) {
  segments = std::max(segments, 6);
  TriangleMesh mesh;
  if (solid.radius > 0) appendSphere(mesh, solid.radius, segments, segments / 2 - 1);
  if (!(solid.shaftLength > 0 && solid.shaftRadius > 0)) return mesh;
  // The shaft: rings at the burr's centre and at the end, and the end's cap.
  const Vec3 axis = solid.shaftAxis.normalized();
  const Vec3 u = axis.unitOrthogonal(), v = axis.cross(u);
  const int32_t base = int32_t(mesh.vertices.size());
  for (const double along : {0.0, solid.shaftLength})
    for (int s = 0; s < segments; ++s) {
      const double azimuth = 2 * std::numbers::pi * s / segments;
      mesh.vertices.push_back(along * axis + solid.shaftRadius * (std::cos(azimuth) * u + std::sin(azimuth) * v));
    }
  mesh.vertices.push_back(solid.shaftLength * axis);
  const int32_t centre = int32_t(mesh.vertices.size()) - 1;
  for (int s = 0; s < segments; ++s) {
    const int32_t a = base + s, b = base + (s + 1) % segments, c = a + segments, d = b + segments;
    mesh.triangles.push_back({a, b, d});
    mesh.triangles.push_back({a, d, c});
    mesh.triangles.push_back({c, d, centre});
  }
  return mesh;
}

TriangleMesh ShellTool::displaySurface() const { return solidSurface(solid()); }

}  // namespace trephine
