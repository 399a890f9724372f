#pragma once
// Rebuilds a drilled skull's surface for a mesh back-end (embree, bullet)
// off the haptic thread. Without it, a frame that cuts re-extracts the
// blocks it changed and rebuilds them and the library's structure over
// every block, in the haptic frame: milliseconds on a CT. With it, the
// back-end keeps a second copy of its surface (MeshVoxelBackend.h), and this
// component, in a rate group of its own:
//  - follows the skull's code changes (a copy of the codes of its own, fed
//    by the skull's edits, so it never reads the codes the haptic loop
//    lowers) and marks the blocks they touch in both copies;
//  - when the haptic loop has adopted the copy published last, brings the
//    other copy up to date (re-extracts and rebuilds its marked blocks) and
//    publishes it; the skull adopts it at the start of a frame
//    (SurfaceHandover.h).
// The tools then meet a surface that lags the drill by up to one period of
// this component plus one rebuild (a few ms on a CT at 0.5 mm): at 100 Hz
// and the removal law's cap of 20 mm/s, at most about 0.3 mm, and some
// 0.02 mm at the feeds a desktop device's forces give (about 1 mm/s).
// On the native back-end (it reads the codes themselves) and on a skull
// that does not drill, it does nothing, with a note at load, so that one
// scene runs on every back-end.
#include <array>
#include <memory>
#include <optional>
#include <vector>

#include "framework/channels/ChangeQueue.h"
#include "framework/core/ChannelHub.h"
#include "framework/core/Component.h"
#include "plugins/voxel_skull/SurfaceHandover.h"
#include "plugins/voxel_skull/VoxelSkull.h"

namespace trephine::voxel {

class SkullSurfaceRebuild final : public Component {
 public:
  static constexpr std::string_view kTypeName = "SkullSurfaceRebuild";

  void init(InitContext& context) override;
  void tick(const TickContext& context) override;
  void finish(FinishContext& context) override;
  void reportCounters(std::vector<Counter>& counters) const override;

 private:
  // Followed at init only: the ticks read the skull's edits and the
  // back-end's idle copy, and hand the copies over through channels.
  Link<VoxelSkull> l_skull{
      this, "skull", {.help = "The drilled skull whose mesh back-end's surface this rebuilds", .required = true,
                      .initOnly = true}};
  RateField d_rate{this, 100.0,
                   "Rate of the rebuild (a rebuild takes milliseconds: keep it off the haptic group); the surface "
                   "the tools meet lags the drill by up to one period"};

  // The codes' edits since the last tick into this component's own codes;
  // marks the blocks they touch in both copies.
  void followEdits();

  MeshVoxelBackend* m_backend = nullptr;
  std::shared_ptr<ChangeQueue<VoxelEdit>> m_edits;
  std::vector<VoxelCode> m_codes;  // this component's copy of the skull's codes
  SolidGrid m_grid;                // over m_codes, with occupancy cells of its own
  std::array<std::vector<uint8_t>, 2> m_dirty;  // per copy, per block: changed since that copy was rebuilt
  std::vector<size_t> m_blocks;                 // the idle copy's marked blocks (reused)
  Channel<SurfaceCopy>* m_ready = nullptr;
  std::optional<ChannelReader<SurfaceCopy>> m_inUse;
  SurfaceCopy m_published;  // the copy published last (version 0: the back-end's own)
  bool m_idle = false;
  uint64_t m_rebuilds = 0, m_editsFollowed = 0;
  double m_longestRebuildMs = 0, m_rebuildMs = 0;
};

}  // namespace trephine::voxel
