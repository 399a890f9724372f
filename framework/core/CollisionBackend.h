#pragma once
// A collision back-end: the code that answers a target's geometric queries
// (contact, sweep, overlap) for the data the target component keeps (a
// density volume, a tetrahedral mesh). Back-ends register with the registry
// under a name for a kind of target, the target's component type
// ("VoxelSkull", "TetraBrain"); the target's `backend` field picks one, so
// the same scene runs on each. Each kind defines its own query interface,
// derived from this class, in the plugin that defines the target.
#include <vector>

namespace trephine {

struct Counter;  // Component.h

class CollisionBackend {
 public:
  virtual ~CollisionBackend() = default;
  // Figures for the target's entry in summary.json (added to the target's own).
  virtual void reportCounters(std::vector<Counter>& counters) const { (void)counters; }
};

}  // namespace trephine
