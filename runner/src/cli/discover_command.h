// `burrlab discover`: the model-gap workflow (analysis/model_gap/discover.h) on
// measured steady penetration velocities, with a report for machines
// (report.json), one for people (report.md) and plots (PNG).
#ifndef BURRLAB_RUNNER_CLI_DISCOVER_COMMAND_H_
#define BURRLAB_RUNNER_CLI_DISCOVER_COMMAND_H_

#include <ostream>

#include "cli/command_table.h"

namespace burrlab::runner {

// `burrlab discover --measured FILE --out DIR [--radius-mm R]
// [--reference MATERIAL] [--json]`; args start after "discover". A first
// argument "matrix" runs RunDiscoverMatrixCommand with the rest.
int RunDiscoverCommand(const Args& args, std::ostream& out, std::ostream& err);

// `burrlab discover matrix [--seeds N] [--null-seeds N] [--snr S1,...]
// [--material NAME] [--full-rig]` (old name: `discover-matrix`): the
// hidden-effect scenario matrix as a Markdown table (power against SNR,
// false-discovery rate).
int RunDiscoverMatrixCommand(const Args& args, std::ostream& out,
                             std::ostream& err);

}  // namespace burrlab::runner

#endif  // BURRLAB_RUNNER_CLI_DISCOVER_COMMAND_H_
