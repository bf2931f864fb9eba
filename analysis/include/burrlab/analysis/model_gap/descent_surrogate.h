// A fast surrogate of the descent rig's steady state (dissertation ch. 8):
// the steady penetration velocity v(F; c_e, alpha, R) of a burr held at force F
// in the continuum limit of eqs. 7.2, 7.3 and 7.12 (no voxels, no time step).
//
// In the burr's frame the material flows up at v and decays as
// drho/dz = -(alpha/v) f(r/R) rho from where it enters the sphere, so with
// kappa = alpha R / v the moment m0 / R^3 is a function of kappa alone; the
// depth h of eq. 7.2 and the force c_e R^2 (h/R)^{3/2} of eq. 7.3 follow. Hence
// F / (c_e R^2) = y(kappa) and v = alpha R / kappa(F / (c_e R^2)). y(kappa) is
// tabulated once by quadrature and inverted by monotone cubic interpolation.
// The effects of sim/effects.h change the model as the simulator does: those
// that scale the erosion rate of eq. 7.12 scale v, the contact exponent and
// porosity change eq. 7.3, and viscous resistance (eq. 7.14) takes its share
// of the held force.
#ifndef BURRLAB_ANALYSIS_MODEL_GAP_DESCENT_SURROGATE_H_
#define BURRLAB_ANALYSIS_MODEL_GAP_DESCENT_SURROGATE_H_

#include "burrlab/sim/descent.h"
#include "burrlab/sim/effects.h"

namespace burrlab::analysis {

// The largest load F / (c_e R^2) the rig can hold: the whole sphere immersed
// (h = 2R) gives 2^{3/2}; the table stops a little below.
double MaxSteadyLoad();

// kappa = alpha R / v at the load y = F / (c_e R^2), 0 < y < MaxSteadyLoad().
double KappaAtLoad(double load);
// d ln kappa / d ln y at the load y.
double KappaLogSlopeAtLoad(double load);
// The load y(kappa) by quadrature (slow; for tests and the table).
double LoadAtKappa(double kappa);
// Steady removal rate over v R^2: the area of the hole the burr leaves,
// 2 pi int_0^1 w (1 - exp(-4/3 kappa w^3)) dw (pi when every column is cut).
double RemovalAreaAtKappa(double kappa);

struct DescentSurrogateInput {
  double force_n = 1.0;          // force held
  double c_e_n_per_mm2 = 2.145;  // elastic constant
  double alpha_per_s = 0.087;    // erosion constant
  double radius_mm = 3.0;        // burr radius
  sim::Effects effects;          // effects beyond the base model
};

// The steady penetration velocity in mm/s; 0 when the burr does not cut
// (below a cutting threshold), +inf when the force exceeds the full-immersion
// force MaxSteadyLoad() c_e R^2 (the burr falls through).
double SteadyVelocityMmS(const DescentSurrogateInput& input);

// The velocity under `definition`, as the fits model it. Settled: as
// SteadyVelocityMmS. Initial: the ideal-control window slope of
// initial_velocity.h (IdealInitialKappa; the power limit at the window's
// mean removal rate, InitialRemovalArea) times `transient_factor`, the rig's
// impact transient (InitialTransientFactor), which the fits hold fixed at a
// reference point and refresh: it costs milliseconds, the ideal slope
// microseconds.
double SurrogateVelocityMmS(const DescentSurrogateInput& input,
                            sim::VelocityDefinition definition,
                            double transient_factor = 1.0);

// The initial velocity of the rig's loop (InitialVelocityMmS, with the input's
// load-cell lag and arm compliance) over the ideal-control slope, at `input`.
double InitialTransientFactor(const DescentSurrogateInput& input);

}  // namespace burrlab::analysis

#endif  // BURRLAB_ANALYSIS_MODEL_GAP_DESCENT_SURROGATE_H_
