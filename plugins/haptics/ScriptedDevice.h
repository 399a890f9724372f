#pragma once
// A device that follows a scripted motion. With a `target` link the motion is
// aimed at that target's surface, found by a ray along `direction` through
// `center` (or the middle of the target's bounds), so the same scene works on
// any skull or brain. Without a target, `center` is taken as the surface point
// and -direction as its normal.
#include <limits>

#include "framework/devices/HapticDevice.h"
#include "framework/geometry/SurfaceTarget.h"
#include "plugins/haptics/ScriptedPath.h"

namespace trephine::haptics {

class ScriptedDevice final : public HapticDevice {
 public:
  static constexpr std::string_view kTypeName = "ScriptedDevice";

  void init(InitContext& context) override;
  double preferredDuration() const override { return m_path.duration(); }
  void prepare(const RunPlan& plan) override;

  const ScriptedPath& scriptedPath() const { return m_path; }
  // Button bits at t (s): button 1 is held after an odd number of `buttonTimes` toggles.
  uint32_t buttonsAt(double t) const;

 protected:
  DeviceSample readSample(double t) override;

 private:
  struct Aim {
    Vec3 surface;  // mm, device point when the tool surface touches the target surface
    Vec3 normal;   // outward unit normal there
  };
  std::optional<Aim> aimAt(const Vec3& offset, InitContext& context) const;
  void buildApproachPressSlide(const Aim& aim, const Vec3& d);
  void buildDrillIn(const Aim& aim, const Vec3& d);
  void buildCircle(const Aim& aim, const Vec3& d);
  void buildRandomWalk(const Aim& aim, const Vec3& d, uint64_t seed);
  bool buildPokes(const Vec3& d, uint64_t seed, InitContext& context);
  bool buildWaypoints(InitContext& context);

  EnumField d_path{this,
                   "path",
                   {"approach-press-slide", "drill-in", "circle", "random-walk", "pokes", "waypoints"},
                   "approach-press-slide",
                   {.help = "Which scripted motion to follow"}};
  Link<SurfaceTarget> l_target{
      this,
      "target",
      {.help = "Target whose surface the motion aims at (optional; used to plan the path)", .initOnly = true}};
  Field<Vec3> d_center{this,
                       "center",
                       Vec3::Zero(),
                       {.help = "Aim point; with a target the approach ray passes through it (default: the middle of "
                                "the target's bounds), without one it is the surface point",
                        .unit = "mm"}};
  Field<Vec3> d_direction{this, "direction", Vec3(0, 0, -1), {.help = "Approach direction, pointing into the target"}};
  Field<double> d_standoff{
      this, "standoff", 10.0, {.help = "Start and end distance from the surface", .unit = "mm", .min = 0.0}};
  Field<double> d_depth{
      this, "depth", 1.0, {.help = "Press depth of the tool surface below the target surface", .unit = "mm"}};
  Field<double> d_tipOffset{this,
                            "tipOffset",
                            0.0,
                            {.help = "Distance from the device point to the tool surface along the approach (the "
                                     "radius for a sphere tool centred on the device), so depths are the tool's; "
                                     "paths are aimed where a sphere of this radius first touches the target, not "
                                     "where the approach ray does (a slot narrower than the tool holds it at the rims)",
                             .unit = "mm",
                             .min = 0.0}};
  Field<double> d_speed{
      this,
      "speed",
      20.0,
      {.help = "Average speed of approach, slide and retract moves", .unit = "mm/s", .min = 0.0, .minExclusive = true}};
  Field<double> d_slideDistance{
      this,
      "slideDistance",
      20.0,
      {.help = "Slide length (approach-press-slide): a straight line in the tangent plane of the pressed point, "
               "depth below it; on a curved surface the depth below the surface itself grows or shrinks along the "
               "slide (a convex one: deeper)",
       .unit = "mm",
       .min = 0.0}};
  Field<Vec3> d_slideDirection{this,
                               "slideDirection",
                               Vec3::UnitX(),
                               {.help = "Slide direction, projected on the tangent plane of the pressed point"}};
  Field<double> d_feedSpeed{this,
                            "feedSpeed",
                            1.0,
                            {.help = "Feed speed while drilling in", .unit = "mm/s", .min = 0.0, .minExclusive = true}};
  Field<double> d_radius{
      this, "radius", 5.0, {.help = "Circle radius, random-walk amplitude, or poke spread", .unit = "mm", .min = 0.0}};
  Field<double> d_period{
      this, "period", 2.0, {.help = "Time of one circle turn", .unit = "s", .min = 0.0, .minExclusive = true}};
  Field<double> d_turns{this, "turns", 2.0, {.help = "Circle turns", .min = 0.0}};
  Field<double> d_walkDuration{
      this, "walkDuration", 10.0, {.help = "Length of the random walk", .unit = "s", .min = 0.0, .minExclusive = true}};
  Field<int> d_count{this, "count", 10, {.help = "Number of pokes", .min = 1.0, .max = 100000.0}};
  Field<double> d_lift{this, "lift", 2.0, {.help = "Height above the surface between pokes", .unit = "mm", .min = 0.0}};
  Field<int> d_seed{this, "seed", -1, {.help = "Seed of random paths; -1 uses the run's --seed", .min = -1.0}};
  Field<std::vector<double>> d_waypoints{this,
                                         "waypoints",
                                         {},
                                         {.help = "For path=waypoints: 't x y z' groups with increasing t (s, mm), "
                                                  "linear in between"}};
  Field<std::vector<double>> d_nanTimes{
      this,
      "nanTimes",
      {},
      {.help = "Times (s) at which the device reports a NaN pose, to test rejection", .unit = "s"}};

  Field<std::vector<double>> d_buttonTimes{
      this,
      "buttonTimes",
      {},
      {.help = "Increasing times (s) at which button 1 toggles, starting released: '1.5 4' holds it from 1.5 s to 4 s",
       .unit = "s",
       .min = 0.0}};

  ScriptedPath m_path;
  std::vector<double> m_nanTimes;  // sorted
  size_t m_nextNaN = 0;
};

}  // namespace trephine::haptics
