#include "plugins/analytic/AnalyticPlane.h"

#include <cmath>

#include "framework/core/Lifecycle.h"

namespace trephine::analytic {

void AnalyticPlane::init(InitContext& context) {
  const double length = d_normal->norm();
  if (length < 1e-12) {
    context.error(d_normal, "the normal must not be zero");
    return;
  }
  m_unitNormal = d_normal.value() / length;
}

Box3 AnalyticPlane::bounds() const {
  const Vec3 half = Vec3::Constant(d_extent.value());
  return Box3(d_point.value() - half, d_point.value() + half);
}

std::optional<SurfaceHit> AnalyticPlane::raycast(const Vec3& origin, const Vec3& direction, double maxDistance) const {
  const double height = (origin - d_point.value()).dot(m_unitNormal);
  if (height <= 0) return SurfaceHit{origin, m_unitNormal, 0.0};  // starts inside the solid
  const double approach = direction.dot(m_unitNormal);
  if (approach >= 0) return std::nullopt;  // parallel or moving away
  const double s = -height / approach;
  if (s > maxDistance) return std::nullopt;
  return SurfaceHit{origin + s * direction, m_unitNormal, s};
}

double AnalyticPlane::signedDistance(const Vec3& p_W, Vec3& normal_W) const {
  normal_W = m_unitNormal;
  return (p_W - d_point.value()).dot(m_unitNormal);
}

}  // namespace trephine::analytic
