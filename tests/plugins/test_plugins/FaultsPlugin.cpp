// Components that misbehave on purpose, to test how runs report it.
#include <chrono>
#include <stdexcept>
#include <thread>

#include "framework/core/Component.h"
#include "framework/core/Registry.h"
#include "plugins/tetra_brain/TetBackend.h"
#include "plugins/voxel_skull/VoxelBackend.h"

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

// What the throwing back-ends' rays hit: a floor through the origin, so that
// scripted devices find a surface.
std::optional<trephine::SurfaceHit> floorHit(const trephine::Vec3& origin, const trephine::Vec3& direction) {
  if (!(direction.z() < 0)) return std::nullopt;
  const double s = -origin.z() / direction.z();
  return trephine::SurfaceHit{origin + s * direction, trephine::Vec3::UnitZ(), s};
}

// What both throwing back-ends answer besides contacts: nothing near, and
// rays that hit the floor; `countContact()` throws at the 100th contact
// query (as a third-party library might): the target must end the run
// naming itself.
template <class Backend>
class ThrowingBackend : public Backend {
 public:
  void reserveShell(std::span<const trephine::ShellPoint>) override {}
  size_t broadPhase(const trephine::Pose&, std::span<const trephine::ShellPoint>) override { return 0; }
  trephine::SweepResult sweep(const trephine::SweepQuery&) const override { return {}; }
  bool overlaps(const trephine::Pose&, std::span<const trephine::ShellPoint>) const override { return false; }
  std::optional<trephine::SurfaceHit> raycast(const trephine::Vec3& origin, const trephine::Vec3& direction,
                                              double) const override {
    return floorHit(origin, direction);
  }

 protected:
  void countContact() {
    if (++m_calls == 100) throw std::runtime_error("deliberate back-end failure");
  }

 private:
  int m_calls = 0;
};

class ThrowingVoxelBackend final : public ThrowingBackend<trephine::voxel::VoxelBackend> {
 public:
  void bind(const trephine::voxel::VoxelData&) override {}
  trephine::voxel::VoxelContact collide(const trephine::Pose&, std::span<const trephine::ShellPoint>, bool) override {
    countContact();
    return {};
  }
};

class ThrowingTetBackend final : public ThrowingBackend<trephine::tetra::TetBackend> {
 public:
  void bind(const trephine::tetra::TetData&) override {}
  size_t siteCapacity() const override { return 0; }
  void moveNodes(const trephine::tetra::NodeFrame&) override {}
  trephine::tetra::TetContact collide(const trephine::Pose&, std::span<const trephine::ShellPoint>, bool,
                                      int32_t&) override {
    countContact();
    return {};
  }
};

}  // namespace

TREPHINE_PLUGIN_ENTRY(registrar) {
  registrar.addBackend<ThrowingVoxelBackend>("VoxelSkull", "throwing", "Throws from its 100th contact query");
  registrar.addBackend<ThrowingTetBackend>("TetraBrain", "throwing", "Throws from its 100th contact query");
  registrar.add<ThrowingComponent>("ThrowingComponent", "Throws from its tick");
  registrar.add<SlowComponent>("SlowComponent", "Spends a set time per call");
}
