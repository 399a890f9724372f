#pragma once
// The scenes of the tests of what follows a failure of the FEM: a 20 mm cube
// of 6^3 cells (1080 tetrahedra), its base held, pressed from above by a
// 2.5 mm probe (0.3 N/mm), its force on the few nodes under it (no forceSpread),
// which the cube cannot carry: the FEM (in its own group, as in the shipped
// scenes) diverges again and again.
#include <filesystem>
#include <string>

#include "plugins/tetra_brain/CubePhantom.h"
#include "framework/formats/mesh/MeditWriter.h"

namespace trephine::fem::scenes {

inline constexpr double kCubeSize = 20.0;  // mm, centred on the origin: its top at z = 10

// The cube as a Medit file, with one node no element holds at `stray` when asked.
inline std::filesystem::path writeCube(const std::filesystem::path& file, const Vec3* stray = nullptr) {
  TetMesh mesh = tetra::makeCubeMesh(6, kCubeSize);
  if (stray) mesh.nodes.push_back(*stray);
  formats::writeMeditMesh(mesh, file);
  return file;
}

// The coarse cube's elements all need mass for the 0.33 ms step (1.04 times
// the mesh's own): accepted here, where only the failures are studied.
inline std::string cubePressScene(const std::filesystem::path& mesh, const std::string& forceFeedback = "") {
  return R"(<Node name="root">
  <RequiredPlugin name="tetra_brain"/>
  <RequiredPlugin name="haptics"/>
  <RequiredPlugin name="fem"/>
  <TetraBrain name="brain" file=")" +
         mesh.string() + R"("/>
  <TLEDForceField name="fem" mesh="@brain" dt="0.33e-3" massScaling="true" maxAddedMass="1.1" forceSmoothing="0"
                  contactDamping="0" rate="1000" group="fem"/>
  <FixedConstraint name="base" fem="@fem" box="-200 -200 -200 200 200 -9"/>
  <ScriptedDevice name="device" record="false" path="drill-in" target="@brain" direction="0 0 -1" center="0 0 0"
                  tipOffset="2.5" standoff="5" speed="20" depth="5" feedSpeed="4"/>
  <PointshellTool name="probe" radius="2.5" angleStep="15" device="@device"/>
  <GodObjectProxy name="proxy" tool="@probe" target="@brain"/>
  <ForceFeedback name="force" proxy="@proxy" stiffness="0.3" damping="0.001" maxForce="3.3" )" +
         forceFeedback + R"(/>
</Node>)";
}

}  // namespace trephine::fem::scenes
