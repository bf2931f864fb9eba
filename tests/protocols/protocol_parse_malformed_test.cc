// `burrlab validate` diagnostics for malformed protocol files: each case is
// the file text and the exact text an author sees (every problem, sorted by
// position, each with the source line and a caret). Parsing takes (path,
// text), so nothing touches the disk.
#include <gtest/gtest.h>

#include <string>
#include <string_view>

#include "burrlab/protocols/protocol.h"

namespace burrlab::protocols {
namespace {

struct MalformedCase {
  std::string_view name;
  std::string_view text;
  std::string_view expected;
};

// The expected texts were reviewed by hand: each names the key path, the
// value, the rule and (where one is close) a suggestion.
constexpr MalformedCase kCases[] = {
    {"bad_counterbalance",
     R"toml(format = "burrlab-protocol/1"

[study]
name = "t"

[materials.pvc]
builtin = "pvc_k70"

[materials.bone]
builtin = "human_temporal_bone"

[axes.ce]
kind = "ratio"
parameter = "c_e_n_per_mm2"
reference = "bone"

[counterbalance]
scheme = "latin"

[[blocks]]
method = "same_different"
task = "probe"
a = "pvc"
b = "bone"
)toml",
     R"toml(NAME:18:10: error: counterbalance.scheme must be one of none, latin_square, reverse, got "latin" (did you mean "latin_square"?)
scheme = "latin"
         ^
)toml"},
    {"bad_method",
     R"toml(format = "burrlab-protocol/1"

[study]
name = "t"

[materials.pvc]
builtin = "pvc_k70"

[materials.bone]
builtin = "human_temporal_bone"

[axes.ce]
kind = "ratio"
parameter = "c_e_n_per_mm2"
reference = "bone"

[[blocks]]
method = "same-different"
task = "probe"
a = "pvc"
b = "bone"
)toml",
     R"toml(NAME:18:10: error: blocks[1].method must be one of same_different, two_interval, constant_stimuli, limits, adjustment, staircase, quest, got "same-different" (did you mean "same_different"?)
method = "same-different"
         ^
)toml"},
    {"bad_task",
     R"toml(format = "burrlab-protocol/1"

[study]
name = "t"

[materials.pvc]
builtin = "pvc_k70"

[materials.bone]
builtin = "human_temporal_bone"

[axes.ce]
kind = "ratio"
parameter = "c_e_n_per_mm2"
reference = "bone"

[[blocks]]
method = "same_different"
task = "poke"
a = "pvc"
b = "bone"
)toml",
     R"toml(NAME:19:8: error: blocks[1].task must be one of probe, drill, got "poke" (did you mean "probe"?)
task = "poke"
       ^
)toml"},
    {"constant_one_level",
     R"toml(format = "burrlab-protocol/1"

[study]
name = "t"

[materials.pvc]
builtin = "pvc_k70"

[materials.bone]
builtin = "human_temporal_bone"

[axes.ce]
kind = "ratio"
parameter = "c_e_n_per_mm2"
reference = "bone"

[[blocks]]
method = "constant_stimuli"
task = "probe"
axis = "ce"
levels = [1.2]
)toml",
     R"toml(NAME:21:10: error: blocks[1].levels needs at least 2 distinct levels, got 1
levels = [1.2]
         ^
)toml"},
    {"duplicate_block_names",
     R"toml(format = "burrlab-protocol/1"

[study]
name = "t"

[materials.pvc]
builtin = "pvc_k70"

[materials.bone]
builtin = "human_temporal_bone"

[axes.ce]
kind = "ratio"
parameter = "c_e_n_per_mm2"
reference = "bone"

[[blocks]]
method = "same_different"
task = "probe"
a = "pvc"
b = "bone"
name = "x"

[[blocks]]
method = "same_different"
task = "probe"
a = "pvc"
b = "bone"
name = "x"
)toml",
     R"toml(NAME:29:8: error: blocks[2]: name "x" is already used by blocks[1]
name = "x"
       ^
)toml"},
    {"empty_study_name",
     R"toml(format = "burrlab-protocol/1"

[study]
name = ""

[materials.pvc]
builtin = "pvc_k70"

[materials.bone]
builtin = "human_temporal_bone"

[axes.ce]
kind = "ratio"
parameter = "c_e_n_per_mm2"
reference = "bone"

[[blocks]]
method = "same_different"
task = "probe"
a = "pvc"
b = "bone"
)toml",
     R"toml(NAME:4:8: error: study.name must not be empty
name = ""
       ^
)toml"},
    {"format_not_string",
     R"toml(format = 1

[study]
name = "t"

[materials.pvc]
builtin = "pvc_k70"

[materials.bone]
builtin = "human_temporal_bone"

[axes.ce]
kind = "ratio"
parameter = "c_e_n_per_mm2"
reference = "bone"

[[blocks]]
method = "same_different"
task = "probe"
a = "pvc"
b = "bone"
)toml",
     R"toml(NAME:1:10: error: format must be "burrlab-protocol/1", got an integer
format = 1
         ^
)toml"},
    {"inline_material_missing",
     R"toml(format = "burrlab-protocol/1"

[study]
name = "t"

[materials.pvc]
c_e_n_per_mm2 = 0.5
alpha_per_s = 0.3

[materials.bone]
builtin = "human_temporal_bone"

[axes.ce]
kind = "ratio"
parameter = "c_e_n_per_mm2"
reference = "bone"

[[blocks]]
method = "same_different"
task = "probe"
a = "pvc"
b = "bone"
)toml",
     R"toml(NAME:6:1: error: [materials.pvc] needs "builtin" or all of c_e_n_per_mm2, alpha_per_s, c_mu_n_per_mm2, mu, c_i_n_s_per_mm3 (missing c_mu_n_per_mm2, mu, c_i_n_s_per_mm3)
