// Private: the volume fraction of a cube on one side of a plane, exactly (used
// by the partial-volume phantoms and by the multi-resolution moments).
#ifndef BURRLAB_SIM_SRC_CUBE_CUT_H_
#define BURRLAB_SIM_SRC_CUBE_CUT_H_

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <glm/vec3.hpp>
#include <utility>

namespace burrlab::sim::internal {

// Volume fraction of the unit cube [0, 1]^3 where a . u <= b, for a sorted
// descending with a[0] >= 1/sqrt(3) (a unit normal with absolute components)
// and the complement symmetry already applied (b <= sum(a) / 2).
//
// With all components positive the volume is the inclusion-exclusion sum over
// the corners v of the cube: sum (-1)^|v| max(0, b - a . v)^d / (d! prod a).
// The sum cancels badly when a component is tiny, so components below kTiny
// are replaced by their mean over the cube (b -= a_i / 2) and the dimension
// drops; that changes the fraction by at most ~kTiny / 8 (near a kink, else
// O(kTiny^2)), while the rounding error of the kept sum is O(eps / kTiny^2),
// ~1e-8: both far below the 1/255 step of an occupancy.
inline double CutUnitCube(std::array<double, 3> a, double b) {
  constexpr double kTiny = 1e-4;
  int dims = 3;
  while (dims > 1 && a[static_cast<std::size_t>(dims - 1)] < kTiny) {
    b -= 0.5 * a[static_cast<std::size_t>(dims - 1)];
    --dims;
  }
  if (b <= 0.0) return 0.0;
  if (dims == 1) return std::min(b / a[0], 1.0);
  if (dims == 3) {
    // The general loop below for three dimensions, unrolled and without a
    // branch per corner (whether a corner counts is as good as random to the
    // branch predictor): a corner with t <= 0 adds max(t, 0)^3 = +-0, which
    // leaves the sum as it was (the sum starts at +0 and is never -0), so the
    // result is the loop's to the bit.
    double sum = 0.0;
    for (int corner = 0; corner < 8; ++corner) {
      double t = b;
      if (corner & 1) t -= a[0];
      if (corner & 2) t -= a[1];
      if (corner & 4) t -= a[2];
      const double m = std::max(t, 0.0);
      const double power = m * m * m;
      sum += ((corner ^ (corner >> 1) ^ (corner >> 2)) & 1) ? -power : power;
    }
    return sum / (6.0 * a[0] * a[1] * a[2]);
  }
  double sum = 0.0;
  const int corners = 1 << dims;
  for (int corner = 0; corner < corners; ++corner) {
    double t = b;
    int parity = 0;
    for (int axis = 0; axis < dims; ++axis) {
      if ((corner >> axis) & 1) {
        t -= a[static_cast<std::size_t>(axis)];
        parity ^= 1;
      }
    }
    if (t <= 0.0) continue;
    const double power = dims == 2 ? t * t : t * t * t;
    sum += parity ? -power : power;
  }
  return dims == 2 ? sum / (2.0 * a[0] * a[1])
                   : sum / (6.0 * a[0] * a[1] * a[2]);
}

// Fraction of a cube (any edge length) where unit . (x - centre) <= s, with s
// given in units of the cube edge.
inline double CubeFractionBelow(const glm::dvec3& unit, double s_over_edge) {
  std::array<double, 3> a = {std::abs(unit.x), std::abs(unit.y),
                             std::abs(unit.z)};
  // Descending, by three compare-exchanges (the same order std::sort gives),
  // each as a max and a min rather than a branch (the components are
  // absolute values and finite, so the two give the same doubles).
  const auto exchange = [&](std::size_t i, std::size_t j) {
    const double hi = std::max(a[i], a[j]), lo = std::min(a[i], a[j]);
    a[i] = hi;
    a[j] = lo;
  };
  exchange(0, 1);
  exchange(1, 2);
  exchange(0, 1);
  const double total = a[0] + a[1] + a[2];
  // Corner form: u = w + 1/2 in [0, 1]^3, so a . u <= s + total / 2.
  const double b = s_over_edge + 0.5 * total;
  if (!(b > 0.0)) return 0.0;  // also NaN
  if (b >= total) return 1.0;
  if (b > 0.5 * total) return 1.0 - CutUnitCube(a, total - b);
  return CutUnitCube(a, b);
}

}  // namespace burrlab::sim::internal

#endif  // BURRLAB_SIM_SRC_CUBE_CUT_H_
