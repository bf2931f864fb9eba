// `burrlab calibrate`: fits c_e and alpha to measured steady penetration
// velocities (analysis/model_gap/calibration.h) and reports identifiability and
// profile-likelihood intervals.
#ifndef BURRLAB_RUNNER_CLI_CALIBRATE_COMMAND_H_
#define BURRLAB_RUNNER_CLI_CALIBRATE_COMMAND_H_

#include <optional>
#include <ostream>
#include <string>

#include "burrlab/analysis/model_gap/measured_data.h"
#include "burrlab/base/result.h"
#include "burrlab/sim/descent.h"
#include "cli/command_table.h"
#include "cli/flags.h"

namespace burrlab::runner {

// `burrlab calibrate --measured FILE [--radius-mm R] [--json]`; args start
// after "calibrate".
int RunCalibrateCommand(const Args& args, std::ostream& out, std::ostream& err);

// Reads measured data (analysis::ReadMeasuredData) and settles the burr
// radius and the velocity definition. The radius flag's value (`*radius_mm`,
// when `radius_given`) must agree with the file's burr_radius_mm column;
// without the flag the column's value; neither is an error naming `path`.
// The definition: `flag_definition` when given (a file whose
// velocity_definition column names another is refused, naming both), else
// the column's, else sim::kDefaultVelocityDefinition. Shared by calibrate and
// discover.
Result<analysis::MeasuredData> ReadMeasuredWithRadius(
    const std::string& path, bool radius_given, double* radius_mm,
    std::optional<sim::VelocityDefinition> flag_definition,
    sim::VelocityDefinition* definition);

// Declares --velocity-definition on `flags`; `*choice` receives the index
// into {"initial", "settled"} (-1 when not given).
void AddVelocityDefinitionFlag(FlagSet* flags, int* choice);
// The definition `choice` names (nothing for -1).
std::optional<sim::VelocityDefinition> VelocityDefinitionChoice(int choice);

}  // namespace burrlab::runner

#endif  // BURRLAB_RUNNER_CLI_CALIBRATE_COMMAND_H_
