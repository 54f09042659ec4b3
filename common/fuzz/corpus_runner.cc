// The normal build's driver for a fuzz target (issue 18): runs the target's
// LLVMFuzzerTestOneInput once over every file of the folders (or the files)
// given on the command line, in name order, so each target's committed seed
// corpus and the crashes it once found are replayed by ctest
// (fuzz_corpus_<name>) without clang or libFuzzer. A crash, a sanitizer
// report or an escaped exception fails the test like any other; the file
// being run is printed first so the failing input is named.
//
// Linked instead of libFuzzer's main into fuzz_corpus_<name> (see
// cmake/EphorFuzz.cmake); tools/ephor fuzz builds the same target with
// libFuzzer for long runs.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

namespace {

std::vector<std::filesystem::path> inputs_of(const std::filesystem::path& arg) {
  std::vector<std::filesystem::path> files;
  if (std::filesystem::is_directory(arg)) {
    for (const auto& entry : std::filesystem::directory_iterator(arg))
      if (entry.is_regular_file()) files.push_back(entry.path());
    std::sort(files.begin(), files.end());
  } else {
    files.push_back(arg);
  }
  return files;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s CORPUS_DIR|FILE...\n", argv[0]);
    return 2;
  }
  std::size_t runs = 0;
  for (int a = 1; a < argc; ++a) {
    const std::filesystem::path arg(argv[a]);
    if (!std::filesystem::exists(arg)) {
      std::fprintf(stderr, "%s: %s: no such file or folder\n", argv[0], argv[a]);
      return 2;
    }
    for (const auto& file : inputs_of(arg)) {
      std::ifstream in(file, std::ios::binary);
      if (!in) {
        std::fprintf(stderr, "%s: %s: cannot open\n", argv[0], file.c_str());
        return 2;
      }
      const std::vector<char> bytes{std::istreambuf_iterator<char>(in),
                                    std::istreambuf_iterator<char>()};
      std::fprintf(stderr, "running %s (%zu bytes)\n", file.c_str(), bytes.size());
      // A copy of exactly the file's size: ASan sees a read past its end.
      std::vector<uint8_t> input(bytes.begin(), bytes.end());
      LLVMFuzzerTestOneInput(input.data(), input.size());
      ++runs;
    }
  }
  if (runs == 0) {
    std::fprintf(stderr, "%s: no inputs found\n", argv[0]);
    return 1;
  }
  std::fprintf(stderr, "%zu inputs ran without a crash\n", runs);
  return 0;
}