[materials.pvc]
^
)toml"},
    {"interval_count",
     R"toml(format = "burrlab-protocol/1"

[study]
name = "t"

[materials.pvc]
builtin = "pvc_k70"

[materials.bone]
builtin = "human_temporal_bone"

[axes.ce]
kind = "ratio"
parameter = "c_e_n_per_mm2"
reference = "bone"

[[blocks]]
method = "same_different"
task = "probe"
a = "pvc"
b = "bone"
interval_s = [20, 20, 20]
)toml",
     R"toml(NAME:22:14: error: blocks[1].interval_s must hold 2 durations (one per interval of this method), got 3
interval_s = [20, 20, 20]
             ^
)toml"},
    {"interval_too_long",
     R"toml(format = "burrlab-protocol/1"

[study]
name = "t"

[materials.pvc]
builtin = "pvc_k70"

[materials.bone]
builtin = "human_temporal_bone"

[axes.ce]
kind = "ratio"
parameter = "c_e_n_per_mm2"
reference = "bone"

[[blocks]]
method = "same_different"
task = "probe"
a = "pvc"
b = "bone"
interval_s = 900
)toml",
     R"toml(NAME:22:14: error: blocks[1].interval_s durations must be in [0.1, 600] s, got 900
interval_s = 900
             ^
)toml"},
    {"key_of_other_method",
     R"toml(format = "burrlab-protocol/1"

[study]
name = "t"

[materials.pvc]
builtin = "pvc_k70"

[materials.bone]
builtin = "human_temporal_bone"

[axes.ce]
kind = "ratio"
parameter = "c_e_n_per_mm2"
reference = "bone"

[[blocks]]
method = "same_different"
task = "probe"
a = "pvc"
b = "bone"
levels = [1, 2]
)toml",
     R"toml(NAME:22:1: error: key "levels" does not apply to method same_different
levels = [1, 2]
^
)toml"},
    {"level_outside_domain",
     R"toml(format = "burrlab-protocol/1"

[study]
name = "t"

[materials.pvc]
builtin = "pvc_k70"

[materials.bone]
builtin = "human_temporal_bone"

[axes.ce]
kind = "ratio"
parameter = "c_e_n_per_mm2"
reference = "bone"

[[blocks]]
method = "staircase"
task = "probe"
axis = "ce"
start_level = 2
floor = -1
max_trials = 20
)toml",
     R"toml(NAME:22:9: error: blocks[1].floor = -1 is outside the domain of axis "ce" (ratio: levels > 0)
floor = -1
        ^
)toml"},
    {"limits_jitter_below_floor",
     R"toml(format = "burrlab-protocol/1"

[study]
name = "t"

[materials.pvc]
builtin = "pvc_k70"

[materials.bone]
builtin = "human_temporal_bone"

[axes.ce]
kind = "ratio"
parameter = "c_e_n_per_mm2"
reference = "bone"

[[blocks]]
method = "limits"
task = "probe"
axis = "ce"
step = 0.1
ascending_start = 1.0
descending_start = 2
floor = 1
ceiling = 2
start_jitter_steps = 1
)toml",
     R"toml(NAME:17:1: error: blocks[1]: limits: ascending_start 1 jittered by up to 1 steps of 0.1 reaches 0.9, below floor_level 1
[[blocks]]
^
)toml"},
    {"log_interp_parameter",
     R"toml(format = "burrlab-protocol/1"

[study]
name = "t"

[materials.pvc]
builtin = "pvc_k70"

[materials.bone]
builtin = "human_temporal_bone"

[axes.mix]
kind = "log_interpolation"
parameter = "c_e_n_per_mm2"
from = "pvc"
to = "bone"

[[blocks]]
method = "same_different"
task = "probe"
a = "pvc"
b = "bone"
)toml",
     R"toml(NAME:14:13: error: axes.mix.parameter does not apply to kind log_interpolation (it moves every parameter)
parameter = "c_e_n_per_mm2"
            ^
)toml"},
    {"ratio_of_a_zero_parameter",
     R"toml(format = "burrlab-protocol/1"

[study]
name = "t"

[materials.soft]
c_e_n_per_mm2 = 0.5
alpha_per_s = 0
c_mu_n_per_mm2 = 0.1
mu = 0.5
c_i_n_s_per_mm3 = 0.001

[materials.bone]
builtin = "human_temporal_bone"

[axes.erosion]
kind = "ratio"
parameter = "alpha_per_s"
reference = "soft"

[[blocks]]
method = "same_different"
task = "probe"
a = "soft"
b = "bone"
)toml",
     R"toml(NAME:16:1: error: axes.erosion: material "soft" has alpha_per_s = 0; a ratio axis scales it, so every level would give 0 (use kind = "value")
[axes.erosion]
^
)toml"},
    {"log_interp_of_a_zero_parameter",
     R"toml(format = "burrlab-protocol/1"

[study]
name = "t"

[materials.soft]
c_e_n_per_mm2 = 0.5
alpha_per_s = 0.1
c_mu_n_per_mm2 = 0.1
mu = 0.5
c_i_n_s_per_mm3 = 0

[materials.bone]
builtin = "human_temporal_bone"

[axes.mix]
kind = "log_interpolation"
from = "soft"
to = "bone"

[[blocks]]
method = "same_different"
task = "probe"
a = "soft"
b = "bone"
)toml",
     R"toml(NAME:16:1: error: axes.mix: material "soft" has c_i_n_s_per_mm3 = 0; a log interpolation needs every parameter > 0
