#include "tools/trephine/study/MeshSurfaceReference.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <unordered_map>

namespace trephine::study {

namespace {

// The point of triangle (a, b, c) nearest to p: Ericson, Real-Time Collision
// Detection (2005), 5.1.5, by the Voronoi regions of its vertices, edges and face.
// The mesh back-ends have their own (framework/geometry/ClosestPoint.h): this
// second one is on purpose, so that the reference shares no code with what
// it measures.
Vec3 closestOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + (d1 / (d1 - d3)) * ab;
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + (d2 / (d2 - d6)) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  const double denominator = 1 / (va + vb + vc);
  return a + ab * (vb * denominator) + ac * (vc * denominator);
}

struct FaceKey {
  std::array<int32_t, 3> sorted;
  bool operator==(const FaceKey&) const = default;
};
struct FaceHash {
  size_t operator()(const FaceKey& k) const {
    uint64_t h = 1469598103934665603ULL;
    for (int32_t v : k.sorted) h = (h ^ uint64_t(uint32_t(v))) * 1099511628211ULL;
    return size_t(h);
  }
};

}  // namespace

BoundarySurface boundarySurface(const TetMesh& mesh) {
  // Face f of a tetrahedron is the one opposite its node f.
  static constexpr int kFace[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
  struct Seen {
    int count = 0;
    std::array<int32_t, 3> face;
    int32_t opposite = 0;
  };
  std::unordered_map<FaceKey, Seen, FaceHash> faces;
  faces.reserve(mesh.tets.size() * 4);
  for (const TetIndices& tet : mesh.tets)
    for (int f = 0; f < 4; ++f) {
      const std::array<int32_t, 3> face = {tet[kFace[f][0]], tet[kFace[f][1]], tet[kFace[f][2]]};
      FaceKey key{face};
      std::sort(key.sorted.begin(), key.sorted.end());
      Seen& seen = faces[key];
      if (seen.count++ == 0) seen.face = face, seen.opposite = tet[f];
    }
  BoundarySurface surface;
  surface.nodes = mesh.nodes;
  for (const auto& [key, seen] : faces) {
    if (seen.count != 1) continue;
    std::array<int32_t, 3> face = seen.face;
    const Vec3 &a = mesh.nodes[face[0]], &b = mesh.nodes[face[1]], &c = mesh.nodes[face[2]];
    // Out: away from the tetrahedron's fourth node.
    if ((b - a).cross(c - a).dot(mesh.nodes[seen.opposite] - a) > 0) std::swap(face[1], face[2]);
    surface.triangles.push_back(face);
  }
  // The map's order is not the file's: sorted, so that a study is repeatable.
  std::sort(surface.triangles.begin(), surface.triangles.end());
  return surface;
}

bool insideSurface(const BoundarySurface& surface, const Vec3& p) {
  // Van Oosterom and Strackee (1983): the solid angle of each triangle seen from p.
  double solidAngle = 0;
  for (const auto& t : surface.triangles) {
    const Vec3 a = surface.nodes[t[0]] - p, b = surface.nodes[t[1]] - p, c = surface.nodes[t[2]] - p;
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    const double numerator = a.dot(b.cross(c));
    const double denominator = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
    solidAngle += 2 * std::atan2(numerator, denominator);
  }
  return std::abs(solidAngle) > 2 * std::numbers::pi;  // winding number above 1/2
}

ExactSphereContact meshSphereContact(const BoundarySurface& surface, const Vec3& center, double radius) {
  double best = std::numeric_limits<double>::infinity();
  Vec3 nearest = center;
  size_t nearestTriangle = 0;
  for (size_t i = 0; i < surface.triangles.size(); ++i) {
    const auto& t = surface.triangles[i];
    const Vec3 q = closestOnTriangle(center, surface.nodes[t[0]], surface.nodes[t[1]], surface.nodes[t[2]]);
    const double d = (q - center).squaredNorm();
    if (d < best) best = d, nearest = q, nearestTriangle = i;
  }
  ExactSphereContact contact;
  if (!std::isfinite(best)) return contact;
  const double distance = std::sqrt(best);
  const bool inside = insideSurface(surface, center);
  contact.penetration = inside ? radius + distance : radius - distance;
  if (contact.penetration <= 0) return contact;
  if (distance > 1e-12) {
    contact.normal = inside ? Vec3((nearest - center) / distance) : Vec3((center - nearest) / distance);
  } else {
    const auto& t = surface.triangles[nearestTriangle];
    const Vec3 &a = surface.nodes[t[0]], &b = surface.nodes[t[1]], &c = surface.nodes[t[2]];
    contact.normal = (b - a).cross(c - a).normalized();
  }
  return contact;
}

}  // namespace trephine::study
