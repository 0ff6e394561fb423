"""Formulation `mesh_motion`: the air mesh's displacement, extended from its boundary.

The air mesh follows the solid: its displacement d equals the solid's on
the fluid-solid interface, vanishes where the air's boundary is fixed
(nozzle, inlet, outlet, and the edge of the moving region), slides on the
symmetry planes, and is extended into the air by a pseudo-elastic problem
on the reference mesh (linear: the reference never changes):

    harmonic:  integral_Omega k Grad d : Grad v dX = 0,
    elastic:   integral_Omega k [2 mu_m eps(d) : eps(v) + lambda_m div d div v] dX = 0,
               mu_m = 1 / (2 (1 + nu_m)),  lambda_m = nu_m / ((1 + nu_m)(1 - 2 nu_m)),

with the Jacobian-based stiffening of Stein, Tezduyar & Benney (2003)

    k = scale (J_0 / J_e)^chi,

J_e the reference cell's Jacobian determinant (6 times its volume): the
small cells, where the jet and the cornea's boundary layer are resolved,
are stiffer and deform less, and the large ones take up the motion.
chi = 0 switches the stiffening off; Stein et al. recommend chi of about
1. `scale` [MPa] makes the rows forces [N], as the other blocks' rows.

On a section (`dimension`, section.py) the extension is the same planar
problem on the section's triangles (J_e twice the cell's area), not
weighted by r: any smooth extension that keeps the cells valid serves,
and the air's ALE form is exact for whatever motion it gives; an
axisymmetric section holds d_r = 0 on the axis, and takes the plane
kernels (CMake builds "3d" and "plane").

Reference: K. Stein, T. E. Tezduyar, R. Benney, Mesh moving techniques for
fluid-structure interactions with large displacements, J. Appl. Mech. 70
(2003) 58-63, eq. (9)-(11); docs/physics.md section 8.
"""
from ufl import (Coefficient, Constant, JacobianDeterminant, Measure, TestFunction,
                 TrialFunction, VectorElement, derivative, div, grad, inner, sym)

from options import dimension
import section

# Cell tag of the moving region (tags.py).
from tags import MOVING

cell = section.cell(dimension)
element = VectorElement("Lagrange", cell, 1)
v = TestFunction(element)
dd = TrialFunction(element)
d = Coefficient(element)           # mesh displacement [mm]

scale = Constant(cell)      # [MPa]
reference_jacobian = Constant(cell)  # J_0 [mm^3; a section's mm^2]
chi = Constant(cell)        # stiffening power [-]
poisson_ratio = Constant(cell)  # nu_m of the elastic extension [-]

# The integrands are constant per cell: one point is exact.
dx = Measure("dx", metadata={"quadrature_degree": 1})

k = scale * (reference_jacobian / abs(JacobianDeterminant(cell)))**chi


def harmonic(d, v):
    """k Grad d : Grad v."""
    return k * inner(grad(d), grad(v))


def elastic(d, v, nu):
    """k [2 mu_m eps(d) : eps(v) + lambda_m div d div v], Young's modulus 1."""
    mu_m = 1.0 / (2.0 * (1.0 + nu))
    lambda_m = nu / ((1.0 + nu) * (1.0 - 2.0 * nu))
    return k * (2.0 * mu_m * inner(sym(grad(d)), sym(grad(v))) + lambda_m * div(d) * div(v))


R_harmonic = harmonic(d, v) * dx(MOVING)
J_harmonic = derivative(R_harmonic, d, dd)
R_elastic = elastic(d, v, poisson_ratio) * dx(MOVING)
J_elastic = derivative(R_elastic, d, dd)

forms = [R_harmonic, J_harmonic, R_elastic, J_elastic]
