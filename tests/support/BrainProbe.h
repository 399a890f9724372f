#pragma once
// The probe the brain tests press with: a 2.5 mm pointshell on a scripted
// device pointing down (-z) at the brain /patient/brain, its proxy and force
// at 1 kHz with the brain's stiffness of the thesis (0.3 N/mm, 3.3 N at most).
#include <string>

namespace trephine::test {

// The scene's <Node name="tool">. `deviceFields`: the path and where it goes
// (path, center, standoff, depth; mm, mm/s); `proxyFields`: more of the
// proxy's (sweep="line", say).
inline std::string brainProbeNode(const std::string& deviceFields, const std::string& proxyFields = "") {
  return R"(<Node name="tool">
    <ScriptedDevice name="device" target="@/patient/brain" direction="0 0 -1" tipOffset="2.5" rate="1000"
                    )" +
         deviceFields + R"(/>
    <PointshellTool name="probe" radius="2.5" angleStep="15" device="@device"/>
    <GodObjectProxy name="proxy" tool="@probe" target="@/patient/brain" )" +
         (proxyFields.empty() ? "" : proxyFields + " ") + R"(rate="1000"/>
    <ForceFeedback name="force" proxy="@proxy" stiffness="0.3" damping="0.001" maxForce="3.3" rate="1000"/>
  </Node>)";
}

}  // namespace trephine::test
