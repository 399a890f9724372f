// TLEDForceField, FixedConstraint, Gravity and LabelMaterial in scenes: the
// component steps the model exactly as the model alone, nothing moves that
// the scene does not move, bad settings are load errors at their fields, and
// the tool's force deforms the brain (determinism and chatter:
// FemCouplingTest).
#include <gtest/gtest.h>

#include <cmath>

#include "framework/core/Diagnostics.h"
#include "framework/core/Strings.h"
#include "framework/formats/mesh/MeditWriter.h"
#include "framework/formats/mesh/TetMeshReader.h"
#include "plugins/fem/MaterialPlausibility.h"
#include "plugins/fem/TLEDModel.h"
#include "plugins/fem/TLEDState.h"
#include "plugins/tetra_brain/CubePhantom.h"
#include "plugins/tetra_brain/TetPhantoms.h"
#include "tests/plugins/fem/FemScenes.h"
#include "tests/support/TestSupport.h"

namespace trephine::fem {
namespace {

using scenes::pressScene;
using scenes::runFor;

// The bar of the cantilever tests: 100 mm, 10 mm square, 2 cells across.
std::string barScene(const std::string& extra, double acceleration = -10, const std::string& fem = R"(dt="0.1e-3")") {
  return R"(<Node name="root">
  <RequiredPlugin name="tetra_brain"/>
  <RequiredPlugin name="fem"/>
  <TetraBrain name="bar" file="phantom:bar?length=100&amp;width=10&amp;cells=2" saveDeformed="bar.vtu"/>
  <TLEDForceField name="fem" mesh="@bar" damping="11" rate="1000" )" +
         fem + R"(/>
  <FixedConstraint name="clamp" fem="@fem" box="-1 -6 -6 0.001 6 6"/>
  )" +
         (std::isnan(acceleration)
              ? std::string()
              : R"(<Gravity name="gravity" fem="@fem" acceleration="0 0 )" + std::to_string(acceleration) + R"("/>)") +
         extra + "\n</Node>";
}

TEST(FemSceneTest, TheComponentStepsTheModelExactlyAsTheModelAlone) {
  test::TempDir out;
  auto simulation = runFor(barScene(""), 0.3, out.path());
  ASSERT_TRUE(simulation);
  EXPECT_EQ(test::componentCounter(*simulation, "TLEDForceField", "steps"), 3000);
  EXPECT_EQ(test::componentCounter(*simulation, "FixedConstraint", "fixed_nodes"), 9);
  const TetMesh saved = formats::readTetMesh(out / "bar.vtu");

  // The same by hand: 3000 steps of 0.1 ms.
  const TetMesh bar = tetra::makeBoxMesh({20, 2, 2}, Vec3(0, -5, -5), Vec3(100, 5, 5));
  const ElementMaterial material{};
  TLEDModel model(bar.nodes, bar.tets, std::span(&material, 1));
  TLEDState state(model);
  for (size_t i = 0; i < bar.nodeCount(); ++i)
    if (bar.nodes[i].x() <= 0.001) model.fixNode(int32_t(i));
  model.setBodyAcceleration(Vec3(0, 0, -10));
  model.setTimeStep(0.1e-3, 11);
  for (int step = 0; step < 3000; ++step) state.step();
  ASSERT_EQ(saved.nodeCount(), bar.nodeCount());
  double largest = 0;
  for (size_t i = 0; i < bar.nodeCount(); ++i) {
    EXPECT_EQ(saved.nodes[i], state.position(int32_t(i))) << "node " << i;
    largest = std::max(largest, state.displacement(int32_t(i)).norm());
  }
  EXPECT_GT(largest, 0.1);  // it sagged
  EXPECT_EQ(test::componentCounter(*simulation, "TLEDForceField", "largest_displacement_mm"), largest);
}

TEST(FemSceneTest, WithoutGravityNothingMoves) {
  test::TempDir out;
  auto simulation = runFor(barScene("", NAN), 0.1, out.path());
  ASSERT_TRUE(simulation);
  EXPECT_EQ(test::componentCounter(*simulation, "TLEDForceField", "steps"), 1000);
  EXPECT_EQ(test::componentCounter(*simulation, "TLEDForceField", "largest_displacement_mm"), 0.0);
  const TetMesh saved = formats::readTetMesh(out / "bar.vtu");
  const TetMesh bar = tetra::makeBoxMesh({20, 2, 2}, Vec3(0, -5, -5), Vec3(100, 5, 5));
  for (size_t i = 0; i < bar.nodeCount(); ++i) EXPECT_EQ(saved.nodes[i], bar.nodes[i]);
}

