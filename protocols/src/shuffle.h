// The one shuffle every trial plan uses.
#ifndef BURRLAB_PROTOCOLS_SRC_SHUFFLE_H_
#define BURRLAB_PROTOCOLS_SRC_SHUFFLE_H_

#include <boost/random/mersenne_twister.hpp>
#include <boost/random/uniform_int_distribution.hpp>
#include <utility>
#include <vector>

namespace burrlab::protocols {

// Fisher-Yates from the back over items[begin, end), one uniform draw per
// position: the same engine state gives the same order on every platform
// (std::shuffle's algorithm is implementation-defined).
template <typename T>
void Shuffle(std::vector<T>& items, int begin, int end,
             boost::random::mt19937& rng) {
  for (int i = end - 1; i > begin; --i) {
    boost::random::uniform_int_distribution<int> pick(begin, i);
    std::swap(items[i], items[pick(rng)]);
  }
}

// Shuffles the whole vector.
template <typename T>
void Shuffle(std::vector<T>& items, boost::random::mt19937& rng) {
  Shuffle(items, 0, static_cast<int>(items.size()), rng);
}

}  // namespace burrlab::protocols

#endif  // BURRLAB_PROTOCOLS_SRC_SHUFFLE_H_
