// Command flags: CLI11 parses the words, a FlagSet turns each flag's text into
// a checked value. Every problem becomes one line naming the flag and the text
// given, e.g. "--radius-mm must be a positive number of mm, got '-1'".
#ifndef BURRLAB_RUNNER_CLI_FLAGS_H_
#define BURRLAB_RUNNER_CLI_FLAGS_H_

#include <cstdint>
#include <deque>
#include <functional>
#include <glm/vec3.hpp>
#include <limits>
#include <optional>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include "burrlab/base/result.h"
#include "cli/command_table.h"

namespace CLI {
class App;
class Option;
}  // namespace CLI

namespace burrlab::runner {

// A finite number: no NaN, no infinity, no overflow, no trailing characters.
Result<double> ParseNumber(std::string_view flag, std::string_view text);
// A finite number > 0; `unit` names the unit in the error ("mm", "N").
Result<double> ParsePositive(std::string_view flag, std::string_view text,
                             std::string_view unit);
// A finite number >= 0.
Result<double> ParseNonNegative(std::string_view flag, std::string_view text,
                                std::string_view unit);
// A whole number in [min, max].
Result<std::int64_t> ParseInteger(std::string_view flag, std::string_view text,
                                  std::int64_t min, std::int64_t max);
// A whole number in [0, 2^64).
Result<std::uint64_t> ParseUnsigned(std::string_view flag,
                                    std::string_view text);
// A master seed: a whole number in [0, 2^64), bare or as the exports write
// it ("seed-N", results_schema::SeedText).
Result<std::uint64_t> ParseSeed(std::string_view flag, std::string_view text);
// "X,Y,Z": three finite numbers, not all zero.
Result<glm::dvec3> ParseDirection(std::string_view flag, std::string_view text);

// The flags of one command. Each Add* call declares a flag on the CLI11 app
// and how its text becomes a value; Convert() checks the given ones after
// parsing. Flags not given keep the value the destination already holds.
class FlagSet {
 public:
  explicit FlagSet(CLI::App* app) : app_(app) {}
  FlagSet(const FlagSet&) = delete;
  FlagSet& operator=(const FlagSet&) = delete;

  // A number > 0 and <= max; `unit` names the unit in errors ("mm").
  CLI::Option* AddPositive(
      const std::string& name, const std::string& help, std::string_view unit,
      double* value, double max = std::numeric_limits<double>::infinity());
  CLI::Option* AddNonNegative(const std::string& name, const std::string& help,
                              std::string_view unit, double* value);
  // The same, into a value that stays unset when the flag is not given.
  CLI::Option* AddNonNegative(const std::string& name, const std::string& help,
                              std::string_view unit,
                              std::optional<double>* value);
  CLI::Option* AddInteger(const std::string& name, const std::string& help,
                          int min, int max, int* value);
  CLI::Option* AddUnsigned(const std::string& name, const std::string& help,
                           std::uint64_t* value);
  CLI::Option* AddSeed(const std::string& name, const std::string& help,
                       std::uint64_t* value);
  CLI::Option* AddDirection(const std::string& name, const std::string& help,
                            glm::dvec3* value);
  // One of `choices`, stored as its index.
  CLI::Option* AddChoice(const std::string& name, const std::string& help,
                         std::vector<std::string> choices, int* index);
  // Free text, taken as given.
  CLI::Option* AddText(const std::string& name, const std::string& help,
                       std::string* value);
  // A switch without a value.
  CLI::Option* AddSwitch(const std::string& name, const std::string& help,
                         bool* value);

  // Whether the flag `name` (e.g. "--c-e") appeared on the command line.
  bool Given(const std::string& name) const;

  // Parses `args`. Returns the exit code when the command is done: 0 after
  // printing --help to `out`, 1 after one error line on `err`; nullopt when
  // the command should go on (then call Convert).
  std::optional<int> Parse(const Args& args, std::ostream& out,
                           std::ostream& err);

  // Converts the given flags in declaration order; the first bad one's error.
  Status Convert() const;

 private:
  struct Flag {
    std::string name;
    std::string text;  // CLI11 writes the word given here
    CLI::Option* option = nullptr;
    std::function<Status(std::string_view)> convert;
  };
  CLI::Option* Add(const std::string& name, const std::string& help,
                   std::string type_name,
                   std::function<Status(std::string_view)> convert);

  CLI::App* app_;
  std::deque<Flag> flags_;  // a deque keeps `text` in place for CLI11
  std::vector<std::string> switches_;
};

}  // namespace burrlab::runner

#endif  // BURRLAB_RUNNER_CLI_FLAGS_H_
