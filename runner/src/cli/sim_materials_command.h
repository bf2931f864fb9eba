// `burrlab sim materials`: the simulator on the three built-in materials, as
// tables and figures.
#ifndef BURRLAB_RUNNER_CLI_SIM_MATERIALS_COMMAND_H_
#define BURRLAB_RUNNER_CLI_SIM_MATERIALS_COMMAND_H_

#include <ostream>

#include "cli/command_table.h"

namespace burrlab::runner {

// `burrlab sim materials`; args start after "materials".
int RunSimMaterialsCommand(const Args& args, std::ostream& out,
                           std::ostream& err);

}  // namespace burrlab::runner

#endif  // BURRLAB_RUNNER_CLI_SIM_MATERIALS_COMMAND_H_
