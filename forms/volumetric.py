"""Volumetric (penalty) strain energy of the nearly incompressible laws.

    U(J) = (kappa/2) (ln J)^2,

with kappa the bulk modulus [MPa]. The reference study writes (1/k)(J-1)^2;
(ln J)^2 has the same small-strain bulk modulus kappa, grows without bound
as J -> 0 (no spurious collapse of a compressed element) and is the
standard choice of e.g. FEBio's uncoupled materials.

Reference: J. C. Simo, R. L. Taylor, CMAME 85 (1991) 273-310; docs/physics.md section 5.
"""
from ufl import ln


def energy(J, kappa):
    """U(J) = kappa/2 (ln J)^2."""
    return 0.5 * kappa * ln(J)**2
