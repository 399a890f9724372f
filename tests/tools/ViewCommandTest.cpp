// `trephine view`: the viewer's data from a run's VTK files (every frame's
// files, packed byte for byte; the skull simplified to the budget; the plots
// from trace.csv) and clear errors for runs it cannot show. The browser
// itself is tested by tests/plugins/viewer/browser.
#include <gtest/gtest.h>

#include <algorithm>

#include <filesystem>
#include <fstream>
#include <vector>
#include <map>
#include <regex>
#include <set>

#include "tests/support/TestSupport.h"
#include "framework/formats/encoding/Base64.h"
#include "plugins/viewer/RunViewerData.h"
#include "framework/data/VertexClustering.h"

namespace trephine {
namespace {

namespace fs = std::filesystem;
using test::runProgram;

// Standard base64 decoding, written apart from the encoder under test.
std::string decodeBase64(const std::string& text) {
  std::string out;
  uint32_t bits = 0;
  int count = 0;
  for (char c : text) {
    int v = c >= 'A' && c <= 'Z'   ? c - 'A'
            : c >= 'a' && c <= 'z' ? c - 'a' + 26
            : c >= '0' && c <= '9' ? c - '0' + 52
            : c == '+'             ? 62
            : c == '/'             ? 63
                                   : -1;
    if (v < 0) continue;  // padding
    bits = (bits << 6) | uint32_t(v);
    if ((count += 6) >= 8) {
      count -= 8;
      out += char((bits >> count) & 0xff);
    }
  }
  return out;
}

TEST(ViewCommandTest, Base64MatchesTheStandardForEveryRemainder) {
  EXPECT_EQ(formats::encodeBase64(""), "");
  EXPECT_EQ(formats::encodeBase64("f"), "Zg==");
  EXPECT_EQ(formats::encodeBase64("fo"), "Zm8=");
  EXPECT_EQ(formats::encodeBase64("foo"), "Zm9v");
  EXPECT_EQ(formats::encodeBase64("foobar"), "Zm9vYmFy");  // RFC 4648's test vectors
  std::string bytes;
  for (int i = 0; i < 1000; ++i) bytes += char(i * 37 + 11);
  EXPECT_EQ(decodeBase64(formats::encodeBase64(bytes)), bytes);
}

using FakeAssets = test::FakeViewerAssets;

TEST(ViewCommandTest, PacksEveryFrameOfADrilledSkullABrainAndTheTool) {
  test::TempDir dir;
  const fs::path run = dir.path() / "run";
  std::string out;
  // The default scene for 3 s: the burr reaches the bone at 0.8 s and drills.
  ASSERT_EQ(runProgram({"run", (test::sourceDir() / "scenes/integrated.xml").string(), "--duration", "3", "--out",
                        run.string(), "--quiet"},
                       &out),
            0)
      << out;
  FakeAssets assets;
  ASSERT_EQ(runProgram({"view", run.string(), "--triangles", "4000"}, &out, assets.environment()), 0) << out;
  EXPECT_TRUE(fs::exists(run / "view/index.html"));
  EXPECT_TRUE(fs::exists(run / "view/viewer.js"));
  const std::string manifest = test::readFile(run / "view/data/manifest.js");
  ASSERT_TRUE(manifest.starts_with("window.trephineRuns = window.trephineRuns || [];\nwindow.trephineRuns[0] = {"))
      << manifest.substr(0, 100);
  for (const char* part : {"\"skull\"", "\"brain\"", "\"tool\""}) EXPECT_NE(manifest.find(part), std::string::npos) << part;
  EXPECT_NE(manifest.find("\"plots\": {"), std::string::npos) << "trace.csv gives the plots";

  // One frame per time of the .pvd, 30 a second over 3 s.
  const std::string pvd = test::readFile(run / "vtk.pvd");
  std::set<std::string> times;
  const std::regex timestep("timestep=\"([^\"]+)\"");
  for (auto it = std::sregex_iterator(pvd.begin(), pvd.end(), timestep); it != std::sregex_iterator(); ++it)
    times.insert((*it)[1]);
  EXPECT_GE(times.size(), 90u) << "30 a second, and the skull as the run left it";
  const std::regex frame("\"t\": [0-9]");
  EXPECT_EQ(size_t(std::distance(std::sregex_iterator(manifest.begin(), manifest.end(), frame), std::sregex_iterator())),
            times.size());

  // Each tool file the .pvd lists is in a chunk, byte for byte.
  std::string chunks;
  for (const auto& entry : fs::directory_iterator(run / "view/data"))
    if (entry.path().filename().string().starts_with("chunk_")) chunks += test::readFile(entry.path());
  size_t checked = 0;
  for (const std::string file : {"vtk/tool_00000.vtp", "vtk/tool_00045.vtp", "vtk/brain_00000.vtu"}) {
    const size_t at = chunks.find("\"" + file + "\": \"");
    ASSERT_NE(at, std::string::npos) << file;
    const size_t start = at + file.size() + 5, end = chunks.find('"', start);
    EXPECT_EQ(decodeBase64(chunks.substr(start, end - start)), test::readFile(run / file)) << file;
    ++checked;
  }
  EXPECT_EQ(checked, 3u);

  // The skull within its budget of triangles, the drilled blocks apart.
  std::smatch numbers;
  ASSERT_TRUE(std::regex_search(out, numbers, std::regex("skull: (\\d+) triangles drawn as (\\d+)"))) << out;
  const double full = std::stod(numbers[1]), drawn = std::stod(numbers[2]);
  EXPECT_GT(full, 100000) << "the 1 mm skull phantom";
  EXPECT_LE(drawn, 4000) << out;
  EXPECT_GT(drawn, 1000) << out;
  // The untouched bone from the skull's volume (the exporter wrote it), not clustered.
  EXPECT_NE(out.find("untouched bone from its volume pooled over"), std::string::npos) << out;
  // The still level, ten times the budget, drawn when the view stands.
  ASSERT_TRUE(std::regex_search(out, numbers, std::regex("(\\d+) when still"))) << out;
  EXPECT_LE(std::stod(numbers[1]), 40000) << out;
  EXPECT_GT(std::stod(numbers[1]), 4 * drawn) << out;
  for (const char* level : {"moving", "still"}) {
    EXPECT_NE(manifest.find(std::string("skull/") + level + "_untouched.tri"), std::string::npos) << level;
    EXPECT_NE(manifest.find(std::string("skull/") + level + "_drilled_"), std::string::npos)
        << level << ": the drill changed blocks after 0.8 s";
  }
  // The colour maps' ranges (the brain rests in the first 3 s: zero), the
  // skull's volume with the voxels cut, and the run's summary as a string.
  EXPECT_TRUE(std::regex_search(manifest, std::regex("\"ranges\": \\{\\s*\"displacement\": [0-9.e-]+,\\s*\"force\": [0-9.e-]+,\\s*\"von_mises\": [0-9.e-]+\\s*\\}")))
      << manifest.substr(0, 400);
  ASSERT_TRUE(std::regex_search(manifest, numbers, std::regex("\"removedVoxels\": (\\d+)")));
  EXPECT_GT(std::stoi(numbers[1]), 0) << "the burr cut bone";
  EXPECT_NE(manifest.find("\"density\": \"skull/volume.vol\""), std::string::npos);
  EXPECT_NE(manifest.find("window.trephineRuns[0].summary = \"{"), std::string::npos);

  // A summary is text the viewer parses, never script: quotes and a line
  // break in it are escaped. A list of cut voxels that does not fit the
  // volume is an error naming the file and the line.
  std::ofstream(run / "summary.json") << "{\"events\": [{\"t\": 1, \"kind\": \"x\", \"detail\": \"\\\"; alert(1); //\"}]}\n\";alert(2);//";
  ASSERT_EQ(runProgram({"view", run.string()}, &out, assets.environment()), 0) << out;
  const std::string hostile = test::readFile(run / "view/data/manifest.js");
  const std::string embedded = hostile.substr(hostile.find("window.trephineRuns[0].summary = "));
  // Between the literal's quotes, every quote is escaped.
  const size_t open = embedded.find('"'), close = embedded.rfind('"');
  ASSERT_LT(open, close);
  for (size_t q = embedded.find('"', open + 1); q < close; q = embedded.find('"', q + 1))
    EXPECT_EQ(embedded[q - 1], '\\') << embedded.substr(0, q + 1);
  EXPECT_NE(embedded.find("\\\";alert(2)"), std::string::npos) << embedded;
  EXPECT_EQ(std::count(embedded.begin(), embedded.end(), '\n'), 1) << "one line: the break is escaped";
  // Side by side: the run with itself; several runs need --out, six at most.
  ASSERT_EQ(runProgram({"view", run.string(), run.string(), "--out", (dir.path() / "both").string()}, &out,
                       assets.environment()),
            0)
      << out;
  const std::string both = test::readFile(dir.path() / "both/data/manifest.js");
  EXPECT_NE(both.find("window.trephineRuns[1] = {"), std::string::npos);
  EXPECT_NE(both.find("\"folder\": \"run_1/\""), std::string::npos);
  EXPECT_TRUE(fs::exists(dir.path() / "both/data/run_1/chunk_00000.js"));
  EXPECT_TRUE(test::readFile(dir.path() / "both/data/run_1/chunk_00000.js").starts_with("trephineChunk(1, 0, {"));
  EXPECT_EQ(runProgram({"view", run.string(), run.string()}, &out, assets.environment()), 2);
  EXPECT_NE(out.find("need --out DIR"), std::string::npos) << out;
  EXPECT_EQ(runProgram({"view", run.string(), run.string(), "--out", run.string()}, &out, assets.environment()), 2);
  EXPECT_NE(out.find("is the run"), std::string::npos) << out;
  EXPECT_TRUE(fs::exists(run / "trace.csv")) << "the run's own files are left";
  // One run, elsewhere.
  ASSERT_EQ(runProgram({"view", run.string(), "--out", (dir.path() / "elsewhere").string()}, &out, assets.environment()), 0)
      << out;
  EXPECT_TRUE(fs::exists(dir.path() / "elsewhere/data/manifest.js"));
  // A study's folder: its settings' runs, in order, into STUDY/view.
  const fs::path study = dir.path() / "study";
  for (const char* setting : {"settings/001", "settings/000"}) {
    fs::create_directories(study / setting);
    fs::copy(run, study / setting, fs::copy_options::recursive);
    fs::remove_all(study / setting / "view");
  }
  std::ofstream(study / "study.csv") << "setting\n0\n1\n";
  ASSERT_EQ(runProgram({"view", study.string()}, &out, assets.environment()), 0) << out;
  const std::string studied = test::readFile(study / "view/data/manifest.js");
  EXPECT_NE(studied.find("window.trephineRuns[1] = {"), std::string::npos);
  EXPECT_LT(studied.find("settings/000"), studied.find("settings/001"));
  std::vector<std::string> seven{"view"};
  for (int i = 0; i < 7; ++i) seven.push_back(run.string());
  seven.insert(seven.end(), {"--out", (dir.path() / "seven").string()});
  EXPECT_EQ(runProgram(seven, &out, assets.environment()), 2);
  EXPECT_NE(out.find("7 runs are more than 6 side by side"), std::string::npos) << out;
  std::ofstream(run / "vtk/skull_removed.csv") << "i,j,k,t\n1,2,3,0.5\n1,2,99999,0.6\n";
  EXPECT_EQ(runProgram({"view", run.string()}, &out, assets.environment()), 1);
  EXPECT_NE(out.find("skull_removed.csv:3: expected i,j,k inside the"), std::string::npos) << out;
}

// Copies into `to` a 0.2 s run of the FEM press example, made once for the
// tests that change and view one.
void copyFemPressRun(const fs::path& to) {
  static test::TempDir made("trephine-fem-press");
  static int status = -1;
  static std::string out;
  if (status < 0)
    status = runProgram({"run", (test::sourceDir() / "scenes/examples/fem_press_export.xml").string(), "--duration",
                         "0.2", "--out", (made / "run").string(), "--quiet"},
                        &out);
  ASSERT_EQ(status, 0) << out;
  fs::copy(made / "run", to, fs::copy_options::recursive);
}

// Rows of trace.csv the plots cannot use (cut short, a value that is not a
// finite number) are left out and said, by line (before, they were plotted
// as they were without a word).
TEST(ViewCommandTest, TraceRowsThePlotsCannotUseAreSaidByLine) {
  test::TempDir dir;
  const fs::path run = dir.path() / "run";
  ASSERT_NO_FATAL_FAILURE(copyFemPressRun(run));
  std::string out;
  std::string trace = test::readFile(run / "trace.csv");
  std::vector<std::string> lines;
  for (size_t at = 0, next; (next = trace.find('\n', at)) != std::string::npos; at = next + 1)
    lines.push_back(trace.substr(at, next - at));
  ASSERT_GT(lines.size(), 20u);
  lines[5] = lines[5].substr(0, lines[5].find(',', lines[5].find(',') + 1));  // two cells
  const size_t firstComma = lines[9].find(',');
  lines[9] = lines[9].substr(0, firstComma) + ",nan" + lines[9].substr(lines[9].find(',', firstComma + 1));  // device_x
  lines[12] = "inf" + lines[12].substr(lines[12].find(','));  // t
  std::ofstream rewritten(run / "trace.csv", std::ios::trunc);
  for (const std::string& line : lines) rewritten << line << "\n";
  rewritten.close();
  FakeAssets assets;
  ASSERT_EQ(runProgram({"view", run.string()}, &out, assets.environment()), 0) << out;
  EXPECT_NE(out.find("trace.csv:6: a row of 2 cells (the header has"), std::string::npos) << out;
  EXPECT_NE(out.find("trace.csv:13: t is 'inf', not a finite number"), std::string::npos) << out;
  EXPECT_EQ(out.find("trace.csv:10:"), std::string::npos) << "device_x is not plotted: its row stays\n" << out;
}

// Every tool's trace is plotted: beside trace.csv's, each trace.PATH.csv of a
// run with several tools, named by its renderer's path (dots back to slashes).
TEST(ViewCommandTest, EveryToolsTraceIsPlottedAndNamed) {
  test::TempDir dir;
  const fs::path run = dir.path() / "run";
  ASSERT_NO_FATAL_FAILURE(copyFemPressRun(run));
  std::string out;
  fs::copy_file(run / "trace.csv", run / "trace.left.force.csv");
  FakeAssets assets;
  ASSERT_EQ(runProgram({"view", run.string()}, &out, assets.environment()), 0) << out;
  const std::string manifest = test::readFile(run / "view/data/manifest.js");
  const size_t tools = manifest.find("\"toolPlots\": [");
  ASSERT_NE(tools, std::string::npos) << manifest.substr(0, 300);
  EXPECT_NE(manifest.find("\"name\": \"/left/force\"", tools), std::string::npos);
  EXPECT_NE(manifest.find("\"force\": [", tools), std::string::npos);
}

TEST(ViewCommandTest, RunsItCannotShowAreClearErrors) {
  test::TempDir dir;
  FakeAssets assets;
  std::string out;
  EXPECT_EQ(runProgram({"view"}, &out, assets.environment()), 2);
  EXPECT_EQ(runProgram({"view", (dir.path() / "absent").string()}, &out, assets.environment()), 1);
  EXPECT_NE(out.find("not a directory"), std::string::npos) << out;
  EXPECT_EQ(runProgram({"view", dir.path().string()}, &out, assets.environment()), 1);
  EXPECT_NE(out.find("no .pvd index"), std::string::npos) << out;
  EXPECT_EQ(runProgram({"view", dir.path().string(), "--triangles", "12x"}, &out, assets.environment()), 2);
  // An index that lists a file that is not there, and one that is not XML.
  std::ofstream(dir.path() / "vtk.pvd") << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\">\n<Collection>\n"
                                           "<DataSet timestep=\"0\" part=\"0\" file=\"vtk/brain_00000.vtu\"/>\n"
                                           "</Collection>\n</VTKFile>\n";
  EXPECT_EQ(runProgram({"view", dir.path().string()}, &out, assets.environment()), 1);
  EXPECT_NE(out.find("lists vtk/brain_00000.vtu, which is missing"), std::string::npos) << out;
  std::ofstream(dir.path() / "vtk.pvd") << "<VTKFile type=\"Collection\"><Collection><DataSet timestep=";
  EXPECT_EQ(runProgram({"view", dir.path().string()}, &out, assets.environment()), 1);
  EXPECT_NE(out.find("vtk.pvd:1: not XML"), std::string::npos) << out;
  // Files outside the run's folder are never read into the viewer's data.
  std::ofstream(dir.path() / "outside.vtp") << "<VTKFile/>";
  fs::create_directories(dir.path() / "run");
  for (const std::string& file :
       std::vector<std::string>{"../outside.vtp", (dir.path() / "outside.vtp").string(), "vtk/../../outside.vtp"}) {
    std::ofstream(dir.path() / "run/vtk.pvd") << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\">\n<Collection>\n"
                                                 "<DataSet timestep=\"0\" part=\"0\" file=\"" + file + "\"/>\n"
                                                 "</Collection>\n</VTKFile>\n";
    EXPECT_EQ(runProgram({"view", (dir.path() / "run").string()}, &out, assets.environment()), 1) << file;
    EXPECT_NE(out.find("run/vtk.pvd:4: '" + file + "' is outside the run's folder"), std::string::npos) << out;
  }
  // A file the viewer cannot draw is named with what it is, to the end of the message.
  fs::create_directories(dir.path() / "run/vtk");
  std::ofstream(dir.path() / "run/vtk/plain") << "x";
  std::ofstream(dir.path() / "run/vtk.pvd") << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\">\n<Collection>\n"
                                               "<DataSet timestep=\"0\" part=\"0\" file=\"vtk/plain\"/>\n"
                                               "</Collection>\n</VTKFile>\n";
  EXPECT_EQ(runProgram({"view", (dir.path() / "run").string()}, &out, assets.environment()), 1);
  EXPECT_NE(out.find("not a file without an extension"), std::string::npos) << out;
}

TEST(ViewCommandTest, TheLiveViewNeedsRealTimeAnExporterAndAPort) {
  test::TempDir dir;
  std::string out;
  const std::string exporting = (test::sourceDir() / "scenes/examples/fem_press_export.xml").string();
  const std::string plain = (test::sourceDir() / "scenes/examples/plane_touch.xml").string();
  EXPECT_EQ(runProgram({"run", exporting, "--view", "0", "--out", dir.path().string()}, &out), 2);
  EXPECT_NE(out.find("--view needs --realtime"), std::string::npos) << out;
  EXPECT_EQ(runProgram({"run", exporting, "--realtime", "--view", "70000", "--out", dir.path().string()}, &out), 2);
  EXPECT_NE(out.find("--view takes a port"), std::string::npos) << out;
  EXPECT_EQ(runProgram({"run", plain, "--realtime", "--view", "--out", dir.path().string()}, &out), 1);
  EXPECT_NE(out.find("has none; add one"), std::string::npos) << out;
}

// A sphere of radius 50 mm as a UV grid of about 2 x n^2 triangles.
TriangleMesh sphere(int n) {
  TriangleMesh s;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j < 2 * n; ++j) {
      const double theta = M_PI * i / n, phi = M_PI * j / n;
      s.vertices.push_back(50 * Vec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)));
    }
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < 2 * n; ++j) {
      const int a = i * 2 * n + j, b = i * 2 * n + (j + 1) % (2 * n), c = a + 2 * n, d = b + 2 * n;
      if (i > 0) s.triangles.push_back({a, b, d});
      if (i + 1 < n) s.triangles.push_back({a, d, c});
    }
  return s;
}

