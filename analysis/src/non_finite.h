// Private: NaN and infinity, for the analysis sources.
#ifndef BURRLAB_ANALYSIS_SRC_NON_FINITE_H_
#define BURRLAB_ANALYSIS_SRC_NON_FINITE_H_

#include <limits>

namespace burrlab::analysis::detail {

inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
inline constexpr double kInf = std::numeric_limits<double>::infinity();

}  // namespace burrlab::analysis::detail

#endif  // BURRLAB_ANALYSIS_SRC_NON_FINITE_H_