TEST(FemSceneTest, ATimeStepAboveTheCriticalOneIsALoadErrorGivingBoth) {
  Diagnostics d;
  EXPECT_FALSE(test::loadScene(barScene("", -10, R"(dt="1e-3")"), d));
  const std::string m = test::messages(d);
  // Where, what was asked and what the mesh allows.
  EXPECT_NE(m.find("inline.xml:5:"), std::string::npos) << m;
  EXPECT_NE(m.find("dt = 1 ms is above the critical time step of this mesh, 0.3"), std::string::npos) << m;
  EXPECT_NE(m.find("massScaling=\"true\""), std::string::npos) << m;
  // With mass scaling on already, and a damping that limits the step, the
  // error does not suggest turning it on: it says what limits the step.
  Diagnostics damped;
  std::string dampedScene = barScene("", -10, R"(dt="1e-3" massScaling="true")");
  dampedScene.replace(dampedScene.find("damping=\"11\""), 13, "damping=\"2000\"");
  EXPECT_FALSE(test::loadScene(dampedScene, damped));
  const std::string dampedMessage = test::messages(damped);
  EXPECT_NE(dampedMessage.find("massScaling is on already and every element's own step reaches dt: the damping "
                               "limits it. Use dt <= 0.908 ms, less damping"),
            std::string::npos)
      << dampedMessage;
  EXPECT_EQ(dampedMessage.find("or massScaling=\"true\""), std::string::npos) << dampedMessage;

  // Accepted explicitly, it loads (and diverges: the positions stay finite, the divergence is counted).
  test::TempDir out;
  auto accepted = runFor(barScene("", -10, R"(dt="1e-3" acceptUnstableTimeStep="true")"), 0.5, out.path());
  ASSERT_TRUE(accepted);
  EXPECT_GT(test::componentCounter(*accepted, "TLEDForceField", "non_finite_ticks"), 0);
  for (const Vec3& p : formats::readTetMesh(out / "bar.vtu").nodes) EXPECT_TRUE(p.allFinite());
}

TEST(FemSceneTest, AContactDampingInNewtonSecondsPerMetreIsWarnedOf) {
  // 2 N s/m, written as the field's N s/mm: a thousand times the damping.
  Diagnostics d;
  EXPECT_TRUE(test::loadScene(barScene("", -10, R"(dt="0.1e-3" contactDamping="2")"), d));
  const std::string m = test::messages(d);
  EXPECT_NE(m.find("inline.xml:5:"), std::string::npos) << m;
  EXPECT_NE(m.find("contactDamping"), std::string::npos) << m;
  EXPECT_NE(m.find("is in N s/mm"), std::string::npos) << m;
  EXPECT_NE(m.find("2 is a damping in N s/m"), std::string::npos) << m;
  // What the contact needs is not warned of.
  Diagnostics quiet;
  EXPECT_TRUE(test::loadScene(barScene("", -10, R"(dt="0.1e-3" contactDamping="0.002")"), quiet));
  EXPECT_EQ(test::messages(quiet).find("contactDamping"), std::string::npos) << test::messages(quiet);
}

// A slip of units in a material constant: warned of at the field, with the
// unit it is in and what the value would be in the likely one; a tissue's
// values are not.
TEST(FemSceneTest, MaterialConstantsFarOutsideTissueAreWarnedOfWithTheLikelyUnit) {
  const auto warnings = [](const std::string& fem, const std::string& extra = "") {
    Diagnostics d;
    // (A modulus a thousand times a tissue's needs far more mass for the same
    // step: refused unless accepted, MassScalingIsSaidWarnedOfOrRefusedByHowMuchItAdds.)
    EXPECT_TRUE(test::loadScene(barScene(extra, -10, R"(dt="0.1e-3" massScaling="true" maxAddedMass="1e9" )" + fem), d))
        << test::messages(d);
    return test::messages(d);
  };
  std::string m = warnings(R"(youngModulus="30000")");
  EXPECT_NE(m.find("inline.xml:5:"), std::string::npos) << m;
  EXPECT_NE(m.find("youngModulus"), std::string::npos) << m;
  EXPECT_NE(m.find("as pascals it would be 30 kPa"), std::string::npos) << m;
  m = warnings(R"(youngModulus="0.03")");
  EXPECT_NE(m.find("as MPa it would be 30 kPa"), std::string::npos) << m;
  m = warnings(R"(density="1.0")");
  EXPECT_NE(m.find("density"), std::string::npos) << m;
  EXPECT_NE(m.find("as g/cm^3 it would be 1e-06 kg/mm^3"), std::string::npos) << m;
  m = warnings(R"(density="1000")");
  EXPECT_NE(m.find("as kg/m^3 it would be 1e-06 kg/mm^3"), std::string::npos) << m;
  // A tissue's own material is not warned of (the bounds are inclusive).
  for (const char* tissue : {R"(youngModulus="3" density="1.04e-6")", R"(youngModulus="300" density="1.9e-6")"})
    EXPECT_EQ(warnings(tissue).find("is in k"), std::string::npos) << warnings(tissue);
  for (const double kPa : {0.05, 1000.0}) EXPECT_FALSE(implausibleYoungModulus(kPa)) << kPa;
  for (const double kPa : {0.049, 1001.0}) EXPECT_TRUE(implausibleYoungModulus(kPa)) << kPa;
}

