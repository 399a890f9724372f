// <Include file="..."/>: resolved relative to the including file, errors in a
// part reported in that part's own file:line:col, cycles and missing files.
#include <gtest/gtest.h>

#include "tests/framework/scene/LoaderAssertions.h"

namespace trephine::test {
namespace {

// Loads `main` from `directory` the way `trephine run` would name it.
std::unique_ptr<Simulation> loadMain(const TempDir& directory, const std::string& main, Diagnostics& d,
                                     const SimulationOptions& options = {}) {
  const auto file = directory.write("main.xml", main);
  return loadScene(main, d, options, file.string());
}

std::string in(const TempDir& directory, const std::string& relative) {
  return (directory.path() / relative).lexically_normal().string();
}

TEST(IncludeTest, IncludesResolveRelativeToTheIncludingFile) {
  TempDir dir;
  dir.write("parts/patient.xml", R"(<Node name="patient">
  <Include file="plane.xml"/>
</Node>)");
  dir.write("parts/plane.xml", R"(<AnalyticPlane name="plane"/>)");
  Diagnostics d;
  auto simulation = loadMain(dir, R"(<Node name="root">
  <RequiredPlugin name="analytic"/>
  <Include file="parts/patient.xml"/>
</Node>)",
                             d);
  ASSERT_NE(simulation, nullptr) << messages(d);
  EXPECT_NE(simulation->scene().findComponent("patient/plane"), nullptr);
}

TEST(IncludeTest, SceneFileLoadedFromDiskResolvesIncludesFromItsDirectory) {
  TempDir dir;
  dir.write("scenes/part.xml", R"(<Node name="part"/>)");
  const auto main = dir.write("scenes/main.xml", R"(<Node name="root"><Include file="part.xml"/></Node>)");
  Diagnostics d;
  auto simulation = Simulation::fromFile(main, {}, d);
  ASSERT_NE(simulation, nullptr) << messages(d);
  EXPECT_NE(simulation->scene().root().findChild("part"), nullptr);
}

TEST(IncludeTest, PartIncludedTwiceInDifferentNodesIsNotACycle) {
  TempDir dir;
  dir.write("plane.xml", R"(<AnalyticPlane name="plane"/>)");
  Diagnostics d;
  auto simulation = loadMain(dir, R"(<Node name="root">
  <RequiredPlugin name="analytic"/>
  <Node name="a"><Include file="plane.xml"/></Node>
  <Node name="b"><Include file="plane.xml"/></Node>
</Node>)",
                             d);
  EXPECT_NE(simulation, nullptr) << messages(d);
}

TEST(IncludeTest, ErrorsInAPartIncludedTwiceSayWhereEachCopyWasIncluded) {
  TempDir dir;
  dir.write("plane.xml", R"(<AnalyticPlane name="plane" normal="0 0 0"/>)");
  Diagnostics d;
  EXPECT_EQ(loadMain(dir, R"(<Node name="root">
  <RequiredPlugin name="analytic"/>
  <Node name="a"><Include file="plane.xml"/></Node>
  <Node name="b"><Include file="plane.xml"/></Node>
</Node>)",
                     d),
            nullptr);
  ASSERT_EQ(d.errorCount(), 2);
  const std::string part = in(dir, "plane.xml") + ":1:37: error: invalid normal of AnalyticPlane 'plane'";
  const std::string main = (dir.path() / "main.xml").string();
  EXPECT_EQ(d.all()[0].str(), part + ": the normal must not be zero [included from " + main + ":3:33]");
  EXPECT_EQ(d.all()[1].str(), part + ": the normal must not be zero [included from " + main + ":4:33]");
}

TEST(IncludeTest, IncludeMayBeTheRootElement) {
  TempDir dir;
  dir.write("real.xml", R"(<Node name="root"/>)");
  Diagnostics d;
  auto simulation = loadMain(dir, R"(<Include file="real.xml"/>)", d);
  EXPECT_NE(simulation, nullptr) << messages(d);
}

