#pragma once
// The cheapest possible ticking component, so a benchmark measures the
// scheduler around the call rather than the work inside it.
#include <cstdint>

#include "framework/core/Component.h"

namespace trephine::bench {

class TrivialComponent final : public Component {
 public:
  explicit TrivialComponent(double rateHz) { d_rate.setValue(rateHz); }
  void tick(const TickContext& context) override { m_lastFrame = context.frame; }
  uint64_t lastFrame() const { return m_lastFrame; }

 private:
  RateField d_rate{this, 1000.0};
  uint64_t m_lastFrame = 0;
};

}  // namespace trephine::bench