[axes.mix]
^
)toml"},
    {"many_errors",
     R"toml(format = "burrlab-protocol/1"

[study]
name = "t"

[materials.pvc]
builtin = "pvc_k70"

[materials.bone]
builtin = "human_temporal_bone"

[axes.ce]
kind = "ratio"
parameter = "c_e_n_per_mm2"
reference = "bone"

[[blocks]]
method = "same_different"
task = "probe"
a = "pvc"
b = "bone"
trials = 14
trails = 3

[[blocks]]
method = "same_different"
task = "poke"
a = "pvc"
b = "bone"
)toml",
     R"toml(NAME:22:10: error: blocks[1].trials = 14 cannot be balanced over AA, AB, BA and BB (same-different needs a multiple of 4)
trials = 14
         ^
NAME:23:1: error: unknown key "trails" in blocks[1] (did you mean "trials"?)
trails = 3
^
NAME:27:8: error: blocks[2].task must be one of probe, drill, got "poke" (did you mean "probe"?)
task = "poke"
       ^
)toml"},
    {"missing_format",
     R"toml(
[study]
name = "t"

[materials.pvc]
builtin = "pvc_k70"

[materials.bone]
builtin = "human_temporal_bone"

[axes.ce]
kind = "ratio"
parameter = "c_e_n_per_mm2"
reference = "bone"

[[blocks]]
method = "same_different"
task = "probe"
a = "pvc"
b = "bone"
)toml",
     R"toml(NAME:1:1: error: the protocol must start with format = "burrlab-protocol/1"

^
)toml"},
    {"missing_method",
     R"toml(format = "burrlab-protocol/1"

[study]
name = "t"

[materials.pvc]
builtin = "pvc_k70"

[materials.bone]
builtin = "human_temporal_bone"

[axes.ce]
kind = "ratio"
parameter = "c_e_n_per_mm2"
reference = "bone"

[[blocks]]
task = "probe"
)toml",
     R"toml(NAME:17:1: error: blocks[1] needs "method" (one of same_different, two_interval, constant_stimuli, limits, adjustment, staircase, quest)
[[blocks]]
^
)toml"},
    {"missing_study",
     R"toml(format = "burrlab-protocol/1"


[materials.pvc]
builtin = "pvc_k70"

[materials.bone]
builtin = "human_temporal_bone"

[axes.ce]
kind = "ratio"
parameter = "c_e_n_per_mm2"
reference = "bone"

[[blocks]]
method = "same_different"
task = "probe"
a = "pvc"
b = "bone"
)toml",
     R"toml(NAME:1:1: error: the protocol needs a [study] table with a name
format = "burrlab-protocol/1"
^
)toml"},
    {"no_blocks",
     R"toml(format = "burrlab-protocol/1"

[study]
name = "t"

[materials.pvc]
builtin = "pvc_k70"

[materials.bone]
builtin = "human_temporal_bone"

[axes.ce]
kind = "ratio"
parameter = "c_e_n_per_mm2"
reference = "bone"
)toml",
     R"toml(NAME:1:1: error: the protocol needs at least one [[blocks]] table
format = "burrlab-protocol/1"
^
)toml"},
    {"observer_lapse",
     R"toml(format = "burrlab-protocol/1"

[study]
name = "t"

[materials.pvc]
builtin = "pvc_k70"

[materials.bone]
builtin = "human_temporal_bone"

[axes.ce]
kind = "ratio"
parameter = "c_e_n_per_mm2"
reference = "bone"

[observer]
lapse = 0.6

[[blocks]]
method = "same_different"
task = "probe"
a = "pvc"
b = "bone"
)toml",
     R"toml(NAME:18:9: error: observer.lapse must be in [0, 0.5), got 0.6
lapse = 0.6
        ^
)toml"},
    {"observer_rule",
     R"toml(format = "burrlab-protocol/1"

[study]
name = "t"

[materials.pvc]
builtin = "pvc_k70"

[materials.bone]
builtin = "human_temporal_bone"

[observer]
rule = "optimal"

[[blocks]]
method = "same_different"
task = "probe"
a = "pvc"
b = "bone"
)toml",
     R"toml(NAME:13:8: error: observer.rule must be one of fixed, differencing, likelihood, got "optimal"
rule = "optimal"
       ^
)toml"},
    {"odd_2afc",
     R"toml(format = "burrlab-protocol/1"

[study]
name = "t"

[materials.pvc]
builtin = "pvc_k70"

[materials.bone]
builtin = "human_temporal_bone"

[axes.ce]
kind = "ratio"
parameter = "c_e_n_per_mm2"
reference = "bone"

[[blocks]]
method = "two_interval"
task = "probe"
standard = "bone"
comparison = "pvc"
trials = 13
)toml",
     R"toml(NAME:22:10: error: blocks[1].trials = 13 cannot be balanced over intervals 1 and 2 (2afc needs an even number)
trials = 13
         ^
)toml"},
    {"quest_missing_table",
     R"toml(format = "burrlab-protocol/1"

[study]
name = "t"

[materials.pvc]
builtin = "pvc_k70"

[materials.bone]
builtin = "human_temporal_bone"

[axes.ce]
kind = "ratio"
parameter = "c_e_n_per_mm2"
reference = "bone"

[[blocks]]
method = "quest"
task = "probe"
axis = "ce"
)toml",
     R"toml(NAME:17:1: error: blocks[1] needs a [blocks.quest] table with at least tGuess and tGuessSd (log10 units)
[[blocks]]
^
)toml"},
    {"quest_pthreshold",
     R"toml(format = "burrlab-protocol/1"

[study]
name = "t"

[materials.pvc]
builtin = "pvc_k70"

[materials.bone]
builtin = "human_temporal_bone"

[axes.ce]
kind = "ratio"
parameter = "c_e_n_per_mm2"
reference = "bone"

[[blocks]]
method = "quest"
task = "probe"
axis = "ce"

[blocks.quest]
tGuess = 0.1
tGuessSd = 1
pThreshold = 1.5
)toml",
     R"toml(NAME:25:14: error: blocks[1].quest.pThreshold must be in (0, 1), got 1.5
