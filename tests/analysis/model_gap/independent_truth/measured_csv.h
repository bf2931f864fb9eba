// "Measured" settled-velocity data from the independent truth
// (settled_descent.h): a design of force levels and replicates, log-normal
// run-to-run noise drawn from a seed, and the CSV a user's rig would give
// (measured_data.h's columns run, material, burr_radius_mm, force_n,
// velocity_mm_s, velocity_definition = settled).
#ifndef BURRLAB_TESTS_ANALYSIS_MODEL_GAP_INDEPENDENT_TRUTH_MEASURED_CSV_H_
#define BURRLAB_TESTS_ANALYSIS_MODEL_GAP_INDEPENDENT_TRUTH_MEASURED_CSV_H_

#include <cstdint>
#include <string>
#include <vector>

#include "independent_truth/settled_descent.h"

namespace burrlab::analysis::independent_truth {

struct Design {
  std::string material_name = "human_temporal_bone";
  double c_e_n_per_mm2 = 2.145;  // the truth's base material
  double alpha_per_s = 0.087;
  double radius_mm = 1.0;
  // Force levels as loads F / (c_e R^2).
  std::vector<double> loads = {0.5, 0.7, 0.9, 1.1, 1.3, 1.5};
  int replicates = 4;
  double noise_cv = 0.1;  // of the log-normal run-to-run factor
  // The CSV's velocity_definition column (sim/descent.h's names).
  std::string velocity_definition = "settled";

  std::vector<double> ForcesN() const;
  // The standard deviation of log v, sqrt(ln(1 + cv^2)).
  double SigmaLogV() const;
};

// Human temporal bone and PVC K70 (dissertation §8.7's fitted constants).
Design BoneDesign();
Design PvcDesign();

// The design's material and burr with `mechanism` at `strength`; the bump
// sits at the middle of the design's log-force range, its width a sixth of
// that range.
Truth TruthFor(const Design& design, Mechanism mechanism, double strength);

// The noise-free settled velocity at each force level (0 where the burr does
// not cut, inf where it falls through).
std::vector<double> NoiseFreeVelocitiesMmS(const Design& design,
                                           const Truth& truth);

// The replicates' velocities, level by level: v exp(sigma z), z ~ N(0, 1)
// (median v), z drawn from `seed` in the same order whatever the truth (a
// level where v is not positive and finite is left out but still takes its
// draws), so two truths on one seed share their noise. noise_cv 0: none.
struct MeasuredRunValue {
  int run = 0;  // 1-based over the runs written
  double force_n = 0.0;
  double velocity_mm_s = 0.0;
};
std::vector<MeasuredRunValue> DrawRuns(const Design& design,
                                       const std::vector<double>& truth_mm_s,
                                       std::uint64_t seed);

// The CSV of `runs` (header run,material,burr_radius_mm,force_n,
// velocity_mm_s,velocity_definition; the force written so that it reads back
// exactly, the velocity to 10 significant digits).
std::string FormatCsv(const Design& design,
                      const std::vector<MeasuredRunValue>& runs);

// DrawRuns then FormatCsv.
std::string MeasuredCsv(const Design& design,
                        const std::vector<double>& truth_mm_s,
                        std::uint64_t seed);

}  // namespace burrlab::analysis::independent_truth

#endif  // BURRLAB_TESTS_ANALYSIS_MODEL_GAP_INDEPENDENT_TRUTH_MEASURED_CSV_H_
