// Signal-detection sensitivity d' (Macmillan & Creelman 2005) for yes/no,
// m-alternative forced-choice and same-different designs, with the
// conventions of R psyphy's dprime.mAFC and dprime.SD. Rates must lie
// strictly inside (0, 1): correct rates of 0 or 1 first (e.g. 1/(2N)).
#ifndef BURRLAB_ANALYSIS_SDT_H_
#define BURRLAB_ANALYSIS_SDT_H_

#include <string_view>

#include "burrlab/base/result.h"

namespace burrlab::analysis {

// Yes/no: d' = z(H) - z(F).
Result<double> DPrimeYesNo(double hit_rate, double false_alarm_rate);

// m-AFC (m >= 2): the d' with Pc = integral phi(x - d') Phi(x)^(m-1) dx,
// searched in [-10, 10] as psyphy does (Pc < 1/m gives d' < 0). For m = 2
// this is sqrt(2) z(Pc).
Result<double> DPrimeMAfc(double proportion_correct, int alternatives);

// Same-different designs (Macmillan & Creelman 2005, ch. 9).
enum class SameDifferentModel {
  // Differencing: F = 2 Phi(-k / sqrt 2), H = Phi((d' - k) / sqrt 2) +
  // Phi((-d' - k) / sqrt 2); d' in [0, 10]; H = F gives 0, H < F an error.
  kDifferencing,
  // Independent observation: p(c)max = Phi((z(H) - z(F)) / 2),
  // d' = 2 z(1/2 + sqrt(2 p(c)max - 1) / 2), negative when H < F.
  kIndependentObservation,
};
// "differencing" or "independent-observation".
std::string_view SameDifferentModelName(SameDifferentModel model);

Result<double> DPrimeSameDifferent(double hit_rate, double false_alarm_rate,
                                   SameDifferentModel model);

}  // namespace burrlab::analysis

#endif  // BURRLAB_ANALYSIS_SDT_H_
