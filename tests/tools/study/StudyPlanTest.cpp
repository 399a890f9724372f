// The settings of a study: parsing of --vary and the cartesian product.
#include <gtest/gtest.h>

#include "tools/trephine/study/StudyPlan.h"

namespace trephine::study {
namespace {

TEST(StudyPlanTest, TheProductVariesTheFirstFieldSlowest) {
  std::string error;
  const auto backend = parseVariation("/patient/skull.backend=native,embree", error);
  const auto file = parseVariation("/patient/skull.file=phantom:skull?voxel=1.5,phantom:skull?voxel=1&x=2", error);
  ASSERT_TRUE(backend && file) << error;
  EXPECT_EQ(file->values[1], "phantom:skull?voxel=1&x=2") << "'=' and '&' in a value are kept";
  const auto settings = expandSettings({*backend, *file});
  ASSERT_EQ(settings.size(), 4u);
  EXPECT_EQ(settings[1].index, 1);
  EXPECT_EQ(settings[1].overrides(), (std::vector<std::string>{"/patient/skull.backend=native",
                                                               "/patient/skull.file=phantom:skull?voxel=1&x=2"}));
  EXPECT_EQ(settings[2].label(), "backend=embree, file=phantom:skull?voxel=1.5");
  EXPECT_EQ(settings[3].directoryName(), "settings/004");
}

TEST(StudyPlanTest, MalformedVariationsSayWhatIsExpected) {
  std::string error;
  EXPECT_FALSE(parseVariation("backend=native", error));
  EXPECT_NE(error.find("path.field"), std::string::npos) << error;
  EXPECT_FALSE(parseVariation("/a/b.c", error));
  EXPECT_NE(error.find("expects"), std::string::npos) << error;
  EXPECT_FALSE(parseVariation("/a/b.c=1,,2", error));
  EXPECT_NE(error.find("empty value"), std::string::npos) << error;
  EXPECT_FALSE(parseVariation("/a/b.c=1,2,1", error));
  EXPECT_NE(error.find("twice"), std::string::npos) << error;
  EXPECT_FALSE(parseVariation("/a/b.c=", error));
}

}  // namespace
}  // namespace trephine::study
