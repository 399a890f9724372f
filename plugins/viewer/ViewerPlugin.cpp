// Seeing a simulation: files ParaView opens, and the browser viewer of a run.
#include "framework/core/Registry.h"
#include "plugins/viewer/RunViewerData.h"
#include "plugins/viewer/VtkExporter.h"

TREPHINE_PLUGIN_ENTRY(registrar) {
  registrar.add<trephine::viewer::VtkExporter>(
      "VtkExporter",
      "Writes the brain, the skull and the tool as VTK XML files (.vtu, .vtp) at its own rate, with a .pvd that ParaView plays");
  // `trephine view`: the browser viewer and a run's data for it.
  registrar.addService<trephine::RunViewer>(trephine::viewer::makeRunViewer());
}