// The fraction of the bar's mass that selective mass scaling adds for a time
// step dt (s), computed here from the elements: each element whose L / c is
// below dt (aimed 1 + damping dt above it) gets its density raised by
// (dt / (L / c))^2, L = 1 / |grad N|.
double barAddedMassFraction(double dt, double damping = 11) {
  const TetMesh bar = tetra::makeBoxMesh({20, 2, 2}, Vec3(0, -5, -5), Vec3(100, 5, 5));
  const ElementMaterial material{};
  const double c =
      ElasticModuli::fromYoung(material.youngModulus, material.poissonRatio).dilatationalWaveSpeed(material.density);
  const double target = dt * (1 + damping * dt);
  double mass = 0, added = 0;
  for (const TetIndices& t : bar.tets) {
    Mat3 D;
    for (int a = 0; a < 3; ++a) D.col(a) = bar.nodes[t[a + 1]] - bar.nodes[t[0]];
    const Mat3 G = D.inverse();
    const double gradient = std::sqrt(G.squaredNorm() + (G.row(0) + G.row(1) + G.row(2)).squaredNorm());
    const double step = 1 / (gradient * c), m = material.density * D.determinant() / 6;
    mass += m;
    if (step < target) added += m * ((target / step) * (target / step) - 1);
  }
  return added / mass;
}

TEST(FemSceneTest, MassScalingMakesTheStepStableAndReportsWhatItAdded) {
  test::TempDir out;
  auto simulation = runFor(barScene("", -10, R"(dt="0.5e-3" massScaling="true" maxAddedMass="1e9")"), 0.3, out.path());
  ASSERT_TRUE(simulation);
  const double added = barAddedMassFraction(0.5e-3);
  EXPECT_NEAR(test::componentCounter(*simulation, "TLEDForceField", "added_mass_fraction"), added, 1e-9);
  EXPECT_GT(added, 0.0);
  EXPECT_GE(test::componentCounter(*simulation, "TLEDForceField", "critical_dt_s"), 0.5e-3);
  EXPECT_EQ(test::componentCounter(*simulation, "TLEDForceField", "non_finite_ticks"), 0);
}

