#pragma once
// The god-object proxy of a pointshell tool against a ShellContactTarget. Each
// haptic frame:
//  1. sweep before moving: the proxy moves from its last position towards the
//     device until the target stops it (placed contactDepth into the target);
//  2. detection at that position: colliding shell points, contact normal and
//     raw penetration from the target (drilling happens here if the target drills);
//  3. god-object projection: the device is projected on the constraint plane
//     through the proxy (lifted out to the contact depth when the raw
//     penetration is deeper), so the proxy slides along the surface;
//  4. rectifying sweep from the proxy to that projection, so the new position
//     never crosses another part of the target;
//  5. penetration = the depth of the device below the constraint plane (the
//     device-proxy distance along the normal) plus the proxy's own contact depth;
//  6. on a target being drilled, the spring's anchor (the proxy lifted by that
//     depth) ends no farther from the device than last frame's anchor now is,
//     so the proxy's own moves never stretch the spring (PassiveAnchor.h:
//     passive at the sampled-data bound).
// In a crease, where this frame's projection would cross the last frame's
// constraint plane, the proxy goes to the nearest point on both planes (the
// god-object with two constraints, Zilles and Salisbury) and the force points
// from the device to it.
// When the sweep stopped the proxy but no shell point collides there (the two
// conflicting cases of the rigid method), the normal is against the sweep
// direction and the penetration is the device-proxy distance.
#include <optional>
#include <vector>

#include "framework/geometry/ShellContactTarget.h"
#include "plugins/haptics/ToolChange.h"

namespace trephine::haptics {

struct ProxyState {
  Vec3 device = Vec3::Zero();  // mm, tool reference point where the device puts it
  Vec3 proxy = Vec3::Zero();   // mm, displayed tool reference point
  Vec3 normal = Vec3::Zero();  // unit contact normal (out of the target); zero without contact
  double penetration = 0;      // mm, rendered depth
  double rawPenetration = 0;   // mm, as detected before rectification
  double overlap = 0;          // mm, depth of the displayed tool in the target (its contact skin)
  int points = 0;              // colliding shell points
  int primitives = 0;          // colliding voxels / tetrahedra
  int removed = 0;             // primitives the target lost at the start of this frame (every tool's cuts of the frame before)
  bool contact = false;
  bool cutting = false;      // the drill runs this frame (pedal held, or no pedal)
  bool proxyInside = false;  // the displayed proxy visibly overlaps the target
  bool deviceValid = false;
  // Let go after what shapes the target failed: the proxy is at the device and
  // no contact is rendered until the tool is clear of the target.
  bool released = false;
};

class GodObjectProxy final : public Component {
 public:
  static constexpr std::string_view kTypeName = "GodObjectProxy";

  void init(InitContext& context) override;
  void tick(const TickContext& context) override;
  void reportCounters(std::vector<Counter>& counters) const override;

  const ProxyState& state() const { return m_state; }
  // The tool and target of this frame (the next ones after a tool change).
  ShellTool& tool() const { return *m_tool; }
  bool changedTools() const { return m_changedTools; }
  bool hasToolChange() const { return bool(l_toolChange); }
  // What this frame's target takes (ShellContactTarget::respond, with the
  // tool's shell) once the force rendered to the user is known (N, on the
  // tool): its opposite onto the target (a deformable one passes it on to its
  // nodes) and, while the drill runs, the burr loaded against it, with what
  // this frame's collide() returned. Zero force without contact.
  ContactResponse response(const Vec3& forceOnTool_N, double t) const;
  ShellContactTarget& target() const { return *m_target; }

 private:
  // mm: how far the proxy may slide along its constraint plane this frame.
  double slideAllowance(const Vec3& device) const;
  // Neither the sweep from `from` to the device nor the tool at the device meets the target.
  bool nothingBetween(const Vec3& from, const Vec3& device, const Quat& orientation) const;
  SweepResult sweepPath(const Vec3& from, const Vec3& to, const Quat& orientation) const;
  void changeTools(const TickContext& context);
  void letGo(const TickContext& context);
  // While let go: the proxy at the device, until the tool is clear of the target.
  void followDevice(ProxyState& s, const Vec3& device, const Quat& orientation);

