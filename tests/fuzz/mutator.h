// A deterministic input mutator for the test suite's fuzz runs: from a seed,
// a corpus and a dictionary it makes the same sequence of inputs on every
// machine (std::mt19937_64 with explicit arithmetic, no std::*_distribution,
// whose output differs between standard libraries).
#ifndef BURRLAB_TESTS_FUZZ_MUTATOR_H_
#define BURRLAB_TESTS_FUZZ_MUTATOR_H_

#include <cstdint>
#include <random>
#include <string>
#include <string_view>
#include <vector>

namespace burrlab::fuzz {

// Tokens of a libFuzzer dictionary file: the quoted string of each
// `name="value"` line, with \\, \" and \xNN unescaped; comments and blank
// lines skipped.
std::vector<std::string> ParseDictionary(std::string_view text);

class Mutator {
 public:
  // `corpus` must not be empty; inputs stay at most `max_len` bytes.
  Mutator(std::uint64_t seed, std::vector<std::string> corpus,
          std::vector<std::string> dictionary, std::size_t max_len);

  // The next input: a corpus entry with one to five mutations stacked
  // (byte flips, inserted, deleted, duplicated or repeated ranges, splices
  // with another entry, dictionary tokens, numbers replaced by extremes,
  // line ends, byte-order marks and control bytes).
  std::string Next();

 private:
  std::size_t Below(std::size_t n);  // uniform in [0, n), n >= 1
  void MutateOnce(std::string* s);

  std::mt19937_64 engine_;
  std::vector<std::string> corpus_;
  std::vector<std::string> dictionary_;
  std::size_t max_len_;
};

}  // namespace burrlab::fuzz

#endif  // BURRLAB_TESTS_FUZZ_MUTATOR_H_
