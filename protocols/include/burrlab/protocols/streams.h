// Seeded random streams. Every random draw of a session comes from one
// Boost.Random stream per purpose, each seeded from the master seed and the
// purpose (StreamFor), so drawing more for one purpose never shifts another:
// trial order (block plans, interval order, interleaving), level jitter
// (limits and adjustment starts), erosion (one seed per interval), the
// simulated hand's exploration (one stream per interval) and
// simulated-observer noise (one stream per trial).
#ifndef BURRLAB_PROTOCOLS_STREAMS_H_
#define BURRLAB_PROTOCOLS_STREAMS_H_

#include <boost/random/mersenne_twister.hpp>
#include <cstdint>

namespace burrlab::protocols {

// What a random stream is for; the value is part of its seed and never
// changes between versions.
enum class StreamPurpose : std::uint32_t {
  kTrialOrder = 1,   // block plans, interval order, interleaving
  kLevelJitter = 2,  // start-level jitter
  kErosion = 3,      // Russian-roulette erosion of one interval
  kObserver = 4,     // simulated observer noise, lapses, response times
  kSubjectSeed = 5,  // per-subject master seeds of a simulated study
  kPopulation = 6,   // simulated observer's per-subject parameters
  kExploration = 7,  // the simulated hand's force and speed of one interval
};

// A stream for `purpose` from `master_seed` and up to two indices (e.g.
// trial and interval), seeded through boost::random::seed_seq with the words
// (seed low, seed high, purpose, a low, a high, b low, b high).
boost::random::mt19937 StreamFor(std::uint64_t master_seed,
                                 StreamPurpose purpose, std::uint64_t a = 0,
                                 std::uint64_t b = 0);
// A 64-bit seed drawn from StreamFor(master_seed, purpose, a, b).
std::uint64_t SeedFor(std::uint64_t master_seed, StreamPurpose purpose,
                      std::uint64_t a = 0, std::uint64_t b = 0);

}  // namespace burrlab::protocols

#endif  // BURRLAB_PROTOCOLS_STREAMS_H_
