#include "plugins/haptics/ScriptedDevice.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numbers>
#include <set>

#include "framework/core/Lifecycle.h"
#include "framework/geometry/FrontRings.h"

namespace trephine::haptics {

namespace {

constexpr double kSettle = 0.1;    // s held at the start and end of each path
constexpr double kEaseTime = 0.5;  // s to reach full speed on a circle or a walk

}  // namespace

std::optional<ScriptedDevice::Aim> ScriptedDevice::aimAt(const Vec3& offset, InitContext& context) const {
  const Vec3 d = d_direction->normalized();
  // The device point sits tipOffset behind the tool surface: aim it there.
  if (!l_target) return Aim{d_center.value() + offset - d * d_tipOffset.value(), -d};
  const Box3 box = l_target->bounds();
  const Vec3 center = (d_center.isSet() ? d_center.value() : box.center()) + offset;
  const double reach = box.diagonal().norm() + (center - box.center()).norm() + d_standoff.value() + 1.0;
  const Vec3 origin = center - d * reach;
  const auto hit = l_target->raycast(origin, d, 2.0 * reach);
  // A hit at distance 0 means the ray starts inside the target: the direction points out of it.
  if (!hit || hit->distance <= 0) {
    context.error(*this, "the approach ray through " + FieldTraits<Vec3>::format(center) + " along " +
                             FieldTraits<Vec3>::format(d) + " misses " + l_target.boundComponent()->path());
    return std::nullopt;
  }
  const double r = d_tipOffset.value();
  if (!(r > 0)) return Aim{hit->point, hit->normal};
  // The tool is a sphere of radius tipOffset around the device point, not a
  // ray: on a rough surface (a sulcus narrower than the tool) the axis ray
  // reaches farther than the sphere can. Rays on rings of the sphere's disc
  // find where it first touches: a ray at distance rho from the axis hitting at
  // t stops the centre at t - sqrt(r^2 - rho^2). Rings every eighth of the
  // radius, rays about that far apart (about 230 rays): at a rim the sphere
  // may sit up to about r/20 too low (0.05 mm for a 2.5 mm tool at a 3 mm slot).
  double stop = hit->distance - r;
  Vec3 normal = hit->normal;
  const auto [u, v] = perpendicularBasis(d);
  constexpr int kRings = 8;
  for (int ring = 1; ring <= kRings; ++ring) {
    const double rho = r * ring / kRings;
    const int count = std::max(6, int(std::ceil(2.0 * std::numbers::pi * ring)));  // circumference / (r / kRings)
    for (int k = 0; k < count; ++k) {
      const double angle = 2.0 * std::numbers::pi * k / count;
      const Vec3 lateral = rho * (std::cos(angle) * u + std::sin(angle) * v);
      const auto side = l_target->raycast(origin + lateral, d, 2.0 * reach);
      if (!side || side->distance <= 0) continue;
      const double centre = side->distance - std::sqrt(std::max(0.0, r * r - rho * rho));
      if (centre < stop) {
        stop = centre;
        normal = side->normal;
      }
    }
  }
  return Aim{origin + stop * d, normal};
}

// The fields each path reads (besides name, rate, maxSpeed, record, path and
// nanTimes, which every path has). Setting another is an error: it would be
// silently ignored.
const std::map<std::string, std::set<std::string>>& fieldsOfPath() {
  static const std::set<std::string> aimed = {"target", "center",    "direction", "standoff",
                                              "depth",  "tipOffset", "speed"};
  static const auto with = [](std::set<std::string> extra) {
    extra.insert(aimed.begin(), aimed.end());
    return extra;
  };
  static const std::map<std::string, std::set<std::string>> table = {
      {"approach-press-slide", with({"slideDistance", "slideDirection"})},
      {"drill-in", with({"feedSpeed"})},
      {"circle", with({"radius", "period", "turns"})},
      {"random-walk", with({"radius", "walkDuration", "seed"})},
      {"pokes", with({"radius", "count", "lift", "seed"})},
      {"waypoints", {"waypoints"}},
  };
  return table;
}

void ScriptedDevice::init(InitContext& context) {
  static const std::set<std::string> common = {"name",     "rate",     "group",      "maxSpeed",
                                                "record",   "path",     "nanTimes",   "buttonTimes"};
  const std::set<std::string>& used = fieldsOfPath().at(d_path.value());
  for (const BaseField* field : fields()) {
    if (!field->isSet() || common.count(field->name()) || used.count(field->name())) continue;
    std::string users;
    for (const auto& [path, names] : fieldsOfPath())
      if (names.count(field->name())) users += (users.empty() ? "" : ", ") + path;
    context.error(*field, "has no effect with path=\"" + d_path.value() + "\" (it is used by " + users + ")");
  }
  if (d_direction->norm() < 1e-12) {
    context.error(d_direction, "the approach direction must not be zero");
    return;
  }
  const Vec3 d = d_direction->normalized();
  const uint64_t seed = d_seed.value() >= 0 ? static_cast<uint64_t>(d_seed.value()) : context.seed();
  m_path = ScriptedPath();
  const auto& toggles = d_buttonTimes.value();
  if (!std::is_sorted(toggles.begin(), toggles.end()) ||
      std::adjacent_find(toggles.begin(), toggles.end()) != toggles.end())
    context.error(d_buttonTimes, "times must be strictly increasing");
  m_nanTimes = d_nanTimes.value();
  std::sort(m_nanTimes.begin(), m_nanTimes.end());
  m_nextNaN = 0;

  if (d_path.is("waypoints")) {
    buildWaypoints(context);
    return;
  }
  if (d_path.is("pokes")) {
    buildPokes(d, seed, context);
    return;
  }
  const auto aim = aimAt(Vec3::Zero(), context);
  if (!aim) return;
  if (d_path.is("approach-press-slide")) {
    buildApproachPressSlide(*aim, d);
  } else if (d_path.is("drill-in")) {
    buildDrillIn(*aim, d);
  } else if (d_path.is("circle")) {
    buildCircle(*aim, d);
  } else {
    buildRandomWalk(*aim, d, seed);
  }
}

void ScriptedDevice::prepare(const RunPlan& plan) {
  HapticDevice::prepare(plan);
  m_nextNaN = 0;
}

void ScriptedDevice::buildApproachPressSlide(const Aim& aim, const Vec3& d) {
  const double speed = d_speed.value();
  const Vec3 start = aim.surface - d * d_standoff.value();
  const Vec3 pressed = aim.surface + d * d_depth.value();
  Vec3 slide = d_slideDirection.value() - d_slideDirection->dot(aim.normal) * aim.normal;
  if (slide.norm() < 1e-9)
    slide = perpendicularBasis(aim.normal).first;  // slide direction along the normal: pick any tangent
  slide.normalize();
  const Vec3 slid = pressed + slide * d_slideDistance.value();
  const Vec3 end = slid - d * (d_depth.value() + d_standoff.value());
  m_path.start(start);
  m_path.hold(kSettle);
  m_path.moveTo(pressed, (pressed - start).norm() / speed);
  m_path.moveTo(slid, d_slideDistance.value() / speed);
  m_path.moveTo(end, (end - slid).norm() / speed);
  m_path.hold(kSettle);
}

void ScriptedDevice::buildDrillIn(const Aim& aim, const Vec3& d) {
  const Vec3 start = aim.surface - d * d_standoff.value();
  const Vec3 bottom = aim.surface + d * d_depth.value();
  m_path.start(start);
  m_path.hold(kSettle);
  m_path.moveTo(aim.surface, d_standoff.value() / d_speed.value());
  m_path.moveTo(bottom, std::abs(d_depth.value()) / d_feedSpeed.value());
  m_path.hold(0.5);
  m_path.moveTo(start, (start - bottom).norm() / d_speed.value());
  m_path.hold(kSettle);
}

void ScriptedDevice::buildCircle(const Aim& aim, const Vec3& d) {
  const auto [u, v] = perpendicularBasis(aim.normal);
  const Vec3 center = aim.surface + d * d_depth.value();
  const double r = d_radius.value(), period = d_period.value();
  const Vec3 first = center + r * u;
  const Vec3 start = first - d * (d_depth.value() + d_standoff.value());
  m_path.start(start);
  m_path.hold(kSettle);
  m_path.moveTo(first, (first - start).norm() / d_speed.value());
  const Vec3 uu = u, vv = v;
  // Eased in and out, so the circle starts and ends at rest like the moves around it.
  const double turning = d_turns.value() * period;
  const double ramp = std::min(kEaseTime, 0.5 * turning), total = turning + ramp;
  m_path.follow(total, [center, uu, vv, r, period, total, ramp](double s) {
    const double angle = 2.0 * std::numbers::pi * easedTime(s, total, ramp) / period;
    return Vec3(center + r * (std::cos(angle) * uu + std::sin(angle) * vv));
  });
  const Vec3 last = m_path.end();
  m_path.moveTo(last - d * (d_depth.value() + d_standoff.value()),
                (d_depth.value() + d_standoff.value()) / d_speed.value());
  m_path.hold(kSettle);
}

void ScriptedDevice::buildRandomWalk(const Aim& aim, const Vec3& d, uint64_t seed) {
  // Free-hand motion: a sum of slow sinusoids with seeded frequencies and
  // phases, in the tangent plane (amplitude `radius`) and along the approach
  // (between a light touch 0.25*depth above the surface and the full depth).
  SeededRandom random(seed);
  constexpr int kWaves = 4;
  struct Wave {
    double frequency, phase, weight;
  };
  std::array<std::array<Wave, kWaves>, 3> waves{};
  for (auto& axis : waves) {
    double total = 0;
    for (Wave& w : axis) {
      w = {random.uniform(0.05, 0.6), random.uniform(0.0, 2.0 * std::numbers::pi), random.uniform(0.3, 1.0)};
      total += w.weight;
    }
    for (Wave& w : axis) w.weight /= total;  // |sum| <= 1
  }
  const auto [u, v] = perpendicularBasis(aim.normal);
  const double r = d_radius.value(), depth = d_depth.value();
  const Vec3 surface = aim.surface;
  const Vec3 dd = d, uu = u, vv = v;
  const auto walk = [waves, surface, dd, uu, vv, r, depth](double s) {
    std::array<double, 3> value{};
    for (int a = 0; a < 3; ++a)
      for (const Wave& w : waves[a])
        value[a] += w.weight * std::sin(2.0 * std::numbers::pi * w.frequency * s + w.phase);
    const double press = depth * (0.375 + 0.625 * value[2]);  // from -0.25*depth to depth
    return Vec3(surface + r * (value[0] * uu + value[1] * vv) + press * dd);
  };
  const Vec3 first = walk(0.0);
  const Vec3 start = first - d * d_standoff.value();
  m_path.start(start);
  m_path.hold(kSettle);
  m_path.moveTo(first, d_standoff.value() / d_speed.value());
  // Eased in and out, so the walk starts and ends at rest like the moves around it.
  const double ramp = std::min(kEaseTime, 0.5 * d_walkDuration.value()), total = d_walkDuration.value() + ramp;
  m_path.follow(total, [walk, total, ramp](double s) { return walk(easedTime(s, total, ramp)); });
  const Vec3 last = m_path.end();
  m_path.moveTo(last - d * (depth + d_standoff.value()), (depth + d_standoff.value()) / d_speed.value());
  m_path.hold(kSettle);
}

bool ScriptedDevice::buildPokes(const Vec3& d, uint64_t seed, InitContext& context) {
  // Repeated pokes at seeded spots within `radius` of the aim point; each spot's
  // surface is found anew, so pokes follow a curved target.
  SeededRandom random(seed);
  const auto [u, v] = perpendicularBasis(d);
  const double speed = d_speed.value(), lift = d_lift.value(), depth = d_depth.value();
  bool first = true;
  for (int i = 0; i < d_count.value(); ++i) {
    const double radius = d_radius.value() * std::sqrt(random.uniform());
    const double angle = random.uniform(0.0, 2.0 * std::numbers::pi);
    const auto aim = aimAt(radius * (std::cos(angle) * u + std::sin(angle) * v), context);
    if (!aim) return false;
    const Vec3 above = aim->surface - d * lift;
    const Vec3 pressed = aim->surface + d * depth;
    if (first) {
      const Vec3 start = aim->surface - d * d_standoff.value();
      m_path.start(start);
      m_path.hold(kSettle);
      m_path.moveTo(above, (above - start).norm() / speed);
      first = false;
    } else {
      m_path.moveTo(above, std::max((above - m_path.end()).norm() / speed, 0.05));
    }
    m_path.moveTo(pressed, (lift + depth) / speed);
    m_path.hold(0.05);
    m_path.moveTo(above, (lift + depth) / speed);
  }
  m_path.moveTo(m_path.end() - d * (d_standoff.value() - lift), std::abs(d_standoff.value() - lift) / speed);
  m_path.hold(kSettle);
  return true;
}

bool ScriptedDevice::buildWaypoints(InitContext& context) {
  const std::vector<double>& w = d_waypoints.value();
  if (w.size() < 4 || w.size() % 4 != 0) {
    context.error(d_waypoints, "path=waypoints needs groups of four numbers 't x y z', got " +
                                   std::to_string(w.size()) + " numbers");
    return false;
  }
  for (size_t i = 4; i < w.size(); i += 4) {
    if (w[i] <= w[i - 4]) {
      context.error(d_waypoints, "waypoint times must increase (group " + std::to_string(i / 4 + 1) + ")");
      return false;
    }
  }
  m_path.start(Vec3(w[1], w[2], w[3]));
  m_path.hold(w[0]);
  for (size_t i = 4; i < w.size(); i += 4) {
    const Vec3 from = m_path.end(), to(w[i + 1], w[i + 2], w[i + 3]);
    const double duration = w[i] - w[i - 4];
    m_path.follow(duration, [from, to, duration](double s) { return Vec3(from + (to - from) * (s / duration)); });
  }
  return true;
}

uint32_t ScriptedDevice::buttonsAt(double t) const {
  const auto& toggles = d_buttonTimes.value();
  const size_t toggled = std::upper_bound(toggles.begin(), toggles.end(), t) - toggles.begin();
  return static_cast<uint32_t>(toggled % 2);
}

DeviceSample ScriptedDevice::readSample(double t) {
  DeviceSample sample{t, m_path.at(t), Quat::Identity(), buttonsAt(t)};
  if (m_nextNaN < m_nanTimes.size() && t >= m_nanTimes[m_nextNaN]) {
    while (m_nextNaN < m_nanTimes.size() && t >= m_nanTimes[m_nextNaN]) ++m_nextNaN;
    sample.position.x() = std::numeric_limits<double>::quiet_NaN();
  }
  return sample;
}

}  // namespace trephine::haptics