TEST(IncludeTest, ErrorInAPartIsReportedWithThePartsPathLineAndColumn) {
  TempDir dir;
  dir.write("parts/tool.xml", R"(<Node name="tool">
  <Recordr name="r"/>
</Node>)");
  Diagnostics d;
  loadMain(dir, R"(<Node name="root">
  <Include file="parts/tool.xml"/>
</Node>)",
           d);
  EXPECT_TRUE(hasError(d, in(dir, "parts/tool.xml") + ":2:3", "unknown component 'Recordr', did you mean 'Recorder'?"));
  EXPECT_EQ(d.errorCount(), 1);
}

TEST(IncludeTest, MalformedPartIsReportedInThePart) {
  TempDir dir;
  dir.write("bad.xml", R"(<Node name="bad">
  <Node name="q"></Nod>
</Node>)");
  Diagnostics d;
  loadMain(dir, R"(<Node name="root"><Include file="bad.xml"/></Node>)", d);
  EXPECT_TRUE(hasError(d, in(dir, "bad.xml") + ":2:18", "malformed XML: end tag </Nod> does not match <Node>"));
}

TEST(IncludeTest, CycleIsReportedAtTheIncludeThatClosesItWithTheWholeChain) {
  TempDir dir;
  dir.write("a.xml", R"(<Node name="a"><Include file="b.xml"/></Node>)");
  dir.write("b.xml", R"(<Node name="b">
  <Include file="a.xml"/>
</Node>)");
  Diagnostics d;
  loadMain(dir, R"(<Node name="root"><Include file="a.xml"/></Node>)", d);
  EXPECT_TRUE(hasError(d, in(dir, "b.xml") + ":2:18",
                       "include cycle: " + in(dir, "a.xml") + " -> " + in(dir, "b.xml") + " -> " + in(dir, "a.xml")));
  EXPECT_EQ(d.errorCount(), 1);
}

TEST(IncludeTest, FileIncludingItselfIsACycle) {
  TempDir dir;
  Diagnostics d;
  loadMain(dir, R"(<Node name="root">
  <Include file="main.xml"/>
</Node>)",
           d);
  EXPECT_TRUE(hasError(d, in(dir, "main.xml") + ":2:18", "include cycle: " + in(dir, "main.xml") + " -> "));
}

TEST(IncludeTest, MissingFileIsReportedAtTheFileValue) {
  TempDir dir;
  Diagnostics d;
  loadMain(dir, R"(<Node name="root">
  <Include file="parts/missing.xml"/>
</Node>)",
           d);
  EXPECT_TRUE(hasError(d, in(dir, "main.xml") + ":2:18", "scene file not found: " + in(dir, "parts/missing.xml")));
  EXPECT_EQ(d.errorCount(), 1);
}

TEST(IncludeTest, DirectoryIsNotARegularFile) {
  TempDir dir;
  dir.write("parts/x.xml", "<Node name=\"x\"/>");
  Diagnostics d;
  loadMain(dir, R"(<Node name="root"><Include file="parts"/></Node>)", d);
  EXPECT_TRUE(hasError(d, in(dir, "main.xml") + ":1:34", "not a regular file: " + in(dir, "parts")));
}

TEST(IncludeTest, IncludeWithoutAFileShowsTheExpectedForm) {
  const Diagnostics d = loadFailure(R"(<Node name="root">
  <Include fil="part.xml"/>
</Node>)");
  EXPECT_TRUE(hasError(d, "inline.xml:2:12", "unknown attribute 'fil' of <Include>, did you mean 'file'?"));
  EXPECT_TRUE(hasError(d, "inline.xml:2:3", "<Include> needs a file attribute: <Include file=\"part.xml\"/>"));
  EXPECT_EQ(d.errorCount(), 2);
}

TEST(IncludeTest, ErrorsInTheMainFileAndInAPartAreAllReported) {
  TempDir dir;
  dir.write("part.xml", R"(<Node name="part" unit="mm"/>)");
  Diagnostics d;
  loadMain(dir, R"(<Node name="root">
  <Include file="part.xml"/>
  <Recordr/>
</Node>)",
           d);
  EXPECT_TRUE(hasError(d, in(dir, "part.xml") + ":1:19", "unknown attribute 'unit' of <Node>"));
  EXPECT_TRUE(hasError(d, in(dir, "main.xml") + ":3:3", "unknown component 'Recordr'"));
  EXPECT_EQ(d.errorCount(), 2);
}

}  // namespace
}  // namespace trephine::test
