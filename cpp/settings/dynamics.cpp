// [dynamics]: the time step of every dynamic phase and the solid's
// integrator (forms/dynamics.py).
#include "settings/settings.h"

namespace nct::dynamics
{

void visit(scene::Visitor& v, TimeStep& s)
{
  v.real({"dynamics.dt", "0.1", "ms", 1e-5, 1e5,
          "time step of the dynamic phases, the rest and the puff, whichever blocks move (the "
          "solid, the air or both; halved when Newton fails, down to 2^-solver.max_step_cuts "
          "of it)"},
         s.dt);
  v.real({"dynamics.rho_inf", "0.8", "", 0, 1,
          "generalised-alpha spectral radius at infinite frequency: 1 keeps every mode (no "
          "numerical dissipation), 0 damps the unresolved ones in one step"},
         s.rho_inf);
  v.real({"dynamics.damping", "0.1", "1/ms", 0, 1e3,
          "mass-proportional (Rayleigh) damping coefficient"},
         s.damping);
}

void visit(scene::Visitor& v, StepControl& s)
{
  v.real({"dynamics.tolerance", "0", "mm", 0, 1,
          "adaptive time steps: the largest local error of a step in the solid's displacement, "
          "estimated from generalised alpha's acceleration change, (beta - 1/6) dt^2 "
          "max|a_n+1 - a_n| (Zienkiewicz & Xie 1991); the steps are dynamics.dt 2^k, the "
          "first dynamics.dt: a step above the tolerance is taken again at half the length, "
          "the next is halved above 0.8 of it and doubled below 1/16 of it, within "
          "[2^-solver.max_step_cuts dynamics.dt, dynamics.dt_max]; 0 = fixed steps of "
          "dynamics.dt"},
         s.tolerance);
  v.real({"dynamics.dt_max", "1", "ms", 1e-5, 1e5,
          "adaptive time steps (dynamics.tolerance > 0): the longest step"},
         s.dt_max);
}

} // namespace nct::dynamics
