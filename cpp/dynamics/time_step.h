// [dynamics]: the time step of every dynamic phase (the rest and the puff,
// whichever blocks move), how a march chooses it, and the generalised-alpha
// parameters of the solid's integrator (forms/dynamics.py); the air steps by
// the same dt with its own BDF order (air.bdf_order).
#pragma once

namespace nct::dynamics
{

/// A time step: its length and how the solid integrates over it.
struct TimeStep
{
  double dt = 0.1;      ///< [ms]
  double rho_inf = 0.8; ///< generalised alpha's spectral radius at infinite frequency, in [0, 1]
  double damping = 0;   ///< mass-proportional damping [1/ms]

  /// The same integrator over a step of another length (a cut step) [ms].
  TimeStep with_dt(double length) const
  {
    TimeStep s = *this;
    s.dt = length;
    return s;
  }
};

/// How a march chooses its steps: the nominal step, halved where Newton
/// fails (tolerance 0), or adapted to the solid's local error estimate.
struct StepControl
{
  double tolerance = 0; ///< [mm] the largest local error of a step; 0: fixed steps
  double dt_max = 1;    ///< [ms] the longest adapted step
};

} // namespace nct::dynamics
