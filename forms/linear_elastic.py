"""Linear elastic material (internal structures), in its frame-indifferent
finite-strain form (Saint Venant-Kirchhoff):

    Psi = lambda/2 (tr E)^2 + mu tr(E^2),   E = (C - I)/2,
    lambda = E nu / ((1 + nu)(1 - 2 nu)),   mu = E / (2 (1 + nu)),

which is Hooke's law at small strain and stays objective under the large
rigid rotations of the eye during the puff.

Reference: G. A. Holzapfel, Nonlinear Solid Mechanics, Wiley 2000, eq. (6.151).
"""
from ufl import Identity, inner, tr

import kinematics


def lame(youngs_modulus, poisson_ratio):
    """Lame parameters (lambda, mu) from E and nu."""
    lmbda = youngs_modulus * poisson_ratio / ((1 + poisson_ratio) * (1 - 2 * poisson_ratio))
    mu = youngs_modulus / (2 * (1 + poisson_ratio))
    return lmbda, mu


def energy(F, youngs_modulus, poisson_ratio):
    """Strain energy density Psi(F) [MPa]."""
    lmbda, mu = lame(youngs_modulus, poisson_ratio)
    E = 0.5 * (kinematics.right_cauchy_green(F) - Identity(F.ufl_shape[0]))
    return 0.5 * lmbda * tr(E)**2 + mu * inner(E, E)
