#pragma once
// The rules of TetraBrain's back-end on a triangle engine (MeshTetBackend),
// whichever library holds the boundary triangles: when a refitted tree is
// rebuilt, and where a contact presses on the nodes.
#include <algorithm>
#include <vector>

#include "framework/core/Component.h"
#include "plugins/tetra_brain/BoundarySurface.h"
#include "plugins/tetra_brain/TetBackend.h"

namespace trephine::tetra {

// A refitted tree keeps the topology it was built with; the farther the
// vertices move from where they were then, the more its boxes overlap and
// the slower its queries (never wrong). Rebuilt when the nodes may have
// moved more than the margin since the build: their displacement from rest
// now plus what it was at the build bounds that move.
class RefitPolicy {
 public:
  explicit RefitPolicy(double margin = 0) : m_margin(margin) {}
  // True: rebuild for this frame's displacement bound (mm); the tree is then
  // taken as built at it.
  bool rebuild(double displacementBound) {
    if (!(displacementBound + m_boundAtBuild > m_margin)) return false;
    m_boundAtBuild = displacementBound;
    return true;
  }
  double margin() const { return m_margin; }

 private:
  double m_margin = 0;        // mm
  double m_boundAtBuild = 0;  // mm, the displacement bound when the tree was last built
};

// Time spent following the nodes (copying them and refitting or rebuilding
// the tree), reported as a mean and a maximum per frame.
struct FollowTiming {
  uint64_t frames = 0;
  double totalUs = 0, maxUs = 0;
  void add(double us) {
    ++frames;
    totalUs += us;
    maxUs = std::max(maxUs, us);
  }
  void report(std::vector<Counter>& counters) const {
    counters.push_back({"follow_frames", double(frames)});
    counters.push_back({"follow_mean_us", frames ? totalUs / double(frames) : 0.0});
    counters.push_back({"follow_max_us", maxUs});
  }
};

// The margin of the boundary trees: half the average boundary edge (mm).
inline double refitMargin(const BoundarySurface& surface) { return 0.5 * surface.averageEdge(); }

// Where a sphere's contact presses: the closest point of the surface to its
// centre, on its triangle's three nodes by the point's barycentric
// coordinates, as deep as the contact.
inline ContactSite siteAt(const BoundarySurface& surface, TriangleRef triangle, const Vec3& point, double depth) {
  ContactSite site;
  site.depth = depth;
  const TriangleMesh& mesh = surface.block(0);
  const auto& t = mesh.triangles[size_t(triangle.triangle)];
  const Vec3 &a = mesh.vertices[size_t(t[0])], &b = mesh.vertices[size_t(t[1])], &c = mesh.vertices[size_t(t[2])];
  const Vec3 n = (b - a).cross(c - a);
  const double area2 = n.squaredNorm();
  std::array<double, 3> w{1.0 / 3, 1.0 / 3, 1.0 / 3};
  if (area2 > 0) {
    w[0] = (c - b).cross(point - b).dot(n) / area2;
    w[1] = (a - c).cross(point - c).dot(n) / area2;
    w[2] = 1.0 - w[0] - w[1];
    double sum = 0;  // clamp round-off outside the triangle: the weights split a force
    for (double& x : w) sum += (x = std::max(0.0, x));
    for (double& x : w) x = sum > 0 ? x / sum : 1.0 / 3;
  }
  for (int i = 0; i < 3; ++i) {
    site.nodes[size_t(i)] = surface.node(t[size_t(i)]);
    site.weights[size_t(i)] = w[size_t(i)];
  }
  return site;
}

}  // namespace trephine::tetra
