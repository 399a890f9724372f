// Analytic targets with exact geometry, for examples and ground truth.
#include "framework/core/Registry.h"
#include "plugins/analytic/AnalyticPlane.h"

TREPHINE_PLUGIN_ENTRY(registrar) {
  registrar.add<trephine::analytic::AnalyticPlane>("AnalyticPlane",
                                                   "Solid half-space bounded by a plane (exact distances)");
}
