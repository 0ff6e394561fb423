"""Finite-strain kinematics shared by the solid material laws.

    F = I + grad u,  C = F^T F,  J = det F,
    Cbar = J^(-2/3) C  (isochoric part, Flory's multiplicative split).

Reference: G. A. Holzapfel, Nonlinear Solid Mechanics, Wiley 2000, ch. 2 and 6.6.
"""
from ufl import Identity, det, grad, variable


def deformation_gradient(u):
    """F = I + grad u, as a UFL variable so that energies can be differentiated."""
    return variable(Identity(len(u)) + grad(u))


def right_cauchy_green(F):
    """C = F^T F."""
    return F.T * F


def isochoric_right_cauchy_green(F):
    """Cbar = J^(-2/3) F^T F."""
    return det(F)**(-2.0 / 3.0) * F.T * F


def cauchy_stress(P, F):
    """sigma = J^-1 P F^T from the first Piola-Kirchhoff stress P."""
    return P * F.T / det(F)
