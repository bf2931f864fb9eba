// `burrlab validate FILE...`: checks protocol files and prints every problem
// as path:line:col: error: ..., the source line and a caret.
#ifndef BURRLAB_RUNNER_CLI_VALIDATE_COMMAND_H_
#define BURRLAB_RUNNER_CLI_VALIDATE_COMMAND_H_

#include <ostream>

#include "cli/command_table.h"

namespace burrlab::runner {

// Exit 0 when every file is valid, 1 otherwise.
int RunValidateCommand(const Args& args, std::ostream& out, std::ostream& err);

}  // namespace burrlab::runner

#endif  // BURRLAB_RUNNER_CLI_VALIDATE_COMMAND_H_
