// Private: the most trials a same-different, two-interval or constant-stimuli
// plan may hold.
#ifndef BURRLAB_PROTOCOLS_SRC_MAX_TRIALS_H_
#define BURRLAB_PROTOCOLS_SRC_MAX_TRIALS_H_

namespace burrlab::protocols {

inline constexpr int kMaxTrials = 100000;

}  // namespace burrlab::protocols

#endif  // BURRLAB_PROTOCOLS_SRC_MAX_TRIALS_H_
