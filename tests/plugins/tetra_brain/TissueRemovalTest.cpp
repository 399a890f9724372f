// The removal law of a resected brain against its closed forms: an
// aspirator's power min(rated, coupling F 4 A f) shared among the touched
// tetrahedra removes one when its energy reaches volume x removal energy (the
// frame is computed here from the formula); a critical tissue is never
// removed and its contact time is counted; coagulated tissue does not bleed,
// uncoagulated tissue loses volume x vascularity.
#include <gtest/gtest.h>

#include <cmath>

#include "plugins/tetra_brain/TissueRemoval.h"

namespace trephine::tetra {
namespace {

// Two tetrahedra of known volume (1000/6 mm^3 each): labels 1 and 2.
TetMesh twoTets() {
  TetMesh mesh;
  mesh.nodes = {Vec3(0, 0, 0), Vec3(10, 0, 0), Vec3(0, 10, 0), Vec3(0, 0, 10), Vec3(0, 0, -10)};
  mesh.tets = {{0, 1, 2, 3}, {0, 2, 1, 4}};
  mesh.labels = {1, 2};
  return mesh;
}

constexpr double kVolume = 1000.0 / 6.0;  // mm^3

TissueTable tissues(bool secondCritical) {
  TissueTable table;
  std::vector<int32_t> labels = {1, 2};
  EXPECT_FALSE(table.declare({"brain", 1, 0.05, 0.03, false}, labels).has_value());
  EXPECT_FALSE(table.declare({"tumour", 2, 0.02, 0.12, secondCritical}, labels).has_value());
  return table;
}

TissueAction aspirator() {
  TissueAction a;
  a.kind = TissueAction::Kind::kAspirate;
  a.tipSpeed_mm_per_s = 4 * 0.15 * 23000;  // 13.8 m/s
  a.coupling = 0.1;
  a.power_W = 20;
  return a;
}

ContactResponse touching(std::span<const int64_t> tets, const TissueAction& action, double force_N, bool engaged) {
  ContactResponse r;
  r.cutting = engaged;
  r.touched = tets;
  r.load.action = action;
  r.load.force_N = Vec3(0, 0, -force_N);
  r.load.dt = 1e-3;
  return r;
}

TEST(TissueRemovalTest, AnAspiratorRemovesATetrahedronWhenItsEnergyReachesVolumeTimesRemovalEnergy) {
  const TetMesh mesh = twoTets();
  TissueRemoval law;
  law.build(mesh, tissues(false));
  const std::array<int64_t, 2> both = {0, 1};
  const double force = 0.4;  // N
  const double power = std::min(20.0, 0.1 * force * 13.8);  // W: 0.552
  EXPECT_NEAR(aspirator().powerAt(force), power, 1e-12);
  // Each takes half the power; the tumour (0.02 J/mm^3) goes first.
  const int tumourFrame = int(std::ceil(kVolume * 0.02 / (0.5 * power * 1e-3)));
  const int brainFrame = int(std::ceil(kVolume * 0.05 / (0.5 * power * 1e-3)));
  std::vector<int32_t> toRemove;
  toRemove.reserve(2);
  int frame = 0;
  int tumourGone = -1, brainGone = -1;
  while (frame < 2 * brainFrame && brainGone < 0) {
    ++frame;
    const ContactResponse r = touching(both, aspirator(), force, true);
    law.act({&r, 1}, toRemove);
    for (int32_t t : toRemove) (t == 1 ? tumourGone : brainGone) = frame;
    law.removed(toRemove);
    toRemove.clear();
  }
  // Within a frame of the closed form (round-off of the sums).
  EXPECT_NEAR(tumourGone, tumourFrame, 1);
  EXPECT_NEAR(brainGone, brainFrame, 1);
  const ResectionTotals& t = law.totals();
  EXPECT_NEAR(t.removed_mm3[0], kVolume, 1e-9);
  EXPECT_NEAR(t.removed_mm3[1], kVolume, 1e-9);
  EXPECT_NEAR(t.bloodLoss_ml, 1e-3 * kVolume * (0.03 + 0.12), 1e-12);
}

TEST(TissueRemovalTest, NoPedalNoForceNoRemoval) {
  const TetMesh mesh = twoTets();
  TissueRemoval law;
  law.build(mesh, tissues(false));
  const std::array<int64_t, 1> tumour = {1};
  std::vector<int32_t> toRemove;
  toRemove.reserve(2);
  for (int i = 0; i < 100000; ++i) {
    const ContactResponse idle = touching(tumour, aspirator(), 1.0, false);  // pedal up
    const ContactResponse light = touching(tumour, aspirator(), 0.0, true);  // no force
    const ContactResponse both[] = {idle, light};
    law.act(both, toRemove);
  }
  EXPECT_TRUE(toRemove.empty());
  EXPECT_EQ(law.totals().energyIn_J, 0.0);
}

TEST(TissueRemovalTest, TheRatedPowerCapsTheRate) {
  TissueAction a = aspirator();
  a.power_W = 0.1;
  EXPECT_DOUBLE_EQ(a.powerAt(100.0), 0.1);
  EXPECT_DOUBLE_EQ(a.powerAt(-1.0), 0.0);
  EXPECT_DOUBLE_EQ(a.powerAt(NAN), 0.0);
}

TEST(TissueRemovalTest, CriticalTissueIsNeverRemovedAndItsContactIsTimed) {
  const TetMesh mesh = twoTets();
  TissueRemoval law;
  law.build(mesh, tissues(true));
  const std::array<int64_t, 1> vessel = {1};
  std::vector<int32_t> toRemove;
  toRemove.reserve(2);
  for (int i = 0; i < 2000; ++i) {
    const ContactResponse r = touching(vessel, aspirator(), 3.0, true);
    EXPECT_TRUE(law.act({&r, 1}, toRemove));
  }
  EXPECT_TRUE(toRemove.empty());
  EXPECT_NEAR(law.totals().criticalContact_s, 2.0, 1e-9);
  EXPECT_EQ(law.totals().criticalContacts, 1u);  // one stretch
  const ContactResponse none;
  EXPECT_FALSE(law.act({&none, 1}, toRemove));
  const ContactResponse again = touching(vessel, aspirator(), 0.1, false);  // touched, pedal up: still counted
  EXPECT_TRUE(law.act({&again, 1}, toRemove));
  EXPECT_EQ(law.totals().criticalContacts, 2u);
}

TEST(TissueRemovalTest, CoagulatedTissueDoesNotBleed) {
  const TetMesh mesh = twoTets();
  TissueRemoval law;
  law.build(mesh, tissues(false));
  TissueAction bipolar;
  bipolar.kind = TissueAction::Kind::kCoagulate;
  bipolar.power_W = 5;
  const std::array<int64_t, 1> tumour = {1};
  std::vector<int32_t> toRemove;
  toRemove.reserve(2);
  // Coagulated after volume x 0.12 J/mm^3 at 5 W: frames of 1 ms.
  const int frames = int(std::ceil(kVolume * kCoagulationEnergy / (5 * 1e-3)));
  for (int i = 0; i < frames - 1; ++i) {
    const ContactResponse r = touching(tumour, bipolar, 0.1, true);
    law.act({&r, 1}, toRemove);
  }
  EXPECT_FALSE(law.coagulated(1));
  const ContactResponse last = touching(tumour, bipolar, 0.1, true);
  law.act({&last, 1}, toRemove);
  EXPECT_TRUE(law.coagulated(1));
  EXPECT_NEAR(law.totals().coagulated_mm3[1], kVolume, 1e-9);
  EXPECT_TRUE(toRemove.empty());  // a bipolar removes nothing
  const std::array<int32_t, 2> both = {0, 1};
  law.removed(both);
  EXPECT_NEAR(law.totals().bloodLoss_ml, 1e-3 * kVolume * 0.03, 1e-12);  // the brain's only
}

TEST(TissueRemovalTest, UndeclaredLabelsAndBadIndicesAreLeftAlone) {
  TetMesh mesh = twoTets();
  mesh.labels = {1, 7};  // 7: no tissue
  TissueRemoval law;
  TissueTable table;
  std::vector<int32_t> labels = {1, 7};
  ASSERT_FALSE(table.declare({"brain", 1, 0.05, 0.03, false}, labels).has_value());
  law.build(mesh, table);
  const std::array<int64_t, 4> touched = {1, -3, 99, 1};
  std::vector<int32_t> toRemove;
  toRemove.reserve(2);
  for (int i = 0; i < 100000; ++i) {
    const ContactResponse r = touching(touched, aspirator(), 2.0, true);
    law.act({&r, 1}, toRemove);
  }
  EXPECT_TRUE(toRemove.empty());
  EXPECT_FALSE(law.removable(1));
}

}  // namespace
}  // namespace trephine::tetra
