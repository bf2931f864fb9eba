// The small protocol the session tests run: same-different probe trials of
// PVC against bone, then a 2-down/1-up staircase of drill trials on the c_e
// increment over bone, every interval short.
#ifndef BURRLAB_TESTS_RUNNER_TWO_BLOCK_PROTOCOL_H_
#define BURRLAB_TESTS_RUNNER_TWO_BLOCK_PROTOCOL_H_

#include <fmt/format.h>

#include <string>
#include <string_view>

namespace burrlab::runner {

// The protocol's text: `sd_trials` same-different trials and a staircase of
// `stair_trials`, every interval `interval_s` long.
inline std::string TwoBlockProtocol(std::string_view study, int sd_trials,
                                    int stair_trials, double interval_s) {
  return fmt::format(R"(format = "burrlab-protocol/1"

[study]
name = "{0}"

[recording]
trace_hz = 100

[materials.pvc]
builtin = "pvc_k70"

[materials.bone]
builtin = "human_temporal_bone"

[axes.ce]
kind = "increment"
parameter = "c_e_n_per_mm2"
reference = "bone"

[[blocks]]
name = "sd"
method = "same_different"
task = "probe"
a = "pvc"
b = "bone"
trials = {1}
interval_s = {3}

[[blocks]]
name = "stairs"
method = "staircase"
task = "drill"
axis = "ce"
interval_s = {3}
n_down = 2
start_level = 0.5
step_scale = "log10"
step_down = 0.1
step_up = 0.1
floor = 0.01
ceiling = 2
max_trials = {2}
)",
                     study, sd_trials, stair_trials, interval_s);
}

}  // namespace burrlab::runner

#endif  // BURRLAB_TESTS_RUNNER_TWO_BLOCK_PROTOCOL_H_
