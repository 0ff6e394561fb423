"""Saint Venant-Kirchhoff material: Hooke's law in the Green-Lagrange strain,

    Psi = lambda/2 (tr E)^2 + mu tr(E^2),   E = (C - I)/2,

with lambda, mu from E and nu (lame.py). Objective under large rotations,
but not stable in compression: the nominal uniaxial stress peaks at the
stretch 1/sqrt(3) and falls to zero as the stretch goes to zero, and under
a hydrostatic Cauchy pressure p the shear wave speed vanishes (loss of
ellipticity) once p > lambda_s mu, lambda_s the stretch (a few per cent
of volume change at nu = 0.45). Kept for benchmarks that prescribe it
(Turek & Hron 2006); the soft internal structures use
compressible_neo_hookean.py.

Reference: G. A. Holzapfel, Nonlinear Solid Mechanics, Wiley 2000, eq. (6.151);
P. G. Ciarlet, Mathematical Elasticity I, North-Holland 1988, sec. 4.10.
"""
from ufl import Identity, inner, tr

import kinematics
import lame


def energy(F, youngs_modulus, poisson_ratio):
    """Strain energy density Psi(F) [MPa]."""
    lmbda, mu = lame.lame(youngs_modulus, poisson_ratio)
    E = 0.5 * (kinematics.right_cauchy_green(F) - Identity(F.ufl_shape[0]))
    return 0.5 * lmbda * tr(E)**2 + mu * inner(E, E)