pThreshold = 1.5
             ^
)toml"},
    {"reference_without_description",
     R"toml(format = "burrlab-protocol/1"

[study]
name = "t"

[materials.pvc]
builtin = "pvc_k70"

[materials.bone]
builtin = "human_temporal_bone"

[axes.ce]
kind = "ratio"
parameter = "c_e_n_per_mm2"
reference = "bone"

[[blocks]]
method = "two_interval"
design = "reference"
task = "drill"
a = "pvc"
b = "bone"
)toml",
     R"toml(NAME:17:1: error: blocks[1] needs "reference_description" (what the real sample is) or "reference_material" (a simulated reference)
[[blocks]]
^
)toml"},
    {"same_a_and_b",
     R"toml(format = "burrlab-protocol/1"

[study]
name = "t"

[materials.pvc]
builtin = "pvc_k70"

[materials.bone]
builtin = "human_temporal_bone"

[axes.ce]
kind = "ratio"
parameter = "c_e_n_per_mm2"
reference = "bone"

[[blocks]]
method = "same_different"
task = "probe"
a = "pvc"
b = "pvc"
)toml",
     R"toml(NAME:21:5: error: blocks[1]: a and b are both "pvc"; a same-different block needs two materials
b = "pvc"
    ^
)toml"},
    {"staircase_floor_above_ceiling",
     R"toml(format = "burrlab-protocol/1"

[study]
name = "t"

[materials.pvc]
builtin = "pvc_k70"

[materials.bone]
builtin = "human_temporal_bone"

[axes.ce]
kind = "ratio"
parameter = "c_e_n_per_mm2"
reference = "bone"

[[blocks]]
method = "staircase"
task = "probe"
axis = "ce"
start_level = 2
floor = 1
max_trials = 20
ceiling = 0.5
)toml",
     R"toml(NAME:17:1: error: blocks[1]: staircase: floor_level (1) must be below ceiling_level (0.5)
[[blocks]]
^
)toml"},
    {"staircase_never_stops",
     R"toml(format = "burrlab-protocol/1"

[study]
name = "t"

[materials.pvc]
builtin = "pvc_k70"

[materials.bone]
builtin = "human_temporal_bone"

[axes.ce]
kind = "ratio"
parameter = "c_e_n_per_mm2"
reference = "bone"

[[blocks]]
method = "staircase"
task = "probe"
axis = "ce"
start_level = 2
floor = 1
max_trials = 0
max_reversals = 8
)toml",
     R"toml(NAME:23:14: error: blocks[1]: the staircase can never stop: give max_trials (1 to 10000); a reversal limit alone never ends when the subject is always right at the floor
max_trials = 0
             ^
)toml"},
    {"staircase_without_max_trials",
     R"toml(format = "burrlab-protocol/1"

[study]
name = "t"

[materials.bone]
builtin = "human_temporal_bone"

[axes.ce]
kind = "ratio"
parameter = "c_e_n_per_mm2"
reference = "bone"

[[blocks]]
method = "staircase"
task = "probe"
axis = "ce"
start_level = 2
floor = 1
ceiling = 4
max_reversals = 8
)toml",
     R"toml(NAME:14:1: error: blocks[1] needs "max_trials" (1 to 10000): the staircase stops after that many trials, or sooner at max_reversals
[[blocks]]
^
)toml"},
    {"interleaved_staircase_without_max_trials",
     R"toml(format = "burrlab-protocol/1"

[study]
name = "t"

[materials.bone]
builtin = "human_temporal_bone"

[axes.ce]
kind = "ratio"
parameter = "c_e_n_per_mm2"
reference = "bone"

[[blocks]]
method = "staircase"
task = "probe"
axis = "ce"
floor = 1
ceiling = 4

[[blocks.staircases]]
start_level = 2
max_trials = 30

[[blocks.staircases]]
start_level = 3
)toml",
     R"toml(NAME:25:1: error: blocks[1].staircases[2] needs "max_trials" (1 to 10000), here or in blocks[1]: the staircase stops after that many trials, or sooner at max_reversals
[[blocks.staircases]]
^
)toml"},
    {"adjustment_without_floor_leaves_domain",
     R"toml(format = "burrlab-protocol/1"

[study]
name = "t"

[materials.bone]
builtin = "human_temporal_bone"

[axes.ce]
kind = "ratio"
parameter = "c_e_n_per_mm2"
reference = "bone"

[axes.inc]
kind = "increment"
parameter = "c_e_n_per_mm2"
reference = "bone"

[[blocks]]
method = "adjustment"
task = "drill"
axis = "inc"
start_level = 0.2
step = 0.05
ceiling = 1
max_steps = 40
)toml",
     R"toml(NAME:19:1: error: blocks[1]: with no floor, 40 steps of 0.05 down from start_level 0.2 reach level -1.8: axis "inc" (increment): level -1.8 is outside its domain (greater than -1); set floor
[[blocks]]
^
)toml"},
    {"constant_level_overflows",
     R"toml(format = "burrlab-protocol/1"

[study]
name = "t"

[materials.bone]
builtin = "human_temporal_bone"

[axes.ce]
kind = "ratio"
parameter = "c_e_n_per_mm2"
reference = "bone"

[axes.inc]
kind = "increment"
parameter = "c_e_n_per_mm2"
reference = "bone"

[[blocks]]
method = "constant_stimuli"
task = "probe"
axis = "ce"
levels = [0.5, 1e308, 2]
)toml",
     R"toml(NAME:23:16: error: blocks[1].levels: level 1e+308: axis "ce" (ratio): level 1e+308 gives c_e = inf, outside (0, 1000000] (the range [materials] accepts)