TEST(FemSceneTest, MassScalingIsSaidWarnedOfOrRefusedByHowMuchItAdds) {
  // Time steps whose added mass falls in each band, found from the closed
  // form above (the bar's critical step is about 0.2 ms).
  double small = 0, warned = 0, refused = 0;  // s
  for (double dt = 0.1e-3; dt < 5e-3; dt *= 1.02) {
    const double f = barAddedMassFraction(dt);
    if (f > 0.005 && f < 0.04 && small == 0) small = dt;
    if (f > 0.07 && f < 0.2 && warned == 0) warned = dt;
    if (f > 0.4 && refused == 0) refused = dt;
  }
  ASSERT_GT(small, 0);
  ASSERT_GT(warned, 0);
  ASSERT_GT(refused, 0);
  const auto load = [](double dt, const std::string& extra, Diagnostics& d) {
    return test::loadScene(barScene("", -10, "dt=\"" + formatDouble(dt) + "\" massScaling=\"true\" " + extra), d);
  };
  // The percentage a message gives after `lead`, NaN when it gives none.
  const auto percentAfter = [](const std::string& text, const std::string& lead) {
    const size_t at = text.find(lead);
    return at == std::string::npos ? std::nan("") : std::stod(text.substr(at + lead.size()));
  };
  Diagnostics noted;
  EXPECT_TRUE(load(small, "", noted)) << test::messages(noted);
  EXPECT_EQ(noted.errorCount(), 0);
  EXPECT_NEAR(percentAfter(test::messages(noted), "massScaling added "), 100 * barAddedMassFraction(small), 1e-3 * 100 * barAddedMassFraction(small))
      << test::messages(noted);
  EXPECT_EQ(test::messages(noted).find("warning:"), std::string::npos) << test::messages(noted);
  EXPECT_NE(test::messages(noted).find("% of the mesh's mass to "), std::string::npos) << test::messages(noted);
  EXPECT_EQ(test::messages(noted).find("%%"), std::string::npos) << test::messages(noted);
  Diagnostics warning;
  EXPECT_TRUE(load(warned, "", warning)) << test::messages(warning);
  EXPECT_NEAR(percentAfter(test::messages(warning), "massScaling added "), 100 * barAddedMassFraction(warned), 1e-3 * 100 * barAddedMassFraction(warned))
      << test::messages(warning);
  EXPECT_NE(test::messages(warning).find("warning:"), std::string::npos) << test::messages(warning);
  EXPECT_NE(test::messages(warning).find("inline.xml:5:"), std::string::npos) << "at the field";
  Diagnostics error;
  EXPECT_FALSE(load(refused, "", error));
  EXPECT_NEAR(percentAfter(test::messages(error), "massScaling would add "), 100 * barAddedMassFraction(refused), 1e-3 * 100 * barAddedMassFraction(refused))
      << test::messages(error);
  EXPECT_NE(test::messages(error).find("more than maxAddedMass = 25%"), std::string::npos) << test::messages(error);
  // Asked for, it loads (with the warning).
  Diagnostics accepted;
  EXPECT_TRUE(load(refused, R"(maxAddedMass="1e9")", accepted)) << test::messages(accepted);
  EXPECT_NE(test::messages(accepted).find("warning:"), std::string::npos) << test::messages(accepted);
}

TEST(FemSceneTest, ConstraintsAndMaterialsRefuseWhatSelectsNothing) {
  const std::string brain = R"(<Node name="root">
  <RequiredPlugin name="tetra_brain"/>
  <RequiredPlugin name="fem"/>
  <TetraBrain name="bar" file="phantom:bar?length=100&amp;width=10&amp;cells=2"/>
  <TLEDForceField name="fem" mesh="@bar" dt="0.1e-3"/>
  )";
  const std::pair<std::string, std::string> cases[] = {
      {R"(<FixedConstraint fem="@fem"/>)", "give exactly one of indices, box or label (0 given)"},
      {R"(<FixedConstraint fem="@fem" box="0 0 0 1 1 1" indices="3"/>)", "(2 given)"},
      {R"(<FixedConstraint fem="@fem" box="200 0 0 300 1 1"/>)", "selects no node"},
      {R"(<FixedConstraint fem="@fem" box="0 0 0 1 1"/>)", "expected six numbers"},
      {R"(<FixedConstraint fem="@fem" indices="5000"/>)",
       "node 5000 is not a node index of a mesh of 189 nodes (0 to 188)"},
      {R"(<FixedConstraint fem="@fem" label="5"/>)", "carries no tissue labels"},
      {R"(<LabelMaterial fem="@fem" label="5" youngModulus="3"/>)", "carries no tissue labels"},
      {R"(<Gravity fem="@fem" acceleration="0 0 nan"/>)", "acceleration"},
  };
  for (const auto& [element, expected] : cases) {
    test::expectLoadError(brain + element + "\n</Node>", expected, element);
  }
}

