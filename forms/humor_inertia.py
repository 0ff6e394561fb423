"""Formulation `humor_inertia`: the mass of a closed cavity's humor, as the
inertia of its translation, in the solid's dynamic balance.

A closed cavity holds its volume V (cavity.py): its humor is incompressible.
Whatever the wall does, the humor's momentum is then that of its centroid,

    P = rho integral_Omega_f w dV = rho dM/dt,   M(u) = integral_Omega_f (x - x0) dV,

(w the humor's velocity: integral w_k dV = integral w . grad x_k dV =
integral_boundary x_k w . n dA by div w = 0), and the wall must push it
with the force f = dP/dt = rho d2M/dt2. By the divergence theorem M is an
integral over the cavity's boundary: its wall, the lid on the cut
(support.py) and planes through x0 that give nothing to the components
kept (a mirror plane's normal component is not kept; the axial one on an
axisymmetric section's axis has no area). With N the solid's outward
normal (into the cavity) and no sum over k,

    M_k(u) = -1/2 integral_wall (x_k - x0_k)^2 (J F^-T N)_k dA
             + 1/2 lid integral_cut (u . N)^2 N_k dA,

the lid's term exact for a lid moving with the cut along its normal.

Each kept component of each cavity has its inertial force f as an
unknown, bordering the Newton system like the cavity pressures. In the
generalised-alpha step (dynamics.py) the humor's acceleration at
n+1-alpha_m is affine in M at the step's end, a = c (M - M*), with
c = (1 - alpha_m) / (beta dt^2) and M* from M_n and its rates. The step's
balance and the force are the stationary point of

    L(u, f) = Pi(u) + f . (M(u) - M*) / V - |f|^2 / (2 rho V c),

so that f = rho c (M - M*) = rho (d2M/dt2)_{n+1-alpha_m} and the solid's
residual gains (f / V) . dM/du: on the wall the pressure
-(f / V) . (x - x0) = -rho a . (x - x0), the pressure field of a fluid
translating rigidly with the acceleration a (Euler's equation,
grad p = -rho a), whose resultant on the wall is -f. The bordered
system stays symmetric: dR/df = dG/du = dM/du / V, dG/df = -1 / (rho V c).
The constant part of that pressure is the cavity's (the multiplier of
V), which is thus the pressure at x0; the humor's mean pressure is
p - (f / V) . M / V.

What this leaves out: the humor's motion relative to its centroid (the
flow a deforming wall drives inside the cavity, e.g. the cornea's), whose
added mass is local to the moving wall (docs/physics.md section 6).

Forms (gdim-vector constants g_1 and g_2 weigh the two cavities' moments):

    moment  = g_1 . M_1(u) + g_2 . M_2(u),   load = d moment/du,
    tangent = d load/du.

The residual uses g_c = f_c / V_c; the border's vectors and the moments
themselves g_c = e_k / V_c and e_k.

Reference: the momentum of an incompressible fluid in a moving container,
G. K. Batchelor, An Introduction to Fluid Dynamics, CUP 1967, sec. 6.4;
R. J. Fritz, J. Eng. Ind. 94 (1972) 167-173 (the fluid in a rigid vessel
adds its mass to the vessel's translation); docs/physics.md section 6.
"""
from ufl import (Coefficient, Constant, FacetNormal, Measure, SpatialCoordinate, TestFunction,
                 TrialFunction, VectorElement, derivative, det, dot, inv)

import kinematics
from options import degree, dimension
import section

# The solid's facet tags (tags.py).
from tags import CAVITY_1_WALL, CAVITY_2_WALL, SUPPORT

cell = section.cell(dimension)
gdim = 3 if dimension == "3d" else 2
element = VectorElement("Lagrange", cell, degree)
v = TestFunction(element)
du = TrialFunction(element)
u = Coefficient(element)  # displacement [mm]

x0 = Constant(cell, shape=(gdim,))  # the volume's origin (forms/solid.py) [mm]
lid_1 = Constant(cell)  # the cut's lid per cavity, A_lid / A_cut (support.py) [-]
lid_2 = Constant(cell)
g_1 = Constant(cell, shape=(gdim,))  # the weights of each cavity's moment
g_2 = Constant(cell, shape=(gdim,))

r = section.weight(cell, dimension)
weighted = 0 if r == 1 else 1
# (x_k - x0_k)^2 of degree 2 degree times the cofactor's (degree - 1) (gdim - 1).
ds = Measure("ds", metadata={"quadrature_degree": 2 * degree + (degree - 1) * (gdim - 1)
                             + weighted})

N = section.vector(FacetNormal(cell), dimension)
F = kinematics.deformation_gradient(u, dimension)
x = section.vector(SpatialCoordinate(cell) + u, dimension)
d = x - section.vector(x0, dimension)
area = det(F) * inv(F).T * N  # J F^-T N


def wall_moment(g):
    """-1/2 sum_k g_k (x_k - x0_k)^2 (J F^-T N)_k."""
    g3 = section.vector(g, dimension)
    return -0.5 * sum(g3[k] * d[k] * d[k] * area[k] for k in range(3))


def lid_moment(g, lid):
    """1/2 lid (u . N)^2 sum_k g_k N_k."""
    # u as a 3-vector inline: in 3D it is u itself, and FFCx names a
    # coefficient after the last global bound to it.
    g3 = section.vector(g, dimension)
    return 0.5 * lid * dot(section.vector(u, dimension), N) ** 2 * dot(g3, N)


moment = (wall_moment(g_1) * r * ds(CAVITY_1_WALL) + wall_moment(g_2) * r * ds(CAVITY_2_WALL)
          + (lid_moment(g_1, lid_1) + lid_moment(g_2, lid_2)) * r * ds(SUPPORT))
load = derivative(moment, u, v)
tangent = derivative(load, u, du)

forms = [moment, load, tangent]
