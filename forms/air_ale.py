"""Formulation `air_ale`: the air on a moving mesh, written on the reference mesh.

Unknowns (u, p) in one mixed space, equal-order continuous Lagrange of
degree `degree` (CMake builds degree 1: P1/P1, stable by PSPG); the mesh
displacement d (P1, the mesh's own element) is a coefficient here and the
unknown of forms/mesh_motion.py. The current air is x = X + d(X) over the
reference mesh X; with F = I + Grad d and J = det F, find (u, p) such that
for every admissible (v, q)

    sum_cells J [Galerkin + SUPG + PSPG + LSIC](u, p; v, q) dX
  + integral_{outlet} -beta rho min((u - w) . n, 0) u . v ds = 0,

(navier_stokes.cell_residual_ale), where the time derivatives at fixed
reference points and the mesh velocity are the same BDF

    du/dt|_X = inv_dt (c0 u + c1 u_n + c2 u_{n-1}),
    w        = inv_dt (c0 d + c1 d_n + c2 d_{n-1}),

(BDF1: c = 1, -1, 0; BDF2 with steps dt_{n+1}, dt_n: see cpp/air). The
mesh velocity being the derivative of the nodes' places by the scheme
that differentiates the nodal values makes a flow linear in x an exact
discrete solution on any moving mesh (the geometric conservation law of
the non-conservative ALE form; tests/test_air.cpp). The outlet's nodes
never move (cpp/mesh_motion holds them), so its facets need no mapping.

Forms:
- R: the residual; J = dR/d(u, p); J_mesh = dR/dd, the shape derivative
  (with the mesh velocity's dependence on d), exact;
- force_x, force_y, force_z: the force of the air on the fluid-solid
  interface, -integral sigma n da (navier_stokes.wall_traction), for a
  check of the consistent reaction the coupled solver moves onto the solid;
- traction_power: the power the air's stress delivers to the solid there,
  -integral sigma n . u da (u the air's velocity, the wall's by no slip):
  the work of the air on the solid from its own stress, independent of the
  reaction (the coupled puff's energy balance, cpp/run/air_block.h);
- mesh_jacobian (expression): det F per cell, whose sign shows a folded cell.

On a section (`dimension`, section.py) F = I + Grad d is the 3x3 one
(axisymmetric: its hoop entry 1 + d_r/R, the mesh's own hoop stretch),
N and the tractions are padded, and every integral is weighted by the
reference radius R (axisymmetric: per radian): R J is the current radius
times the in-plane Jacobian, the current volume element. The forces are
the meshed part's, per radian (axisymmetric: their radial sum is zero
over the revolution) or per unit thickness.

`degree`, `quadrature_degree` and `dimension` are its compile options (options.py).
"""
from ufl import (Constant, Coefficient, FacetNormal, FiniteElement, Identity, Measure,
                 MixedElement, SpatialCoordinate, TestFunctions, TrialFunction, VectorElement,
                 derivative, det, dot, split)

import navier_stokes
from options import degree, quadrature_degree, dimension
import section

# Facet tags (tags.py).
from tags import OUTLET, INTERFACE

cell = section.cell(dimension)
velocity_element = VectorElement("Lagrange", cell, degree)
pressure_element = FiniteElement("Lagrange", cell, degree)
element = MixedElement([velocity_element, pressure_element])
mesh_element = VectorElement("Lagrange", cell, 1)

v, q = TestFunctions(element)
dup = TrialFunction(element)
up = Coefficient(element)          # (u [mm/ms], p [MPa]) at t_{n+1}
up_n = Coefficient(element)        # at t_n
up_nm1 = Coefficient(element)      # at t_{n-1}
d = Coefficient(mesh_element)      # mesh displacement [mm] at t_{n+1}
d_n = Coefficient(mesh_element)    # at t_n
d_nm1 = Coefficient(mesh_element)  # at t_{n-1}
w_n = Coefficient(mesh_element)    # mesh velocity of the last step [mm/ms] (for tau)
dd = TrialFunction(mesh_element)
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
N = section.vector(FacetNormal(cell), dimension)  # reference outward normal
X_r = section.weight(cell, dimension)  # the reference radius R, else 1

F = Identity(3) + section.gradient(d, dimension)  # the mesh map's gradient
F_n = Identity(3) + section.gradient(d_n, dimension)
w = inv_dt * (c0 * d + c1 * d_n + c2 * d_nm1)        # mesh velocity
dudt = inv_dt * (c0 * u + c1 * u_n + c2 * u_nm1)     # du/dt at fixed X
# The current radius (axisymmetric).
r = SpatialCoordinate(cell)[0] + d[0] if dimension == "axisymmetric" else None

R = (navier_stokes.cell_residual_ale(u, p, v, q, dudt, w, F, u_n, w_n, F_n, rho, mu, inv_tau_time,
                                     cell, continuity_scale, dimension, r) * X_r * dx
     + navier_stokes.backflow(u, v, w, FacetNormal(cell), rho, beta) * X_r * ds(OUTLET))
J = derivative(R, up, dup)
J_mesh = derivative(R, d, dd)

# The air's force on the interface [N] (meshed part), -sigma n da.
traction = navier_stokes.wall_traction(u, p, mu, F, N, dimension)
force_x = -traction[0] * X_r * ds(INTERFACE)
force_y = -traction[1] * X_r * ds(INTERFACE)
force_z = -traction[2] * X_r * ds(INTERFACE)

# The power the air's stress delivers to the solid [W = N mm/ms] (meshed part).
traction_power = -dot(traction, section.vector(u, dimension)) * X_r * ds(INTERFACE)

# The current volume and the pressure's integral over it: a closed fluid's
# (the humor's) mean pressure.
volume = det(F) * X_r * dx
pressure_volume = p * det(F) * X_r * dx

forms = [R, J, J_mesh, force_x, force_y, force_z, traction_power, volume, pressure_volume]
mesh_jacobian = det(F)
expressions = [(mesh_jacobian, [[0.25, 0.25, 0.25] if dimension == "3d"
                                else [1.0 / 3.0, 1.0 / 3.0]])]
