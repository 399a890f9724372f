#pragma once
// The fields of a spinning burr, declared once for every pointshell tool that
// can drill. Only a drillable target with the force-driven removal law reads
// them (VoxelSkull removal="force"); elsewhere they have no effect.
#include "framework/core/Field.h"
#include "framework/geometry/ShellTool.h"

namespace trephine::haptics {

struct BurrFields {
  explicit BurrFields(FieldOwner* owner)
      : spindleSpeed{owner,
                     "spindleSpeed",
                     60000.0,
                     {.help = "Burr speed; cranial high-speed drills run at 60,000 to 80,000 rpm. The cutting power "
                              "at a given thrust grows with it; 0 makes the tool cut nothing",
                      .unit = "rpm",
                      .min = 0.0}},
        sharpness{owner,
                  "sharpness",
                  0.5,
                  {.help = "Ratio of the tangential (cutting) force to the thrust at the burr's edge: about 0.5 for "
                           "a fluted steel or carbide burr, less for a worn or diamond one; the cutting power at a "
                           "given thrust is proportional to it",
                   .min = 0.0,
                   .max = 2.0}} {}

  CuttingBurr value() const { return {spindleSpeed.value(), sharpness.value()}; }

  Field<double> spindleSpeed;
  Field<double> sharpness;
};

}  // namespace trephine::haptics
