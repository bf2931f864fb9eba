// `burrlab sim ...`: the burr simulator on the command line (force-curve,
// descent, bench).
#ifndef BURRLAB_RUNNER_CLI_SIM_COMMANDS_H_
#define BURRLAB_RUNNER_CLI_SIM_COMMANDS_H_

#include <ostream>

#include "cli/command_table.h"

namespace burrlab::runner {

// `burrlab sim <command> ...`; args start after "sim".
int RunSimCommand(const Args& args, std::ostream& out, std::ostream& err);

}  // namespace burrlab::runner

#endif  // BURRLAB_RUNNER_CLI_SIM_COMMANDS_H_
