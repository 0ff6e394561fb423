"""Fluid-filled cavities: follower pressure on the wall and the enclosed volume.

Pressure p in the cavity pushes on its wall with the Cauchy traction
t = -p n (n the outward normal of the solid, pointing into the cavity).
Pulled back by Nanson's formula n da = J F^-T N dA, its virtual work enters
the residual as

    R_p(u; v) = integral_wall p J F^-T N . v dA.

The volume enclosed by the wall (and by planes through x0 that need no mesh:
symmetry planes through the axis, a fixed cut plane through x0) is

    V(u) = -1/3 integral_wall (x - x0) . J F^-T N dA,   x = X + u,

the minus sign because N points out of the solid, i.e. into the cavity.
On a section (section.py) F, N, v and x are the 3D ones: axisymmetric,
the same formulas weighted by r give them per radian; plane, the
"volume" is the area per unit thickness, with 1/2 for 1/3 (the
divergence theorem in two dimensions).

Reference: J. Bonet, R. D. Wood, Nonlinear Continuum Mechanics for Finite
Element Analysis, 2nd ed. 2008, sec. 8.4 (follower pressure); docs/physics.md sec. 6.
"""
from ufl import det, dot, inv


def follower_pressure(p, F, N, v):
    """Virtual work integrand of the cavity pressure, p J F^-T N . v."""
    return p * det(F) * dot(inv(F).T * N, v)


def volume(x, F, N, x0, space_dimension=3):
    """Integrand of the enclosed volume, -1/3 (x - x0) . J F^-T N (1/2 in 2D)."""
    return -dot(x - x0, det(F) * inv(F).T * N) / float(space_dimension)
