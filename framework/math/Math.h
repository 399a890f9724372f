#pragma once
// Linear algebra vocabulary of the framework. Lengths are millimetres, time is
// seconds, force is newtons throughout. Names carry frames where it matters:
// p_WT is the position of the tool T in the world W, X_WD the pose of device D.
#include <cmath>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace trephine {

using Vec3 = Eigen::Vector3d;
using Quat = Eigen::Quaterniond;
using Box3 = Eigen::AlignedBox3d;

// A rigid pose: position in mm and orientation as a unit quaternion.
struct Pose {
  Vec3 position = Vec3::Zero();
  Quat orientation = Quat::Identity();
};

// The shortest rotation taking the direction `from` to the direction `to`
// (neither zero), as a unit quaternion: Eigen's Quaternion::FromTwoVectors,
// normalised (Eigen's is off unit by up to eps/(1 + cos) near opposite
// directions), and opposite directions turned half about
// from.unitOrthogonal(), where Eigen's instantiates a JacobiSVD to find an
// axis (about 10 s of compile time in every file that calls it).
inline Quat rotationBetween(const Vec3& from, const Vec3& to) {
  const Vec3 v0 = from.normalized(), v1 = to.normalized();
  const double c = v1.dot(v0);
  if (c < -1 + Eigen::NumTraits<double>::dummy_precision()) {
    const Vec3 axis = v0.unitOrthogonal();
    return Quat(0, axis.x(), axis.y(), axis.z());
  }
  const Vec3 axis = v0.cross(v1);
  const double s = std::sqrt((1 + c) * 2);
  Quat q;
  q.vec() = axis * (1 / s);
  q.w() = s * 0.5;
  return q.normalized();
}

inline bool isFinite(const Vec3& v) { return v.allFinite(); }
inline bool isFinite(const Quat& q) { return q.coeffs().allFinite(); }

}  // namespace trephine
