// Stub: being written.
#include "burrlab/sim/step.h"
namespace burrlab::sim {
Result<State> State::Create(const Model&, Volume volume, std::uint64_t) {
  State s;
  s.volume_ = std::move(volume);
  return s;
}
void Step(const Model&, State&, const Input&, Output* output) noexcept { *output = Output{}; }
Output EvaluateForce(const Model&, const Volume&, const MomentOctree&, const Input&) noexcept {
  return Output{};
}
}  // namespace burrlab::sim
