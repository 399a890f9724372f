// scenes/resection.xml, the tumour resection, run for its first 9 s (the
// aspirator's first passes across the tumour, the bipolar beside it, the
// TLED FEM deforming the brain and dropping what goes) and judged as a user
// would: the `resection` block of summary.json and resection.csv agree with
// each other and with the mesh's own volumes, the tumour loses volume and
// the blood loss follows, the haptics stay within the targets (unexplained
// force steps p99 0.05 N, max 0.3 N; no NaN; passive), the FEM never
// diverges, and the file saveDeformed writes holds exactly the remaining
// tetrahedra with their labels, read back here by a parser of its own (not
// the project's mesh reader): every index in range, every node used, no face
// shared by three tetrahedra. Seconds of simulation: label numerics.
#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "tests/support/TestSupport.h"

namespace trephine {
namespace {

// A Medit .mesh read with nothing but streams: the Vertices and Tetrahedra
// sections (1-based indices, a reference per element).
struct Medit {
  std::vector<std::array<double, 3>> vertices;
  std::vector<std::array<int64_t, 4>> tets;
  std::vector<int64_t> refs;
};

Medit readMedit(const std::filesystem::path& file) {
  Medit m;
  std::ifstream in(file);
  std::string word;
  while (in >> word) {
    if (word == "Vertices") {
      size_t n = 0;
      in >> n;
      m.vertices.resize(n);
      for (auto& v : m.vertices) {
        int64_t ref = 0;
        in >> v[0] >> v[1] >> v[2] >> ref;
      }
    } else if (word == "Tetrahedra") {
      size_t n = 0;
      in >> n;
      m.tets.resize(n);
      m.refs.resize(n);
      for (size_t i = 0; i < n; ++i) in >> m.tets[i][0] >> m.tets[i][1] >> m.tets[i][2] >> m.tets[i][3] >> m.refs[i];
    }
  }
  return m;
}

// "key": number, the first after `after` in the JSON text.
double jsonNumber(const std::string& json, const std::string& key, const std::string& after = "") {
  const size_t from = after.empty() ? 0 : json.find("\"" + after + "\"");
  const size_t at = json.find("\"" + key + "\":", from == std::string::npos ? 0 : from);
  if (at == std::string::npos) return NAN;
  return std::stod(json.substr(at + key.size() + 3));
}

TEST(ResectionSceneTest, ATumourResectionMeasuresWhatItRemovesAndLeavesAValidMesh) {
  test::TempDir dir{"trephine-resection"};
  SimulationOptions options;
  options.duration = 9.0;
  options.outputDirectory = dir.path();
  options.overrides = {"/patient/brain.saveDeformed=brain_final.mesh"};
  auto simulation = test::loadSceneFile("scenes/resection.xml", options);
  ASSERT_TRUE(simulation);
  simulation->run();
  simulation->writeOutputs(dir.path());
  const std::string summary = test::readFile(dir / "summary.json");

  // What was removed and what remains, by tissue: the sum is the tissue's volume.
  const double tumourRemoved = jsonNumber(summary, "tumour", "removed_mm3");
  const double tumourLeft = jsonNumber(summary, "tumour", "remaining_mm3");
  const double tumourVolume = test::componentCounterAt(*simulation, "/patient/resection", "volume_mm3.tumour");
  EXPECT_GT(tumourRemoved, 20.0);  // mm^3
  EXPECT_NEAR(tumourRemoved + tumourLeft, tumourVolume, 1e-6 * tumourVolume);
  EXPECT_EQ(jsonNumber(summary, "vessel", "removed_mm3"), 0.0);  // critical: never removed
  const double blood = jsonNumber(summary, "blood_loss_ml");
  // At most every removed tetrahedron's volume times its tissue's vascularity (0.12, 0.035).
  EXPECT_GT(blood, 0.0);
  EXPECT_LE(blood, 1e-3 * (0.12 * tumourRemoved + 0.035 * jsonNumber(summary, "brain_tissue", "removed_mm3")) + 1e-12);
  EXPECT_GT(jsonNumber(summary, "path_length_mm", "/aspirator/force"), 20.0);
  EXPECT_GT(jsonNumber(summary, "path_length_mm", "/bipolar/force"), 1.0);

  // resection.csv: a row a millisecond, the removed volume never falls, its
  // last row is the summary's.
  std::ifstream csv(dir / "resection.csv");
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line.rfind("t,removed_mm3,blood_loss_ml,critical_contact_s,removed_mm3.brain_tissue", 0), 0u) << line;
  double lastRemoved = 0, lastBlood = 0;
  size_t rows = 0;
  while (std::getline(csv, line)) {
    std::istringstream row(line);
    double t, removed, bloodNow;
    char comma;
    row >> t >> comma >> removed >> comma >> bloodNow;
    EXPECT_GE(removed, lastRemoved);
    EXPECT_GE(bloodNow, lastBlood);
    lastRemoved = removed;
    lastBlood = bloodNow;
    ++rows;
  }
  EXPECT_GE(rows, 8900u);
  EXPECT_NEAR(lastBlood, blood, 1e-9 + 1e-6 * blood);

