#pragma once
// Point clouds on a unit sphere for pointshells.
#include <span>
#include <vector>

#include "framework/geometry/ShellTool.h"
#include "framework/math/Math.h"

namespace trephine {

// The angle-step scheme of the spherical parametrisation
//   x = cos(a) sin(b), y = sin(a) sin(b), z = cos(b),
// with a = 0, s, 2s, ... < 360 and b = 0, s, ... <= 180 degrees (the step s in
// degrees), duplicates at the poles merged. Step 10 gives 614 points, step 15
// gives 266. Denser near the poles than at the equator.
std::vector<Vec3> angleStepDirections(double stepDegrees);

// `count` directions spread evenly by area (the Fibonacci lattice): every
// point covers about the same solid angle.
std::vector<Vec3> evenDirections(int count);

// How far a tool's shell lies within its leading sphere at most (mm): the
// largest gap, over every direction d, between the sphere of `radius` and the
// shell's farthest point along d (radius - max_i p_i . d, where positive;
// sampled over 4096 even directions). A sweep that stops the sphere's
// leading point in a surface may find no shell point there when the shell
// has no point right at the front: the proxy then settles this much farther.
// O(shell x 4096): at initialisation.
double shellSag(std::span<const ShellPoint> shell, double radius);

// Largest angle (rad) from any direction on the sphere to its nearest sample,
// estimated on a dense probe set: the coverage gap a shell leaves.
double largestGapAngle(const std::vector<Vec3>& directions);

}  // namespace trephine
