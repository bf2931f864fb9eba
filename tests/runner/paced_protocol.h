// A protocol that paces its session as an experimenter would with naive
// subjects (§13.5.1's familiarization before the scored trials): study and
// block instructions, a practice block with feedback, gaps between intervals
// and trials, a response deadline and rest breaks; every interval short.
#ifndef BURRLAB_TESTS_RUNNER_PACED_PROTOCOL_H_
#define BURRLAB_TESTS_RUNNER_PACED_PROTOCOL_H_

#include <fmt/format.h>

#include <string>

namespace burrlab::runner {

// Block "familiarize": 4 same-different practice trials (feedback by
// default); block "main": 8 scored trials with a break after the 4th and a
// response deadline of `deadline_s`; a break between the blocks. Both blocks
// wait isi_s between intervals and iti_s after each answer.
inline std::string PacedProtocol(double interval_s, double isi_s, double iti_s,
                                 double deadline_s) {
  return fmt::format(R"(format = "burrlab-protocol/1"

[study]
name = "paced"
instructions = "Feel both intervals, then say whether they felt the same."
breaks_between_blocks = true

[recording]
trace_hz = 100

[materials.pvc]
builtin = "pvc_k70"

[materials.bone]
builtin = "human_temporal_bone"

[[blocks]]
name = "familiarize"
method = "same_different"
task = "probe"
a = "pvc"
b = "bone"
trials = 4
interval_s = {0}
practice = true
instructions = "Practice: you will be told whether you were right."
isi_s = {1}
iti_s = {2}

[[blocks]]
name = "main"
method = "same_different"
task = "probe"
a = "pvc"
b = "bone"
trials = 8
interval_s = {0}
instructions = "Now the scored trials, without feedback."
break_every = 4
response_deadline_s = {3}
isi_s = {1}
iti_s = {2}
)",
                     interval_s, isi_s, iti_s, deadline_s);
}

}  // namespace burrlab::runner

#endif  // BURRLAB_TESTS_RUNNER_PACED_PROTOCOL_H_
