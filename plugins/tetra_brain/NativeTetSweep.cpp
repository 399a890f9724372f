// NativeTetBackend: the sweep that keeps the proxy out, and the ray cast that aims
// scripted paths, by the boundary faces the segment's box covers.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "framework/geometry/FrontRings.h"
#include "plugins/tetra_brain/NativeTetBackend.h"

namespace trephine::tetra {

namespace {

// Where segment p + t (q - p), t in [0, 1], crosses triangle (a, b, c), or a value > 1.
double segmentTriangle(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 d = q - p, e1 = b - a, e2 = c - a;
  const Vec3 h = d.cross(e2);
  const double det = e1.dot(h);
  if (std::abs(det) < 1e-300) return 2.0;
  const double inv = 1.0 / det;
  const Vec3 s = p - a;
  const double u = inv * s.dot(h);
  if (u < 0 || u > 1) return 2.0;
  const Vec3 r = s.cross(e1);
  const double v = inv * d.dot(r);
  if (v < 0 || u + v > 1) return 2.0;
  const double t = inv * e2.dot(r);
  return t >= 0 && t <= 1 ? t : 2.0;
}

}  // namespace

double NativeTetBackend::firstEntry(const Vec3& a, const Vec3& b, bool skipInitialInside, bool& startsInside) const {
  startsInside = locate(a) >= 0;
  if (startsInside && !skipInitialInside) return 0.0;
  // Boundary faces in the cells the segment's box covers; the first crossing
  // from outside to inside (moving against the face's outward normal).
  Box3 box;
  box.extend(a);
  box.extend(b);
  box = Box3(box.min() - Vec3::Constant(m_queryGrowth), box.max() + Vec3::Constant(m_queryGrowth));
  const auto faces = this->faces();
  const Vec3 direction = b - a;
  double first = 2.0;
  auto cross = [&](const BoundaryFace& f) {
    const Vec3 n = faceNormal(f);
    if (direction.dot(n) >= 0) return;  // leaving, or grazing
    const auto v = faceNodes(m_mesh->tets[f.tet], f.face);
    const double t = segmentTriangle(a, b, m_nodes[v[0]], m_nodes[v[1]], m_nodes[v[2]]);
    if (t < first && !(startsInside && t == 0)) first = t;
  };
  // The cavity's faces (a resection's), a list, with the box's test first.
  for (const BoundaryFace& f : m_live.exposed()) {
    const auto v = faceNodes(m_mesh->tets[f.tet], f.face);
    Box3 faceBox;
    for (int32_t i : v) faceBox.extend(m_nodes[i]);
    if (faceBox.intersects(box)) cross(f);
  }
  anyFaceInCells(box, [&](int32_t f) {
    if (m_live.onBoundary(faces[f])) cross(faces[f]);
    return false;  // every face: the first entry is the smallest t
  });
  return first;
}

SweepResult NativeTetBackend::sweep(const SweepQuery& query) const {
  SweepResult result;
  const Vec3 path = query.to - query.from;
  const double length = path.norm();
  if (!(length > 0) || !std::isfinite(length)) return result;
  const Vec3 u = path / length;
  const bool buried = locate(query.from) >= 0;
  auto probe = [&](const Vec3& offset, bool blockAtStart) {
    bool startsInside = false;
    const double t = firstEntry(query.from + offset, query.to + offset, buried || !blockAtStart, startsInside);
    if (startsInside && blockAtStart && !buried) {
      result.blocked = result.startsInside = true;
      result.freeFraction = 0;
      result.contactPoint = query.from + offset;
      return true;
    }
    if (t <= 1.0 && (!result.blocked || t < result.freeFraction)) {
      result.blocked = true;
      result.freeFraction = t;
      result.contactPoint = query.from + offset + t * path;
    }
    return false;
  };
  const double R = query.leadingRadius;
  if (probe(R * u, true)) return result;
  if (query.probe != SweepProbe::Line && R > 0) {
    // Cylinder (and, here, spheres): lines from rings on the front hemisphere,
    // half an edge apart (no thinner than 0.25 mm).
    forEachFrontRingPoint(u, R, std::max(0.25, 0.5 * m_averageEdge), probe);
  }
  return result;
}

std::optional<SurfaceHit> NativeTetBackend::raycast(const Vec3& origin, const Vec3& direction,
                                                    double maxDistance) const {
  bool startsInside = false;
  const Vec3 end = origin + maxDistance * direction;
  const double t = firstEntry(origin, end, false, startsInside);
  if (startsInside) return SurfaceHit{origin, -direction, 0.0};
  if (t > 1.0) return std::nullopt;
  SurfaceHit hit;
  hit.distance = t * maxDistance;
  hit.point = origin + hit.distance * direction;
  Vec3 normal;
  depthBelowSurface(hit.point, normal);
  hit.normal = normal.squaredNorm() > 0.5 ? normal : Vec3(-direction);
  return hit;
}

}  // namespace trephine::tetra
