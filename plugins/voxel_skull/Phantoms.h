#pragma once
// Deterministic test volumes, the same on every machine, at any voxel size.
// Densities are CT-like (bone 300 to 1500, soft tissue about 40, air 0) and
// edges are partial-volume averaged over each voxel, so a phantom resampled at
// another voxel size keeps its surface where it was.
#include <map>
#include <string>

#include "framework/geometry/ExactShape.h"
#include "framework/data/DensityVolume.h"

namespace trephine::voxel {

// Table 3.1 cubes: `voxelsPerAxis` voxels over a 200 mm grid, solid (density
// `density`) in the central 160 mm cube, air outside.
DensityVolume makeCubePhantom(int voxelsPerAxis, double density = 1200.0);

// Skull phantom: the thesis's skull extent (212.5 x 201.5 x 141.5 mm, so
// voxel 0.5 gives Table 3.2's 425 x 403 x 283) holding an ellipsoidal shell
// 4.5 to 8.5 mm thick (varying with direction): an outer cortical table of
// density 1500, diploe of 700 and an inner table of 1300, soft tissue (40)
// inside, and an opening of 16 mm radius at the base (foramen magnum).
// `shift` (mm, under a voxel) moves the voxel grid against the shape along
// each axis: the same skull scanned at another phase.
DensityVolume makeSkullPhantom(double voxelSize, double shift = 0.0);
// Its voxel counts per axis, without building it.
std::array<int32_t, 3> skullPhantomDims(double voxelSize);

// A half-space of density `density` below the plane through the grid centre
// with unit `normal`, in a cube grid of `size` mm. Partial-volume edges make
// the isosurface at density/2 the plane itself: the ground truth of accuracy tests.
// The skull phantom as a head CT in Hounsfield units: air at -1000 outside
// the skull, the cavity at 40 (brain), the bone as in makeSkullPhantom.
DensityVolume makeHeadPhantom(double voxelSize);
// A segmentation of that head's brain on the same grid: 1 (grey matter) in
// the cavity 2 mm clear of the inner table and above z = -40 mm, 2 (white
// matter) in its core, 0 elsewhere.
DensityVolume makeHeadLabelsPhantom(double voxelSize);
DensityVolume makeHalfSpacePhantom(double voxelSize, const Vec3& normal, double size = 40.0, double density = 1000.0);

// A wall of `thickness` mm (axis-aligned, normal +z) across a cube grid of
// `size` mm, centred: thin-bone and drilling-through tests.
DensityVolume makeWallPhantom(double voxelSize, double thickness, double size = 40.0, double density = 1000.0);

// A solid block with a square channel of `width` mm drilled along z through
// its middle: a cavity narrower or wider than the tool.
DensityVolume makeChannelPhantom(double voxelSize, double width, double size = 40.0, double density = 1000.0);

// "name?key=value&key=value" as written after "phantom:" in a scene. Throws
// std::invalid_argument naming the unknown phantom or key, or the bad value.
DensityVolume makePhantom(const std::string& specification);
// The solid a phantom's volume samples, exactly (mm, negative inside): the
// geometric surface, which the partial-volume densities place at density / 2
// (halfspace, wall, channel, cube); the skull's isosurface at another isovalue
// lies off it by a fraction of a voxel. Throws as makePhantom.
LevelSet phantomShape(const std::string& specification);
// The phantoms and their keys with defaults, for help texts.
std::string phantomHelp();

}  // namespace trephine::voxel
