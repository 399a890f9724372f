// Runs saved inputs through a fuzz target's LLVMFuzzerTestOneInput without
// libFuzzer, so that every test build (release, AddressSanitizer+UBSan) replays
// the inputs that once broke a parser.
//
//   replay_volume_reader tests/fuzz/regressions/volume_reader [more files or directories]
//
// A failing input crashes the program (the targets trap on a broken
// invariant; the sanitizers abort on a report); the name of each input is
// printed before it runs, so the log says which one it was.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

namespace {

std::vector<std::filesystem::path> inputsOf(const std::filesystem::path& argument) {
  std::vector<std::filesystem::path> inputs;
  if (std::filesystem::is_directory(argument)) {
    for (const auto& entry : std::filesystem::directory_iterator(argument))
      if (entry.is_regular_file()) inputs.push_back(entry.path());
    std::sort(inputs.begin(), inputs.end());
  } else if (std::filesystem::is_regular_file(argument)) {
    inputs.push_back(argument);
  }
  return inputs;
}

}  // namespace

int main(int argc, char** argv) {
  size_t replayed = 0;
  for (int a = 1; a < argc; ++a) {
    const std::vector<std::filesystem::path> inputs = inputsOf(argv[a]);
    if (inputs.empty()) {
      std::fprintf(stderr, "%s: no input files there\n", argv[a]);
      return 2;
    }
    for (const auto& input : inputs) {
      std::printf("%s\n", input.c_str());
      std::fflush(stdout);
      std::ifstream in(input, std::ios::binary);
      const std::vector<uint8_t> bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
      LLVMFuzzerTestOneInput(bytes.data(), bytes.size());
      ++replayed;
    }
  }
  if (replayed == 0) {
    std::fprintf(stderr, "usage: %s INPUT_FILE_OR_DIRECTORY...\n", argv[0]);
    return 2;
  }
  std::printf("replayed %zu inputs without a failure\n", replayed);
  return 0;
}