TEST(VertexClusteringTest, MeetsTheBudgetAndKeepsTheShape) {
  const TriangleMesh fine = sphere(150);  // 89,400 triangles, 1 mm edges
  ASSERT_GT(fine.triangles.size(), 80000u);
  double cell = 0;
  const TriangleMesh coarse = simplifyToBudget({&fine}, 3000, 0, &cell);
  EXPECT_LE(coarse.triangles.size(), 3000u);
  EXPECT_GT(coarse.triangles.size(), 1500u) << "the cell grows by 1.25 a try: not far under the budget";
  EXPECT_GT(cell, 1.0);
  // The cluster means stay near the sphere (within a cell of it) and cover
  // it: the clustered surface's area is the sphere's within 10%.
  double area = 0;
  for (const Vec3& p : coarse.vertices) EXPECT_NEAR(p.norm(), 50.0, cell);
  for (const auto& t : coarse.triangles)
    area += 0.5 * (coarse.vertices[t[1]] - coarse.vertices[t[0]]).cross(coarse.vertices[t[2]] - coarse.vertices[t[0]]).norm();
  EXPECT_NEAR(area, 4 * M_PI * 50 * 50, 0.1 * 4 * M_PI * 50 * 50);
  // Within the budget: unchanged.
  const TriangleMesh same = simplifyToBudget({&fine}, 100000, 0, &cell);
  EXPECT_EQ(same.triangles.size(), fine.triangles.size());
  EXPECT_EQ(cell, 0.0);
}

