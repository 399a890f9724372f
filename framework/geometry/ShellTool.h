#pragma once
// A rigid tool described by a cloud of points on its surface (its shell),
// each with the unit normal pointing into the tool. Collision targets test
// these points; a new tool shape is one component implementing this
// interface (PointshellTool: a sphere; CapsuleTool: a burr on a shaft).
#include <span>
#include <string_view>

#include "framework/data/TriangleMesh.h"
#include "framework/math/Math.h"

namespace trephine {

class HapticDevice;  // framework/devices/HapticDevice.h

struct ShellPoint {
  Vec3 position;      // mm, tool frame (origin at the tool's reference point)
  Vec3 inwardNormal;  // unit, tool frame, pointing into the tool
};

// A tool that cuts bone when its target is drillable: how fast it spins and how
// sharp it is. The removal law of the target turns these and the contact load
// into removed material (see CuttingLoad in ShellContactTarget.h).
struct CuttingBurr {
  double spindleSpeed_rpm = 0;  // 0: the tool does not spin and cuts nothing
  double sharpness = 0;         // tangential over normal force at the cutting edge (dimensionless)
};

// What a tool does to the brain tissue it touches while its pedal is held
// (resection; a target that resects reads it, others ignore it). An
// ultrasonic aspirator removes tissue: its tip, vibrating along its axis with
// a stroke of amplitude A at frequency f, moves at a mean speed of 4 A f, and
// a share (the coupling) of the contact force times that speed goes into the
// tissue, up to the handpiece's rated power. A bipolar forceps coagulates the
// tissue it touches with its power: coagulated tissue does not bleed when it
// is removed.
struct TissueAction {
  enum class Kind { kNone, kAspirate, kCoagulate };
  Kind kind = Kind::kNone;
  double tipSpeed_mm_per_s = 0;  // aspirator: the mean speed of the vibrating tip, 4 A f
  double coupling = 0;           // aspirator: share of force times tip speed that goes into the tissue
  double power_W = 0;            // aspirator: rated power (the most it puts in); bipolar: power into the tissue
  int pedal = 0;                 // device button that engages it; 0: always engaged
  // W: the power a contact force of `force_N` puts into the tissue.
  double powerAt(double force_N) const {
    if (kind == Kind::kCoagulate) return power_W;
    if (kind != Kind::kAspirate || !(force_N > 0)) return 0;
    const double mechanical = coupling * force_N * tipSpeed_mm_per_s * 1e-3;  // N * m/s
    return mechanical < power_W ? mechanical : power_W;
  }
};

// The solid a tool's shell samples, for targets whose back-ends test
// primitives rather than points (Bullet): a sphere of `radius` at the
// reference point and, when shaftLength > 0, a cylinder of shaftRadius from
// the reference point along the unit shaftAxis (tool frame), open at its end.
struct ToolSolid {
  double radius = 0;       // mm
  double shaftRadius = 0;  // mm
  double shaftLength = 0;  // mm, 0: no shaft
  Vec3 shaftAxis = Vec3::UnitZ();
};

class ShellTool {
 public:
  static constexpr std::string_view kTypeName = "ShellTool";
  virtual ~ShellTool() = default;

  // The shell in the tool frame; fixed after initialisation (spans stay valid).
  virtual std::span<const ShellPoint> shellPoints() const = 0;
  // The device that moves the tool.
  virtual HapticDevice& device() const = 0;
  // X_WT: the tool frame in the world when the device is at X_WD.
  virtual Pose toolPose(const Pose& X_WD) const = 0;
  // Radius of the working end around the reference point (mm): how far the
  // surface reaches ahead of the reference point when it moves (the burr radius).
  virtual double leadingRadius() const = 0;
  // Every shell point lies within this distance of the reference point (mm).
  virtual double boundingRadius() const = 0;
  // The burr at the reference point, a sphere of leadingRadius(); a tool that
  // does not spin keeps the default (cuts nothing under the force law).
  virtual CuttingBurr cuttingBurr() const { return {}; }
  // What it does to brain tissue (an aspirator, a bipolar forceps); none by default.
  virtual TissueAction tissueAction() const { return {}; }
  // The solid the shell samples: by default the sphere of leadingRadius().
  virtual ToolSolid solid() const { return {leadingRadius(), 0, 0, Vec3::UnitZ()}; }
  // What the tool looks like (tool frame, mm), for the files and the viewer:
  // by default the surface of solid() (ToolSurface.h); a tool of another
  // shape returns its own. Called once, at initialisation.
  virtual TriangleMesh displaySurface() const;
};

}  // namespace trephine
