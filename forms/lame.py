"""Lame parameters of isotropic elasticity from Young's modulus and Poisson's ratio.

    lambda = E nu / ((1 + nu)(1 - 2 nu)),   mu = E / (2 (1 + nu)),
    bulk modulus K = lambda + 2 mu / 3 = E / (3 (1 - 2 nu)).

Reference: G. A. Holzapfel, Nonlinear Solid Mechanics, Wiley 2000, eq. (6.150).
"""


def lame(youngs_modulus, poisson_ratio):
    """(lambda, mu) [MPa] from E [MPa] and nu [-]."""
    lmbda = youngs_modulus * poisson_ratio / ((1 + poisson_ratio) * (1 - 2 * poisson_ratio))
    mu = youngs_modulus / (2 * (1 + poisson_ratio))
    return lmbda, mu
