// Components that misbehave on purpose, to test how runs report it.
#include <chrono>
#include <stdexcept>
#include <thread>

#include "framework/core/Component.h"
#include "framework/core/Registry.h"

namespace {

// Throws from its tick at `failAt` s (a tick must not throw; the run must
// still end cleanly and say which component failed).
class ThrowingComponent final : public trephine::Component {
 public:
  void tick(const trephine::TickContext& context) override {
    if (context.t >= d_failAt.value()) throw std::runtime_error("deliberate failure");
  }

 private:
  trephine::RateField d_rate{this, 1000.0};
  trephine::Field<double> d_failAt{this, "failAt", 0.5, {.help = "When to throw", .unit = "s"}};
};

// Busy for `busy` s every call: longer than its period means a deadline miss.
class SlowComponent final : public trephine::Component {
 public:
  void tick(const trephine::TickContext&) override {
    const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(d_busy.value());
    while (std::chrono::steady_clock::now() < until) {
    }
  }

 private:
  trephine::RateField d_rate{this, 1000.0};
  trephine::Field<double> d_busy{this, "busy", 0.002, {.help = "Time spent per call", .unit = "s"}};
};

}  // namespace

TREPHINE_PLUGIN_ENTRY(registrar) {
  registrar.add<ThrowingComponent>("ThrowingComponent", "Throws from its tick");
  registrar.add<SlowComponent>("SlowComponent", "Spends a set time per call");
}
