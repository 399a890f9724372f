#include "plugins/fem/MaterialPlausibility.h"

#include "framework/core/Strings.h"

namespace trephine::fem {

std::optional<std::string> implausibleYoungModulus(double kPa) {
  const std::string given = formatDouble(kPa) + " kPa";
  if (kPa > kStiffestSoftTissue_kPa)
    return "is in kPa: " + given +
           " is stiffer than any soft tissue (brain 0.1 to 10 kPa, up to about 1000 kPa "
           "for skin); as pascals it would be " +
           formatDouble(kPa / 1000) + " kPa";
  if (kPa < kSoftestTissue_kPa)
    return "is in kPa: " + given + " is softer than any tissue (brain 0.1 to 10 kPa); as MPa it would be " +
           formatDouble(kPa * 1000) + " kPa";
  return std::nullopt;
}

std::optional<std::string> implausibleDensity(double kgPerMm3) {
  const std::string given = formatDouble(kgPerMm3) + " kg/mm^3";
  if (kgPerMm3 > kHeaviestTissue_kgPerMm3 || kgPerMm3 < kLightestTissue_kgPerMm3) {
    std::string message = "is in kg/mm^3: " + given + " is " +
                          (kgPerMm3 > kHeaviestTissue_kgPerMm3 ? "heavier" : "lighter") +
                          " than any tissue (water is 1e-06, bone about 1.9e-06)";
    // The units a slip would come from: g/cm^3 (1 for water) and kg/m^3 (1000).
    if (kgPerMm3 >= 0.5 && kgPerMm3 <= 3)
      message += "; as g/cm^3 it would be " + formatDouble(kgPerMm3 / 1e6) + " kg/mm^3";
    else if (kgPerMm3 >= 500 && kgPerMm3 <= 3000)
      message += "; as kg/m^3 it would be " + formatDouble(kgPerMm3 / 1e9) + " kg/mm^3";
    return message;
  }
  return std::nullopt;
}

}  // namespace trephine::fem
