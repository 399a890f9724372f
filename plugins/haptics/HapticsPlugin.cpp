// Devices, tools and force rendering.
#include "framework/core/Registry.h"
#include "plugins/haptics/CapsuleTool.h"
#include "plugins/haptics/ContactWarning.h"
#include "plugins/haptics/ForceFeedback.h"
#include "plugins/haptics/GodObjectProxy.h"
#include "plugins/haptics/HandDevice.h"
#include "plugins/haptics/PointshellTool.h"
#include "plugins/haptics/ReplayDevice.h"
#include "plugins/haptics/ScriptedDevice.h"
#include "plugins/haptics/SphereTool.h"
#include "plugins/haptics/SpringForce.h"
#include "plugins/haptics/TissueTools.h"
#include "plugins/haptics/ToolChange.h"

TREPHINE_PLUGIN_ENTRY(registrar) {
  using namespace trephine::haptics;
  registrar.add<ReplayDevice>("ReplayDevice", "Replays a recorded device stream (CSV t,x,y,z,qw,qx,qy,qz,buttons)");
  registrar.add<ScriptedDevice>(
      "ScriptedDevice", "Scripted tool motion: approach-press-slide, drill-in, circle, random-walk, pokes, waypoints");
  registrar.add<HandDevice>("HandDevice",
                            "Simulated hand holding the device: follows a ScriptedDevice's path through a grip "
                            "spring-damper, moved by the rendered force (closed loop)");
  registrar.add<SphereTool>("SphereTool", "Sphere tool following a device");
  registrar.add<PointshellTool>("PointshellTool", "Spherical burr covered by a pointshell (angle-step or even points)");
  registrar.add<CapsuleTool>("CapsuleTool", "Spherical burr on a cylindrical shaft, covered by a pointshell");
  registrar.add<AspiratorTool>("AspiratorTool",
                               "Ultrasonic aspirator on a tube: removes the brain tissue it touches while its pedal "
                               "is held, at a rate its power, the contact force and the tissue set");
  registrar.add<BipolarForceps>("BipolarForceps",
                                "Bipolar forceps: coagulates the brain tissue it touches while its pedal is held "
                                "(coagulated tissue does not bleed when removed)");
  registrar.add<GodObjectProxy>("GodObjectProxy",
                                "God-object proxy of a pointshell tool: sweep, detection, constraint-plane projection");
  registrar.add<ForceFeedback>("ForceFeedback", "Viscoelastic force F = k p n - b (v.n) n of a proxy contact");
  registrar.add<ToolChange>("ToolChange",
                            "The moment a procedure changes tools (a time or a device button): proxies move on to "
                            "their next tool and target");
  registrar.add<ContactWarning>("ContactWarning",
                                "Logs a contact_warning event when a proxy's tool touches a target it must not "
                                "(the burr reaching the brain), with no force");
  registrar.add<SpringForce>("SpringForce", "Penalty spring-damper force of a sphere tool against an implicit surface");
}
