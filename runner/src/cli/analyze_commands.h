// `burrlab analyze ...`: statistics on data files (psychometric fits with
// bootstrap intervals, d'). Exit codes: analysis/README.md.
#ifndef BURRLAB_RUNNER_CLI_ANALYZE_COMMANDS_H_
#define BURRLAB_RUNNER_CLI_ANALYZE_COMMANDS_H_

#include <ostream>

#include "cli/command_table.h"

namespace burrlab::runner {

// `burrlab analyze <command> ...`; args start after "analyze".
int RunAnalyzeCommand(const Args& args, std::ostream& out, std::ostream& err);

}  // namespace burrlab::runner

#endif  // BURRLAB_RUNNER_CLI_ANALYZE_COMMANDS_H_
