"""Holzapfel-Gasser-Ogden anisotropic hyperelasticity (cornea, limbus).

    Psi = Psi_iso + U(J),
    Psi_iso = C10 (Ibar1 - 3) + k1/(2 k2) sum_{i=4,6} [exp(k2 <Ibar_i - 1>^2) - 1],
    Ibar1 = tr Cbar,  Ibar_i = a_i . Cbar a_i,

where a_4, a_6 are the unit fibre directions in the reference configuration
and <x> = max(x, 0): a fibre family carries load only in tension (a zero
fibre vector switches its family off, Ibar_i = 0). The exponent is capped
at `exponent_cap` so that a very stiff fibre (large k2) under a wild Newton
iterate gives a large but finite stress instead of overflow. This module
gives Psi_iso; the formulation adds the volumetric U(J) of volumetric.py
(a mixed formulation integrates it differently).

Reference: G. A. Holzapfel, T. C. Gasser, R. W. Ogden, J. Elasticity 61 (2000)
1-48, eq. (53)-(55); docs/physics.md section 5.
"""
from ufl import conditional, dot, exp, gt, min_value, tr

import kinematics

# Largest k2 (Ibar_i - 1)^2 evaluated: exp(200) ~ 7e86 is finite in double.
exponent_cap = 200.0


def fibre_energy(k1, k2, Ibar):
    """k1/(2 k2) [exp(k2 <Ibar-1>^2) - 1], zero in compression."""
    E = Ibar - 1.0
    exponent = min_value(k2 * E**2, exponent_cap)
    return conditional(gt(E, 0.0), k1 / (2.0 * k2) * (exp(exponent) - 1.0), 0.0)


def isochoric_energy(F, c10, k1, k2, a4, a6):
    """Isochoric strain energy density Psi_iso(F) [MPa]."""
    Cbar = kinematics.isochoric_right_cauchy_green(F)
    Ibar4 = dot(a4, Cbar * a4)
    Ibar6 = dot(a6, Cbar * a6)
    return (c10 * (tr(Cbar) - 3.0)
            + fibre_energy(k1, k2, Ibar4) + fibre_energy(k1, k2, Ibar6))
