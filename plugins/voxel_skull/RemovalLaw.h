#pragma once
// Force-driven bone removal: how fast the bone surface under a spinning burr
// recedes for a given thrust. A power balance (constant specific cutting
// energy, after Arbabtafti et al. 2011): the burr's edge, moving at the
// surface speed w r, drags with the tangential force s (F - F0) (s the burr's
// sharpness, F the thrust, F0 the thrust below which it only polishes), so it
// cuts with the power P = s (F - F0) w r; removing bone of specific cutting
// energy u(rho) costs u per unit volume, over the burr's projected area
// pi r^2, so the surface recedes at
//     v = P / (u(rho) pi r^2) = s w (F - F0 H) / (pi r u(rho)),   capped at vMax.
// The energy grows with the bone's density: u(rho) = u_ref H(rho) with
// H = (rho / rho_ref)^e (the strength of bone grows with the square of its
// apparent density, Carter and Hayes 1977: e = 2), never below the hardness of
// bone at the isovalue. Pure functions, no state: the same in every frame.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "framework/geometry/ShellTool.h"

namespace trephine::voxel {

struct RemovalLaw {
  double cuttingEnergy = 0;     // N/mm^2 (= mJ/mm^3), u_ref: bone of the reference density
  double referenceDensity = 1;  // density units, rho_ref (> 0)
  double hardnessExponent = 2;  // e
  double softestBone = 0;       // density units: the isovalue, where the hardness stops falling
  double thrustThreshold = 0;   // N, F0
  double maxSpeed = 0;          // mm/s, vMax

  // Hardness relative to bone of the reference density (dimensionless, > 0).
  double hardness(double density) const {
    const double floorDensity = std::max(softestBone, 1e-6 * referenceDensity);
    return std::pow(std::max(density, floorDensity) / referenceDensity, hardnessExponent);
  }

  // mm/s at which the surface under a burr of `radius` (mm) recedes when it is
  // pressed with `thrust` (N) on bone of `density`.
  double recessionSpeed(double thrust, double density, const CuttingBurr& burr, double radius) const {
    // The threshold scales with the hardness too: a thin rim of soft or
    // partial-volume bone gives way under a light touch.
    const double excess = thrust - thrustThreshold * hardness(density);
    if (!(excess > 0) || !(radius > 0) || !(cuttingEnergy > 0)) return 0;
    const double omega = burr.spindleSpeed_rpm * 2.0 * std::numbers::pi / 60.0;  // rad/s
    const double v = burr.sharpness * omega * excess / (std::numbers::pi * radius * cuttingEnergy * hardness(density));
    return std::isfinite(v) ? std::clamp(v, 0.0, maxSpeed) : 0.0;
  }
};

}  // namespace trephine::voxel
