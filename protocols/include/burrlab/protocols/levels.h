// The levels a track presents (staircases, adjustments, limits series, QUEST
// placements): step scales, and the rounding that gives every level one
// exact value, so a level printed twice prints the same.
//
// Why: moving a running level by repeated steps (level += 0.1, or level *=
// 10^0.2) accumulates rounding error, so one level of the track comes out as
// 0.6 on one trial and 0.6000000000000001 on another, and every reader that
// groups by value (pandas, R, burrlab's own pooling) splits it in two.
// PsychoPy's StairHandler and Palamedes' PAL_AMUD_updateUD move the running
// value that way and round nothing. burrlab instead:
//  - keeps a track's position as an anchor level (its start, or the bound it
//    last stopped at) and an offset in step-scale units, the sum of its moves,
//    rounded to the step (RoundToStep) after every move: the offset is the
//    exact decimal sum (0.2 + 0.1 is 0.3), so no error accumulates;
//  - computes each level afresh from anchor and offset (LevelAt): anchor +
//    offset on a linear scale, rounded to the step, so 0.5 - 3 x 0.1 is 0.2
//    and 0.3 - 3 x 0.1 is 0; anchor x 10^offset (log10) or anchor x
//    10^(offset/20) (dB), rounded to kLevelDigits significant digits, the
//    resolution of a level that has no step of its own (QUEST placements are
//    rounded so too).
// Twelve digits are far below anything a subject or the simulator can tell
// apart (a material parameter changes by 1e-12 of itself), and they make the
// levels the same with any libm, whose pow may differ in the last bit. The
// rounded value is the one presented and the one recorded.
#ifndef BURRLAB_PROTOCOLS_LEVELS_H_
#define BURRLAB_PROTOCOLS_LEVELS_H_

#include <string_view>

namespace burrlab::protocols {

// How a step size changes a level (staircases and the method of adjustment).
enum class StepScale {
  kLinear,   // a step s adds s to the level (level in any unit)
  kLog10,    // a step s multiplies the level by 10^s (level > 0)
  kDecibel,  // a step s multiplies the level by 10^(s/20) (level > 0)
};

// "linear", "log10" or "db".
std::string_view StepScaleName(StepScale scale);
// `level` moved by `steps` step units (signed; negative moves down), not
// rounded (for bounds and messages; tracks present LevelAt).
double ApplyStep(double level, double steps, StepScale scale);
// The level in the scale's own domain: level, log10(level) or 20 log10(level).
double ToScaleDomain(double level, StepScale scale);
// Inverse of ToScaleDomain.
double FromScaleDomain(double value, StepScale scale);

// Significant digits kept in a level (and in a step offset, counted from the
// step's leading digit).
inline constexpr int kLevelDigits = 12;

// `value` rounded to kLevelDigits significant digits: the double nearest to
// that decimal (0.39810717055349726 -> 0.398107170553). 0, infinities and NaN
// stay as they are.
double RoundSignificant(double value);

// The place RoundToStep rounds to: 10^(e - kLevelDigits + 1) for a step
// (> 0) whose leading digit is at 10^e (0.05 -> 1e-13).
double StepResolution(double step);

// `value` rounded to the decimal place kLevelDigits - 1 places below the
// leading digit of `step` (> 0): for a step of 0.05, to a multiple of 1e-13,
// so 0.49999999999999994 -> 0.5 and 5.55e-17 -> 0 (never -0).
double RoundToStep(double value, double step);

// The level `offset` step-scale units from `anchor`: anchor + offset (linear,
// rounded to `step`), anchor x 10^offset (log10) or anchor x 10^(offset/20)
// (dB), rounded to kLevelDigits significant digits. `step` is the track's
// smallest step; `offset` should already be rounded to it.
double LevelAt(double anchor, double offset, double step, StepScale scale);

}  // namespace burrlab::protocols

#endif  // BURRLAB_PROTOCOLS_LEVELS_H_
