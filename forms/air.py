"""Formulation `air`: the air, incompressible Navier-Stokes in ALE form.

Unknowns (u, p) in one mixed space: equal-order continuous Lagrange of
degree `degree` for both (CMake builds degree 1: P1/P1), stable by the
PSPG term (forms/navier_stokes.py).
Find (u, p) such that, for every admissible (v, q),

    sum_cells [Galerkin + SUPG + PSPG + LSIC](u, p; v, q) dx
  + integral_{outlet} -beta rho min((u - w) . n, 0) u . v ds = 0,

with du/dt|_X = inv_dt (c0 u + c1 u_n + c2 u_{n-1}) on the mesh that
moves with velocity w (BDF1: c = 1, -1, 0; BDF2: 3/2, -2, 1/2; steady
flow: inv_dt = 0). Walls, symmetry planes and the inlet are Dirichlet
conditions on u (cpp/air); the outlet's natural condition is sigma n = 0.

On a section (`dimension`, section.py) every integral is weighted by r
(axisymmetric: per radian) and the residual is the 3D one
(navier_stokes.py).

`degree`, `quadrature_degree` and `dimension` are its compile options (options.py).
"""
from ufl import (Constant, Coefficient, FacetNormal, FiniteElement, Measure, MixedElement,
                 TestFunctions, TrialFunction, VectorElement, derivative, split)

import navier_stokes
from options import degree, quadrature_degree, dimension
import section

# Facet tag of the outlet (tags.py).
from tags import OUTLET

cell = section.cell(dimension)
velocity_element = VectorElement("Lagrange", cell, degree)
pressure_element = FiniteElement("Lagrange", cell, degree)
element = MixedElement([velocity_element, pressure_element])
mesh_velocity_element = VectorElement("Lagrange", cell, 1)

v, q = TestFunctions(element)
dup = TrialFunction(element)
up = Coefficient(element)          # (u [mm/ms], p [MPa]) at t_{n+1}
up_n = Coefficient(element)        # at t_n
up_nm1 = Coefficient(element)      # at t_{n-1}
w = Coefficient(mesh_velocity_element)  # mesh velocity [mm/ms]
u, p = split(up)
u_n, _ = split(up_n)
u_nm1, _ = split(up_nm1)

rho = Constant(cell)        # [g/mm^3]
mu = Constant(cell)         # [MPa ms]
inv_dt = Constant(cell)     # 1/dt [1/ms]; 0: steady
inv_tau_time = Constant(cell)  # 1/T of the stabilisation [1/ms] (navier_stokes.tau)
c0 = Constant(cell)         # BDF coefficients
c1 = Constant(cell)
c2 = Constant(cell)
beta = Constant(cell)       # backflow coefficient [-]
continuity_scale = Constant(cell)  # [g/(mm^2 ms)]: continuity rows in N

# Fixed quadrature: tau's square root and division make UFL's estimate explode.
dx = Measure("dx", metadata={"quadrature_degree": quadrature_degree})
ds = Measure("ds", metadata={"quadrature_degree": 2 * degree})
n = FacetNormal(cell)
r = section.weight(cell, dimension)

dudt = inv_dt * (c0 * u + c1 * u_n + c2 * u_nm1)
R = (navier_stokes.cell_residual(u, p, v, q, dudt, w, u_n, rho, mu, inv_tau_time, cell,
                                 continuity_scale, dimension) * r * dx
     + navier_stokes.backflow(u, v, w, n, rho, beta) * r * ds(OUTLET))
J = derivative(R, up, dup)

forms = [R, J]
