// Private: an NLopt optimiser owned by a std::unique_ptr (nlopt_destroy when
// it is released).
#ifndef BURRLAB_ANALYSIS_SRC_NLOPT_PTR_H_
#define BURRLAB_ANALYSIS_SRC_NLOPT_PTR_H_

#include <nlopt.h>

#include <memory>

namespace burrlab::analysis::detail {

struct NloptDeleter {
  void operator()(nlopt_opt opt) const { nlopt_destroy(opt); }
};
using NloptPtr = std::unique_ptr<nlopt_opt_s, NloptDeleter>;

}  // namespace burrlab::analysis::detail

#endif  // BURRLAB_ANALYSIS_SRC_NLOPT_PTR_H_
