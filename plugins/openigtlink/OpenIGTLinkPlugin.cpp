// OpenIGTLink: trackers, robots, 3D Slicer and PLUS drive a scene.
#include "framework/core/Registry.h"
#include "plugins/openigtlink/IGTLinkDevice.h"
#include "plugins/openigtlink/IGTLinkExporter.h"

TREPHINE_PLUGIN_ENTRY(registrar) {
  registrar.add<trephine::openigtlink::IGTLinkDevice>(
      "IGTLinkDevice", "Haptic device whose pose comes as OpenIGTLink TRANSFORMs and whose force goes back as a SENSOR");
  registrar.add<trephine::openigtlink::IGTLinkExporter>(
      "IGTLinkExporter", "Streams the tool's and proxy's poses, the force, the drilled skull (IMAGE) and the brain's "
                         "surface (POLYDATA) to 3D Slicer's OpenIGTLinkIF");
}
