"""Nearly incompressible neo-Hookean hyperelasticity (sclera).

    Psi = Psi_iso + U(J),   Psi_iso = C10 (Ibar1 - 3),   Ibar1 = tr(J^(-2/3) C),

shear modulus mu = 2 C10 at small strain. This module gives Psi_iso; the
formulation adds the volumetric U(J) of volumetric.py.

Reference: G. A. Holzapfel, Nonlinear Solid Mechanics, Wiley 2000, eq. (6.148);
docs/physics.md section 5.
"""
from ufl import tr

import kinematics


def isochoric_energy(F, c10):
    """Isochoric strain energy density Psi_iso(F) [MPa]."""
    Cbar = kinematics.isochoric_right_cauchy_green(F)
    return c10 * (tr(Cbar) - 3.0)
