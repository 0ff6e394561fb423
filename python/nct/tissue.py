"""The cornea's stiffness by age (docs/physics.md section 5, "The cornea's
stiffness by age").

Knox Cartwright, Tyrer and Marshall (Invest. Ophthalmol. Vis. Sci. 52
(2011) 4324-4329) inflated 50 human corneas by 0.5 mmHg at 15 mmHg: a
tangent modulus rising linearly from 0.27 MPa at 20 years to 0.52 MPa at
100. The model's counterpart is the HGO membrane's tangent at the IOP's
stress: equibiaxial stretch lambda of an incompressible sheet with the two
fibre families in its plane,

    sigma(lambda) = 2 C10 (lambda^2 - lambda^-4)
                    + 2 k1 (lambda^2 - 1) exp(k2 (lambda^2 - 1)^2) lambda^2,

at sigma = p R / (2 t), and E = (1 - nu) d sigma / d ln lambda with
nu = 1/2 (the biaxial modulus of an isotropic sheet is E / (1 - nu)).

    membrane_modulus(0.05, 0.01, 100, 14.4)   # 0.33 MPa
    age_scale(69)                             # 1.31: C10 and k1 of 69 years
"""
import math

MMHG = 1.333224e-4  # MPa


def _stress(lam, c10, k1, k2):
    e = lam * lam - 1
    return 2 * c10 * (lam ** 2 - lam ** -4) + 2 * k1 * e * math.exp(k2 * e * e) * lam ** 2


def _solve(f, lo, hi):
    """The root of an increasing f on [lo, hi] by bisection."""
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if f(mid) < 0 else (lo, mid)
    return 0.5 * (lo + hi)


def membrane_modulus(c10, k1, k2, iop_mmHg, radius=7.8, thickness=0.55):
    """The tangent modulus [MPa] of the HGO membrane at the IOP's stress."""
    sigma = iop_mmHg * MMHG * radius / (2 * thickness)
    lam = _solve(lambda l: _stress(l, c10, k1, k2) - sigma, 1.0, 1.5)
    h = 1e-7
    slope = (_stress(lam * math.exp(h), c10, k1, k2)
             - _stress(lam * math.exp(-h), c10, k1, k2)) / (2 * h)
    return 0.5 * slope


def modulus_at_age(age):
    """Knox Cartwright et al.'s line [MPa]: 0.27 at 20 years, 0.52 at 100."""
    return 0.27 + (0.52 - 0.27) * (age - 20) / 80


def age_scale(age, c10=0.05, k1=0.01, k2=100.0, iop_mmHg=14.4):
    """The factor on C10 and k1 that gives the membrane the modulus of
    `age` years."""
    target = modulus_at_age(age)
    return _solve(lambda s: membrane_modulus(s * c10, s * k1, k2, iop_mmHg) - target, 0.1, 10)
