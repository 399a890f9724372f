#pragma once
// The exact contact of a burr on a shaft (ToolSolid: a sphere, and a
// flat-ended cylinder of the shaft's radius from the burr's centre along
// its axis) with a solid, built on the exact contact of spheres with that
// solid (a scan's isosurface or a mesh's boundary: the study's references).
// The reference a study measures a non-spherical tool against; offline only.
//
// Penetration: the deeper of the burr's (the sphere's, as for a spherical
// tool) and the shaft's. The shaft's is the largest over its axis of the
// depth its cross-section reaches: at axis point p, the disc of radius rho
// square to the axis reaches -sd(p) + rho |n x a| deep, sd the signed
// distance of p to the surface (negative inside), n the direction to the
// nearest surface point and a the axis: exact where the surface is flat
// across the disc, so that a shaft lying along the surface reaches rho below
// its axis and a shaft pushed end first reaches as deep as its end's centre
// (the end is flat). The normal is that of the deeper part.
#include <functional>

#include "framework/geometry/ShellTool.h"
#include "tools/trephine/study/ExactSphereContact.h"

namespace trephine::study {

// The exact contact of a sphere of `radius` centred at a point with the solid.
using SphereReference = std::function<ExactSphereContact(const Vec3& centre, double radius)>;

// The tool at X_WT (its burr's centre and its orientation). The shaft's
// axis is sampled every `axisStep` mm where a sphere covering that stretch
// reaches the solid, and the deepest sample refined by golden-section search.
ExactSphereContact exactToolContact(const SphereReference& sphere, const Pose& X_WT, const ToolSolid& tool,
                                    double axisStep = 0.1);

}  // namespace trephine::study
