"""Compressible neo-Hookean material (the internal structures), with the
Lame parameters of Hooke's law (lame.py):

    Psi = mu/2 (I1 - 3) - mu ln J + lambda/2 (ln J)^2,   I1 = tr C,

which is Hooke's law with lambda, mu at small strain and grows without
bound as J -> 0: stable in compression at any strain. Under a hydrostatic
stretch l (J = l^3) the Cauchy stress is (mu (l^2 - 1) + lambda ln J) / J,
monotone in J, and the shear wave speed stays mu / l > 0. This module
splits Psi into its shear part and the volumetric lambda/2 (ln J)^2, which
the mixed formulation integrates at the centroid like U(J) of the
nearly incompressible laws (selective reduced integration of lambda).

Reference: J. Bonet, R. D. Wood, Nonlinear Continuum Mechanics for Finite
Element Analysis, 2nd ed., Cambridge 2008, eq. (6.28); FEBio User's Manual,
"Neo-Hookean" (the same law, parameters E and v).
"""
from ufl import ln, tr

import kinematics
import lame


def shear_energy(F, J, youngs_modulus, poisson_ratio):
    """mu/2 (I1 - 3) - mu ln J [MPa]."""
    _, mu = lame.lame(youngs_modulus, poisson_ratio)
    return 0.5 * mu * (tr(kinematics.right_cauchy_green(F)) - 3.0) - mu * ln(J)


def volumetric_energy(J, youngs_modulus, poisson_ratio):
    """lambda/2 (ln J)^2 [MPa]."""
    lmbda, _ = lame.lame(youngs_modulus, poisson_ratio)
    return 0.5 * lmbda * ln(J)**2