levels = [0.5, 1e308, 2]
               ^
)toml"},
    {"limits_default_floor_outside_domain",
     R"toml(format = "burrlab-protocol/1"

[study]
name = "t"

[materials.bone]
builtin = "human_temporal_bone"

[axes.ce]
kind = "ratio"
parameter = "c_e_n_per_mm2"
reference = "bone"

[axes.inc]
kind = "increment"
parameter = "c_e_n_per_mm2"
reference = "bone"

[[blocks]]
method = "limits"
task = "drill"
axis = "ce"
step = 0.1
ascending_start = 0.5
descending_start = 1.5
ceiling = 2
)toml",
     R"toml(NAME:19:1: error: blocks[1]: with no floor, series go on to level 0 (the default floor): axis "ce" (ratio): level 0 is outside its domain (greater than 0); set floor
[[blocks]]
^
)toml"},
    {"quest_ceiling_below_floor",
     R"toml(format = "burrlab-protocol/1"

[study]
name = "t"

[materials.bone]
builtin = "human_temporal_bone"

[axes.ce]
kind = "ratio"
parameter = "c_e_n_per_mm2"
reference = "bone"

[axes.inc]
kind = "increment"
parameter = "c_e_n_per_mm2"
reference = "bone"

[[blocks]]
method = "quest"
task = "drill"
axis = "ce"
floor = 2
ceiling = 1
[blocks.quest]
tGuess = 0
tGuessSd = 1
)toml",
     R"toml(NAME:24:11: error: blocks[1].ceiling = 1 must be above floor = 2
ceiling = 1
          ^
)toml"},
    {"staircase_without_ceiling_beyond_materials",
     R"toml(format = "burrlab-protocol/1"

[study]
name = "t"

[materials.bone]
builtin = "human_temporal_bone"

[axes.ce]
kind = "ratio"
parameter = "c_e_n_per_mm2"
reference = "bone"

[axes.inc]
kind = "increment"
parameter = "c_e_n_per_mm2"
reference = "bone"

[[blocks]]
method = "staircase"
task = "drill"
axis = "ce"
step_scale = "log10"
start_level = 1
step_down = 0.5
step_up = 0.5
floor = 0.5
max_trials = 40
)toml",
     R"toml(NAME:19:1: error: blocks[1]: with no ceiling, 40 steps of 0.5 up from start_level 1 reach level 1e+20: axis "ce" (ratio): level 1e+20 gives c_e = 2.145e+20, outside (0, 1000000] (the range [materials] accepts); set ceiling
[[blocks]]
^
)toml"},
    {"staircase_without_floor_leaves_domain",
     R"toml(format = "burrlab-protocol/1"

[study]
name = "t"

[materials.bone]
builtin = "human_temporal_bone"

[axes.ce]
kind = "ratio"
parameter = "c_e_n_per_mm2"
reference = "bone"

[axes.inc]
kind = "increment"
parameter = "c_e_n_per_mm2"
reference = "bone"

[[blocks]]
method = "staircase"
task = "probe"
axis = "inc"
start_level = 0.5
step_down = 0.1
step_up = 0.1
ceiling = 1
max_trials = 40
)toml",
     R"toml(NAME:19:1: error: blocks[1]: with no floor, 20 steps of 0.1 down from start_level 0.5 reach level -1.5: axis "inc" (increment): level -1.5 is outside its domain (greater than -1); set floor
[[blocks]]
^
)toml"},
    {"staircase_step_zero",
     R"toml(format = "burrlab-protocol/1"

[study]
name = "t"

[materials.pvc]
builtin = "pvc_k70"

[materials.bone]
builtin = "human_temporal_bone"

[axes.ce]
kind = "ratio"
parameter = "c_e_n_per_mm2"
reference = "bone"

[[blocks]]
method = "staircase"
task = "probe"
axis = "ce"
start_level = 2
floor = 1
max_trials = 20
step_down = 0
)toml",
     R"toml(NAME:24:13: error: blocks[1].step_down must be positive, got 0
step_down = 0
            ^
)toml"},
    {"tab_indented",
     R"toml(format = "burrlab-protocol/1"

[study]
name = "t"

[materials.pvc]
builtin = "pvc_k70"

[materials.bone]
builtin = "human_temporal_bone"

[axes.ce]
kind = "ratio"
parameter = "c_e_n_per_mm2"
reference = "bone"

[[blocks]]
method = "same_different"
task = "probe"
a = "pvc"
b = "bone"
	trials = 14
)toml",
     R"toml(NAME:22:11: error: blocks[1].trials = 14 cannot be balanced over AA, AB, BA and BB (same-different needs a multiple of 4)
	trials = 14
	         ^
)toml"},
    {"toml_syntax",
     R"toml(format = "burrlab-protocol/1"

[study]
name = "t"

[materials.pvc]
builtin = "pvc_k70"

[materials.bone]
builtin = "human_temporal_bone"

[axes.ce]
kind = "ratio"
parameter = "c_e_n_per_mm2"
reference = "bone"

[[blocks]]
method = "same_different"
task = "probe"
a = "pvc"
b = "bone"
trials = [12
)toml",
     R"toml(NAME:22:14: error: invalid TOML in array: encountered end-of-file
trials = [12
             ^
)toml"},
    {"trace_hz_300",
     R"toml(format = "burrlab-protocol/1"

[study]
name = "t"

[materials.pvc]
builtin = "pvc_k70"

[materials.bone]
builtin = "human_temporal_bone"

[axes.ce]
kind = "ratio"
parameter = "c_e_n_per_mm2"
reference = "bone"

[recording]
trace_hz = 300

[[blocks]]
method = "same_different"
task = "probe"
a = "pvc"
b = "bone"
)toml",
     R"toml(NAME:18:12: error: recording.trace_hz must divide 1000 (1, 2, 4, 5, 8, 10, ..., 500, 1000), got 300
trace_hz = 300
           ^
)toml"},
    {"trials_not_multiple_of_4",
     R"toml(format = "burrlab-protocol/1"

[study]
name = "t"

[materials.pvc]
builtin = "pvc_k70"

[materials.bone]
builtin = "human_temporal_bone"

[axes.ce]
kind = "ratio"
parameter = "c_e_n_per_mm2"
reference = "bone"

[[blocks]]
method = "same_different"
task = "probe"
a = "pvc"
b = "bone"
trials = 14
)toml",
     R"toml(NAME:22:10: error: blocks[1].trials = 14 cannot be balanced over AA, AB, BA and BB (same-different needs a multiple of 4)
