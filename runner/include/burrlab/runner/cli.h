// The burrlab command line: one table of subcommands (name, one-line help,
// handler), as in Ninja. main() is a thin layer over RunCli so tests drive the
// CLI without a process.
#ifndef BURRLAB_RUNNER_CLI_H_
#define BURRLAB_RUNNER_CLI_H_

#include <ostream>
#include <string>
#include <vector>

namespace burrlab::runner {

// Runs `burrlab <args...>` (args excludes the program name); returns the exit
// code: 0 success, 1 any error (reported as one "burrlab: ..." line on `err`).
// Throws nothing.
int RunCli(const std::vector<std::string>& args, std::ostream& out,
           std::ostream& err);

}  // namespace burrlab::runner

#endif  // BURRLAB_RUNNER_CLI_H_
