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

} // namespace nct::dynamics
