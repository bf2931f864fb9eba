// Running `burrlab` in-process for the runner tests: the exit code and
// everything printed, and the example protocols parsed.
#ifndef BURRLAB_TESTS_RUNNER_RUN_CLI_H_
#define BURRLAB_TESTS_RUNNER_RUN_CLI_H_

#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

#include "burrlab/runner/cli.h"
#include "session.h"

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

// The path of protocols/examples/`name` in the source tree.
inline std::string ExamplePath(const std::string& name) {
  return std::string(BURRLAB_SOURCE_DIR) + "/protocols/examples/" + name;
}

// protocols/examples/`name`, parsed (a failed expectation when it is not).
inline protocols::Protocol ExampleProtocol(const std::string& name) {
  Result<LoadedProtocol> loaded = LoadProtocol(ExamplePath(name));
  EXPECT_TRUE(loaded.ok()) << loaded.error().message;
  return loaded.ok() ? loaded->protocol : protocols::Protocol{};
}

}  // namespace burrlab::runner

#endif  // BURRLAB_TESTS_RUNNER_RUN_CLI_H_
