// `burrlab calibrate`: fits c_e and alpha to measured steady penetration
// velocities (analysis/model_gap/calibration.h) and reports identifiability and
// profile-likelihood intervals.
#ifndef BURRLAB_RUNNER_CALIBRATE_COMMAND_H_
#define BURRLAB_RUNNER_CALIBRATE_COMMAND_H_

#include <ostream>
#include <string>

#include "burrlab/analysis/model_gap/measured_data.h"
#include "burrlab/sim/result.h"
#include "command_table.h"

namespace burrlab::runner {

// `burrlab calibrate --measured FILE [--radius-mm R] [--json]`; args start
// after "calibrate".
int RunCalibrateCommand(const Args& args, std::ostream& out, std::ostream& err);

// Reads measured data (analysis::ReadMeasuredData) and settles the burr
// radius: the flag's value (`*radius_mm`, when `flag_given`) must agree with
// the file's burr_radius_mm column; without the flag the column's value;
// neither is an error naming `path`. Shared by calibrate and discover.
Result<analysis::MeasuredData> ReadMeasuredWithRadius(const std::string& path,
                                                      bool flag_given,
                                                      double* radius_mm);

}  // namespace burrlab::runner

#endif  // BURRLAB_RUNNER_CALIBRATE_COMMAND_H_
