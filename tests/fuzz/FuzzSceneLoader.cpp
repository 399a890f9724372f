// libFuzzer target: arbitrary bytes as a scene file, through the whole load
// (XML, includes, plugins, fields, links, initialisation). Any
// crash, sanitizer report, leak or hang is a loader bug: a scene, however
// broken, must end in diagnostics.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <system_error>

#include "framework/runtime/Simulation.h"

namespace {

// The scene is named as a file in an empty directory of its own, so that a
// relative <Include file="..."/> finds nothing there; absolute and "../" paths
// still reach only what the loader accepts (regular files up to 16 MiB).
class ScratchDirectory {
 public:
  ScratchDirectory() {
    std::error_code ec;
    const auto base = std::filesystem::temp_directory_path(ec);
    m_path = (ec ? std::filesystem::path("/tmp") : base) / ("trephine-fuzz-" + std::to_string(::getpid()));
    std::filesystem::create_directories(m_path, ec);
  }
  ~ScratchDirectory() {
    std::error_code ec;
    std::filesystem::remove_all(m_path, ec);
  }
  std::string sceneName() const { return (m_path / "fuzz.xml").string(); }

 private:
  std::filesystem::path m_path;
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const ScratchDirectory directory;
  static const std::string sceneName = directory.sceneName();
  const std::string_view xml(reinterpret_cast<const char*>(data), size);
  trephine::Diagnostics diagnostics;
  auto simulation = trephine::Simulation::fromString(xml, sceneName, {}, diagnostics);
  // A scene either loads or says why; never both, never neither.
  if ((simulation != nullptr) == diagnostics.hasErrors()) __builtin_trap();
  return 0;
}
