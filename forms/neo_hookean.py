"""Nearly incompressible neo-Hookean hyperelasticity (sclera).

    Psi = C10 (Ibar1 - 3) + U(J),   Ibar1 = tr(J^(-2/3) C),

shear modulus mu = 2 C10 at small strain.

Reference: G. A. Holzapfel, Nonlinear Solid Mechanics, Wiley 2000, eq. (6.148);
design.md section 5.
"""
from ufl import det, tr

import kinematics
import volumetric


def energy(F, c10, kappa):
    """Strain energy density Psi(F) [MPa]."""
    Cbar = kinematics.isochoric_right_cauchy_green(F)
    return c10 * (tr(Cbar) - 3.0) + volumetric.energy(det(F), kappa)
