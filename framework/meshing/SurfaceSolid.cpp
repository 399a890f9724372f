#include "framework/meshing/SurfaceSolid.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>
#include <unordered_map>

namespace trephine {

namespace {

double cross2(double ax, double ay, double bx, double by) { return ax * by - ay * bx; }

// Whether a point exactly on edge u -> v of a counter-clockwise triangle
// belongs to it: the top-left rule, so that of two triangles sharing the
// edge (traversing it in opposite directions) exactly one has it.
bool ownsEdge(double dx, double dy) { return dy > 0 || (dy == 0 && dx < 0); }

}  // namespace

SurfaceSolid::SurfaceSolid(TriangleMesh surface) : m_surface(std::move(surface)) {
  const auto& v = m_surface.vertices;
  for (const Vec3& p : v) m_bounds.extend(p);
  for (const auto& t : m_surface.triangles) {
    const Vec3 &a = v[t[0]], &b = v[t[1]], &c = v[t[2]];
    m_area += 0.5 * (b - a).cross(c - a).norm();
    m_volume += a.dot(b.cross(c)) / 6;  // the divergence theorem, about the origin
  }
  if (!(m_area > 0)) throw std::invalid_argument("the surface has no area");
  // Closed: every edge is shared by an even number of triangles (two, or
  // four where the surface passes through itself along an edge). An edge of
  // one triangle is a hole's rim: the inside is undefined there (a ray
  // through the hole counts a crossing too few).
  std::unordered_map<uint64_t, int32_t> edges;
  edges.reserve(3 * m_surface.triangles.size());
  for (const auto& t : m_surface.triangles)
    for (int e = 0; e < 3; ++e) {
      uint32_t a = uint32_t(t[size_t(e)]), b = uint32_t(t[size_t(e + 1) % 3]);
      if (a > b) std::swap(a, b);
      ++edges[uint64_t(a) << 32 | b];
    }
  size_t open = 0;
  for (const auto& [key, count] : edges) open += count % 2;
  if (open > 0)
    throw std::invalid_argument("the surface is not closed: " + std::to_string(open) +
                                " edges belong to one triangle only (the rims of holes); close them first");
  // About two triangles a column.
  const double width = std::max(m_bounds.sizes().x(), 1e-12), depth = std::max(m_bounds.sizes().y(), 1e-12);
  m_side = std::sqrt(width * depth / std::max<double>(1, double(m_surface.triangles.size()) / 2));
  m_origin = m_bounds.min();
  m_columns[0] = std::clamp(int32_t(std::ceil(width / m_side)), 1, 4096);
  m_columns[1] = std::clamp(int32_t(std::ceil(depth / m_side)), 1, 4096);
  m_side = std::max(width / m_columns[0], depth / m_columns[1]) * (1 + 1e-9);
  const size_t columns = size_t(m_columns[0]) * size_t(m_columns[1]);
  std::vector<std::array<int32_t, 4>> ranges(m_surface.triangles.size());
  m_start.assign(columns + 1, 0);
  for (size_t t = 0; t < m_surface.triangles.size(); ++t) {
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (int32_t n : m_surface.triangles[t])
      for (int a = 0; a < 2; ++a) {
        lo[a] = std::min(lo[a], v[n][a]);
        hi[a] = std::max(hi[a], v[n][a]);
      }
    auto& r = ranges[t];
    for (int a = 0; a < 2; ++a) {
      r[size_t(a)] = std::clamp(int32_t(std::floor((lo[a] - m_origin[a]) / m_side)), 0, m_columns[a] - 1);
      r[size_t(a) + 2] = std::clamp(int32_t(std::floor((hi[a] - m_origin[a]) / m_side)), 0, m_columns[a] - 1);
    }
    for (int32_t j = r[1]; j <= r[3]; ++j)
      for (int32_t i = r[0]; i <= r[2]; ++i) ++m_start[size_t(i) + size_t(m_columns[0]) * size_t(j) + 1];
  }
  for (size_t c = 0; c < columns; ++c) m_start[c + 1] += m_start[c];
  m_items.resize(m_start[columns]);
  std::vector<uint32_t> fill(m_start.begin(), m_start.end() - 1);
  for (size_t t = 0; t < ranges.size(); ++t)
    for (int32_t j = ranges[t][1]; j <= ranges[t][3]; ++j)
      for (int32_t i = ranges[t][0]; i <= ranges[t][2]; ++i)
        m_items[fill[size_t(i) + size_t(m_columns[0]) * size_t(j)]++] = int32_t(t);
}

int SurfaceSolid::windingNumber(const Vec3& p) const {
  const double gx = (p.x() - m_origin.x()) / m_side, gy = (p.y() - m_origin.y()) / m_side;
  if (!(gx >= 0 && gy >= 0 && gx < m_columns[0] && gy < m_columns[1])) return 0;
  const size_t column = size_t(gx) + size_t(m_columns[0]) * size_t(gy);
  const auto& v = m_surface.vertices;
  int winding = 0;
  for (uint32_t k = m_start[column]; k < m_start[column + 1]; ++k) {
    const auto& t = m_surface.triangles[size_t(m_items[k])];
    Vec3 a = v[t[0]], b = v[t[1]], c = v[t[2]];
    double area2 = cross2(b.x() - a.x(), b.y() - a.y(), c.x() - a.x(), c.y() - a.y());
    if (area2 == 0) continue;  // seen edge-on from above: the ray does not cross it
    int sign = 1;
    if (area2 < 0) {
      std::swap(b, c);
      area2 = -area2;
      sign = -1;
    }
    const Vec3* corner[3] = {&a, &b, &c};
    double weight[3];
    bool inside = true;
    for (int e = 0; e < 3 && inside; ++e) {
      const Vec3& u = *corner[e];
      const Vec3& w = *corner[(e + 1) % 3];
      const double dx = w.x() - u.x(), dy = w.y() - u.y();
      const double side = cross2(dx, dy, p.x() - u.x(), p.y() - u.y());
      inside = side > 0 || (side == 0 && ownsEdge(dx, dy));
      weight[(e + 2) % 3] = side / area2;  // the barycentric weight of the corner opposite the edge
    }
    if (!inside) continue;
    const double z = weight[0] * a.z() + weight[1] * b.z() + weight[2] * c.z();
    if (z > p.z()) winding += sign;
  }
  return winding;
}

ImplicitSolid SurfaceSolid::solid() const {
  ImplicitSolid s;
  // The mesher calls the distance long after this returns: it holds the surface.
  auto self = std::make_shared<SurfaceSolid>(*this);
  s.distance = [self](const Vec3& p) { return self->windingNumber(p) != 0 ? -1.0 : 1.0; };
  s.centre = m_bounds.center();
  s.boundingRadius = 0.5 * m_bounds.diagonal().norm() * 1.05 + 1e-9;
  s.volumeTerm = 4.2 * std::abs(m_volume);
  s.surfaceTerm = 4.3 * m_area;
  s.leastFacetDistance = 0;
  return s;
}

}  // namespace trephine
