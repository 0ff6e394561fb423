"""Formulation `viscoelasticity`: finite-strain viscoelasticity of the
isochoric matrix (Holzapfel and Simo), added to the solid's dynamic balance.

    Psi = U(J) + Psi_iso(Cbar) + sum_k Upsilon_k,
    S = S_vol + S_iso + sum_k Q_k,  S_iso = 2 dPsi_m/dC,
    dQ_k/dt + Q_k / tau_k = beta_k dS_iso/dt,  Q_k(0) = 0,

with Psi_m = C10 (Ibar1 - 3) the matrix part of the part's law (hgo.py,
neo_hookean.py): each Prony term k relaxes the matrix's isochoric stress
with relaxation time tau_k and relative modulus beta_k, relative to the
long-time (equilibrium) response. A step's strain thus meets the
instantaneous matrix stiffness (1 + sum_k beta_k) C10, which relaxes to C10;
at small strain the shear modulus is the standard linear solid's
mu(t) = 2 C10 (1 + sum_k beta_k exp(-t / tau_k)). The volumetric part and
the fibres stay elastic.

The quasi-static phases are the long-time response (Q = 0): the eye has
sat under its pressure for much longer than any tau_k. The history starts
with the dynamics, at the stress of that state. Over a step the
convolution is integrated exactly for S_iso linear in time,

    Q_k,n+1 = exp(-dt/tau_k) Q_k,n + beta_k g_k (S_iso,n+1 - S_iso,n),
    g_k = tau_k / dt (1 - exp(-dt / tau_k)),

second order and unconditionally stable (R. L. Taylor, K. S. Pister,
G. L. Goudreau, Int. J. Numer. Methods Eng. 2 (1970) 45-59; the midpoint
variant is J. C. Simo, CMAME 60 (1987) 153-173, and G. A. Holzapfel,
Nonlinear Solid Mechanics, Wiley 2000, section 6.10, eq. (6.230)). As the
elastic stress (dynamics.py), the viscous one enters the balance at the
generalised-alpha level n+1-alpha_f: the same update over the part
(1 - alpha_f) dt of the step, at F_{n+1-alpha_f},

    P_visc = F_m sum_k Q_k(F_m, (1 - alpha_f) dt),  F_m = F(u_{n+1-alpha_f}),

so that its tangent is symmetric like the elastic one's (a symmetric
factorisation, solver.factorisation = "ldlt", keeps Newton's rate); with
alpha_f = 0 it is the update itself.

History lives at the cell quadrature points (the solid's cell
quadrature, so `quadrature_degree` must be the solid's): S_iso,n and each
Q_k,n, symmetric, stored as (11, 22, 33, 12, 13, 23). Up to `terms`
Prony terms; a cell's unused ones have beta_k = 0.

`work` is the work done on the viscous branches over the step,
integral P_visc : (F_{n+1} - F_n) dV: summed over a load cycle that ends
relaxed it is the energy dissipated, never negative.
"""
import basix
from ufl import (Coefficient, Constant, FiniteElement, Measure, TestFunction, TrialFunction,
                 VectorElement, as_matrix, as_vector, derivative, diff, exp, inner, inv, tr)

import dynamics
import kinematics
from options import degree, quadrature_degree, dimension
import section

HGO, NEO_HOOKEAN = 1, 2  # the law tags of forms/solid.py whose matrix relaxes
terms = 3  # the most Prony terms a part may have

cell = section.cell(dimension)
element = VectorElement("Lagrange", cell, degree)
cell_scalar = FiniteElement("DG", cell, 0)
history = VectorElement("Quadrature", cell, quadrature_degree, dim=6,
                        quad_scheme="default")

v = TestFunction(element)
du = TrialFunction(element)
u = Coefficient(element)       # u_{n+1} [mm]
u_old = Coefficient(element)   # u_n [mm]
c10 = Coefficient(cell_scalar)  # matrix stiffness [MPa] (the solid's field)
stress_old = Coefficient(history)  # S_iso,n [MPa]
# Per term k (FFCx names a coefficient after its variable): Q_k,n [MPa],
# beta_k [-], tau_k [ms].
overstress_old_1, overstress_old_2, overstress_old_3 = (Coefficient(history) for k in range(3))
modulus_1, modulus_2, modulus_3 = (Coefficient(cell_scalar) for k in range(3))
relaxation_time_1, relaxation_time_2, relaxation_time_3 = (Coefficient(cell_scalar)
                                                           for k in range(3))
overstress_old = [overstress_old_1, overstress_old_2, overstress_old_3]
modulus = [modulus_1, modulus_2, modulus_3]
relaxation_time = [relaxation_time_1, relaxation_time_2, relaxation_time_3]
dt = Constant(cell)       # [ms]
alpha_f = Constant(cell)

dx = Measure("dx", metadata={"quadrature_degree": quadrature_degree})
r = section.weight(cell, dimension)


def voigt(T):
    """A symmetric 3x3 tensor as (11, 22, 33, 12, 13, 23)."""
    return as_vector([T[0, 0], T[1, 1], T[2, 2], T[0, 1], T[0, 2], T[1, 2]])


def tensor(q):
    """The symmetric 3x3 tensor of its (11, 22, 33, 12, 13, 23) entries."""
    return as_matrix([[q[0], q[3], q[4]], [q[3], q[1], q[5]], [q[4], q[5], q[2]]])


def matrix_stress(F):
    """S_iso of the matrix energy C10 (Ibar1 - 3): F^-1 dPsi/dF."""
    return inv(F) * diff(c10 * (tr(kinematics.isochoric_right_cauchy_green(F)) - 3.0), F)


def overstress(F, h):
    """Q_k of each term a time h after t_n, at the deformation gradient F."""
    dS = matrix_stress(F) - tensor(stress_old)
    out = []
    for k in range(terms):
        decay = exp(-h / relaxation_time[k])
        g = relaxation_time[k] / h * (1.0 - decay)
        out.append(decay * tensor(overstress_old[k]) + modulus[k] * g * dS)
    return out


F = kinematics.deformation_gradient(u, dimension)
F_old = kinematics.deformation_gradient(u_old, dimension)
F_mid = kinematics.deformation_gradient(dynamics.level(u, u_old, alpha_f), dimension)
Q_new = overstress(F, dt)
P_visc = F_mid * sum(overstress(F_mid, (1.0 - alpha_f) * dt))


def over_matrix(integrand):
    """The integral over the cells whose matrix relaxes (weighted by r)."""
    return integrand * r * dx(HGO) + integrand * r * dx(NEO_HOOKEAN)


R = over_matrix(inner(P_visc, section.gradient(v, dimension)))
J = derivative(R, u, du)
work = over_matrix(inner(P_visc, F - F_old))

# The history's update, at the cell quadrature points (the solid's rule).
reference_cell = basix.CellType.tetrahedron if dimension == "3d" else basix.CellType.triangle  # noqa: E501
points = basix.make_quadrature(reference_cell, quadrature_degree)[0].tolist()
# Q_k,n+1 of every term in one expression (one per term would be
# identical kernels, which FFCx names alike): entries 6k to 6k+5.
stress_new = voigt(matrix_stress(F))
overstress_new = as_vector([voigt(q)[i] for q in Q_new for i in range(6)])

forms = [R, J, work]
expressions = [(stress_new, points), (overstress_new, points)]
