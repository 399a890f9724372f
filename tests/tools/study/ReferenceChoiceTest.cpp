// Which setting of a study is the reference without an exact shape: the
// finest in every target and tool; a coarser one only when asked for so.
#include <gtest/gtest.h>

#include <filesystem>

#include "tools/trephine/study/ReferenceChoice.h"

namespace trephine::study {
namespace {

// Settings varying the skull's voxels (1, 0.5 mm) and the back-end (native, embree).
struct Study {
  std::vector<StudySetting> settings;
  std::vector<SettingResolution> resolutions;
};

Study voxelsAndBackends(bool exact = false) {
  std::string error;
  const auto voxels = parseVariation("/patient/skull.voxel=1,0.5", error);
  const auto backend = parseVariation("/patient/skull.backend=native,embree", error);
  Study study;
  study.settings = expandSettings({*voxels, *backend});
  for (const double voxel : {1.0, 1.0, 0.5, 0.5}) {
    SettingResolution r;
    r.loaded = true;
    r.exactEverywhere = exact;
    r.sizes = {{"the target /patient/skull", voxel}, {"the shell of /tool/burr", 0.4}};
    study.resolutions.push_back(r);
  }
  return study;
}

TEST(ReferenceChoiceTest, TheFinestSettingIsTheReferenceAndTheReportSaysWhy) {
  const Study study = voxelsAndBackends();
  const ReferenceChoice choice = chooseReference(study.settings, study.resolutions, std::nullopt, false);
  EXPECT_TRUE(choice.error.empty()) << choice.error;
  EXPECT_EQ(choice.index, 2) << "the first setting with 0.5 mm voxels";
  EXPECT_EQ(choice.reason, "the finest (the target /patient/skull 0.5 mm, the shell of /tool/burr 0.4 mm)");
  // Asked for, the other finest one (another back-end at the same voxels) is taken.
  EXPECT_EQ(chooseReference(study.settings, study.resolutions, 3, false).index, 3);
}

TEST(ReferenceChoiceTest, ACoarserReferenceIsRefusedUnlessAskedForSo) {
  const Study study = voxelsAndBackends();
  const ReferenceChoice refused = chooseReference(study.settings, study.resolutions, 0, false);
  EXPECT_EQ(refused.error,
            "the reference setting 1 (voxel=1, backend=native) is coarser than setting 3 (voxel=0.5, backend=native): "
            "the target /patient/skull 1 mm against 0.5 mm; against it the finer settings would be measured by its "
            "own error. Use --reference 3, or --coarse-reference to compare against setting 1 anyway");
  const ReferenceChoice allowed = chooseReference(study.settings, study.resolutions, 0, true);
  EXPECT_TRUE(allowed.error.empty());
  EXPECT_EQ(allowed.index, 0);
  EXPECT_NE(allowed.reason.find("coarser than setting 3"), std::string::npos) << allowed.reason;
}

TEST(ReferenceChoiceTest, AgainstAnExactShapeSettingOneGivesThePoses) {
  const Study study = voxelsAndBackends(true);
  const ReferenceChoice choice = chooseReference(study.settings, study.resolutions, std::nullopt, false);
  EXPECT_EQ(choice.index, 0);
  EXPECT_TRUE(choice.error.empty() && choice.reason.empty());
  EXPECT_TRUE(chooseReference(study.settings, study.resolutions, 1, false).error.empty()) << "any may be asked for";
}

TEST(ReferenceChoiceTest, SettingsAlikeOrTradingOneSizeForAnotherAreSaidSo) {
  Study study = voxelsAndBackends();
  for (SettingResolution& r : study.resolutions) r.sizes[0].second = 0.7;  // only the back-end varies
  const ReferenceChoice alike = chooseReference(study.settings, study.resolutions, std::nullopt, false);
  EXPECT_EQ(alike.index, 0);
  EXPECT_EQ(alike.reason, "every setting resolving its targets and tools alike");
  // Finer voxels with a coarser shell, and the other way round: neither is the finest.
  study.resolutions[0].sizes = {{"the target /patient/skull", 0.5}, {"the shell of /tool/burr", 0.6}};
  study.resolutions[1].sizes = {{"the target /patient/skull", 1.0}, {"the shell of /tool/burr", 0.3}};
  study.resolutions.resize(2);
  study.settings.resize(2);
  const ReferenceChoice none = chooseReference(study.settings, study.resolutions, std::nullopt, false);
  EXPECT_NE(none.error.find("no setting resolves every target and tool finest"), std::string::npos) << none.error;
  EXPECT_TRUE(chooseReference(study.settings, study.resolutions, 1, true).error.empty());
  // A setting that does not load takes no part (its run reports why).
  study = voxelsAndBackends();
  study.resolutions[2].loaded = study.resolutions[3].loaded = false;
  EXPECT_EQ(chooseReference(study.settings, study.resolutions, std::nullopt, false).index, 0);
}

// Each setting is described in a process of its own, through a file: what
// is written is read back, a missing file is a setting that did not load,
// with the reason.
TEST(ReferenceChoiceTest, ADescriptionSurvivesItsFileAndAMissingOneSaysWhy) {
  const std::filesystem::path file = std::filesystem::temp_directory_path() / "trephine-resolution-test.txt";
  SettingResolution written;
  written.loaded = true;
  written.exactEverywhere = false;
  written.sizes = {{"the target /patient/skull", 0.7}, {"the shell of /tool/a, b", 0.123456789012345}};
  writeSettingResolution(written, file);
  const SettingResolution read = readSettingResolution(file);
  EXPECT_TRUE(read.loaded);
  EXPECT_FALSE(read.exactEverywhere);
  EXPECT_EQ(read.sizes, written.sizes);
  SettingResolution failed;
  failed.loadError = "scene.xml:3: no component Foo\nscene.xml:4: another\n";
  writeSettingResolution(failed, file);
  EXPECT_FALSE(readSettingResolution(file).loaded);
  EXPECT_EQ(readSettingResolution(file).loadError, failed.loadError);
  std::filesystem::remove(file);
  const SettingResolution missing = readSettingResolution(file);
  EXPECT_FALSE(missing.loaded);
  EXPECT_NE(missing.loadError.find("was not written"), std::string::npos) << missing.loadError;
}

}  // namespace
}  // namespace trephine::study
