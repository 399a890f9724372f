#include "tests/support/TestSupport.h"

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>

namespace trephine::test {

std::filesystem::path sourceDir() { return TREPHINE_SOURCE_DIR; }
std::filesystem::path programPath() { return TREPHINE_PROGRAM; }

TempDir::TempDir(const std::string& prefix) {
  std::random_device device;
  for (int attempt = 0; attempt < 100; ++attempt) {
    auto candidate = std::filesystem::temp_directory_path() / (prefix + "-" + std::to_string(device()));
    if (std::filesystem::create_directory(candidate)) {
      m_path = candidate;
      return;
    }
  }
  throw std::runtime_error("cannot create a temporary directory");
}

TempDir::~TempDir() {
  std::error_code ec;
  std::filesystem::remove_all(m_path, ec);
}

std::filesystem::path TempDir::write(const std::string& name, const std::string& text) const {
  const auto file = m_path / name;
  std::filesystem::create_directories(file.parent_path());
  std::ofstream(file) << text;
  return file;
}

std::unique_ptr<Simulation> loadScene(const std::string& xml, Diagnostics& diagnostics,
                                      const SimulationOptions& options, const std::string& fileName) {
  return Simulation::fromString(xml, fileName, options, diagnostics);
}

std::unique_ptr<Simulation> loadSceneFile(const std::string& relative, const SimulationOptions& options) {
  Diagnostics d;
  auto simulation = Simulation::fromFile(sourceDir() / relative, options, d);
  EXPECT_TRUE(simulation) << relative << ":\n" << messages(d);
  return simulation;
}

std::unique_ptr<Simulation> runScene(const std::string& xml) {
  Diagnostics d;
  auto simulation = loadScene(xml, d);
  EXPECT_TRUE(simulation) << messages(d);
  if (simulation) simulation->run();
  return simulation;
}

void expectLoadError(const std::string& xml, const std::string& expected, const std::string& what) {
  Diagnostics d;
  EXPECT_FALSE(loadScene(xml, d)) << what;
  EXPECT_NE(messages(d).find(expected), std::string::npos) << what << ":\n" << messages(d);
}

std::string messages(const Diagnostics& diagnostics) {
  std::string s;
  for (const Diagnostic& d : diagnostics.all()) s += d.str() + "\n";
  return s;
}

int runProgram(const std::vector<std::string>& arguments, std::string* output, const std::string& environment) {
  std::string command = environment.empty() ? "" : environment + " ";
  command += "'" + programPath().string() + "'";
  for (const std::string& a : arguments) command += " '" + a + "'";
  command += " 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return -1;
  std::array<char, 4096> buffer{};
  std::string captured;
  size_t n = 0;
  while ((n = fread(buffer.data(), 1, buffer.size(), pipe)) > 0) captured.append(buffer.data(), n);
  const int status = pclose(pipe);
  if (output) *output = captured;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

int startProgram(const std::vector<std::string>& arguments) {
  const std::string program = programPath().string();
  std::vector<char*> argv;
  argv.push_back(const_cast<char*>(program.c_str()));
  for (const std::string& a : arguments) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  const pid_t pid = fork();
  if (pid == 0) {
    if (!freopen("/dev/null", "w", stdout) || !freopen("/dev/null", "w", stderr)) _exit(126);
    execv(program.c_str(), argv.data());
    _exit(127);
  }
  return pid;
}

int waitForProgram(int pid) {
  int status = 0;
  if (waitpid(pid, &status, 0) != pid) return -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

FakeViewerAssets::FakeViewerAssets() {
  std::ofstream(dir.path() / "index.html") << "<html></html>";
  std::ofstream(dir.path() / "viewer.js") << "// viewer";
}

std::string readFile(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

double counter(const Component& component, const std::string& name) {
  std::vector<Counter> counters;
  component.reportCounters(counters);
  for (const Counter& k : counters)
    if (k.name == name) return k.value;
  std::string reported;
  for (const Counter& k : counters) reported += " " + k.name;
  ADD_FAILURE() << component.typeName() << " reports no counter " << name << " (it reports:" << reported << ")";
  return std::numeric_limits<double>::quiet_NaN();
}

double componentCounter(const Simulation& simulation, const std::string& type, const std::string& name) {
  const Component* found = nullptr;
  for (const Component* c : simulation.scene().components()) {
    if (c->typeName() != type) continue;
    if (found) {
      ADD_FAILURE() << "more than one " << type << " in the scene: name the one whose " << name << " is meant";
      return std::numeric_limits<double>::quiet_NaN();
    }
    found = c;
  }
  if (!found) {
    ADD_FAILURE() << "no " << type << " in the scene, so no counter " << name;
    return std::numeric_limits<double>::quiet_NaN();
  }
  return counter(*found, name);
}

double componentCounterAt(const Simulation& simulation, const std::string& path, const std::string& name) {
  const Component* c = simulation.scene().findComponent(path);
  if (!c) {
    ADD_FAILURE() << "no component " << path << " in the scene, so no counter " << name;
    return std::numeric_limits<double>::quiet_NaN();
  }
  return counter(*c, name);
}

}  // namespace trephine::test
