#pragma once
// Builds the native back-end's grids again on the deformed shape, off the
// haptic thread, and hands them to the brain through a channel. The grids of
// the rest shape serve while the nodes stay within the displacement margin;
// beyond it every query widens and the haptic step grows with the
// deformation. This component follows the deformation's node positions in a
// rate group of its own and, when the nodes have drifted more than
// `threshold` times the margin from the shape the grids in use were built on,
// builds new ones on the current shape (allocating, on its own thread) and
// publishes them; the brain adopts them at the start of a haptic frame and
// measures the displacement from their shape, so the queries stay narrow
// whatever the deformation. For the native back-end only (the mesh back-ends
// refit their own trees): on another it does nothing, with a note at load,
// so that one scene runs on every back-end.
#include <optional>
#include <string>
#include <vector>

#include "framework/core/ChannelHub.h"
#include "framework/core/Component.h"
#include "framework/data/MeshDeformation.h"
#include "plugins/tetra_brain/TetGridSet.h"
#include "plugins/tetra_brain/TetraBrain.h"

namespace trephine::tetra {

class NativeTetBackend;

class TetGridRebuild final : public Component {
 public:
  static constexpr std::string_view kTypeName = "TetGridRebuild";

  void init(InitContext& context) override;
  void tick(const TickContext& context) override;
  void reportCounters(std::vector<Counter>& counters) const override;

 private:
  // Followed at init only: the ticks read the deformation's channel and the
  // mesh's constant topology, and hand the grids over through a channel.
  Link<TetraBrain> l_mesh{
      this, "mesh", {.help = "The brain whose grids this rebuilds", .required = true, .initOnly = true}};
  Field<double> d_threshold{this,
                            "threshold",
                            0.5,
                            {.help = "Rebuild when a node has moved this fraction of the displacement margin from "
                                     "the shape the grids were built on",
                             .min = 0.0,
                             .max = 1.0,
                             .minExclusive = true}};
  RateField d_rate{this, 100.0, "Rate of the check (a rebuild takes milliseconds: keep it off the haptic group)"};

  const TetMesh* m_mesh = nullptr;
  std::optional<ChannelReader<NodePositions>> m_positions;
  Channel<TetGridSet>* m_channel = nullptr;
  TetGridSet m_set;  // the grids last published (their reference is the shape the brain uses)
  const NativeTetBackend* m_native = nullptr;
  double m_margin = 0;
  uint64_t m_rebuilds = 0;
  bool m_idle = false;  // the brain's back-end is not the native one: nothing to rebuild
  double m_longestBuildMs = 0, m_largestDrift = 0;
};

}  // namespace trephine::tetra
