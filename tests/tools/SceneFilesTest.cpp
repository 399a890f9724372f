// Every scene shipped in scenes/ loads and runs a few steps (the patient
// template, whose inputs come from the user, runs in PatientSceneTest).
#include <gtest/gtest.h>

#include "tests/support/TestSupport.h"

namespace trephine {
namespace {

std::vector<std::filesystem::path> sceneFiles() {
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(test::sourceDir() / "scenes"))
    if (entry.path().extension() == ".xml" && entry.path().parent_path().filename() != "parts" &&
        entry.path().parent_path().filename() != "patient")
      files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  return files;
}

class SceneFileTest : public testing::TestWithParam<std::filesystem::path> {};

TEST_P(SceneFileTest, LoadsAndRunsAFewSteps) {
  const std::filesystem::path& file = GetParam();
  // Scenes on the shared real data skip when that data is not present.
  if (test::readFile(file).find("shared/data") != std::string::npos &&
      !std::filesystem::exists(test::sourceDir() / "../shared/data"))
    GTEST_SKIP() << file << " needs ../shared/data, which is absent";
  Diagnostics diagnostics;
  SimulationOptions options;
  options.duration = 0.05;
  auto simulation = Simulation::fromFile(file, options, diagnostics);
  ASSERT_TRUE(simulation) << test::messages(diagnostics);
  simulation->run();
  EXPECT_TRUE(simulation->complete()) << simulation->incompleteReason();
  EXPECT_EQ(simulation->hapticLog().stats().nanFrames, 0u);
}

INSTANTIATE_TEST_SUITE_P(
    Scenes, SceneFileTest, testing::ValuesIn(sceneFiles()),
    [](const testing::TestParamInfo<std::filesystem::path>& info) {
      std::string name =
          std::filesystem::relative(info.param, test::sourceDir() / "scenes").replace_extension().string();
      for (char& c : name)
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
      return name;
    });

}  // namespace
}  // namespace trephine
