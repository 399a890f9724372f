// The plugin's one registration function: the program calls it after loading
// trephine_lissajous.so for <RequiredPlugin name="lissajous"/>.
#include "EllipsoidTool.h"
#include "LissajousDevice.h"
#include "framework/core/Registry.h"

TREPHINE_PLUGIN_ENTRY(registrar) {
  registrar.add<lissajous::LissajousDevice>("LissajousDevice", "Device tracing a Lissajous figure about a centre");
  registrar.add<lissajous::EllipsoidTool>("EllipsoidTool", "An ellipsoid sampled by a pointshell, moved by a device");
}
