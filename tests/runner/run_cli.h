// Running `burrlab` in-process for the runner tests: the exit code and
// everything printed (and, from example_protocol.h, the example protocols).
#ifndef BURRLAB_TESTS_RUNNER_RUN_CLI_H_
#define BURRLAB_TESTS_RUNNER_RUN_CLI_H_

#include <sstream>
#include <string>
#include <vector>

#include "burrlab/runner/cli.h"
#include "example_protocol.h"

namespace burrlab::runner {

// What one `burrlab ...` call returned and printed.
struct CliRun {
  int code = -1;
  std::string out;
  std::string err;
};

// Runs `burrlab args...` in this process.
inline CliRun RunBurrlab(const std::vector<std::string>& args) {
  std::ostringstream out, err;
  CliRun run;
  run.code = RunCli(args, out, err);
  run.out = out.str();
  run.err = err.str();
  return run;
}

}  // namespace burrlab::runner

#endif  // BURRLAB_TESTS_RUNNER_RUN_CLI_H_
