// Falcon delta-mechanism kinematics: closed-form inverse kinematics per leg,
// its Jacobian by implicit differentiation, forward kinematics by Newton.
#include "devices/falcon_kinematics.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <numbers>

#include "burrlab/sim/finite.h"

namespace burrlab::runner::falcon {
namespace {

constexpr double kRadPerDeg = std::numbers::pi / 180.0;

// One leg at an end-effector position: the position in the leg's (u, v, w)
// frame and the angles that follow from it.
struct Leg {
  double u = 0.0, v = 0.0, w = 0.0;  // effector in the leg frame, mm
  double cos_theta3 = 0.0;           // shin angle: v = b cos(theta3) - f
  double sin_theta3 = 0.0;
  double reach_mm = 0.0;  // L = d + e + b sin(theta3): knee to effector in u-w
  double theta1 = 0.0;    // motor arm angle
};

// Solves leg `i`; false when the position is out of its reach.
bool SolveLeg(const glm::dvec3& p, int i, Leg* leg) {
  const double phi = kLegAngleRad[static_cast<std::size_t>(i)];
  const double c = std::cos(phi), s = std::sin(phi);
  leg->u = c * p.x + s * p.y - kBaseUMm;
  leg->v = -s * p.x + c * p.y - kBaseVMm;
  leg->w = p.z;
  leg->cos_theta3 = (leg->v + kEffectorVMm) / kShinMm;
  if (!(std::abs(leg->cos_theta3) < 1.0)) return false;
  leg->sin_theta3 = std::sqrt(1.0 - leg->cos_theta3 * leg->cos_theta3);
  leg->reach_mm = kShinJointMm + kKneeJointMm + kShinMm * leg->sin_theta3;
  // The knee lies on the circle of radius a about the motor axis and at
  // distance L from Q = (u + c, w): intersect the two circles and take the
  // branch the Falcon is built in (the arm below the line to Q).
  const double qu = leg->u + kEffectorUMm, qw = leg->w;
  const double q = std::hypot(qu, qw);
  if (!(q > 0.0)) return false;
  const double cos_beta =
      (q * q + kArmMm * kArmMm - leg->reach_mm * leg->reach_mm) /
      (2.0 * kArmMm * q);
  if (!(std::abs(cos_beta) <= 1.0)) return false;
  leg->theta1 = std::atan2(qw, qu) - std::acos(cos_beta);
  return true;
}

// Solves J x = y for the rows of J; false when J is singular.
bool Solve(const std::array<glm::dvec3, 3>& rows, const glm::dvec3& y,
           glm::dvec3* x) {
  const glm::dvec3 c0 = glm::cross(rows[1], rows[2]);
  const glm::dvec3 c1 = glm::cross(rows[2], rows[0]);
  const glm::dvec3 c2 = glm::cross(rows[0], rows[1]);
  const double det = glm::dot(rows[0], c0);
  if (!(std::abs(det) > 1e-300) || !std::isfinite(det)) return false;
  *x = (y.x * c0 + y.y * c1 + y.z * c2) / det;
  return true;
}

}  // namespace

double EncoderToAngleRad(std::int16_t count) noexcept {
  return (kEncoderZeroDeg + kEncoderDegreesPerCount * count) * kRadPerDeg;
}

double AngleRadToEncoder(double angle_rad) noexcept {
  return (angle_rad / kRadPerDeg - kEncoderZeroDeg) / kEncoderDegreesPerCount;
}

bool InverseKinematics(const glm::dvec3& position_mm,
                       glm::dvec3* angles_rad) noexcept {
  glm::dvec3 angles;
  for (int i = 0; i < 3; ++i) {
    Leg leg;
    if (!SolveLeg(position_mm, i, &leg)) return false;
    angles[i] = leg.theta1;
  }
  *angles_rad = angles;
  return true;
}

bool AngleJacobian(const glm::dvec3& position_mm,
                   std::array<glm::dvec3, 3>* rows) noexcept {
  std::array<glm::dvec3, 3> result;
  for (int i = 0; i < 3; ++i) {
    Leg leg;
    if (!SolveLeg(position_mm, i, &leg)) return false;
    // g(theta1, u, v, w) = (u + c - a cos t1)^2 + (w - a sin t1)^2 - L(v)^2 = 0
    // and d theta1 / dx = -(dg/dx) / (dg/dtheta1).
    const double ct = std::cos(leg.theta1), st = std::sin(leg.theta1);
    const double du = leg.u + kEffectorUMm - kArmMm * ct;
    const double dw = leg.w - kArmMm * st;
    const double dg_dtheta =
        2.0 * kArmMm * ((leg.u + kEffectorUMm) * st - leg.w * ct);
    if (!(std::abs(dg_dtheta) > 1e-12) || !(leg.sin_theta3 > 1e-12)) {
      return false;
    }
    // dL/dv = b d(sin theta3)/dv = -cos(theta3) / sin(theta3).
    const double dg_du = 2.0 * du;
    const double dg_dv = 2.0 * leg.reach_mm * leg.cos_theta3 / leg.sin_theta3;
    const double dg_dw = 2.0 * dw;
    const double dt_du = -dg_du / dg_dtheta;
    const double dt_dv = -dg_dv / dg_dtheta;
    const double dt_dw = -dg_dw / dg_dtheta;
    // (u, v) = R(phi) (x, y) - (r, s): chain rule through the rotation.
    const double phi = kLegAngleRad[static_cast<std::size_t>(i)];
    const double c = std::cos(phi), s = std::sin(phi);
    result[static_cast<std::size_t>(i)] =
        glm::dvec3(c * dt_du - s * dt_dv, s * dt_du + c * dt_dv, dt_dw);
  }
  *rows = result;
  return true;
}

bool ForwardKinematics(const glm::dvec3& angles_rad, const glm::dvec3& guess_mm,
                       glm::dvec3* position_mm) noexcept {
  constexpr int kMaxIterations = 60;
  constexpr double kToleranceRad = 1e-14;
  if (!sim::IsFinite(angles_rad) || !sim::IsFinite(guess_mm)) return false;
  glm::dvec3 p = guess_mm;
  glm::dvec3 theta;
  if (!InverseKinematics(p, &theta)) {
    p = kWorkspaceCentreMm;
    if (!InverseKinematics(p, &theta)) return false;
  }
  double residual = glm::length(theta - angles_rad);
  for (int iteration = 0; iteration < kMaxIterations; ++iteration) {
    if (residual <= kToleranceRad) break;
    std::array<glm::dvec3, 3> rows;
    glm::dvec3 step;
    if (!AngleJacobian(p, &rows) || !Solve(rows, angles_rad - theta, &step)) {
      return false;
    }
    // Damped Newton: halve the step until the residual falls and the trial
    // point stays within reach.
    bool improved = false;
    for (int halving = 0; halving < 30 && !improved; ++halving) {
      const glm::dvec3 trial = p + step;
      glm::dvec3 trial_theta;
      if (InverseKinematics(trial, &trial_theta)) {
        const double trial_residual = glm::length(trial_theta - angles_rad);
        if (trial_residual < residual) {
          p = trial;
          theta = trial_theta;
          residual = trial_residual;
          improved = true;
        }
      }
      step *= 0.5;
    }
    if (!improved) break;  // at the limit of double precision
  }
  if (!(residual <= 1e-9)) return false;
  *position_mm = p;
  return true;
}

bool ForceToTorques(const glm::dvec3& position_mm, const glm::dvec3& force_n,
                    glm::dvec3* torques_n_m) noexcept {
  std::array<glm::dvec3, 3> rows;
  if (!sim::IsFinite(force_n) || !AngleJacobian(position_mm, &rows))
    return false;
  // tau = J^-T F: solve J^T tau = F with the columns of J^T = rows of J.
  const glm::dvec3 c0 = glm::cross(rows[1], rows[2]);
  const glm::dvec3 c1 = glm::cross(rows[2], rows[0]);
  const glm::dvec3 c2 = glm::cross(rows[0], rows[1]);
  const double det = glm::dot(rows[0], c0);  // rad^3/mm^3
  if (!(std::abs(det) > 1e-300) || !std::isfinite(det)) return false;
  const glm::dvec3 torques_n_mm(glm::dot(force_n, c0) / det,
                                glm::dot(force_n, c1) / det,
                                glm::dot(force_n, c2) / det);
  *torques_n_m = torques_n_mm * 1e-3;
  return true;
}

std::array<std::int16_t, 3> TorquesToMotorCommands(
    const glm::dvec3& torques_n_m) noexcept {
  if (!sim::IsFinite(torques_n_m)) return {};
  glm::dvec3 counts = -kMotorCountsPerNewtonMetre * torques_n_m;
  const double largest =
      std::max({std::abs(counts.x), std::abs(counts.y), std::abs(counts.z)});
  if (largest > kMaxMotorCommand) counts *= kMaxMotorCommand / largest;
  std::array<std::int16_t, 3> commands{};
  for (int i = 0; i < 3; ++i) {
    commands[static_cast<std::size_t>(i)] =
        static_cast<std::int16_t>(std::lround(counts[i]));
  }
  return commands;
}

}  // namespace burrlab::runner::falcon
