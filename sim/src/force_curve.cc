// Force-depth curves of a burr pressed into a half-space
// (figs. 6.4(a), 7.1(a)).
#include "burrlab/sim/force_curve.h"

#include <fmt/format.h>

#include <cmath>

#include "burrlab/sim/moments.h"
#include "burrlab/sim/octree.h"
#include "burrlab/sim/phantoms.h"
#include "burrlab/sim/step.h"

namespace burrlab::sim {

Status ForceCurveOptions::Validate() const {
  if (!(std::isfinite(c_e_n_per_mm2) && c_e_n_per_mm2 > 0.0)) {
    return Error{fmt::format("c_e must be a positive finite number, got {}",
                             c_e_n_per_mm2)};
  }
  if (!(std::isfinite(radius_mm) && radius_mm > 0.0)) {
    return Error{fmt::format("radius must be a positive number of mm, got {}",
                             radius_mm)};
  }
  if (!(std::isfinite(voxel_mm) && voxel_mm > 0.0)) {
    return Error{fmt::format(
        "voxel size must be a positive number of mm, got {}", voxel_mm)};
  }
  if (!(std::isfinite(max_depth_mm) && max_depth_mm >= 0.0 &&
        max_depth_mm <= 2.0 * radius_mm)) {
    return Error{
        fmt::format("max depth must be between 0 and 2R = {} mm, got {}",
                    2.0 * radius_mm, max_depth_mm)};
  }
  if (points < 2 || points > 100000) {
    return Error{
        fmt::format("points must be between 2 and 100000, got {}", points)};
  }
  if (!(std::isfinite(ell_over_r) && ell_over_r >= 0.0)) {
    return Error{
        fmt::format("ell/R must be zero or positive, got {}", ell_over_r)};
  }
  const double n2 =
      normal.x * normal.x + normal.y * normal.y + normal.z * normal.z;
  if (!std::isfinite(n2) || n2 <= 0.0) {
    return Error{"normal must be a non-zero finite vector"};
  }
  if (!std::isfinite(offset_voxels)) return Error{"offset must be finite"};
  if (4.0 * radius_mm / voxel_mm > 1000.0) {
    return Error{
        fmt::format("R / voxel = {} is too large for a force curve volume",
                    radius_mm / voxel_mm)};
  }
  return {};
}

Result<std::vector<ForceCurvePoint>> ComputeForceCurve(
    const ForceCurveOptions& options) {
  if (Status s = options.Validate(); !s.ok()) return s.error();
  const double radius = options.radius_mm;
  const double v = options.voxel_mm;
  const glm::dvec3 n =
      options.normal / std::sqrt(options.normal.x * options.normal.x +
                                 options.normal.y * options.normal.y +
                                 options.normal.z * options.normal.z);
  // A cube wide enough for the burr sphere wherever the curve takes it.
  const int cells = static_cast<int>(std::ceil((4.0 * radius + 8.0 * v) / v));
  const PhantomGrid grid{cells, cells, cells, v};
  // Contact point near the centre, shifted along a direction in the plane.
  const glm::dvec3 any =
      std::abs(n.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  glm::dvec3 tangent = any - (any.x * n.x + any.y * n.y + any.z * n.z) * n;
  tangent /= std::sqrt(tangent.x * tangent.x + tangent.y * tangent.y +
                       tangent.z * tangent.z);
  const glm::dvec3 contact = glm::dvec3(0.5 * cells * v + 0.123 * v) +
                             options.offset_voxels * v * tangent;
  Result<Volume> volume = MakeHalfSpace(grid, contact, n);
  if (!volume.ok()) return volume.error();
  const MomentOctree octree = MomentOctree::Build(*volume);
  Model model;
  model.material.c_e_n_per_mm2 = options.c_e_n_per_mm2;
  model.radius_mm = radius;
  model.method = options.method;
  model.ell_over_r = options.ell_over_r;
  const double max_depth =
      options.max_depth_mm > 0.0 ? options.max_depth_mm : radius;
  std::vector<ForceCurvePoint> points;
  points.reserve(static_cast<std::size_t>(options.points));
  for (int p = 1; p <= options.points; ++p) {
    const double depth = max_depth * p / options.points;
    Input input;
    input.position_mm = contact + (radius - depth) * n;
    const Output out = EvaluateForce(model, *volume, octree, input);
    points.push_back({depth, out.h_mm, out.m0_mm3,
                      std::sqrt(out.elastic_n.x * out.elastic_n.x +
                                out.elastic_n.y * out.elastic_n.y +
                                out.elastic_n.z * out.elastic_n.z),
                      out.normal});
  }
  return points;
}

}  // namespace burrlab::sim