trials = 14
         ^
)toml"},
    {"trials_wrong_type",
     R"toml(format = "burrlab-protocol/1"

[study]
name = "t"

[materials.pvc]
builtin = "pvc_k70"

[materials.bone]
builtin = "human_temporal_bone"

[axes.ce]
kind = "ratio"
parameter = "c_e_n_per_mm2"
reference = "bone"

[[blocks]]
method = "same_different"
task = "probe"
a = "pvc"
b = "bone"
trials = "12"
)toml",
     R"toml(NAME:22:10: error: blocks[1].trials must be an integer, got a string
trials = "12"
         ^
)toml"},
    {"unknown_axis",
     R"toml(format = "burrlab-protocol/1"

[study]
name = "t"

[materials.pvc]
builtin = "pvc_k70"

[materials.bone]
builtin = "human_temporal_bone"

[axes.ce]
kind = "ratio"
parameter = "c_e_n_per_mm2"
reference = "bone"

[[blocks]]
method = "staircase"
task = "probe"
axis = "c_e"
start_level = 2
floor = 1
max_trials = 20
)toml",
     R"toml(NAME:20:8: error: blocks[1].axis: unknown axis "c_e" (did you mean "ce"?)
axis = "c_e"
       ^
)toml"},
    {"unknown_block_key",
     R"toml(format = "burrlab-protocol/1"

[study]
name = "t"

[materials.pvc]
builtin = "pvc_k70"

[materials.bone]
builtin = "human_temporal_bone"

[axes.ce]
kind = "ratio"
parameter = "c_e_n_per_mm2"
reference = "bone"

[[blocks]]
method = "same_different"
task = "probe"
a = "pvc"
b = "bone"
trails = 12
)toml",
     R"toml(NAME:22:1: error: unknown key "trails" in blocks[1] (did you mean "trials"?)
trails = 12
^
)toml"},
    {"unknown_builtin",
     R"toml(format = "burrlab-protocol/1"

[study]
name = "t"

[materials.pvc]
builtin = "pvc_k7"

[materials.bone]
builtin = "human_temporal_bone"

[axes.ce]
kind = "ratio"
parameter = "c_e_n_per_mm2"
reference = "bone"

[[blocks]]
method = "same_different"
task = "probe"
a = "pvc"
b = "bone"
)toml",
     R"toml(NAME:7:11: error: materials.pvc.builtin: unknown material 'pvc_k7': known materials are human_temporal_bone, pettigrew_temporal_bone, pvc_k70 (did you mean 'pvc_k70'?)
builtin = "pvc_k7"
          ^
)toml"},
    {"unknown_material_in_block",
     R"toml(format = "burrlab-protocol/1"

[study]
name = "t"

[materials.pvc]
builtin = "pvc_k70"

[materials.bone]
builtin = "human_temporal_bone"

[axes.ce]
kind = "ratio"
parameter = "c_e_n_per_mm2"
reference = "bone"

[[blocks]]
method = "same_different"
task = "probe"
a = "pcv"
b = "bone"
)toml",
     R"toml(NAME:20:5: error: blocks[1].a: unknown material "pcv" (did you mean "pvc"?)
a = "pcv"
    ^
)toml"},
    {"unknown_top_key_list",
     R"toml(format = "burrlab-protocol/1"

[study]
name = "t"

[materials.pvc]
builtin = "pvc_k70"

[materials.bone]
builtin = "human_temporal_bone"

[axes.ce]
kind = "ratio"
parameter = "c_e_n_per_mm2"
reference = "bone"
[zzz]
q = 1

[[blocks]]
method = "same_different"
task = "probe"
a = "pvc"
b = "bone"
)toml",
     R"toml(NAME:16:1: error: unknown key "zzz" in the protocol; accepted: format, study, recording, observer, counterbalance, materials, axes, blocks
[zzz]
^
)toml"},
    {"unknown_top_key_suggestion",
     R"toml(format = "burrlab-protocol/1"

[study]
name = "t"

[materials.pvc]
builtin = "pvc_k70"

[materials.bone]
builtin = "human_temporal_bone"

[axes.ce]
kind = "ratio"
parameter = "c_e_n_per_mm2"
reference = "bone"
[stduy]
name = "x"

[[blocks]]
method = "same_different"
task = "probe"
a = "pvc"
b = "bone"
)toml",
     R"toml(NAME:16:1: error: unknown key "stduy" in the protocol (did you mean "study"?)
[stduy]
^
)toml"},
    {"wrong_format",
     R"toml(format = "burrlab-protocol/2"

[study]
name = "t"

[materials.pvc]
builtin = "pvc_k70"

[materials.bone]
builtin = "human_temporal_bone"

[axes.ce]
kind = "ratio"
parameter = "c_e_n_per_mm2"
reference = "bone"

[[blocks]]
method = "same_different"
task = "probe"
a = "pvc"
b = "bone"
)toml",
     R"toml(NAME:1:10: error: format must be "burrlab-protocol/1", got "burrlab-protocol/2"
format = "burrlab-protocol/2"
         ^
)toml"},
    {"practice_not_boolean",
     R"toml(format = "burrlab-protocol/1"

[study]
name = "t"

[materials.pvc]
builtin = "pvc_k70"

[materials.bone]
builtin = "human_temporal_bone"

[axes.ce]
kind = "ratio"
parameter = "c_e_n_per_mm2"
reference = "bone"

[[blocks]]
method = "same_different"
task = "probe"
a = "pvc"
b = "bone"
practice = "yes"
)toml",
     R"toml(NAME:22:12: error: blocks[1].practice must be true or false, got a string
