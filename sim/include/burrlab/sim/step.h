// One simulator step: collide -> force -> erode -> update moments (dissertation
// ch. 6-7). Model is read-only; State holds every mutable value (volume,
// octree, random stream, filter history, counters) and is allocated before the
// loop: Step allocates nothing, does no I/O, takes no lock and throws nothing,
// so it may run inside the 1 kHz tick.
#ifndef BURRLAB_SIM_STEP_H_
#define BURRLAB_SIM_STEP_H_

#include <boost/random/mersenne_twister.hpp>
#include <cstdint>
#include <glm/vec3.hpp>

#include "burrlab/base/result.h"
#include "burrlab/sim/model.h"
#include "burrlab/sim/moments.h"
#include "burrlab/sim/octree.h"
#include "burrlab/sim/seh.h"
#include "burrlab/sim/volume.h"

namespace burrlab::sim {

// What the device (or a simulated hand) gives the simulator each step.
struct Input {
  glm::dvec3 position_mm{0.0};  // burr centre
  glm::dvec3 velocity_mm_s{
      0.0};  // burr centre velocity (impact force, eq. 7.14)
  glm::dvec3 spindle_rad_s{0.0};  // angular velocity vector; zero = probing (no
                                  // friction, no erosion)
};

// What one step returns.
struct Output {
  glm::dvec3 force_n{0.0};  // to the device: filtered (§6.4.3) and clamped
  glm::dvec3 model_force_n{0.0};  // F_e + F_mu + F_i before filter and clamp
  glm::dvec3 elastic_n{0.0};      // F_e (eq. 7.3)
  glm::dvec3 friction_n{0.0};     // F_mu (eq. 7.13 or 6.23)
  glm::dvec3 impact_n{0.0};       // F_i (eq. 7.14)
  glm::dvec3 normal{0.0};         // n = -m1/|m1|, zero when undefined
  double m0_mm3 = 0.0;            // zeroth moment in the burr sphere
  glm::dvec3 m1_mm4{0.0};         // first moment about the burr centre
  double h_mm = 0.0;              // effective depth (eq. 7.2)
  double removed_mm3 = 0.0;  // solid-equivalent material eroded in this step
  std::int64_t eroded_units = 0;  // occupancy units removed in this step
  bool clamped = false;           // |force| was limited to max_force_n
  bool non_finite = false;  // the model produced NaN/inf: force set to zero
};

// Warning counters, MuJoCo style: fixed fields, never reset by Step.
struct StepCounters {
  std::int64_t steps = 0;
  std::int64_t clamped = 0;
  std::int64_t non_finite = 0;
  double removed_mm3 = 0.0;  // total material removed
  // Steps that computed the moments afresh (all of them unless
  // Model::moment_reuse_over_h > 0).
  std::int64_t moment_evaluations = 0;
};

class State {
 public:
  // Takes ownership of the volume, builds its octree and seeds the erosion
  // stream.
  static Result<State> Create(const Model& model, Volume volume,
                              std::uint64_t seed);

  const Volume& volume() const { return volume_; }
  const MomentOctree& octree() const { return octree_; }
  const StepCounters& counters() const { return counters_; }
  // Forgets the output filter's history (e.g. when the burr is teleported).
  void ResetFilter() noexcept { seh_.Reset(); }
  // Volume::ShiftContentUp, then rebuilds the octree; the erosion stream and
  // the counters go on. Allocates: for the descent rig between ticks, never
  // inside the real-time loop.
  void ShiftContentUp(int layers, std::uint8_t occupancy);

 private:
  friend void Step(const Model&, State&, const Input&, Output*) noexcept;
  Volume volume_;
  MomentOctree octree_;
  boost::random::mt19937 erosion_rng_;
  SampleEstimateHold seh_;
  StepCounters counters_;
  double max_erosion_factor_ = 1.0;
  // motor_power_limit: filtered removal rate the burr would reach without the
  // limit (mm^3/s), the motor's load.
  double unlimited_removal_mm3_per_s_ = 0.0;
  // Model::moment_reuse_over_h: the moments last computed, about the centre
  // they were computed at, less the material eroded since; reused by a step
  // whose centre is within reuse_reach_mm_ of that centre (none while < 0)
  // while the material eroded since is under the budget (r m0 when computed).
  Moments reuse_moments_;
  glm::dvec3 reuse_centre_mm_{0.0};
  double reuse_reach_mm_ = -1.0;
  double reuse_budget_mm3_ = 0.0;
  // The material the sphere sweeps over per millimetre moved, along the last
  // move between two computations (mm^3/mm): what that move added to m0
  // beyond the erosion's account.
  glm::dvec3 reuse_sweep_mm2_{0.0};
};

// Advances the simulation by model.dt_s. `output` must not be null.
void Step(const Model& model, State& state, const Input& input,
          Output* output) noexcept;

// Force only (no erosion, no filter): the elastic force and moments at a burr
// position, as used by force-depth curves.
Output EvaluateForce(const Model& model, const Volume& volume,
                     const MomentOctree& octree, const Input& input) noexcept;

}  // namespace burrlab::sim

#endif  // BURRLAB_SIM_STEP_H_
