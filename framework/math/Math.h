#pragma once
// Linear algebra vocabulary of the framework. Lengths are millimetres, time is
// seconds, force is newtons throughout. Names carry frames where it matters:
// p_WT is the position of the tool T in the world W, X_WD the pose of device D.
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

inline bool isFinite(const Vec3& v) { return v.allFinite(); }
inline bool isFinite(const Quat& q) { return q.coeffs().allFinite(); }

}  // namespace trephine
