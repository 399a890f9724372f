// The device bridge: real devices (and the emulator) drive a scene from
// another process or machine.
#include "framework/core/Registry.h"
#include "plugins/device_bridge/BridgeDevice.h"
#include "plugins/device_bridge/BridgeDeviceSide.h"

TREPHINE_PLUGIN_ENTRY(registrar) {
  registrar.add<trephine::device_bridge::BridgeDevice>(
      "BridgeDevice", "Haptic device driven from another process through the device bridge (shared memory or UDP)");
  registrar.add<trephine::device_bridge::BridgeDeviceSide>(
      "BridgeDeviceSide", "The device's end of the bridge: sends a device's poses, commands it the forces that come "
                          "back (with a HandDevice: the device emulator)");
}