TEST(VertexClusteringTest, PiecesAddedApartJoinWithoutCracks) {
  // A sphere cut in two halves and clustered piece by piece gives the
  // clustering of the whole sphere: the same triangles on the same points,
  // no crack along the cut.
  const TriangleMesh whole = sphere(60);
  TriangleMesh top = whole, bottom = whole;
  top.triangles.clear();
  bottom.triangles.clear();
  for (const auto& t : whole.triangles) (whole.vertices[t[0]].z() > 0 ? top : bottom).triangles.push_back(t);
  auto openEdges = [](const TriangleMesh& s) {
    std::map<std::pair<int, int>, int> edges;
    for (const auto& t : s.triangles)
      for (int k = 0; k < 3; ++k) ++edges[std::minmax(t[k], t[(k + 1) % 3])];
    size_t open = 0;
    for (const auto& [edge, n] : edges) open += n == 1;
    return open;
  };
  VertexClustering pieces(7.0), one(7.0);
  pieces.add(top);
  pieces.add(bottom);
  one.add(whole);
  const TriangleMesh joined = pieces.result(), reference = one.result();
  EXPECT_GT(joined.triangles.size(), 100u);
  EXPECT_EQ(joined.triangles.size(), reference.triangles.size());
  EXPECT_EQ(openEdges(joined), openEdges(reference));
  EXPECT_EQ(joined.vertices.size(), reference.vertices.size());
}

}  // namespace
}  // namespace trephine