practice = "yes"
           ^
)toml"},
    {"feedback_in_adjustment",
     R"toml(format = "burrlab-protocol/1"

[study]
name = "t"

[materials.pvc]
builtin = "pvc_k70"

[materials.bone]
builtin = "human_temporal_bone"

[axes.ce]
kind = "ratio"
parameter = "c_e_n_per_mm2"
reference = "bone"

[[blocks]]
method = "adjustment"
task = "probe"
axis = "ce"
start_level = 1.2
step = 0.05
floor = 0.5
ceiling = 2
practice = true
feedback = true
)toml",
     R"toml(NAME:26:12: error: blocks[1].feedback cannot be true: method adjustment has no correct answer (the level the subject sets is recorded)
feedback = true
           ^
)toml"},
    {"feedback_in_limits",
     R"toml(format = "burrlab-protocol/1"

[study]
name = "t"

[materials.pvc]
builtin = "pvc_k70"

[materials.bone]
builtin = "human_temporal_bone"

[axes.ce]
kind = "ratio"
parameter = "c_e_n_per_mm2"
reference = "bone"

[[blocks]]
method = "limits"
task = "probe"
axis = "ce"
step = 0.1
ascending_start = 1.0
descending_start = 1.8
floor = 0.5
ceiling = 2
feedback = true
)toml",
     R"toml(NAME:26:12: error: blocks[1].feedback cannot be true: method limits has no correct answer (the subject says whether the comparison felt different)
feedback = true
           ^
)toml"},
    {"feedback_in_yes_no_staircase",
     R"toml(format = "burrlab-protocol/1"

[study]
name = "t"

[materials.pvc]
builtin = "pvc_k70"

[materials.bone]
builtin = "human_temporal_bone"

[axes.ce]
kind = "ratio"
parameter = "c_e_n_per_mm2"
reference = "bone"

[[blocks]]
method = "staircase"
task = "probe"
axis = "ce"
response = "yesno"
start_level = 1.5
step_down = 0.1
step_up = 0.1
floor = 1.0
ceiling = 2
max_trials = 20
feedback = true
)toml",
     R"toml(NAME:28:12: error: blocks[1].feedback cannot be true: a yes/no staircase block counts every "yes" as correct, so feedback would only repeat the answer
feedback = true
           ^
)toml"},
    {"isi_negative",
     R"toml(format = "burrlab-protocol/1"

[study]
name = "t"

[materials.pvc]
builtin = "pvc_k70"

[materials.bone]
builtin = "human_temporal_bone"

[axes.ce]
kind = "ratio"
parameter = "c_e_n_per_mm2"
reference = "bone"

[[blocks]]
method = "same_different"
task = "probe"
a = "pvc"
b = "bone"
isi_s = -0.5
)toml",
     R"toml(NAME:22:9: error: blocks[1].isi_s must be in [0, 600], got -0.5
isi_s = -0.5
        ^
)toml"},
    {"iti_too_long",
     R"toml(format = "burrlab-protocol/1"

[study]
name = "t"

[materials.pvc]
builtin = "pvc_k70"

[materials.bone]
builtin = "human_temporal_bone"

[axes.ce]
kind = "ratio"
parameter = "c_e_n_per_mm2"
reference = "bone"

[[blocks]]
method = "same_different"
task = "probe"
a = "pvc"
b = "bone"
iti_s = 900
)toml",
     R"toml(NAME:22:9: error: blocks[1].iti_s must be in [0, 600], got 900
iti_s = 900
        ^
)toml"},
    {"response_deadline_zero",
     R"toml(format = "burrlab-protocol/1"

[study]
name = "t"

[materials.pvc]
builtin = "pvc_k70"

[materials.bone]
builtin = "human_temporal_bone"

[axes.ce]
kind = "ratio"
parameter = "c_e_n_per_mm2"
reference = "bone"

[[blocks]]
method = "same_different"
task = "probe"
a = "pvc"
b = "bone"
response_deadline_s = 0
)toml",
     R"toml(NAME:22:23: error: blocks[1].response_deadline_s must be in (0, 600], got 0
response_deadline_s = 0
                      ^
)toml"},
    {"break_every_zero",
     R"toml(format = "burrlab-protocol/1"

[study]
name = "t"

[materials.pvc]
builtin = "pvc_k70"

[materials.bone]
builtin = "human_temporal_bone"

[axes.ce]
kind = "ratio"
parameter = "c_e_n_per_mm2"
reference = "bone"

[[blocks]]
method = "same_different"
task = "probe"
a = "pvc"
b = "bone"
break_every = 0
)toml",
     R"toml(NAME:22:15: error: blocks[1].break_every must be in [1, 10000], got 0
break_every = 0
              ^
)toml"},
    {"break_every_fraction",
     R"toml(format = "burrlab-protocol/1"

[study]
name = "t"

[materials.pvc]
builtin = "pvc_k70"

[materials.bone]
builtin = "human_temporal_bone"

[axes.ce]
kind = "ratio"
parameter = "c_e_n_per_mm2"
reference = "bone"

[[blocks]]
method = "same_different"
task = "probe"
a = "pvc"
b = "bone"
break_every = 1.5
)toml",
     R"toml(NAME:22:15: error: blocks[1].break_every must be an integer, got a number
break_every = 1.5
              ^
)toml"},
    {"breaks_between_blocks_not_boolean",
     R"toml(format = "burrlab-protocol/1"

[study]
name = "t"
breaks_between_blocks = 1

[materials.pvc]
builtin = "pvc_k70"

[materials.bone]
builtin = "human_temporal_bone"

[axes.ce]
kind = "ratio"
parameter = "c_e_n_per_mm2"
reference = "bone"

[[blocks]]
method = "same_different"
task = "probe"
a = "pvc"
b = "bone"
)toml",
     R"toml(NAME:5:25: error: study.breaks_between_blocks must be true or false, got an integer
