// The meshing plugin registers no component: it provides the framework's
// TetMesher, which tetMesher() loads on demand (the brain and sphere
// phantoms, `trephine mesh`).
#include "framework/core/Registry.h"
#include "plugins/meshing/CgalMesher.h"

TREPHINE_PLUGIN_ENTRY(registrar) { registrar.addService<trephine::TetMesher>(trephine::meshing::makeCgalTetMesher()); }
