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

    tau_M = (C_t / T^2 + a . G a + C_I nu^2 G : G)^(-1/2),   nu = mu / rho,
    tau_C = 1 / (tau_M g . g),   G = K^T K,  g_j = sum_i K_ij,  K = dxi/dx,

so the stabilisation scales with the cell's size and shape in every
direction, vanishes for the exact solution (consistent) and holds on
coarse meshes at high Reynolds number. Bazilevs et al. take the time
step for T; then the discrete solution depends on the step even where
the flow is steady (a known defect: the stabilisation belongs to the
space discretisation, cf. V. John, J. Novo, SIAM J. Numer. Anal. 49
(2011) 1149-1176), and on the Corvis jet's stagnation region it moved the
apex pressure by 40 % between steps of 0.1 and 0.025 ms. T is therefore a
fixed time scale of the air (air.stabilisation_time): it still bounds
tau where the air is still, and the time steps converge to one solution.

The residual is written either on the current mesh (`cell_residual`: the
mesh's own coordinates are the current ones, w a given field) or on a
reference mesh that the current one is mapped from by the mesh
displacement d (`cell_residual_ale`): x = X + d, F = I + Grad d,
J = det F, so that grad_x f = Grad f F^-1 and dx = J dX. The second is
what a monolithic fluid-structure Newton needs: the residual is a
function of d, and its derivative with respect to d (the shape
derivative) is exact.

At an outlet (natural condition sigma n = 0) flow may enter: the backflow
traction beta rho min(a . n, 0) u of Esmaily Moghadam et al. (2011) puts
back the kinetic energy such inflow carries in (energy stable for beta >= 1/2).

References: T. E. Tezduyar, Int. J. Numer. Meth. Fluids 43 (2003) 555-575;
Y. Bazilevs, V. M. Calo, J. A. Cottrell, T. J. R. Hughes, A. Reali,
G. Scovazzi, Comput. Methods Appl. Mech. Engrg. 197 (2007) 173-201, eq.
(63)-(65); M. Esmaily Moghadam, Y. Bazilevs, T.-Y. Hsia, I. E.
Vignon-Clementel, A. L. Marsden, Comput. Mech. 48 (2011) 277-291; J. Donea,
A. Huerta, J.-Ph. Ponthot, A. Rodriguez-Ferran, Arbitrary Lagrangian-Eulerian
methods, Encyclopedia of Computational Mechanics, Wiley 2004, sec. 3
(the ALE equations on the reference mesh); docs/physics.md section 8.

On a section (section.py, `dimension`), velocities, gradients, stresses
and normals are the 3D ones, padded: an axisymmetric section's velocity
gradient has the hoop entry u_r/r (r the current radius), so div u =
du_r/dr + u_r/r + du_z/dz and the viscous stress has eps_thth = u_r/r;
the convective hoop terms vanish without swirl. The strong momentum
residual keeps the viscous hoop terms, -2 mu [(eps_rr - eps_thth)/r,
eps_rz/r], which do not vanish for a linear velocity (docs/physics.md
section 21). The stabilisation's metric is the section's own (2D).
"""
from ufl import (Identity, JacobianInverse, SpatialCoordinate, as_matrix, as_vector, det, dot,
                 grad, inner, inv, min_value, sqrt, sym, tr)

import section

# Constants of the stabilisation parameter tau_M (Bazilevs et al. 2007):
# C_t for the time step, C_I of the inverse estimate for linear tetrahedra.
C_t = 4.0
C_I = 36.0


def stress(grad_u, p, mu):
    """Cauchy stress sigma = -p I + 2 mu eps(u) [MPa], from the velocity gradient."""
    return -p * Identity(3) + 2.0 * mu * sym(grad_u)


def tau(a, rho, mu, inv_time, K):
    """tau_M [ms] and tau_C [mm^2/ms] from the cell metric K = dxi/dx (Bazilevs et al. 2007),
    with inv_time = 1/T."""
    G = K.T * K
    n = K.ufl_shape[0]
    g = as_vector([K[0, j] + K[1, j] + K[2, j] if n == 3 else K[0, j] + K[1, j]
                   for j in range(n)])
    nu = mu / rho
    tau_m = 1.0 / sqrt(C_t * inv_time**2 + dot(a, G * a) + C_I * nu**2 * inner(G, G))
    tau_c = 1.0 / (tau_m * dot(g, g))
    return tau_m, tau_c


def _residual(grad_x, u, p, v, q, dudt, a, tau_m, tau_c, rho, mu, continuity_scale,
              dimension, r=None):
    """The stabilised integrand with the current gradient grad_x (3D:
    3x3 for a vector, a 3-vector for a scalar; per unit current volume);
    r the current radius of an axisymmetric section.

    The strong momentum residual r_M = rho (du/dt + grad(u) a) + grad p
    leaves out -mu lap u: it vanishes for the piecewise linear velocity of
    the built element on affine cells, fixed or moved by a piecewise
    linear d; except, axisymmetric, its hoop terms (above).
    """
    grad_u = grad_x(u)
    div_u = tr(grad_u)
    v3, a3, dudt3 = (section.vector(f, dimension) for f in (v, a, dudt))
    r_m = rho * (dudt3 + grad_u * a3) + grad_x(p)
    if dimension == "axisymmetric":
        eps = sym(grad_u)
        r_m = r_m - 2.0 * mu * as_vector([(eps[0, 0] - eps[2, 2]) / r, eps[1, 0] / r, 0.0])
    galerkin = (rho * inner(dudt3 + grad_u * a3, v3) + inner(stress(grad_u, p, mu), grad_x(v))
                + continuity_scale * q * div_u)                      # inertia, stress, continuity
    supg = tau_m * inner(grad_x(v) * a3, r_m)                          # streamline upwinding
    pspg = continuity_scale * tau_m / rho * inner(grad_x(q), r_m)      # pressure stabilisation
    lsic = rho * tau_c * div_u * tr(grad_x(v))                         # grad-div
    return galerkin + supg + pspg + lsic


def gradient(f, dimension):
    """Grad f (3D, section.py): 3x3 for a vector, a 3-vector for a scalar."""
    if f.ufl_shape == ():
        return section.vector(grad(f), dimension)
    return section.gradient(f, dimension)


def cell_residual(u, p, v, q, dudt, w, u_tau, rho, mu, inv_time, cell, continuity_scale,
                  dimension="3d"):
    """The stabilised residual's cell integrand on the current mesh, tested with (v, q).

    The parameters tau are taken at the velocity u_tau (the last time
    step's) and the time scale 1/inv_time: they vary by orders of
    magnitude with the velocity, and
    differentiating them would leave Newton a far harder problem for a
    change of the stabilisation alone.
    `continuity_scale` [g/(mm^2 ms)] multiplies the continuity rows so
    that they too are forces [N]: one residual norm for both equations.
    """
    tau_m, tau_c = tau(u_tau - w, rho, mu, inv_time, JacobianInverse(cell))
    if dimension == "3d":
        return _residual(grad, u, p, v, q, dudt, u - w, tau_m, tau_c, rho, mu, continuity_scale,
                         dimension)
    return _residual(lambda f: gradient(f, dimension), u, p, v, q, dudt, u - w, tau_m, tau_c,
                     rho, mu, continuity_scale, dimension, SpatialCoordinate(cell)[0])


def cell_residual_ale(u, p, v, q, dudt, w, F, u_tau, w_tau, F_tau, rho, mu, inv_time, cell,
                      continuity_scale, dimension="3d", r=None):
    """The same residual on the reference mesh, per unit reference volume.

    F = I + Grad d (3x3) maps the reference mesh onto the current one; w is
    the mesh velocity; r the current radius (axisymmetric). tau is lagged
    like the velocity: taken at the last time step's velocity u_tau, mesh
    velocity w_tau and mesh map F_tau, with the current cell metric
    K = dxi/dX F_tau^-1 (a section's: the in-plane block of F_tau).
    """
    F_inv = inv(F)

    def grad_x(f):
        return dot(grad(f) if dimension == "3d" else gradient(f, dimension), F_inv)

    F_tau_plane = F_tau if dimension == "3d" else as_matrix(
        [[F_tau[0, 0], F_tau[0, 1]], [F_tau[1, 0], F_tau[1, 1]]])
    tau_m, tau_c = tau(u_tau - w_tau, rho, mu, inv_time,
                       JacobianInverse(cell) * inv(F_tau_plane))
    return det(F) * _residual(grad_x, u, p, v, q, dudt, u - w, tau_m, tau_c, rho, mu,
                              continuity_scale, dimension, r)


def wall_traction(u, p, mu, F, N, dimension="3d"):
    """Traction sigma n da of the air on its boundary, per unit reference area (Nanson).

    sigma n da = sigma J F^-T N dA with N the reference outward normal of
    the air: the force the air receives from beyond its boundary is
    sigma n; the solid there receives the opposite. On a section F and N
    are 3D (padded).
    """
    F_inv = inv(F)
    grad_u = grad(u) if dimension == "3d" else gradient(u, dimension)
    return stress(dot(grad_u, F_inv), p, mu) * det(F) * F_inv.T * N


def backflow(u, v, w, n, rho, beta):
    """Outlet integrand -beta rho min(a . n, 0) u . v (Esmaily Moghadam et al. 2011)."""
    return -beta * rho * min_value(dot(u - w, n), 0.0) * dot(u, v)
