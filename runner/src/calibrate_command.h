// `burrlab calibrate`: fits c_e and alpha to measured steady penetration
// velocities (analysis/calibration.h) and reports identifiability and
// profile-likelihood intervals.
#ifndef BURRLAB_RUNNER_CALIBRATE_COMMAND_H_
#define BURRLAB_RUNNER_CALIBRATE_COMMAND_H_

#include <ostream>

#include "command_table.h"

namespace burrlab::runner {

// `burrlab calibrate --measured FILE [--radius-mm R] [--json]`; args start
// after "calibrate".
int RunCalibrateCommand(const Args& args, std::ostream& out, std::ostream& err);

}  // namespace burrlab::runner

#endif  // BURRLAB_RUNNER_CALIBRATE_COMMAND_H_
