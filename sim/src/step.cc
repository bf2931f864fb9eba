// The simulator step: collide -> force -> erode -> update moments (dissertation
// ch. 6-7). Nothing here allocates, locks, does I/O or throws.
#include "burrlab/sim/step.h"

#include <algorithm>
#include <boost/random/bernoulli_distribution.hpp>
#include <boost/random/uniform_01.hpp>
#include <cmath>
#include <numbers>

#include "burrlab/sim/finite.h"
#include "burrlab/sim/moments.h"
#include "octree_walk.h"

namespace burrlab::sim {
namespace {

double Norm(const glm::dvec3& v) {
  return std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z);
}
glm::dvec3 Cross(const glm::dvec3& a, const glm::dvec3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
double Dot(const glm::dvec3& a, const glm::dvec3& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}

// Erosion shape f(r/R) of eq. 7.12: maximal at the burr centre, zero at and
// beyond the rim. The dissertation leaves f open within those constraints;
// burrlab uses the smooth parabola 1 - (r/R)^2.
double ErosionShape(double r_over_r) {
  return r_over_r < 1.0 ? 1.0 - r_over_r * r_over_r : 0.0;
}

// Whether the first geometric skip of parameter p = 1 - keep (boost's
// floor(log(x) / log(keep)), x = 1 - u) is at least 2^count_log2, i.e. passes
// a block of that many voxels, decided without a logarithm where that is
// certain: exactly when ln x / ln keep >= count; it holds with a margin when
// x <= keep^count (1 - 1e-10), keep^count here by repeated squaring (relative
// error under 2^count_log2 ulp, 64 ulp for a block of 4^3). The margin stands
// for a quotient above count (1 + 1e-12) for any keep >= 1/2 (p < 1/2, the
// thinning's range), far more than the logarithms (< 1 ulp in glibc) and the
// division can take off. False means: compute the skip.
bool FirstSkipPassesBlock(double x, double keep, int count_log2) {
  double power = keep;
  for (int s = 0; s < count_log2; ++s) power *= power;
  return x <= power * (1.0 - 1e-10);
}

// Russian-roulette erosion (§7.3.2): each voxel with its centre inside the burr
// loses on average lambda * occupancy units per step, lambda = alpha k f(r/R) w
// dt, with k the voxel's erosion factor and w its overlap fraction with the
// burr (voxel-sphere approximation). The integer part is removed for certain,
// the fraction with that probability, so the expected loss equals the
// continuous rate exactly.
//
// Blocks are sampled by thinning instead of one draw per voxel:
// with p_max >= every voxel's probability in the block, candidates are found by
// geometric skips of parameter p_max and each is kept with probability p_i /
// p_max. Every voxel is still removed independently with probability p_i, at a
// cost proportional to the number of candidates rather than of voxels.
struct ErosionVisitor {
  // Blocks of up to 2^kThinningLevel voxels per axis are sampled by thinning.
  static constexpr int kThinningLevel = 2;
  // FirstSkipPassesBlock's margin holds for blocks of up to 4^3 voxels.
  static_assert(kThinningLevel <= 2);
  Volume* volume;
  MomentOctree* octree;
  boost::random::mt19937* rng;
  double radius_vox, eta_vox, rate_per_step;  // rate_per_step = alpha dt
  double max_factor;  // largest erosion factor of any label
  // Moments kept for reuse (Model::moment_reuse_over_h), about reuse_centre:
  // each removal takes its units out of them; null when none are kept.
  Moments* reuse = nullptr;
  double* reuse_budget_mm3 = nullptr;
  glm::dvec3 reuse_centre_vox{0.0};
  double inverse_r2 = 0.0;  // 1 / radius_vox^2
  double unit_mm3 = 0.0;    // volume of one occupancy unit
  double voxel_mm = 0.0;
  std::int64_t removed_units = 0;

  // Units to remove from one voxel; `probability` is its fractional part's
  // chance.
  double Expected(std::size_t index, std::uint8_t occupancy,
                  double d_vox) const {
    double overlap = 1.0;
    if (d_vox > radius_vox - eta_vox) {
      overlap = LensVolume(d_vox, radius_vox, eta_vox) /
                (4.0 / 3.0 * std::numbers::pi * eta_vox * eta_vox * eta_vox);
    }
    const double lambda = std::min(
        1.0, rate_per_step * volume->ErosionFactor(volume->labels()[index]) *
                 ErosionShape(d_vox / radius_vox) * overlap);
    return lambda * occupancy;
  }
  void Remove(int i, int j, int k, std::size_t index, std::uint8_t occupancy,
              int units, double d_vox) {
    units = std::min(units, static_cast<int>(occupancy));
    if (units <= 0) return;
    volume->occupancy()[index] = static_cast<std::uint8_t>(occupancy - units);
    octree->OnVoxelDecrement(i, j, k, units);
    removed_units += units;
    if (reuse != nullptr) {
      // The voxel's centre lies inside the burr; its voxel sphere counts
      // whole there, or by its overlap with the burr near the burr's surface
      // (eqs. 6.17, 6.21-6.22).
      double dm0 = units * unit_mm3;
      if (d_vox > radius_vox - eta_vox) {
        dm0 *= LensVolume(d_vox, radius_vox, eta_vox) /
               (4.0 / 3.0 * std::numbers::pi * eta_vox * eta_vox * eta_vox);
      }
      *reuse_budget_mm3 -= dm0;
      reuse->m0_mm3 -= dm0;
      reuse->m1_mm4 -=
          dm0 * voxel_mm *
          (glm::dvec3(i + 0.5, j + 0.5, k + 0.5) - reuse_centre_vox);
    }
  }

  internal::BlockAction OnBlock(const internal::BlockView& b) {
    if (b.level > kThinningLevel) return internal::BlockAction::kRefine;
    boost::random::uniform_01<double> uniform;
    // Bounds of p_max below without its square root and division (f = 1 -
    // d^2/R^2 to within rounding, widened as in the candidates' bound). Where
    // they show that the block is thinned and that its first skip passes it
    // (see below), p_max itself is never needed.
    const double f_approx = 1.0 - b.dmin2_vox2 * inverse_r2;
    const double p_scale = rate_per_step * max_factor * kSolidOccupancy;
    const double p_high = p_scale * (f_approx + 1e-9) * (1.0 + 1e-6);
    const double p_low = p_scale * (f_approx - 1e-9) * (1.0 - 1e-6);
    double first_x = -1.0;  // the first skip's 1 - u once drawn
    if (p_low >= 1e-9 && p_high < 0.5) {
      first_x = 1.0 - uniform(*rng);
      // keep^count falls with p: the bound from p_high is the smaller.
      if (FirstSkipPassesBlock(first_x, 1.0 - p_high, 3 * b.level)) {
        return internal::BlockAction::kAccept;
      }
    }
    const double p_max = std::min(
        1.0, rate_per_step * max_factor *
                 ErosionShape(b.DminVox() / radius_vox) * kSolidOccupancy);
    if (p_max >= 0.5)
      return internal::BlockAction::kRefine;  // per-voxel draws are cheaper
    if (p_max <= 0.0)
      return internal::BlockAction::kSkip;  // f = 0 on the whole block
    // Tiny probabilities would make the geometric skips overflow: draw per
    // voxel.
    if (p_max < 1e-9) return internal::BlockAction::kRefine;
    const int size = 1 << b.level;
    const int x0 = b.bx * size, y0 = b.by * size, z0 = b.bz * size;
    const std::int64_t count = std::int64_t{size} * size * size;
    // The skips are boost::random::geometric_distribution<std::int64_t,
    // double>(p_max)'s draws, computed as it does (the same uniform, the same
    // log(1 - p_max), the same quotient; the quotient is >= 0, so truncation
    // is its floor): byte-identical to drawing from it.
    const double keep = 1.0 - p_max;
    // Most blocks get no candidate: the first skip already passes the block,
    // i.e. x = 1 - u <= keep^count. Where x is clearly below keep^count (by
    // far more than the logarithm's and the division's rounding can move the
    // quotient, see FirstSkipPassesBlock) the block is done without a
    // logarithm; otherwise the skip is computed as boost computes it.
    if (first_x < 0.0) first_x = 1.0 - uniform(*rng);
    if (FirstSkipPassesBlock(first_x, keep, 3 * b.level)) {
      return internal::BlockAction::kAccept;
    }
    const double log_keep = std::log(keep);
    const auto skip = [&](double x) {
      return static_cast<std::int64_t>(std::log(x) / log_keep);
    };
    for (std::int64_t n = skip(first_x); n < count;
         n += 1 + skip(1.0 - uniform(*rng))) {
      const int cell = static_cast<int>(n);
      const int i = x0 + (cell & (size - 1)),
                j = y0 + ((cell >> b.level) & (size - 1)),
                k = z0 + (cell >> (2 * b.level));
      if (!volume->Contains(i, j, k)) continue;
      const std::size_t index = volume->Index(i, j, k);
      const std::uint8_t occupancy = volume->occupancy()[index];
      if (occupancy == 0) continue;
      const double dx = i + 0.5 - centre_vox.x, dy = j + 0.5 - centre_vox.y,
                   dz = k + 0.5 - centre_vox.z;
      const double d2 = dx * dx + dy * dy + dz * dz;
      const double threshold = uniform(*rng) * p_max;
      // The candidate is kept if threshold < p (Expected). Most are not, and
      // an upper bound of p without the square root, the division and the
      // lens shows it: p <= alpha dt k f occupancy with the overlap <= 1 and
      // f = 1 - d^2 / R^2, the bound widened far beyond rounding (1e-9 in f,
      // 1e-6 relative, against errors near 1e-15 and, for the lens, 1e-9).
      const double factor =
          rate_per_step * volume->ErosionFactor(volume->labels()[index]);
      const double bound =
          factor * occupancy * (1.0 - d2 * inverse_r2 + 1e-9) * (1.0 + 1e-6);
      if (threshold >= bound) continue;
      const double d = std::sqrt(d2);
      const double p = Expected(index, occupancy, d);
      if (threshold < p) Remove(i, j, k, index, occupancy, 1, d);
    }
    return internal::BlockAction::kAccept;
  }
  void OnVoxel(int i, int j, int k, std::uint8_t occupancy, const glm::dvec3&,
               double d2_vox2) {
    if (d2_vox2 >= radius_vox * radius_vox) return;
    const double d_vox = std::sqrt(d2_vox2);
    const std::size_t index = volume->Index(i, j, k);
    const double expected = Expected(index, occupancy, d_vox);
    double whole = std::floor(expected);
    const double fraction = expected - whole;
    if (fraction > 0.0) {
      boost::random::bernoulli_distribution<double> coin(fraction);
      if (coin(*rng)) whole += 1.0;
    }
    Remove(i, j, k, index, occupancy, static_cast<int>(whole), d_vox);
  }

  glm::dvec3 centre_vox{0.0};
};

// Friction of eq. 6.23: the Hertz pressure of eq. 6.13 over the contact disk of
// radius a* = sqrt(2Rh - h^2), sampled on the voxels that cross the burr
// surface, each pushing along (c x omega)/(|c||omega|) with area Delta sigma
// (6.19). Eq. 6.23 as printed measures xi_i perpendicular to omega; that puts
// every point of a contact whose normal is perpendicular to omega outside the
// contact disk and so gives no friction at theta = 90 deg, against fig. 6.4(b).
// burrlab measures xi_i in the contact plane, perpendicular to the surface
// normal, as eq. 6.13 intends.
struct SurfaceFrictionVisitor {
  double radius_vox, eta_vox, voxel_mm;
  glm::dvec3 normal, omega_hat;
  double contact_radius_mm,
      pressure_scale;  // pressure_scale = 3 |F_e| / (2 pi a^2)
  glm::dvec3 force{0.0};

  internal::BlockAction OnBlock(const internal::BlockView& b) {
    return b.DmaxVox() <= radius_vox - eta_vox ? internal::BlockAction::kSkip
                                               : internal::BlockAction::kRefine;
  }
  void OnVoxel(int, int, int, std::uint8_t occupancy,
               const glm::dvec3& offset_vox, double d2_vox2) {
    const double d_vox = std::sqrt(d2_vox2);
    if (d_vox <= radius_vox - eta_vox || d_vox <= 0.0) return;
    const double area =
        LensArea(d_vox, radius_vox, eta_vox) * voxel_mm * voxel_mm;  // eq. 6.19
    const glm::dvec3 c = offset_vox * voxel_mm;
    const double d = d_vox * voxel_mm;
    const glm::dvec3 surface_point =
        c * (RadicalPlaneDistance(d_vox, radius_vox, eta_vox) / d_vox);
    const glm::dvec3 xi = surface_point - Dot(surface_point, normal) * normal;
    const double q = Dot(xi, xi) / (contact_radius_mm * contact_radius_mm);
    if (q >= 1.0) return;
    const double pressure = pressure_scale * std::sqrt(1.0 - q);  // eq. 6.13
    const double density = occupancy / static_cast<double>(kSolidOccupancy);
    force += (density * area * pressure / d) * Cross(c, omega_hat);
  }
};

// Forces from the moments (eqs. 7.2, 7.3, 7.13, 7.14). Friction needs the
// volume only for the surface model of eq. 6.23.
void ComputeForces(const Model& model, const Volume& volume,
                   const MomentOctree& octree, const Input& input,
                   const Moments& moments, Output* out) {
  const double radius = model.radius_mm;
  out->m0_mm3 = moments.m0_mm3;
  out->m1_mm4 = moments.m1_mm4;
  out->h_mm = DepthFromM0(moments.m0_mm3, radius);
  const double depth_ratio = out->h_mm / radius;
  const double m1_norm = Norm(moments.m1_mm4);
  out->normal = m1_norm > 1e-12 * radius * radius * radius * radius
                    ? -moments.m1_mm4 / m1_norm
                    : glm::dvec3(0.0);
  const Material& mat = model.material;
  const Effects& effects = model.effects;
  // Eq. 7.3, with the effects' changes: a porous skeleton is softer by
  // (1 - phi)^2 and plastic contact has another exponent than Hertz's 3/2.
  const double solid = 1.0 - effects.porosity;
  const double c_e = mat.c_e_n_per_mm2 * solid * solid;
  const double shape = effects.contact_exponent == 1.5
                           ? depth_ratio * std::sqrt(depth_ratio)
                           : std::pow(depth_ratio, effects.contact_exponent);
  out->elastic_n = c_e * radius * radius * shape * out->normal;
  out->friction_n = glm::dvec3(0.0);
  const double omega = Norm(input.spindle_rad_s);
  if (omega > 0.0 && moments.m0_mm3 > 0.0) {
    const glm::dvec3 omega_hat = input.spindle_rad_s / omega;
    if (model.friction == FrictionModel::kCheap) {
      // Eq. 7.13 with omega taken as a unit vector and m1/m0 in units of R, so
      // that c_mu is in N/mm^2 like c_e.
      out->friction_n =
          mat.c_mu_n_per_mm2 * radius * radius * depth_ratio *
          Cross(moments.m1_mm4 / (moments.m0_mm3 * radius), omega_hat);
    } else if (out->h_mm > 0.0 && Norm(out->normal) > 0.0) {
      const double a2 =
          std::max(2.0 * radius * out->h_mm - out->h_mm * out->h_mm, 1e-12);
      const double v = volume.voxel_mm();
      SurfaceFrictionVisitor visitor{
          radius / v,
          EqualVolumeSphereRadius(v) / v,
          v,
          out->normal,
          omega_hat,
          std::sqrt(a2),
          3.0 * Norm(out->elastic_n) / (2.0 * std::numbers::pi * a2)};
      internal::WalkSphere(octree, volume, input.position_mm / v,
                           (radius + EqualVolumeSphereRadius(v)) / v, visitor);
      out->friction_n = mat.mu * visitor.force;
    }
  }
  // eq. 7.14, and viscous_resistance in its shape: c_i R^2 (h/R) v_ref
  // (|v| / v_ref)^m along v, v_ref = 1 mm/s.
  out->impact_n = -mat.c_i_n_s_per_mm3 * radius * radius * depth_ratio *
                  input.velocity_mm_s;
  if (effects.impact_c_i_n_s_per_mm3 > 0.0) {
    const double speed = Norm(input.velocity_mm_s);
    if (speed > 0.0) {
      const double scale =
          effects.viscous_exponent == 1.0
              ? 1.0
              : std::pow(speed, effects.viscous_exponent - 1.0);
      out->impact_n -= effects.impact_c_i_n_s_per_mm3 * radius * radius *
                       depth_ratio * scale * input.velocity_mm_s;
    }
  }
  out->model_force_n = out->elastic_n + out->friction_n + out->impact_n;
}

Moments ComputeMoments(const Model& model, const Volume& volume,
                       const MomentOctree& octree,
                       const glm::dvec3& position_mm) {
  if (model.method == MomentMethod::kMono) {
    return ComputeMomentsMono(volume, position_mm, model.radius_mm);
  }
  return ComputeMomentsOctree(octree, volume, position_mm, model.radius_mm,
                              model.ell_over_r * model.radius_mm);
}

}  // namespace

Result<State> State::Create(const Model& model, Volume volume,
                            std::uint64_t seed) {
  if (Status s = model.Validate(); !s.ok()) return s.error();
  if (volume.size() == 0)
    return Error{"the simulator needs a non-empty volume"};
  State state;
  state.octree_ = MomentOctree::Build(volume);
  state.volume_ = std::move(volume);
  state.erosion_rng_.seed(static_cast<std::uint32_t>(seed ^ (seed >> 32)));
  state.max_erosion_factor_ = 0.0;
  for (int label = 0; label < 256; ++label) {
    state.max_erosion_factor_ =
        std::max(state.max_erosion_factor_,
                 state.volume_.ErosionFactor(static_cast<std::uint8_t>(label)));
  }
  return state;
}

void State::ShiftContentUp(int layers, std::uint8_t occupancy) {
  volume_.ShiftContentUp(layers, occupancy);
  octree_ = MomentOctree::Build(volume_);
  reuse_reach_mm_ = -1.0;  // the moments kept are of the content before
}

Output EvaluateForce(const Model& model, const Volume& volume,
                     const MomentOctree& octree, const Input& input) noexcept {
  Output out;
  const Moments moments =
      ComputeMoments(model, volume, octree, input.position_mm);
  ComputeForces(model, volume, octree, input, moments, &out);
  return out;
}

void Step(const Model& model, State& state, const Input& input,
          Output* out) noexcept {
  *out = Output{};
  ++state.counters_.steps;
  if (!IsFinite(input.position_mm) || !IsFinite(input.velocity_mm_s) ||
      !IsFinite(input.spindle_rad_s)) {
    out->non_finite = true;
    ++state.counters_.non_finite;
    state.seh_.Reset();
    return;
  }
  // Collide and force: the moments afresh, or those of a nearby centre moved
  // to this one (Model::moment_reuse_over_h).
  const bool reusing = model.moment_reuse_over_h > 0.0;
  Moments moments;
  const glm::dvec3 move_mm = input.position_mm - state.reuse_centre_mm_;
  if (reusing && state.reuse_reach_mm_ > 0.0 &&
      state.reuse_budget_mm3_ >= 0.0 &&
      Norm(move_mm) <= state.reuse_reach_mm_) {
    moments.m0_mm3 =
        state.reuse_moments_.m0_mm3 + Dot(state.reuse_sweep_mm2_, move_mm);
    moments.m1_mm4 = state.reuse_moments_.m1_mm4 - moments.m0_mm3 * move_mm;
    ComputeForces(model, state.volume_, state.octree_, input, moments, out);
  } else {
    moments =
        ComputeMoments(model, state.volume_, state.octree_, input.position_mm);
    ++state.counters_.moment_evaluations;
    ComputeForces(model, state.volume_, state.octree_, input, moments, out);
    if (reusing) {
      // What the move since the last computation added beyond the erosion's
      // account, per millimetre along that move; estimated from a move of at
      // least half the reach (a shorter one, ended by the erosion budget,
      // leaves too little to measure).
      const double moved2 = Dot(move_mm, move_mm);
      state.reuse_sweep_mm2_ =
          state.reuse_reach_mm_ > 0.0 &&
                  moved2 >= 0.25 * state.reuse_reach_mm_ * state.reuse_reach_mm_
              ? ((moments.m0_mm3 - state.reuse_moments_.m0_mm3) / moved2) *
                    move_mm
              : glm::dvec3(0.0);
      state.reuse_moments_ = moments;
      state.reuse_centre_mm_ = input.position_mm;
      state.reuse_reach_mm_ = model.moment_reuse_over_h * out->h_mm;
      state.reuse_budget_mm3_ = model.moment_reuse_over_h * moments.m0_mm3;
    }
  }
  // Erode: only a spinning burr cuts (a probing burr has no friction and no
  // erosion).
  const double alpha = model.material.alpha_per_s;
  // Effects that change the cutting (sim/effects.h): the blades engage only
  // with the elastic force above the threshold, the spindle slows under load,
  // friction-driven wear adds k |F_e| to alpha, and the motor cannot remove
  // more than its power allows (the load is estimated from the recent
  // removal). Each scales the rate of eq. 7.12.
  const Effects& effects = model.effects;
  const double elastic_n = Norm(out->elastic_n);
  const double engaged = ErosionRateScale(effects, elastic_n, alpha);
  double power_scale = 1.0;
  const bool power_limited = std::isfinite(effects.max_removal_mm3_per_s);
  if (power_limited) {
    const double demand =
        engaged * state.unlimited_removal_mm3_per_s_;  // what the blades ask
    power_scale = PowerLimitScale(effects, demand);
  }
  const double scale = engaged * power_scale;
  if (Norm(input.spindle_rad_s) > 0.0 && alpha > 0.0 && scale > 0.0 &&
      moments.m0_mm3 > 0.0) {
    const double v = state.volume_.voxel_mm();
    ErosionVisitor erosion{&state.volume_,
                           &state.octree_,
                           &state.erosion_rng_,
                           model.radius_mm / v,
                           EqualVolumeSphereRadius(v) / v,
                           alpha * scale * model.dt_s,
                           state.max_erosion_factor_};
    erosion.centre_vox = input.position_mm / v;
    erosion.inverse_r2 = 1.0 / (erosion.radius_vox * erosion.radius_vox);
    if (reusing && state.reuse_reach_mm_ > 0.0) {
      erosion.reuse = &state.reuse_moments_;
      erosion.reuse_budget_mm3 = &state.reuse_budget_mm3_;
      erosion.reuse_centre_vox = state.reuse_centre_mm_ / v;
      erosion.unit_mm3 = v * v * v / kSolidOccupancy;
      erosion.voxel_mm = v;
    }
    internal::WalkSphere(state.octree_, state.volume_, input.position_mm / v,
                         model.radius_mm / v, erosion);
    out->eroded_units = erosion.removed_units;
    out->removed_mm3 = static_cast<double>(erosion.removed_units) /
                       kSolidOccupancy * v * v * v;
    state.counters_.removed_mm3 += out->removed_mm3;
    if (power_limited) {
      // First-order filter (0.1 s) of the removal rate at scale 1.
      constexpr double kLoadFilterS = 0.1;
      const double unlimited = out->removed_mm3 / (model.dt_s * scale);
      state.unlimited_removal_mm3_per_s_ +=
          model.dt_s / (kLoadFilterS + model.dt_s) *
          (unlimited - state.unlimited_removal_mm3_per_s_);
    }
  }
  // Filter and clamp what goes to the device.
  if (!IsFinite(out->model_force_n)) {
    out->non_finite = true;
    ++state.counters_.non_finite;
    state.seh_.Reset();
    out->force_n = glm::dvec3(0.0);
    return;
  }
  glm::dvec3 force = model.sample_estimate_hold
                         ? state.seh_.Update(out->model_force_n)
                         : out->model_force_n;
  const double magnitude = Norm(force);
  if (magnitude > model.max_force_n) {
    force *= model.max_force_n / magnitude;
    out->clamped = true;
    ++state.counters_.clamped;
  }
  out->force_n = force;
}

}  // namespace burrlab::sim
