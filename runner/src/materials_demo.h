// `burrlab sim materials`: the simulator on the three built-in materials, as
// tables and figures.
#ifndef BURRLAB_RUNNER_MATERIALS_DEMO_H_
#define BURRLAB_RUNNER_MATERIALS_DEMO_H_

#include <ostream>

#include "command_table.h"

namespace burrlab::runner {

// `burrlab sim materials`; args start after "materials".
int RunMaterialsDemoCommand(const Args& args, std::ostream& out,
                            std::ostream& err);

}  // namespace burrlab::runner

#endif  // BURRLAB_RUNNER_MATERIALS_DEMO_H_
