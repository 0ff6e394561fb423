"""Incompressible Navier-Stokes in ALE form, stabilised by SUPG/PSPG/LSIC.

On a mesh moving with velocity w, for velocity u and pressure p,

    rho (du/dt|_X + grad(u) (u - w)) - div sigma(u, p) = 0,   div u = 0,
    sigma = -p I + 2 mu eps(u),

du/dt|_X the time derivative at a fixed mesh point (BDF of nodal values).
The Galerkin form, with test functions (v, q), is augmented on each cell
by the residual-based terms of Tezduyar (2003), with the element metric
of Bazilevs et al. (2007) for the parameters:

    SUPG   tau_M (grad(v) a) . r_M          a = u - w, r_M = the momentum residual
    PSPG   tau_M / rho grad(q) . r_M
    LSIC   rho tau_C div(u) div(v)

    tau_M = (C_t / dt^2 + a . G a + C_I nu^2 G : G)^(-1/2),   nu = mu / rho,
    tau_C = 1 / (tau_M g . g),   G = K^T K,  g_j = sum_i K_ij,  K = dxi/dx,

so the stabilisation scales with the cell's size and shape in every
direction, vanishes for the exact solution (consistent) and holds on
coarse meshes at high Reynolds number.

At an outlet (natural condition sigma n = 0) flow may enter: the backflow
traction beta rho min(a . n, 0) u of Esmaily Moghadam et al. (2011) puts
back the kinetic energy such inflow carries in (energy stable for beta >= 1/2).

References: T. E. Tezduyar, Int. J. Numer. Meth. Fluids 43 (2003) 555-575;
Y. Bazilevs, V. M. Calo, J. A. Cottrell, T. J. R. Hughes, A. Reali,
G. Scovazzi, Comput. Methods Appl. Mech. Engrg. 197 (2007) 173-201, eq.
(63)-(65); M. Esmaily Moghadam, Y. Bazilevs, T.-Y. Hsia, I. E.
Vignon-Clementel, A. L. Marsden, Comput. Mech. 48 (2011) 277-291; design.md
section 8.
"""
from ufl import (Identity, JacobianInverse, as_vector, div, dot, grad, inner, min_value,
                 sqrt, sym)

# Constants of the stabilisation parameter tau_M (Bazilevs et al. 2007):
# C_t for the time step, C_I of the inverse estimate for linear tetrahedra.
C_t = 4.0
C_I = 36.0


def stress(u, p, mu):
    """Cauchy stress sigma = -p I + 2 mu eps(u) [MPa]."""
    return -p * Identity(3) + 2.0 * mu * sym(grad(u))


def momentum_residual(u, p, dudt, a, rho, mu):
    """Strong momentum residual r_M = rho (du/dt + grad(u) a) + grad p - mu lap u [N/mm^3].

    (-div sigma differs by mu grad(div u), zero for the exact solution; both
    viscous terms vanish on P1.)
    """
    return rho * (dudt + grad(u) * a) + grad(p) - mu * div(grad(u))


def tau(a, rho, mu, inv_dt, cell):
    """tau_M [ms] and tau_C [mm^2/ms] from the cell metric (Bazilevs et al. 2007)."""
    K = JacobianInverse(cell)
    G = K.T * K
    g = as_vector([K[0, j] + K[1, j] + K[2, j] for j in range(3)])
    nu = mu / rho
    tau_m = 1.0 / sqrt(C_t * inv_dt**2 + dot(a, G * a) + C_I * nu**2 * inner(G, G))
    tau_c = 1.0 / (tau_m * dot(g, g))
    return tau_m, tau_c


def cell_residual(u, p, v, q, dudt, w, u_tau, rho, mu, inv_dt, cell, continuity_scale):
    """The stabilised residual's cell integrand, tested with (v, q).

    The parameters tau are taken at the velocity u_tau (the last time
    step's): they vary by orders of magnitude with the velocity, and
    differentiating them would leave Newton a far harder problem for a
    change of the stabilisation alone.
    `continuity_scale` [g/(mm^2 ms)] multiplies the continuity rows so
    that they too are forces [N]: one residual norm for both equations.
    """
    a = u - w
    r_m = momentum_residual(u, p, dudt, a, rho, mu)
    tau_m, tau_c = tau(u_tau - w, rho, mu, inv_dt, cell)
    galerkin = (rho * inner(dudt + grad(u) * a, v) + inner(stress(u, p, mu), grad(v))
                + continuity_scale * q * div(u))
    supg = tau_m * inner(grad(v) * a, r_m)
    pspg = continuity_scale * tau_m / rho * inner(grad(q), r_m)
    lsic = rho * tau_c * div(u) * div(v)
    return galerkin + supg + pspg + lsic


def backflow(u, v, w, n, rho, beta):
    """Outlet integrand -beta rho min(a . n, 0) u . v (Esmaily Moghadam et al. 2011)."""
    return -beta * rho * min_value(dot(u - w, n), 0.0) * dot(u, v)
