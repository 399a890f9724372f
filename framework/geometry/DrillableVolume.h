#pragma once
// A density volume that a drill lowers in place (VoxelSkull): what an
// exporter of its surface reads. It copies the codes once, at its init, and
// then follows the changes the volume records for it (VoxelEdit on a
// ChangeQueue, drained on its own thread), so it never reads the codes
// while the haptic loop lowers them.
#include <memory>
#include <string_view>

#include "framework/channels/ChangeQueue.h"
#include "framework/core/Interface.h"
#include "framework/data/VoxelGrid.h"

namespace trephine {

class TREPHINE_INTERFACE DrillableVolume {
 public:
  static constexpr std::string_view kTypeName = "DrillableVolume";
  virtual ~DrillableVolume();

  // The codes on their grid, valid from the end of the volume's init(); the
  // codes are the volume's own, lowered in place while it drills.
  virtual const VoxelGrid& voxelGrid() const = 0;
  // Whether the scene drills this volume (its codes may change).
  virtual bool drills() const = 0;
  // Every code change from now on goes to `edits` as well (each reader gives
  // a queue of its own: an exporter, a rebuild of a back-end's surface). Call
  // it in init(), before the first frame.
  virtual void recordEdits(std::shared_ptr<ChangeQueue<VoxelEdit>> edits) = 0;
};

}  // namespace trephine
