#pragma once
// Closest points on simple primitives, shared by the collision back-ends.
#include <algorithm>
#include <cmath>

#include "framework/math/Math.h"

namespace trephine {

// The point of triangle (a, b, c) closest to p (Ericson, Real-Time Collision
// Detection, 5.1.5): the Voronoi region of p among the vertices, edges and face.
inline Vec3 closestOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + d1 / (d1 - d3) * ab;
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + d2 / (d2 - d6) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b);
  const double denom = 1.0 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

// The squared distance between segments [p1, q1] and [p2, q2] (Ericson,
// 5.1.9), degenerate segments (points) included.
inline double segmentSegmentDistance2(const Vec3& p1, const Vec3& q1, const Vec3& p2, const Vec3& q2) {
  const Vec3 d1 = q1 - p1, d2 = q2 - p2, r = p1 - p2;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  double s = 0, t = 0;
  if (a <= 0 && e <= 0) return r.squaredNorm();
  if (a <= 0) {
    t = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = d1.dot(r);
    if (e <= 0) {
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = d1.dot(d2), denom = a * e - b * b;
      s = denom > 0 ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      if (t < 0) {
        t = 0;
        s = std::clamp(-c / a, 0.0, 1.0);
      } else if (t > 1) {
        t = 1;
        s = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  return ((p1 + s * d1) - (p2 + t * d2)).squaredNorm();
}

// The distance between segment [p, q] and triangle (a, b, c): 0 when the
// segment crosses the triangle, else the least of its ends' distances to the
// triangle and its distances to the triangle's edges (where the minimum of
// two convex sets that do not meet is attained).
inline double segmentTriangleDistance(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 n = (b - a).cross(c - a);
  const double sp = n.dot(p - a), sq = n.dot(q - a);
  if ((sp <= 0 && sq >= 0) || (sp >= 0 && sq <= 0)) {
    // The segment meets the triangle's plane: inside the triangle there?
    // (On the plane up to rounding: the sides of its edges decide, not a
    // closest point that rounding puts a hair off the face.)
    const Vec3 x = sp == sq ? p : Vec3(p + sp / (sp - sq) * (q - p));
    if (n.squaredNorm() > 0 && (b - a).cross(x - a).dot(n) >= 0 && (c - b).cross(x - b).dot(n) >= 0 &&
        (a - c).cross(x - c).dot(n) >= 0)
      return 0;
  }
  double best = std::min((closestOnTriangle(p, a, b, c) - p).squaredNorm(),
                         (closestOnTriangle(q, a, b, c) - q).squaredNorm());
  best = std::min(best, segmentSegmentDistance2(p, q, a, b));
  best = std::min(best, segmentSegmentDistance2(p, q, b, c));
  best = std::min(best, segmentSegmentDistance2(p, q, c, a));
  return std::sqrt(best);
}

}  // namespace trephine
