"""Holzapfel-Gasser-Ogden anisotropic hyperelasticity (cornea, limbus).

    Psi = Psi_iso + U(J),
    Psi_iso = C10 (Ibar1 - 3) + sum_{i=4,6} W(Ebar_i) [Ibar_i > 1],
    W(E) = k1/(2 k2) [exp(k2 E^2) - 1],
    Ebar_i = kappa_f (Ibar1 - 3) + (1 - 3 kappa_f) (Ibar_i - 1),
    Ibar1 = tr Cbar,  Ibar_i = a_i . Cbar a_i,

where a_4, a_6 are the unit fibre directions in the reference configuration
(a zero fibre vector switches its family off, Ibar_i = 0) and kappa_f in
[0, 1/3] is the fibres' dispersion about them (scene key `dispersion`):
0 is perfectly aligned fibres, Holzapfel, Gasser and Ogden's 2000 law;
1/3 an isotropic distribution (T. C. Gasser, R. W. Ogden, G. A. Holzapfel,
J. R. Soc. Interface 3 (2006) 15-35, eq. (2.7) and (2.8)). A family
carries load only when its mean direction is stretched, Ibar_i > 1, the
switch as published there (a dispersed family's compressed fibres are
then neither excluded nor counted separately: Holzapfel and Ogden,
J. Elasticity 129 (2017) 49-68, discuss what this misses). The exponent is capped
at `exponent_cap` so that a very stiff fibre (large k2) under a wild Newton
iterate gives a large but finite stress instead of overflow. This module
gives Psi_iso; the formulation adds the volumetric U(J) of volumetric.py
(a mixed formulation integrates it differently).

On an axisymmetric section (section.py) a family whose direction turns
with the azimuth phi (the cornea's nasal-temporal and superior-inferior
families: fixed directions in space, so in the local frame (r, z, theta)
they turn) is not axisymmetric. Its azimuthal mean is: the section holds
the fibre energy averaged over the azimuth,

    Psi_f = 1/n sum_k [W(Ibar_4(phi_k)) + W(Ibar_6(phi_k))],
    phi_k = 2 pi (k + 1/2) / n,  W(I) = k1/(2 k2) [exp(k2 <I-1>^2) - 1],

with each family's direction at phi_k in the local frame taken from the
3D rule (cpp/solid/material.cpp): the midpoint rule, exact to round-off
for a family fixed in the local frame (the limbus' circumferential one,
Ibar_4 = Cbar_thth) and spectrally accurate for the smooth turning of
the cornea's. The energy is averaged, not the structure tensor: a
generalised structure tensor (Gasser, Ogden, Holzapfel, J. R. Soc.
Interface 3 (2006) 15-35) puts the mean stretch into one exponential and
changes the response; averaging the energy over the directions is the
angular integration of Y. Lanir, J. Biomech. 16 (1983) 1-12. At the apex
the cornea's mean is the planar-isotropic distribution; away from it the
families lean towards the meridian as the surface tilts.

Reference: G. A. Holzapfel, T. C. Gasser, R. W. Ogden, J. Elasticity 61 (2000)
1-48, eq. (53)-(55); docs/physics.md section 5.
"""
from ufl import as_vector, conditional, dot, exp, gt, min_value, tr

import kinematics

# Largest k2 (Ibar_i - 1)^2 evaluated: exp(200) ~ 7e86 is finite in double.
exponent_cap = 200.0


def fibre_energy(k1, k2, dispersion, Ibar1, Ibar):
    """W(Ebar) of one family, zero unless Ibar > 1."""
    E = dispersion * (Ibar1 - 3.0) + (1.0 - 3.0 * dispersion) * (Ibar - 1.0)
    exponent = min_value(k2 * E**2, exponent_cap)
    return conditional(gt(Ibar, 1.0), k1 / (2.0 * k2) * (exp(exponent) - 1.0), 0.0)


def isochoric_energy(F, c10, k1, k2, dispersion, a4, a6):
    """Isochoric strain energy density Psi_iso(F) [MPa]."""
    Cbar = kinematics.isochoric_right_cauchy_green(F)
    Ibar1 = tr(Cbar)
    return (c10 * (Ibar1 - 3.0)
            + fibre_energy(k1, k2, dispersion, Ibar1, dot(a4, Cbar * a4))
            + fibre_energy(k1, k2, dispersion, Ibar1, dot(a6, Cbar * a6)))


def azimuthal_isochoric_energy(F, c10, k1, k2, dispersion, g4, g6, angles):
    """Psi_iso(F) [MPa] of an axisymmetric section, the fibre energy averaged
    over `angles` azimuths; g4, g6 hold each family's unit (or zero)
    direction in (r, z, theta) at phi_k as entries 3k to 3k+2."""
    Cbar = kinematics.isochoric_right_cauchy_green(F)
    Ibar1 = tr(Cbar)
    psi = c10 * (Ibar1 - 3.0)
    for k in range(angles):
        for g in (g4, g6):
            a = as_vector([g[3 * k], g[3 * k + 1], g[3 * k + 2]])
            psi = psi + fibre_energy(k1, k2, dispersion, Ibar1, dot(a, Cbar * a)) / angles
    return psi
