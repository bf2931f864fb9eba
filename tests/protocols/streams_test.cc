// The seeded random streams: one per purpose and indices, repeatable, and
// SeedFor the stream's first two words.
#include "burrlab/protocols/streams.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <set>

namespace burrlab::protocols {
namespace {

TEST(Streams, DifferByPurposeAndIndexAndRepeatForTheSameInputs) {
  EXPECT_EQ(SeedFor(1, StreamPurpose::kErosion, 3, 1),
            SeedFor(1, StreamPurpose::kErosion, 3, 1));
  std::set<std::uint64_t> seeds;
  for (std::uint64_t purpose = 1; purpose <= 6; ++purpose) {
    for (std::uint64_t a = 0; a < 10; ++a) {
      seeds.insert(SeedFor(42, static_cast<StreamPurpose>(purpose), a, 0));
    }
  }
  EXPECT_EQ(seeds.size(), 60u);
  EXPECT_NE(SeedFor(1, StreamPurpose::kObserver),
            SeedFor(2, StreamPurpose::kObserver));
}

// SeedFor is the stream's first word (low half) and second (high half).
TEST(Streams, SeedForIsTheFirstTwoWordsOfTheStream) {
  boost::random::mt19937 rng = StreamFor(7, StreamPurpose::kPopulation, 2, 9);
  const std::uint64_t lo = rng();
  const std::uint64_t hi = rng();
  EXPECT_EQ(SeedFor(7, StreamPurpose::kPopulation, 2, 9), (hi << 32) | lo);
}

}  // namespace
}  // namespace burrlab::protocols
