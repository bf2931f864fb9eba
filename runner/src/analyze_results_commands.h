// `burrlab analyze scores|thresholds|kinematics DIR`: analyses of the
// results a study wrote (its BIDS exports), and `burrlab analyze power`.
// Exit codes: analysis/README.md.
#ifndef BURRLAB_RUNNER_ANALYZE_RESULTS_COMMANDS_H_
#define BURRLAB_RUNNER_ANALYZE_RESULTS_COMMANDS_H_

#include <ostream>

#include "command_table.h"

namespace burrlab::runner {

// Scores, significance and same-different d' per block.
int RunScoresCommand(const Args& args, std::ostream& out, std::ostream& err);
// Thresholds per subject and block by each method's estimator.
int RunThresholdsCommand(const Args& args, std::ostream& out,
                         std::ostream& err);
// Force and speed histograms, mean force and removal rate.
int RunKinematicsCommand(const Args& args, std::ostream& out,
                         std::ostream& err);
// Probability of a significant result from simulated studies.
int RunPowerCommand(const Args& args, std::ostream& out, std::ostream& err);
// Fits a simulated-observer population to a group result; optionally
// predicts another protocol with it.
int RunFitObserversCommand(const Args& args, std::ostream& out,
                           std::ostream& err);

}  // namespace burrlab::runner

#endif  // BURRLAB_RUNNER_ANALYZE_RESULTS_COMMANDS_H_
