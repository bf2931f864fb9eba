// The seeded random streams.
#include "burrlab/protocols/streams.h"

#include <boost/random/seed_seq.hpp>
#include <iterator>

namespace burrlab::protocols {
namespace {

std::uint32_t Low(std::uint64_t v) {
  return static_cast<std::uint32_t>(v & 0xffffffffu);
}
std::uint32_t High(std::uint64_t v) {
  return static_cast<std::uint32_t>(v >> 32);
}

}  // namespace

boost::random::mt19937 StreamFor(std::uint64_t master_seed,
                                 StreamPurpose purpose, std::uint64_t a,
                                 std::uint64_t b) {
  const std::uint32_t words[] = {
      Low(master_seed), High(master_seed), static_cast<std::uint32_t>(purpose),
      Low(a),           High(a),           Low(b),
      High(b)};
  boost::random::seed_seq seq(std::begin(words), std::end(words));
  return boost::random::mt19937(seq);
}

std::uint64_t SeedFor(std::uint64_t master_seed, StreamPurpose purpose,
                      std::uint64_t a, std::uint64_t b) {
  boost::random::mt19937 rng = StreamFor(master_seed, purpose, a, b);
  const std::uint64_t lo = rng();
  const std::uint64_t hi = rng();
  return (hi << 32) | lo;
}

}  // namespace burrlab::protocols
