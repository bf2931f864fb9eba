// Independent pieces of work on a few threads (fits of blocks, variants and
// simulated studies), each writing only its own result.
#ifndef BURRLAB_RUNNER_STUDIES_PARALLEL_FOR_H_
#define BURRLAB_RUNNER_STUDIES_PARALLEL_FOR_H_

#include <functional>

namespace burrlab::runner {

// Runs task(0) ... task(n - 1) on up to `jobs` threads (on this one when
// jobs <= 1); `done` (may be empty) is called after each with the index
// finished, one call at a time.
void ParallelFor(int n, int jobs, const std::function<void(int)>& task,
                 const std::function<void(int)>& done = {});

}  // namespace burrlab::runner

#endif  // BURRLAB_RUNNER_STUDIES_PARALLEL_FOR_H_
