// From images to a running scene, as scenes/patient/README.md walks a user
// through it: a head CT as a DICOM series in Hounsfield units and a
// segmentation of its brain (the head phantoms stand in for a patient's
// images), the segmentation meshed with its labels, and the patient template
// run on both with VoxelSkull's defaults: the burr cuts through the bone
// and reaches the brain, whose two labels load with their own materials.
#include <gtest/gtest.h>

#include "tests/support/TestSupport.h"

namespace trephine {
namespace {

using test::runProgram;

TEST(PatientSceneTest, ACtSeriesAndASegmentationRunWithoutTuning) {
  test::TempDir dir;
  std::string out;
  const std::string ct = (dir / "ct").string() + "/", labels = (dir / "labels.mha").string(),
                    brain = (dir / "brain.mesh").string(), run = (dir / "run").string();
  ASSERT_EQ(runProgram({"phantom", "head?voxel=1.5", "--out", ct}, &out), 0) << out;
  EXPECT_NE(out.find("values -1000 to"), std::string::npos) << out;  // Hounsfield units
  ASSERT_EQ(runProgram({"phantom", "head-labels?voxel=1.5", "--out", labels}, &out), 0) << out;
  ASSERT_EQ(runProgram({"mesh", labels, "--labels", "1,2", "--tets", "6000", "--out", brain}, &out), 0) << out;
  const std::string scene = (test::sourceDir() / "scenes/patient/patient.xml").string();
  ASSERT_EQ(runProgram({"run", scene, "--set", "patient/skull.file=" + ct, "--set", "patient/brain.file=" + brain,
                        "--out", run},
                       &out),
            0)
      << out;
  const std::string summary = test::readFile(dir / "run" / "summary.json");
  EXPECT_NE(summary.find("\"complete\": true"), std::string::npos) << summary.substr(0, 400);
  EXPECT_NE(summary.find("\"nan_frames\": 0"), std::string::npos);
  // The bone was cut through (a breakthrough), and the burr then reached the brain.
  EXPECT_NE(summary.find("\"kind\": \"breakthrough\""), std::string::npos) << out;
  EXPECT_NE(summary.find("\"kind\": \"contact_warning\""), std::string::npos) << out;
  EXPECT_EQ(summary.find("\"voxels_removed\": 0,"), std::string::npos) << out;
  // Without the inputs the template says what it needs.
  EXPECT_EQ(runProgram({"validate", scene}, &out), 1) << out;
  EXPECT_NE(out.find("missing required file of VoxelSkull 'skull'"), std::string::npos) << out;
  EXPECT_NE(out.find("missing required file of TetraBrain 'brain'"), std::string::npos) << out;
}

}  // namespace
}  // namespace trephine
