#include "plugins/fem/Gravity.h"

#include "framework/core/Lifecycle.h"

namespace trephine::fem {

void Gravity::init(InitContext& context) {
  if (!d_acceleration.value().allFinite()) {
    context.error(d_acceleration, "must be finite");
    return;
  }
  if (l_fem->hasModel()) l_fem->model().setBodyAcceleration(d_acceleration.value());
}

}  // namespace trephine::fem
