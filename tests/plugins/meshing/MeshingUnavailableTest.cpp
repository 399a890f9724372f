// Without the meshing plugin (a build with -DTREPHINE_WITH_MESHING=OFF, or
// an installation that leaves it out) every meshing call throws, naming what
// was asked for, what is missing and how to get it.
#include <gtest/gtest.h>

#include "framework/meshing/TetMeshing.h"
#include "tests/support/TestSupport.h"

namespace trephine {
namespace {

TEST(MeshingUnavailable, WithoutThePluginEveryMeshingCallSaysWhatIsMissing) {
  test::TempDir empty;
  for (const char* feature : {"meshing a solid into tetrahedra", "meshing a labelled image into tetrahedra"}) {
    try {
      tetMesherFrom({empty.path()}, feature);
      ADD_FAILURE() << "a mesher was found in an empty folder";
    } catch (const MeshingUnavailable& e) {
      const std::string text = e.what();
      EXPECT_NE(text.find(feature), std::string::npos) << text;
      EXPECT_NE(text.find("CGAL Mesh_3, GPL-3.0-or-later"), std::string::npos) << text;
      EXPECT_NE(text.find("-DTREPHINE_WITH_MESHING=ON"), std::string::npos) << text;
      EXPECT_NE(text.find("plugin 'meshing' not found"), std::string::npos) << text;
    }
  }
}

#ifdef TREPHINE_WITH_MESHING_PLUGIN
// The build's plugin is found on the default search path and meshes.
TEST(MeshingUnavailable, TheBuildsPluginIsLoadedOnDemand) {
  ASSERT_TRUE(meshingAvailable());
  const TetMesh ball = meshImplicitSolid(ballSolid(10), 1000);
  EXPECT_GT(ball.tetCount(), 500u);
}
#endif

}  // namespace
}  // namespace trephine
