#pragma once
// A half-space: everything below the plane through `point` with outward
// `normal` is solid. Exact distances make it the ground truth for tests.
#include "framework/geometry/ImplicitSurface.h"

namespace trephine::analytic {

class AnalyticPlane final : public Component, public ImplicitSurface {
 public:
  static constexpr std::string_view kTypeName = "AnalyticPlane";

  void init(InitContext& context) override;
  Box3 bounds() const override;
  std::optional<SurfaceHit> raycast(const Vec3& origin, const Vec3& direction, double maxDistance) const override;
  double signedDistance(const Vec3& p_W, Vec3& normal_W) const override;

 private:
  Field<Vec3> d_point{this, "point", Vec3::Zero(), {.help = "A point on the plane", .unit = "mm"}};
  Field<Vec3> d_normal{this, "normal", Vec3::UnitZ(), {.help = "Outward normal (normalised on load; not zero)"}};
  Field<double> d_extent{this,
                         "extent",
                         100.0,
                         {.help = "Half size of the region reported as the plane's bounds",
                          .unit = "mm",
                          .min = 0.0,
                          .minExclusive = true}};
  Vec3 m_unitNormal = Vec3::UnitZ();
};

}  // namespace trephine::analytic
