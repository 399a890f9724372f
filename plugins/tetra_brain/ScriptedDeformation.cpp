#include "plugins/tetra_brain/ScriptedDeformation.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "framework/core/Lifecycle.h"

namespace trephine::tetra {

void ScriptedDeformation::init(InitContext& context) {
  // A field the shape does not read would be silently ignored: refuse it.
  if (d_shape.is("wave") && d_radius.isSet()) context.error(d_radius, "has no effect with shape=\"wave\" (bump only)");
  if (d_shape.is("bump") && d_wavelength.isSet())
    context.error(d_wavelength, "has no effect with shape=\"bump\" (wave only)");
  const double length = d_direction.value().norm();
  if (!(length > 0) || !std::isfinite(length)) {
    context.error(d_direction, "the direction must be a non-zero vector");
    return;
  }
  m_unitDirection = d_direction.value() / length;
  m_wave = d_shape.is("wave");
  TetraBrain& brain = *l_mesh;
  m_rest = brain.mesh().nodes;
  m_profile.resize(m_rest.size());
  m_frame.positions = m_rest;
  const Vec3& c = d_center.value();
  if (m_wave) {
    for (size_t i = 0; i < m_rest.size(); ++i)
      m_profile[i] = 2 * std::numbers::pi * (m_rest[i] - c).norm() / d_wavelength.value();
    m_frame.allMoved = true;
  } else {
    const double R = d_radius.value();
    m_frame.allMoved = false;
    for (size_t i = 0; i < m_rest.size(); ++i) {
      const double s = (m_rest[i] - c).norm() / R;
      m_profile[i] = s < 1 ? (1 - s * s) * (1 - s * s) : 0.0;
      if (s < 1) m_frame.movedNodes.push_back(int32_t(i));
    }
  }
  m_frame.displacementBound = d_amplitude.value();
  m_channel = &context.channels().publish<NodePositions>(*this, kNodePositionsChannel);
  if (auto error = brain.followDeformation(*this, context.channels())) {
    context.error(l_mesh, *error);
    return;
  }
  m_channel->reserve(m_frame);  // slots as large as a frame: publishing never allocates
}

void ScriptedDeformation::tick(const TickContext& context) {
  const double A = d_amplitude.value();
  const double omega = 2 * std::numbers::pi / d_period.value();  // rad/s
  const Vec3 d = m_unitDirection;
  // The largest move since the frame before, for readers that bound a drift frame to frame.
  double largestMove = 0;
  auto place = [&](size_t i, const Vec3& p) {
    largestMove = std::max(largestMove, (p - m_frame.positions[i]).norm());
    m_frame.positions[i] = p;
  };
  if (m_wave) {
    const double phase = omega * context.t;
    for (size_t i = 0; i < m_rest.size(); ++i) place(i, m_rest[i] + (A * std::sin(m_profile[i] - phase)) * d);
  } else {
    const double s = A * std::sin(omega * context.t);
    for (int32_t i : m_frame.movedNodes) place(size_t(i), m_rest[i] + (s * m_profile[i]) * d);
  }
  m_frame.largestMove = largestMove;
  ++m_frame.step;
  m_channel->publish(m_frame);
}

void ScriptedDeformation::reportCounters(std::vector<Counter>& counters) const {
  counters.push_back({"published_steps", double(m_frame.step)});
  counters.push_back({"moved_nodes", double(m_frame.allMoved ? m_rest.size() : m_frame.movedNodes.size())});
}

}  // namespace trephine::tetra