breaks_between_blocks = 1
                        ^
)toml"},
};

std::string Formatted(std::string_view path, std::string_view text) {
  const ParseOutcome outcome = ParseProtocol(path, text);
  std::string all;
  for (const Diagnostic& d : outcome.diagnostics) {
    all += FormatDiagnostic(path, text, d);
  }
  return all;
}

class Malformed : public ::testing::TestWithParam<MalformedCase> {};

TEST_P(Malformed, PrintsEveryProblemWithLineColumnAndCaret) {
  const MalformedCase& c = GetParam();
  const ParseOutcome outcome = ParseProtocol("NAME", c.text);
  EXPECT_FALSE(outcome.protocol.has_value());
  EXPECT_EQ(Formatted("NAME", c.text), c.expected);
}

INSTANTIATE_TEST_SUITE_P(
    ProtocolParse, Malformed, ::testing::ValuesIn(kCases),
    [](const ::testing::TestParamInfo<MalformedCase>& param_info) {
      return std::string(param_info.param.name);
    });

// Hostile bytes: the exact text shows every control character escaped, in
// the message and in the quoted source line, so none reaches the terminal.
TEST(ProtocolParse, ControlBytesInAKeyAndAValueAreEscaped) {
  // A raw ESC in a bare key and a raw BEL in a string stop toml++.
  const std::string raw_key =
      "format = \"burrlab-protocol/1\"\nbad\x1b[31mkey = 1\n";
  EXPECT_EQ(Formatted("NAME", raw_key),
            "NAME:2:4: error: invalid TOML in key-value pair: expected '=', "
            "saw '\\u001B'\n"
            "bad\\x1b[31mkey = 1\n"
            "   ^\n");
  const std::string raw_value =
      "format = \"burrlab-protocol/1\"\nscheme = \"la\x07tin\"\n";
  EXPECT_EQ(Formatted("NAME", raw_value),
            "NAME:2:13: error: invalid TOML in string: unescaped control "
            "characters other than TAB (U+0009) are explicitly prohibited\n"
            "scheme = \"la\\x07tin\"\n"
            "            ^\n");
  // TOML escapes put ESC into a key and BEL into a value that parse: the
  // messages quote them escaped.
  const std::string escaped = R"toml(format = "burrlab-protocol/1"
"bad\u001b[2Jkey" = 1

[study]
name = "t"

[counterbalance]
scheme = "la\u0007tin"

[[blocks]]
method = "same_different"
task = "probe"
)toml";
  EXPECT_EQ(Formatted("NAME", escaped),
            "NAME:2:1: error: unknown key \"bad\\x1b[2Jkey\" in the protocol; "
            "accepted: format, study, recording, observer, counterbalance, "
            "materials, axes, blocks\n"
            "\"bad\\u001b[2Jkey\" = 1\n"
            "^\n"
            "NAME:8:10: error: counterbalance.scheme must be one of none, "
            "latin_square, reverse, got \"la\\x07tin\"\n"
            "scheme = \"la\\u0007tin\"\n"
            "         ^\n"
            "NAME:10:1: error: blocks[1] needs \"a\" (a material id from "
            "[materials])\n"
            "[[blocks]]\n"
            "^\n"
            "NAME:10:1: error: blocks[1] needs \"b\" (a material id from "
            "[materials])\n"
            "[[blocks]]\n"
            "^\n");
}

// Many bad keys: every one is found, parsing and formatting stay linear
// (tests/bench/protocol_bench.cc times it) and at most 100 are printed, then
// a count of the rest.
TEST(ProtocolParse, FiftyThousandBadKeysPrintAHundredAndACount) {
  std::string text =
      "format = \"burrlab-protocol/1\"\n[study]\nname = \"t\"\n"
      "[materials.pvc]\nbuiltin = \"pvc_k70\"\n"
      "[materials.bone]\nbuiltin = \"human_temporal_bone\"\n"
      "[[blocks]]\nmethod = \"same_different\"\ntask = \"probe\"\n"
      "a = \"pvc\"\nb = \"bone\"\n[observer]\n";
  for (int i = 0; i < 50000; ++i) {
    text += 'k';  // appended piece by piece: GCC 12's -Wrestrict misfires on
    text += std::to_string(i);  // "k" + std::to_string(i) + ...
    text += " = 1\n";
  }
  const ParseOutcome outcome = ParseProtocol("big.toml", text);
  EXPECT_EQ(outcome.diagnostics.size(), 50000u);
  const std::string printed =
      FormatDiagnostics("big.toml", text, outcome.diagnostics);
  std::size_t errors = 0;
  for (std::size_t at = printed.find(": error: "); at != std::string::npos;
       at = printed.find(": error: ", at + 1)) {
    ++errors;
  }
  EXPECT_EQ(errors, kMaxPrintedDiagnostics);
  EXPECT_TRUE(printed.starts_with(
      "big.toml:14:1: error: unknown key \"k0\" in [observer]; accepted: "
      "weber_stiffness, weber_removal, lapse, criterion, rule, bias, "
      "probe_force_n, drill_force_n, exploration, force_spread, "
      "speed_spread, subject_force_spread, subject_speed_spread\nk0 = "
      "1\n^\n"))
      << printed.substr(0, 300);
  EXPECT_TRUE(printed.ends_with("big.toml: ... and 49900 more errors\n"))
      << printed.substr(printed.size() - 300);
}

TEST(ProtocolParse, AtLeastThirtyMalformedCases) {
  EXPECT_GE(std::size(kCases), 30u);
}

}  // namespace
}  // namespace burrlab::protocols
