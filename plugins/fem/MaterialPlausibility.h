#pragma once
// Material constants far outside those of tissue, as a slip of units gives
// them (pascals written for kilopascals, g/cm^3 or kg/m^3 for kg/mm^3): the
// warning a scene gets at load, naming the unit the field is in and what the
// value would mean in the likely one. Valid values still load: a researcher
// may mean them (a stiff phantom), and --strict makes warnings errors.
#include <optional>
#include <string>

namespace trephine::fem {

// Soft tissue: brain 0.1 to 10 kPa, muscle and liver up to about 100 kPa,
// skin and tendon towards 1 MPa.
inline constexpr double kSoftestTissue_kPa = 0.05, kStiffestSoftTissue_kPa = 1000;
// Tissue is 0.9 to 1.1 g/cm^3 (fat to muscle), bone about 1.9: 1e-6 kg/mm^3 is water.
inline constexpr double kLightestTissue_kgPerMm3 = 2e-7, kHeaviestTissue_kgPerMm3 = 5e-6;

// Why `kPa` is not a tissue's Young's modulus, or nothing.
std::optional<std::string> implausibleYoungModulus(double kPa);
// Why `kgPerMm3` is not a tissue's density, or nothing.
std::optional<std::string> implausibleDensity(double kgPerMm3);

}  // namespace trephine::fem
