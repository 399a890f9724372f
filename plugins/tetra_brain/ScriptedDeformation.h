#pragma once
// Moves the nodes of a TetraBrain by a prescribed displacement field, to test
// and measure collision on a deforming mesh without a mechanical model:
//   wave - u = A sin(2 pi (|X - c| / lambda - t / T)) d: a spherical wave from
//          the centre c; every node moves every frame (a pulsating brain);
//   bump - u = A (1 - (r / R)^2)^2 sin(2 pi t / T) d for nodes within R of c:
//          only those nodes move (a local press).
// X is a node's rest position, d the unit displacement direction. The
// displacement bound published with the positions is A (exact).
#include <vector>

#include "framework/core/Component.h"
#include "framework/data/MeshDeformation.h"
#include "plugins/tetra_brain/TetraBrain.h"

namespace trephine::tetra {

class ScriptedDeformation final : public Component {
 public:
  static constexpr std::string_view kTypeName = "ScriptedDeformation";

  void init(InitContext& context) override;
  void tick(const TickContext& context) override;
  void reportCounters(std::vector<Counter>& counters) const override;

 private:
  Link<TetraBrain> l_mesh{this, "mesh", {.help = "The mesh whose nodes this moves", .required = true}};
  EnumField d_shape{this,
                    "shape",
                    {"wave", "bump"},
                    "wave",
                    {.help = "wave: a spherical wave from the centre moves every node; bump: a pulsing dent moves "
                             "only the nodes within the radius"}};
  Field<double> d_amplitude{
      this, "amplitude", 0.5, {.help = "Largest displacement of a node", .unit = "mm", .min = 0.0}};
  Field<double> d_wavelength{this,
                             "wavelength",
                             40.0,
                             {.help = "Wave: distance between crests", .unit = "mm", .min = 0.0, .minExclusive = true}};
  Field<double> d_period{
      this, "period", 1.0, {.help = "Time of one oscillation", .unit = "s", .min = 0.0, .minExclusive = true}};
  Field<Vec3> d_direction{this, "direction", Vec3(0, 0, 1), {.help = "Direction of the displacement (normalised)"}};
  Field<Vec3> d_center{this, "center", Vec3::Zero(), {.help = "Centre of the wave or the bump", .unit = "mm"}};
  Field<double> d_radius{
      this, "radius", 10.0, {.help = "Bump: radius of the moved region", .unit = "mm", .min = 0.0, .minExclusive = true}};
  RateField d_rate{this, 1000.0, "Deformation rate (a new shape every tick)"};

  Channel<NodePositions>* m_channel = nullptr;
  std::vector<Vec3> m_rest;          // mm
  std::vector<double> m_profile;     // per node: wave phase (rad) or bump weight, fixed at rest
  NodePositions m_frame;
  Vec3 m_unitDirection = Vec3::UnitZ();
  bool m_wave = true;  // d_shape, read once at init (not compared as a string every frame)
};

}  // namespace trephine::tetra
