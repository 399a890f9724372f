#include "framework/core/FramePacer.h"

namespace trephine {

// The key function: FramePacer's type information lives in trephine_core.
FramePacer::~FramePacer() = default;

}  // namespace trephine
