// `burrlab analyze scores|rt|thresholds|kinematics DIR`: analyses of the
// results a study wrote (its BIDS exports), and `burrlab analyze power`.
// Exit codes: analysis/README.md.
#ifndef BURRLAB_RUNNER_CLI_ANALYZE_RESULTS_COMMANDS_H_
#define BURRLAB_RUNNER_CLI_ANALYZE_RESULTS_COMMANDS_H_

#include <ostream>
#include <string>

#include "burrlab/results_schema/bids_read.h"
#include "cli/command_table.h"

namespace burrlab::runner {

// The warning for a subject whose session stopped before its end, whose
// saved trials (in the exports of results folder `dir`) are analysed all the
// same: "burrlab: warning: sub-02's session is incomplete: it stopped after 6
// of 10 planned trials; its 6 trials are analysed, and `burrlab run PROTOCOL
// --subject 02 --out DIR --resume` finishes it\n" ("after 6 trials" when the
// plan depends on the answers).
std::string IncompleteSessionWarning(
    const results_schema::IncompleteSession& session, const std::string& dir);

// Scores, significance and same-different d' per block, with response times.
int RunScoresCommand(const Args& args, std::ostream& out, std::ostream& err);
// Response times per subject, block and condition.
int RunResponseTimesCommand(const Args& args, std::ostream& out,
                            std::ostream& err);
// Thresholds per subject and block by each method's estimator.
int RunThresholdsCommand(const Args& args, std::ostream& out,
                         std::ostream& err);
// Force and speed histograms, mean force and removal rate; two groups
// compared.
int RunKinematicsCommand(const Args& args, std::ostream& out,
                         std::ostream& err);
// Probability of a significant result from simulated studies.
int RunPowerCommand(const Args& args, std::ostream& out, std::ostream& err);
// Fits a simulated-observer population to a group result; optionally
// predicts another protocol with it.
int RunFitObserversCommand(const Args& args, std::ostream& out,
                           std::ostream& err);

}  // namespace burrlab::runner

#endif  // BURRLAB_RUNNER_CLI_ANALYZE_RESULTS_COMMANDS_H_
