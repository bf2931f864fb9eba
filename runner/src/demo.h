// `burrlab demo`: the simulator on the three built-in materials, as tables.
#ifndef BURRLAB_RUNNER_DEMO_H_
#define BURRLAB_RUNNER_DEMO_H_

#include <ostream>

#include "command_table.h"

namespace burrlab::runner {

// `burrlab demo`; args start after "demo".
int RunDemoCommand(const Args& args, std::ostream& out, std::ostream& err);

}  // namespace burrlab::runner

#endif  // BURRLAB_RUNNER_DEMO_H_
