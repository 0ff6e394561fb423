"""Finite-strain kinematics shared by the solid material laws.

    F = I + Grad u,  C = F^T F,  J = det F,
    Cbar = J^(-2/3) C  (isochoric part, Flory's multiplicative split),

F always 3x3: on a section, Grad u carries the out-of-plane entry
(section.py).

Reference: G. A. Holzapfel, Nonlinear Solid Mechanics, Wiley 2000, ch. 2 and 6.6.
"""
from ufl import Identity, det, variable

import section


def deformation_gradient(u, dimension="3d"):
    """F = I + Grad u (3x3), as a UFL variable so that energies can be differentiated."""
    return variable(Identity(3) + section.gradient(u, dimension))


def right_cauchy_green(F):
    """C = F^T F."""
    return F.T * F


def isochoric_right_cauchy_green(F):
    """Cbar = J^(-2/3) F^T F."""
    return det(F)**(-2.0 / 3.0) * F.T * F


def cauchy_stress(P, F):
    """sigma = J^-1 P F^T from the first Piola-Kirchhoff stress P."""
    return P * F.T / det(F)
