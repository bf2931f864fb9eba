// Kinematics of the Novint Falcon's parallel delta mechanism (R. E. Stamper,
// "A three degree of freedom parallel manipulator with only translational
// degrees of freedom", PhD thesis, Univ. of Maryland, 1997; the Falcon's
// dimensions as measured by libnifalcon). Each of the three legs has a motor
// arm of length a at angle theta1 and a parallelogram shin of length b; the
// legs' planes are rotated by phi_i about the z axis. Positions are in mm in
// libnifalcon's device frame (its metres times 1000), angles in radians,
// theta1 measured as libnifalcon measures it (35 degrees at encoder count 0).
//
// Everything here is closed form or a bounded Newton iteration: no
// allocation, no exceptions, safe inside the 1 kHz tick.
#ifndef BURRLAB_RUNNER_DEVICES_FALCON_KINEMATICS_H_
#define BURRLAB_RUNNER_DEVICES_FALCON_KINEMATICS_H_

#include <array>
#include <cstdint>
#include <glm/vec3.hpp>

namespace burrlab::runner::falcon {

// Mechanism dimensions, mm (Stamper's figure of one leg).
inline constexpr double kArmMm = 60.0;          // a: motor arm
inline constexpr double kShinMm = 102.5;        // b: parallelogram side
inline constexpr double kEffectorUMm = 14.0;    // c: effector offset, u
inline constexpr double kShinJointMm = 11.25;   // d: shin-to-effector joint
inline constexpr double kKneeJointMm = 11.25;   // e: knee-to-shin joint
inline constexpr double kEffectorVMm = -25.0;   // f: effector offset, v
inline constexpr double kBaseUMm = 37.233758;   // r: frame origin to leg base
inline constexpr double kBaseVMm = -27.330909;  // s: frame origin to leg base
inline constexpr double kLegTiltRad = 0.2617993877991494;  // pi/12 (15 deg)
// phi_i: the legs at 90, -30 and -150 degrees, each tilted by 15 degrees.
inline constexpr std::array<double, 3> kLegAngleRad = {
    1.5707963267948966 + kLegTiltRad, -0.5235987755982988 + kLegTiltRad,
    -2.6179938779914944 + kLegTiltRad};

// Encoders: 320 slots read in quadrature on a 14.25 mm shaft driving a
// 110 mm arm pulley; count 0 is at 35 degrees.
inline constexpr double kEncoderDegreesPerCount =
    360.0 * 14.25 / (4.0 * 320.0 * 110.0);
inline constexpr double kEncoderZeroDeg = 35.0;

// Motor command counts per N m of arm torque (libnifalcon's scale; the sign
// is libnifalcon's: a positive arm torque is a negative command).
inline constexpr double kMotorCountsPerNewtonMetre = 10000.0;
inline constexpr std::int16_t kMaxMotorCommand = 32767;

// theta1 of one leg from its encoder count, rad.
double EncoderToAngleRad(std::int16_t count) noexcept;
// The (fractional) encoder count of theta1.
double AngleRadToEncoder(double angle_rad) noexcept;

// theta1 of the three legs at an end-effector position; false when the
// position is out of reach (angles unchanged).
bool InverseKinematics(const glm::dvec3& position_mm,
                       glm::dvec3* angles_rad) noexcept;

// d theta1_i / d position_j at a position, rad/mm, as three rows (row i is
// the gradient of leg i's angle); false out of reach or at a singularity.
bool AngleJacobian(const glm::dvec3& position_mm,
                   std::array<glm::dvec3, 3>* rows) noexcept;

// The end-effector position with the given theta1's: Newton's method on the
// inverse kinematics from `guess_mm` (the previous position, or the
// workspace centre). False when it does not converge (position unchanged).
bool ForwardKinematics(const glm::dvec3& angles_rad, const glm::dvec3& guess_mm,
                       glm::dvec3* position_mm) noexcept;

// Arm torques, N m, that make the end effector push with force_n at a
// position: tau = (d position / d theta)^T force (virtual work).
bool ForceToTorques(const glm::dvec3& position_mm, const glm::dvec3& force_n,
                    glm::dvec3* torques_n_m) noexcept;

// Motor commands for arm torques: -kMotorCountsPerNewtonMetre * tau, rounded;
// when one exceeds kMaxMotorCommand all three are scaled down together so the
// force keeps its direction. Non-finite torques give zero commands.
std::array<std::int16_t, 3> TorquesToMotorCommands(
    const glm::dvec3& torques_n_m) noexcept;

// The centre of the Falcon's nominal workspace, mm (a start for
// ForwardKinematics).
inline constexpr glm::dvec3 kWorkspaceCentreMm{0.0, 0.0, 120.0};

}  // namespace burrlab::runner::falcon

#endif  // BURRLAB_RUNNER_DEVICES_FALCON_KINEMATICS_H_
