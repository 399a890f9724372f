#pragma once
// The two hands of a tumour resection (CapsuleShape.h gives their shape):
//  - AspiratorTool, an ultrasonic aspirator: its tip vibrates along its axis
//    (amplitude, frequency) and, while its pedal is held, removes the tissue
//    it touches at a rate its power, the contact force and the tissue's
//    removal energy set (TissueAction, ShellTool.h);
//  - BipolarForceps: while its pedal is held, coagulates the tissue it
//    touches with its power, so that tissue does not bleed when removed.
// Both act only on a resected brain (a TetraBrain with a Resection): their
// proxy refuses another target at load.
#include <vector>

#include "framework/devices/HapticDevice.h"
#include "framework/geometry/ShellTool.h"
#include "plugins/haptics/CapsuleShape.h"

namespace trephine::haptics {

class AspiratorTool final : public Component, public ShellTool {
 public:
  static constexpr std::string_view kTypeName = "AspiratorTool";

  void init(InitContext& context) override;
  void reportCounters(std::vector<Counter>& counters) const override;

  std::span<const ShellPoint> shellPoints() const override { return m_points; }
  HapticDevice& device() const override { return *l_device; }
  Pose toolPose(const Pose& X_WD) const override { return d_shape.toolPose(X_WD); }
  double leadingRadius() const override { return d_shape.radius.value(); }
  double boundingRadius() const override { return m_boundingRadius; }
  ToolSolid solid() const override { return d_shape.solid(); }
  TissueAction tissueAction() const override;

 private:
  Link<HapticDevice> l_device{this, "device", {.help = "Device that moves the tool", .required = true}};
  // The 20 mm of the tube that can reach into a cavity. Points 0.4 mm apart
  // on a 1.2 mm ball sag 0.03 mm below the sphere, within the brain's
  // contact depth (0.05 mm): coarser, a proxy stopped on a slope may hold
  // no point in the tissue, and then presses no node and removes nothing.
  CapsuleFields d_shape{this, {1.2, 1.2, 20.0, 0.4}};
  Field<double> d_amplitude{this,
                            "amplitude",
                            0.15,
                            {.help = "Stroke of the tip's vibration: clinical handpieces reach about 0.3 mm at "
                                     "full amplitude",
                             .unit = "mm",
                             .min = 0.0,
                             .max = 1.0}};
  Field<double> d_frequency{this,
                            "frequency",
                            23000.0,
                            {.help = "Vibration frequency of the tip (clinical handpieces: 23 or 36 kHz)",
                             .unit = "Hz",
                             .min = 0.0}};
  Field<double> d_coupling{this,
                           "coupling",
                           0.1,
                           {.help = "Share of the contact force times the tip's mean speed (4 amplitude frequency) "
                                    "that goes into the tissue (calibrated: 0.1 removes about 14 mm^3/s of "
                                    "0.05 J/mm^3 tissue at 0.5 N)",
                            .min = 0.0,
                            .max = 1.0}};
  Field<double> d_power{this,
                        "power",
                        20.0,
                        {.help = "Rated power of the handpiece: the most it puts into the tissue",
                         .unit = "W",
                         .min = 0.0}};
  Field<int> d_pedal{this,
                     "pedal",
                     0,
                     {.help = "Device button of the foot pedal that runs it; 0: it runs whenever it touches tissue",
                      .min = 0.0,
                      .max = 32.0}};

  std::vector<ShellPoint> m_points;
  double m_boundingRadius = 0;
};

class BipolarForceps final : public Component, public ShellTool {
 public:
  static constexpr std::string_view kTypeName = "BipolarForceps";

  void init(InitContext& context) override;
  void reportCounters(std::vector<Counter>& counters) const override;

  std::span<const ShellPoint> shellPoints() const override { return m_points; }
  HapticDevice& device() const override { return *l_device; }
  Pose toolPose(const Pose& X_WD) const override { return d_shape.toolPose(X_WD); }
  double leadingRadius() const override { return d_shape.radius.value(); }
  double boundingRadius() const override { return m_boundingRadius; }
  ToolSolid solid() const override { return d_shape.solid(); }
  TissueAction tissueAction() const override;

 private:
  Link<HapticDevice> l_device{this, "device", {.help = "Device that moves the tool", .required = true}};
  CapsuleFields d_shape{this, {1.0, 1.0, 20.0, 0.4}};
  Field<double> d_power{this,
                        "power",
                        5.0,
                        {.help = "Power the tips put into the tissue they touch (generators are set to 10 to 30 W; "
                                 "part of it reaches the tissue)",
                         .unit = "W",
                         .min = 0.0,
                         .minExclusive = true}};
  Field<int> d_pedal{this,
                     "pedal",
                     0,
                     {.help = "Device button of the foot pedal that runs it; 0: it runs whenever it touches tissue",
                      .min = 0.0,
                      .max = 32.0}};

  std::vector<ShellPoint> m_points;
  double m_boundingRadius = 0;
};

}  // namespace trephine::haptics
