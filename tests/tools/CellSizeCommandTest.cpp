// `trephine cellsize`: the prediction as text and JSON, the experiment's
// outputs, and clear errors for bad arguments and meshes.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cstdio>
#include <filesystem>

#include "tests/support/TestSupport.h"

namespace trephine {
namespace {

using test::runProgram;

// The number after "key": in a one-line JSON object; NaN when missing or null.
double jsonNumber(const std::string& json, const std::string& key) {
  const size_t at = json.find("\"" + key + "\": ");
  if (at == std::string::npos || json.compare(at + key.size() + 4, 4, "null") == 0) return NAN;
  return std::stod(json.substr(at + key.size() + 4));
}

TEST(CellSizeCommandTest, JsonGivesTheModelsCellAndTheAverageEdge) {
  std::string out;
  ASSERT_EQ(runProgram({"cellsize", "phantom:cube?cells=6", "--json"}, &out), 0) << out;
  // The cube phantom: 200 mm, 6 cells, each split into five tetrahedra.
  EXPECT_EQ(jsonNumber(out, "tetrahedra"), 1080.0) << out;
  const double a = jsonNumber(out, "delta_a"), trad = jsonNumber(out, "delta_trad");
  EXPECT_GT(a, trad) << "the model's cell is larger than the average edge (about 1.5 times): " << out;
  EXPECT_LT(a, 2 * trad) << out;
  // Another p_nc moves the cell: fewer collisions, larger cells.
  ASSERT_EQ(runProgram({"cellsize", "phantom:cube?cells=6", "--json", "--pnc", "0.999"}, &out), 0) << out;
  EXPECT_GT(jsonNumber(out, "delta_a"), a);
}

TEST(CellSizeCommandTest, TheExperimentWritesItsTableAndReportsTheZone) {
  test::TempDir dir;
  std::string out;
  ASSERT_EQ(runProgram({"cellsize", "phantom:cube?cells=6", "--experiment", "--json", "--frames", "2", "--rounds",
                        "1", "--out", dir.path().string()},
                       &out),
            0)
      << out;
  const double optimal = jsonNumber(out, "delta_opt");
  EXPECT_GT(optimal, 0.0) << out;
  // The errors are in widths of the zone around the optimum. Two frames on a
  // loaded machine can leave it no width at all (every neighbour of the
  // optimum more than 10% slower): then any other cell is infinitely many
  // widths away, written as null. Otherwise they are numbers.
  const size_t zone = out.find("\"zone\": [");
  ASSERT_NE(zone, std::string::npos) << out;
  const double low = std::stod(out.substr(zone + 9)), high = std::stod(out.substr(out.find(',', zone) + 1));
  EXPECT_LE(low, optimal) << out;
  EXPECT_GE(high, optimal) << out;
  if (low < optimal || high > optimal) {
    EXPECT_TRUE(std::isfinite(jsonNumber(out, "epsilon_a"))) << out;
    EXPECT_TRUE(std::isfinite(jsonNumber(out, "epsilon_trad"))) << out;
  }
  EXPECT_TRUE(std::filesystem::exists(dir.path() / "cellsize.json"));
  const std::string csv = test::readFile(dir.path() / "cellsize.csv");
  EXPECT_TRUE(csv.starts_with("cell_size_mm,cells_per_mm,time_us,fitted_us,")) << csv;
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 26) << "a header and 25 cell sizes";
}

// Outputs that cannot be written (a file-size limit, as a full disk): the
// experiment fails naming the file (before, it exited 0 with an empty
// cellsize.json), and a plot that cannot be written is the plot script's
// failure, not a missing python3-matplotlib.
TEST(CellSizeCommandTest, OutputsThatCannotBeWrittenAreErrorsNamingTheFile) {
  test::TempDir dir;
  const std::string program = test::programPath().string();
  const auto limited = [&](int kilobytes, const std::string& out, std::string& output) {
    const std::string command = "bash -c \"ulimit -f " + std::to_string(kilobytes) + "; exec '" + program +
                                "' cellsize 'phantom:cube?cells=4' --experiment --out '" + out + "'\" 2>&1";
    FILE* pipe = popen(command.c_str(), "r");
    char buffer[4096];
    output.clear();
    for (size_t n; (n = fread(buffer, 1, sizeof buffer, pipe)) > 0;) output.append(buffer, n);
    const int status = pclose(pipe);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  };
  std::string out;
  EXPECT_EQ(limited(0, (dir / "none").string(), out), 3) << out;
  EXPECT_NE(out.find("cellsize.csv"), std::string::npos) << out;
  EXPECT_NE(out.find("File too large"), std::string::npos) << out;
  EXPECT_FALSE(std::filesystem::exists(dir / "none/cellsize.json")) << "no empty JSON left";
  // Room for the table and the JSON, not for the plot.
  limited(12, (dir / "table").string(), out);
  ASSERT_TRUE(std::filesystem::exists(dir / "table/cellsize.json")) << out;
  EXPECT_EQ(out.find("needs python3-matplotlib"), std::string::npos) << out;
  EXPECT_NE(out.find("the plot script failed"), std::string::npos) << out;
}

TEST(CellSizeCommandTest, BadArgumentsAndMeshesAreClearErrors) {
  std::string out;
  EXPECT_EQ(runProgram({"cellsize"}, &out), 2);
  EXPECT_EQ(runProgram({"cellsize", "phantom:cube?cells=3", "--pnc", "1.5"}, &out), 2);
  EXPECT_NE(out.find("--pnc is a probability"), std::string::npos) << out;
  EXPECT_EQ(runProgram({"cellsize", "phantom:cube?cells=3", "--rt", "x"}, &out), 2);
  EXPECT_NE(out.find("--rt takes a number, not 'x'"), std::string::npos) << out;
  EXPECT_EQ(runProgram({"cellsize", "phantom:cube?cells=3", "--rt", "4", "--calibrate"}, &out), 2);
  EXPECT_EQ(runProgram({"cellsize", "phantom:cube?cells=3", "--experiment", "--frames", "2.5"}, &out), 2);
  EXPECT_NE(out.find("take whole counts"), std::string::npos) << out;
  EXPECT_EQ(runProgram({"cellsize", "/nonexistent/brain.mesh"}, &out), 1);
  EXPECT_NE(out.find("/nonexistent/brain.mesh"), std::string::npos) << out;
}

// --tool: the tool query's cell, which TetraBrain takes by default.
TEST(CellSizeCommandTest, AToolGetsTheToolQuerysCellAndItsExperiment) {
  test::TempDir dir;
  std::string out;
  ASSERT_EQ(runProgram({"cellsize", "phantom:cube?cells=20", "--tool", "2.5", "--json"}, &out), 0) << out;
  const double tool = jsonNumber(out, "delta_tool"), edge = jsonNumber(out, "delta_trad");
  EXPECT_EQ(jsonNumber(out, "shell_points"), 266.0) << "the 15 degree angle-step shell: " << out;
  EXPECT_DOUBLE_EQ(jsonNumber(out, "delta_half_edge"), 0.5 * edge) << out;
  // 12 mm edges against a 2.5 mm tool: cells near the tool's size, below
  // half an edge, and no smaller than the quarter edge the search stops at.
  EXPECT_GE(tool, 0.25 * edge - 1e-9) << out;
  EXPECT_LT(tool, 0.4 * edge) << out;
  // A tool twice as large, the same point count: its points are twice as far
  // apart, and the cell grows with them (on a deforming mesh, whose listed
  // tetrahedra cost and keep the optimum off the quarter edge).
  ASSERT_EQ(runProgram({"cellsize", "phantom:cube?cells=20", "--tool", "5", "--deforming", "--json"}, &out), 0)
      << out;
  const double five = jsonNumber(out, "delta_tool");
  EXPECT_GT(five, 0.3 * edge) << out;
  ASSERT_EQ(runProgram({"cellsize", "phantom:cube?cells=20", "--tool", "10", "--deforming", "--json"}, &out), 0)
      << out;
  EXPECT_GT(jsonNumber(out, "delta_tool"), 1.2 * five) << out;
  ASSERT_EQ(runProgram({"cellsize", "phantom:cube?cells=6", "--tool", "2.5", "--experiment", "--json", "--poses",
                        "20", "--rounds", "1", "--out", dir.path().string()},
                       &out),
            0)
      << out;
  EXPECT_GT(jsonNumber(out, "delta_opt"), 0.0) << out;
  EXPECT_TRUE(std::isfinite(jsonNumber(out, "epsilon_tool"))) << out;
  const std::string csv = test::readFile(dir.path() / "tool_cellsize.csv");
  EXPECT_TRUE(csv.starts_with("cell_size_mm,time_ns,fitted_ns,cells,listed,")) << csv;
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 18) << "a header and 17 cell sizes";
  EXPECT_EQ(runProgram({"cellsize", "phantom:cube?cells=3", "--tool", "-1"}, &out), 2);
  EXPECT_NE(out.find("--tool is the tool's radius"), std::string::npos) << out;
  EXPECT_EQ(runProgram({"cellsize", "phantom:cube?cells=3", "--tool", "2", "--rt", "4"}, &out), 2);
  EXPECT_NE(out.find("belong to the two-mesh model"), std::string::npos) << out;
}

}  // namespace
}  // namespace trephine