  Link<ShellTool> l_tool{this, "tool", {.help = "Pointshell tool moved by the device", .required = true}};
  Link<ShellContactTarget> l_target{this, "target", {.help = "What the tool collides with", .required = true}};
  EnumField d_sweep{this,
                    "sweep",
                    {"line", "cylinder", "spheres", "none"},
                    "line",
                    {.help = "How the path of the tool is swept before it moves: its leading point, a cylinder of "
                             "lines, the whole shell at steps, or not at all (the proxy jumps to the device)"}};
  Field<bool> d_rectify{
      this, "rectify", true, {.help = "Sweep again from the proxy to its god-object position before moving it"}};
  Field<bool> d_godObject{this,
                          "godObject",
                          true,
                          {.help = "Project the device on the constraint plane so the proxy slides on the surface "
                                   "(visual feedback); off keeps the proxy where the sweep left it"}};
  Field<int> d_drillButton{this,
                           "drillButton",
                           0,
                           {.help = "0: the tool cuts whenever the target can be drilled; n: only while device "
                                    "button n is held (a foot pedal)",
                            .min = 0.0,
                            .max = 32.0}};
  Link<ToolChange> l_toolChange{
      this,
      "toolChange",
      {.help = "From this tool change on, the proxy moves nextTool against nextTarget (the procedure's next phase)"}};
  Link<ShellTool> l_nextTool{
      this, "nextTool", {.help = "The tool after the change (the same device's); unset keeps the tool"}};
  Link<ShellContactTarget> l_nextTarget{
      this, "nextTarget", {.help = "What the tool collides with after the change; unset keeps the target"}};
  RateField d_rate{this, 1000.0, "Haptic rate"};

  ShellTool* m_tool = nullptr;        // l_tool, then l_nextTool
  ShellContactTarget* m_target = nullptr;  // l_target, then l_nextTarget
  bool m_changedTools = false;

  // d_sweep, read once at init: the probe, or none.
  SweepProbe m_probe = SweepProbe::Line;
  bool m_sweeps = true;
  ProxyState m_state;
  // This frame's answer of collide() (its spans: until the next one) and the
  // point where a sweep stopped a cutting tool between its shell points: what
  // response() gives the target.
  ShellContact m_frameContact;
  std::optional<Vec3> m_stoppedAt;
  Vec3 m_lastNormal = Vec3::Zero();
  Vec3 m_lastDevice = Vec3::Zero();  // mm, the device's point last frame
  bool m_hadDevice = false;
  bool m_heldBack = false;  // last frame's sweep towards the device was held to the plane
  // This frame's and the last frame's constraint plane (a point on it and its normal).
  Vec3 m_planePoint = Vec3::Zero(), m_planeNormal = Vec3::Zero(), m_lastPlanePoint = Vec3::Zero();
  bool m_hasPlane = false, m_hadPlane = false;
  bool m_started = false;
  uint64_t m_blockedSweeps = 0, m_conflictFrames = 0, m_degenerateNormals = 0, m_contactFrames = 0, m_creaseFrames = 0,
           m_nonFiniteFrames = 0;
  uint64_t m_releasedHolds = 0;      // frames a hold to last frame's plane found no surface and let the proxy go
  uint64_t m_seenShapeFailures = 0;  // the target's shapeFailures() last seen
  bool m_released = false;           // let go after a shape failure, until the tool is clear
  uint64_t m_releases = 0;           // times the proxy was let go after a shape failure
  uint64_t m_heldAnchors = 0;        // frames whose anchor was held to the last one's distance from the device
};

}  // namespace trephine::haptics