  // The haptics within the targets, both hands; the FEM never diverged.
  for (const char* tool : {"/aspirator/force", "/bipolar/force"}) {
    const std::string block = summary.substr(summary.find("\"" + std::string(tool) + "\": {\n      \"source\""));
    EXPECT_LE(jsonNumber(block, "p99", "force_step_unexplained_N"), 0.05) << tool;
    EXPECT_LE(jsonNumber(block, "max", "force_step_unexplained_N"), 0.3) << tool;
    EXPECT_EQ(jsonNumber(block, "nan_frames"), 0.0) << tool;
    EXPECT_GE(jsonNumber(block, "min_energy_in_mJ"), 0.0) << tool;
  }
  EXPECT_EQ(summary.find("fem_diverged"), std::string::npos);
  EXPECT_EQ(test::componentCounter(*simulation, "TLEDForceField", "non_finite_ticks"), 0);
  const double removedTets = test::componentCounterAt(*simulation, "/patient/brain", "removed_tetrahedra");
  EXPECT_EQ(test::componentCounter(*simulation, "TLEDForceField", "removed_elements"), removedTets);

  // The remaining mesh, read by a parser of its own.
  const Medit mesh = readMedit(dir / "brain_final.mesh");
  const double remaining = test::componentCounterAt(*simulation, "/patient/brain", "remaining_tetrahedra");
  ASSERT_EQ(double(mesh.tets.size()), remaining);
  std::vector<int> used(mesh.vertices.size(), 0);
  std::map<std::array<int64_t, 3>, int> faces;
  std::map<int64_t, size_t> labels;
  for (size_t i = 0; i < mesh.tets.size(); ++i) {
    for (int64_t v : mesh.tets[i]) {
      ASSERT_GE(v, 1);
      ASSERT_LE(v, int64_t(mesh.vertices.size()));
      used[size_t(v - 1)] = 1;
    }
    for (int skip = 0; skip < 4; ++skip) {
      std::array<int64_t, 3> face;
      for (int k = 0, j = 0; k < 4; ++k)
        if (k != skip) face[size_t(j++)] = mesh.tets[i][size_t(k)];
      std::sort(face.begin(), face.end());
      ++faces[face];
    }
    ++labels[mesh.refs[i]];
  }
  for (size_t v = 0; v < used.size(); ++v) EXPECT_TRUE(used[v]) << "vertex " << v + 1 << " is used by no tetrahedron";
  for (const auto& [face, count] : faces) ASSERT_LE(count, 2) << "a face shared by three tetrahedra";
  EXPECT_EQ(labels.size(), 3u);  // brain, tumour, vessel
  EXPECT_GT(labels[2], 0u);
}

}  // namespace
}  // namespace trephine
