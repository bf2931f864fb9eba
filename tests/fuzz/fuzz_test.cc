// The fuzz targets in the test suite: every corpus file replayed, then a
// fixed number of deterministic mutations (mutator.h) per target, so a run is
// reproducible and its time bounded. An input that breaks a property fails
// the test with its bytes in hex and is saved under the build folder
// (tests/fuzz/failures/<target>-<n>.bin) for `fuzz_<target> FILE` or a unit
// test.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "fuzz_targets.h"
#include "mutator.h"

namespace burrlab::fuzz {

// gtest names a parameter by its target.
void PrintTo(const Target& target, std::ostream* out) { *out << target.name; }

namespace {

namespace fs = std::filesystem;

// Mutated inputs per target (the sanitizer build runs fewer: about 5x
// slower per input); BURRLAB_FUZZ_EXECS in the environment overrides it.
#ifndef BURRLAB_FUZZ_EXECS
#define BURRLAB_FUZZ_EXECS 30000
#endif
constexpr std::uint64_t kSeed = 20261127;
// Failures reported per target before the run stops.
constexpr int kMaxReported = 3;

std::string ReadFile(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

fs::path FuzzDir() { return fs::path(BURRLAB_SOURCE_DIR) / "tests" / "fuzz"; }

// The corpus files of a target, sorted by name.
std::vector<fs::path> CorpusFiles(std::string_view target) {
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(FuzzDir() / "corpus" / target)) {
    if (e.is_regular_file()) files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

std::string HexDump(std::string_view bytes) {
  std::string out;
  const std::size_t shown = std::min<std::size_t>(bytes.size(), 512);
  for (std::size_t i = 0; i < shown; ++i) {
    static constexpr char kDigits[] = "0123456789abcdef";
    const auto b = static_cast<unsigned char>(bytes[i]);
    if (i % 32 == 0) out += i == 0 ? "  " : "\n  ";
    out += kDigits[b >> 4];
    out += kDigits[b & 15];
  }
  if (shown < bytes.size())
    out += "\n  ... (" + std::to_string(bytes.size()) + " bytes)";
  return out;
}

// Saves a failing input; returns where.
fs::path SaveFailure(std::string_view target, std::uint64_t n,
                     std::string_view input) {
  const fs::path dir =
      fs::path(BURRLAB_BINARY_DIR) / "tests" / "fuzz" / "failures";
  fs::create_directories(dir);
  const fs::path path =
      dir / (std::string(target) + "-" + std::to_string(n) + ".bin");
  std::ofstream(path, std::ios::binary)
      .write(input.data(), static_cast<std::streamsize>(input.size()));
  return path;
}

std::string Joined(const Violations& violations) {
  std::string out;
  for (const std::string& v : violations) out += "\n  " + v;
  return out;
}

std::uint64_t Executions() {
  if (const char* env = std::getenv("BURRLAB_FUZZ_EXECS")) {
    return std::strtoull(env, nullptr, 10);
  }
  return BURRLAB_FUZZ_EXECS;
}

class FuzzTarget : public testing::TestWithParam<Target> {};

TEST_P(FuzzTarget, EveryCorpusFileHoldsTheProperties) {
  const Target& target = GetParam();
  const std::vector<fs::path> files = CorpusFiles(target.name);
  ASSERT_FALSE(files.empty()) << "no corpus for " << target.name;
  for (const fs::path& file : files) {
    const Violations violations = target.run(ReadFile(file));
    EXPECT_TRUE(violations.empty()) << file.string() << Joined(violations);
  }
}

TEST_P(FuzzTarget, MutatedInputsHoldTheProperties) {
  const Target& target = GetParam();
  std::vector<std::string> corpus;
  for (const fs::path& file : CorpusFiles(target.name)) {
    corpus.push_back(ReadFile(file));
  }
  ASSERT_FALSE(corpus.empty()) << "no corpus for " << target.name;
  const fs::path dictionary =
      FuzzDir() / "dictionaries" / (std::string(target.name) + ".dict");
  Mutator mutator(kSeed, std::move(corpus),
                  ParseDictionary(ReadFile(dictionary)), target.max_len);
  const std::uint64_t executions = Executions();
  int reported = 0;
  for (std::uint64_t n = 0; n < executions && reported < kMaxReported; ++n) {
    const std::string input = mutator.Next();
    const Violations violations = target.run(input);
    if (violations.empty()) continue;
    ++reported;
    ADD_FAILURE() << target.name << " input " << n << " (saved as "
                  << SaveFailure(target.name, n, input).string()
                  << "):" << Joined(violations) << "\n"
                  << HexDump(input);
  }
  std::cout << target.name << ": " << executions << " mutated executions (seed "
            << kSeed << ")\n";
}

INSTANTIATE_TEST_SUITE_P(Parsers, FuzzTarget, testing::ValuesIn(Targets()),
                         [](const testing::TestParamInfo<Target>& param) {
                           return std::string(param.param.name);
                         });

}  // namespace
}  // namespace burrlab::fuzz
