"""Formulation `humor_flow`: the flow a moving wall drives in a closed
cavity's humor, as the hydroelastic pressure field of an inviscid,
incompressible fluid, linear in the wall's acceleration.

In the humor (mesh Omega_h, moved with the wall), Euler's equation
linearised about rest, rho dw/dt = -grad p, with div w = 0 gives
Laplace's equation for the pressure, and on the wall (normal N out of
the solid, into the humor; the wall's acceleration a) the normal
component of Euler's equation its Neumann condition, dp/dN = rho a . N:

    integral_Omega_h grad p . grad q dx = rho integral_wall (a . n da) q     (1)

for every q, with n da = J F^-T N dA (cavity.py). Where the humor's
boundary is not a wall (a rigid lid, a fixed container), dp/dn = 0.
The constant part of p is the cavity's pressure multiplier P_c, which
holds the cavity's volume (cavity.py): the Newton unknown here is the
rest, p~ = p - P_c, held at zero at one node of each cavity (a separate
mean pressure and the multiplier together would be singular). The wall
feels the whole pressure, P_c (solid.py) and p~:

    R_solid += integral_wall p~ J F^-T N . v dA.                          (2)

In the generalised-alpha step (dynamics.py) the wall's acceleration at
n+1-alpha_m is a = c (u - u*), c = (1 - alpha_m) / (beta dt^2), so
(1) divided by -rho c,

    G(q) = integral_wall (a / c) . J F^-T N q dA
           - 1 / (rho c) integral_Omega_h grad p~ . grad q dx = 0,           (3)

has dG/du = integral_wall du . J F^-T N q dA + ..., the transpose of
(2)'s dR/dp~: the coupled matrix is symmetric to leading order, with a
negative definite pressure block -H / (rho c). Eliminating p~ gives the
added mass rho B^T H^-1 B on the wall (Morand and Ohayon).

The lid. Where the model is cut (support.py), the humor ends at the lid
on the cut, which moves with the cut face's mean displacement: its
normal acceleration into the humor is -1 / A_cut integral_cut a . N dA,
and (3) gains, with L(q) = integral_lid q dA on the humor's mesh,

    G_lid(q) = W(u) L(q),   W(u) = -1 / A_cut integral_cut (a / c) . N dA,

while the cap carries p~'s resultant on the lid onto the cut face as
support.py carries the cavity's pressure:

    R_lid(u; v) = -L(p~) / A_cut integral_cut N . v dA.

Their blocks are rank one, -L (x) n / A_cut and its transpose, with
n(v) = integral_cut N . v dA (`cut_normal`): the system stays
symmetric. A translating eye then drives p~ = -rho a . (x - x0) + const:
the humor's translation (humor_inertia.py) is the flow's special case.

The wall's terms (2), (3) are integrated on the solid's mesh, where u, its
history and the cavity's normal are: the pressure there is a P1 field of
the solid's mesh per cavity (p_1, p_2), whose wall nodes are the humor
mesh's (cpp/humor_flow pairs them by place). The humor mesh's term (3) is
on its current geometry (`laplace`, P1), weighted by the current radius
on an axisymmetric section; the compatibility of (1), integral a . n da
= 0, holds to the neglected order rho |w|^2 (cavity.py holds the volume).

Reference: H. J.-P. Morand, R. Ohayon, Fluid Structure Interaction,
Wiley 1995, ch. 4 and 8 (the incompressible, inviscid liquid in a
flexible container: the pressure formulation and its added mass);
docs/physics.md section 6 (the humor's flow).
"""
from ufl import (Coefficient, Constant, FacetNormal, FiniteElement, Measure,
                 TestFunction, TrialFunction, VectorElement, derivative, grad, inner)

import cavity
import dynamics
import kinematics
from options import degree, dimension
import section

# The solid's facet tags and the humor's (tags.py).
from tags import CAVITY_1_WALL, CAVITY_2_WALL, HUMOR_LID, SUPPORT

cell = section.cell(dimension)
element = VectorElement("Lagrange", cell, degree)
scalar = FiniteElement("Lagrange", cell, 1)

# The solid's displacement, its history and the wall's pressure per cavity.
v = TestFunction(element)
du = TrialFunction(element)
q = TestFunction(scalar)
dp = TrialFunction(scalar)
u = Coefficient(element)      # [mm]
u_old = Coefficient(element)  # u_n [mm]
v_old = Coefficient(element)  # v_n [mm/ms]
a_old = Coefficient(element)  # a_n [mm/ms^2]
p_1 = Coefficient(scalar)     # p~ on cavity 1's wall [MPa]
p_2 = Coefficient(scalar)     # p~ on cavity 2's wall [MPa]
dt = Constant(cell)           # [ms]
alpha_m = Constant(cell)
beta = Constant(cell)

r = section.weight(cell, dimension)
weighted = 0 if r == 1 else 1
gdim = 3 if dimension == "3d" else 2
# p or q (1) times v or a (degree) times the cofactor ((degree - 1)(gdim - 1)).
ds = Measure("ds", metadata={"quadrature_degree": 1 + degree
                             + (degree - 1) * (gdim - 1) + weighted})

N = section.vector(FacetNormal(cell), dimension)
F = kinematics.deformation_gradient(u, dimension)
c = (1 - alpha_m) / (beta * dt**2)
a_mid = dynamics.level(dynamics.acceleration(u, u_old, v_old, a_old, dt, beta), a_old, alpha_m)
a_scaled = section.vector(a_mid, dimension) / c
v3 = section.vector(v, dimension)

# (2): the wall's load, and its blocks.
load = (cavity.follower_pressure(p_1, F, N, v3) * r * ds(CAVITY_1_WALL)
        + cavity.follower_pressure(p_2, F, N, v3) * r * ds(CAVITY_2_WALL))
load_u = derivative(load, u, du)
load_p_1 = derivative(load, p_1, dp)
load_p_2 = derivative(load, p_2, dp)

# (3)'s wall term per cavity (test q), and its block.
flux_1 = cavity.follower_pressure(q, F, N, a_scaled) * r * ds(CAVITY_1_WALL)
flux_2 = cavity.follower_pressure(q, F, N, a_scaled) * r * ds(CAVITY_2_WALL)
flux_1_u = derivative(flux_1, u, du)
flux_2_u = derivative(flux_2, u, du)

# The lid's: the cut face's normal, area, (a / c) . N and u . N.
cut_normal = inner(N, v3) * r * ds(SUPPORT)
cut_area = inner(N, N) * r * ds(SUPPORT)
cut_flux = inner(a_scaled, N) * r * ds(SUPPORT)
cut_motion = inner(section.vector(u, dimension), N) * r * ds(SUPPORT)

# (3)'s humor term, on the humor's mesh (its current geometry).
p = Coefficient(scalar)       # p~ in the humor [MPa]
compliance = Constant(cell)   # 1 / (rho c) [mm^2 / MPa]
radius = section.weight(cell, dimension)  # the current r: the mesh moves
dx = Measure("dx", metadata={"quadrature_degree": 0 + weighted})
laplace = -compliance * inner(grad(p), grad(q)) * radius * dx
laplace_p = derivative(laplace, p, dp)
ds_humor = Measure("ds", metadata={"quadrature_degree": 1 + weighted})
lid_area = q * radius * ds_humor(HUMOR_LID)

forms = [load, load_u, load_p_1, load_p_2, flux_1, flux_2, flux_1_u, flux_2_u, cut_normal,
         cut_area, cut_flux, cut_motion, laplace, laplace_p, lid_area]
