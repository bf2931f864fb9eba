// Stub: being written.
#include "burrlab/sim/bench.h"
namespace burrlab::sim {
std::vector<BenchCase> DefaultBenchCases() { return {}; }
BenchCaseResult RunBenchCase(const BenchCase& c) { return BenchCaseResult{c, 0, 0, 0, 0}; }
}  // namespace burrlab::sim
