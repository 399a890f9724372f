// A build without the meshing plugin (-DTREPHINE_WITH_MESHING=OFF) links
// MeshingUnavailable.cpp in its place: every meshing function throws,
// naming what is missing and how to get it.
#include <gtest/gtest.h>

#include "plugins/meshing/ImplicitMesher.h"
#include "plugins/meshing/LabelledImageMesher.h"
#include "plugins/meshing/Meshing.h"

namespace trephine::tetra {
namespace {

void expectMissing(const std::function<void()>& call, const std::string& feature) {
  try {
    call();
    ADD_FAILURE() << "no error for " << feature;
  } catch (const MeshingUnavailable& e) {
    const std::string text = e.what();
    EXPECT_NE(text.find(feature), std::string::npos) << text;
    EXPECT_NE(text.find("CGAL Mesh_3, GPL-3.0-or-later"), std::string::npos) << text;
    EXPECT_NE(text.find("-DTREPHINE_WITH_MESHING=ON"), std::string::npos) << text;
  }
}

TEST(MeshingUnavailable, EveryMeshingFunctionSaysWhatIsMissing) {
  EXPECT_FALSE(meshingBuilt());
  expectMissing([] { meshImplicitSolid(ballSolid(10), 1000); }, "meshing a solid");
  expectMissing([] { meshImplicitSolidAtSize(ballSolid(10), 2); }, "meshing a solid");
  LabelledImage image;
  expectMissing([&] { meshLabelledImage(image, 1000); }, "meshing a labelled image");
  expectMissing([&] { meshLabelledImageAtSize(image, 2); }, "meshing a labelled image");
}

}  // namespace
}  // namespace trephine::tetra