TEST(FemSceneTest, ALabelsMaterialGoesToItsElementsOnly) {
  // A bar of two tissues: label 1 for x < 50 mm, label 2 beyond. Label 2 ten
  // times stiffer: its waves are sqrt(10) times faster, so the critical step
  // (set by the same element shapes on both sides) falls by sqrt(10).
  TetMesh bar = tetra::makeBoxMesh({20, 2, 2}, Vec3(0, -5, -5), Vec3(100, 5, 5));
  for (const TetIndices& t : bar.tets) {
    const double x = 0.25 * (bar.nodes[t[0]].x() + bar.nodes[t[1]].x() + bar.nodes[t[2]].x() + bar.nodes[t[3]].x());
    bar.labels.push_back(x < 50 ? 1 : 2);
  }
  test::TempDir dir;
  formats::writeMeditMesh(bar, dir / "bar.mesh");
  const auto scene = [&](const std::string& material) {
    return dir.write("scene.xml", R"(<Node name="root">
  <RequiredPlugin name="tetra_brain"/>
  <RequiredPlugin name="fem"/>
  <TetraBrain name="bar" file="bar.mesh"/>
  <TLEDForceField name="fem" mesh="@bar" dt="0.05e-3" damping="0" rate="1000"/>
  )" + material + "\n</Node>");
  };
  const auto critical = [&](const std::string& material) {
    Diagnostics d;
    SimulationOptions options;
    options.duration = 0.001;
    auto simulation = Simulation::fromFile(scene(material), options, d);
    EXPECT_TRUE(simulation) << test::messages(d);
    return simulation ? test::componentCounter(*simulation, "TLEDForceField", "critical_dt_s") : NAN;
  };
  const double plain = critical("");
  EXPECT_NEAR(critical(R"(<LabelMaterial fem="@fem" label="2" youngModulus="300"/>)") * std::sqrt(10.0), plain,
              1e-12 * plain);
  // Softer on its side: the other side's elements still set the step.
  EXPECT_DOUBLE_EQ(critical(R"(<LabelMaterial fem="@fem" label="1" youngModulus="3"/>)"), plain);
  // A label no element has is an error at the label.
  Diagnostics d;
  EXPECT_FALSE(Simulation::fromFile(scene(R"(<LabelMaterial fem="@fem" label="7"/>)"), {}, d));
  EXPECT_NE(test::messages(d).find("no element of /bar has label 7"), std::string::npos) << test::messages(d);
  // A label's material in the wrong unit is warned of at its own attribute.
  Diagnostics slip;
  SimulationOptions quick;
  quick.duration = 0.001;
  EXPECT_TRUE(Simulation::fromFile(scene(R"(<LabelMaterial fem="@fem" label="2" density="1050" youngModulus="3"/>)"),
                                   quick, slip));
  EXPECT_NE(test::messages(slip).find("scene.xml:6:"), std::string::npos) << test::messages(slip);
  EXPECT_NE(test::messages(slip).find("density of LabelMaterial"), std::string::npos) << test::messages(slip);
  EXPECT_NE(test::messages(slip).find("as kg/m^3 it would be 1.05e-06 kg/mm^3"), std::string::npos)
      << test::messages(slip);
}

TEST(FemSceneTest, TheToolsForceDeformsTheBrainWhichComesBackWhenReleased) {
  test::TempDir out;
  auto simulation = runFor(pressScene(), 1.4, out.path());
  ASSERT_TRUE(simulation);
  EXPECT_GT(test::componentCounter(*simulation, "TLEDForceField", "force_updates"), 50);
  // Pressed 4 mm in with a 0.3 N/mm spring: the surface gives way by a millimetre or more.
  const double largest = test::componentCounter(*simulation, "TLEDForceField", "largest_displacement_mm");
  EXPECT_GT(largest, 1.0);
  EXPECT_LT(largest, 20.0);
  EXPECT_EQ(test::componentCounter(*simulation, "TLEDForceField", "non_finite_ticks"), 0);
  EXPECT_GT(test::componentCounter(*simulation, "TetraBrain", "deformation_frames"), 500);
  EXPECT_EQ(test::componentCounter(*simulation, "TLEDForceField", "inverted_element_steps"), 0);
  // Released at the end, it has come back (damping 50 /s: a time constant of 40 ms).
  const TetMesh rest = formats::readTetMesh(out / "brain_final.mesh");
  double remaining = 0;
  const TetMesh start = tetra::makeTetPhantom("brain?tets=1200");
  for (size_t i = 0; i < start.nodeCount(); ++i)
    remaining = std::max(remaining, (rest.nodes[i] - start.nodes[i]).norm());
  EXPECT_LT(remaining, 0.05 * largest) << remaining << " mm left of " << largest << " mm";
}

TEST(FemSceneTest, ABrainWithoutAFemIsNeverDeformed) {
  // No deformation component: the brain reports no deformation at all (the
  // counters of a deforming brain are absent, not zero), with the FEM it does.
  test::TempDir out;
  std::string rigid = pressScene();
  const size_t begin = rigid.find("<TLEDForceField"), end = rigid.find("<Node name=\"tool\">");
  rigid.erase(begin, end - begin);
  rigid.insert(begin, "</Node>\n  ");
  rigid.replace(rigid.find("  <RequiredPlugin name=\"fem\"/>\n"), 31, "");
  auto simulation = runFor(rigid, 0.5, out.path());
  ASSERT_TRUE(simulation);
  const Component* brain = simulation->scene().findComponent("/patient/brain");
  ASSERT_NE(brain, nullptr);
  std::vector<Counter> counters;
  brain->reportCounters(counters);
  for (const Counter& c : counters) EXPECT_NE(c.name, "deformation_frames");
  EXPECT_GT(test::componentCounter(*simulation, "TetraBrain", "contact_frames"), 0);
}

}  // namespace
}  // namespace trephine::fem
