"""Formulation `solid`: the finite-strain solid, unknown u; quasi-static
forms, and the dynamic balance of the generalised-alpha step (below).

Find u such that, for every admissible v,

    sum_laws integral_{Omega_law} P_law(F) : grad v dX            (internal work)
  + sum_c integral_{wall of cavity c} p_c J F^-T N . v dA        (cavity pressures)
  + integral_{pressed surface} p_press f J F^-T N . v dA = 0    (the press)

with f(X) the shape of the press (1 for a uniform one): the press phase's
pressure and a prescribed puff's p(r, t) act through it. A
closed cavity's pressure p_c is a Lagrange multiplier of V_c(u) = target;
its border of the Newton system (cpp/cavity) is dR/dp_c = `cavity_load_c`
(the residual's cavity term at unit pressure) and dV_c/du = `dvolume_c`.

with P = dPsi/dF. Cells carry the tag of their material law, facets the
tag of their load. Material parameters and fibres are per-cell (DG0)
fields, so any number of parts can share one law.

The nearly incompressible laws split Psi = Psi_iso(F) + U(J) (hgo.py,
neo_hookean.py, volumetric.py), the compressible neo-Hookean Psi =
Psi_shear(F) + lambda/2 (ln J)^2 (compressible_neo_hookean.py);
Saint Venant-Kirchhoff (saint_venant_kirchhoff.py) is not split.
`variant` chooses how the volumetric part is integrated:

- "" (displacement): at every cell quadrature point, like Psi_iso. The
  volumetric constraint J ~ 1 then binds at every point, and the elements
  lock as kappa/mu grows (Hughes, The Finite Element Method, 2000, ch. 4).
- "mixed" (displacement-pressure, P2/P0): the pressure p = U'(J) is one
  constant per cell, condensed out of the element: the volumetric energy
  is taken at the cell's centroid (Malkus & Hughes, CMAME 15 (1978)
  63-81; for P2, div u is linear, so the one-point rule is the exact
  P2/P0 mixed method at small strain; P2/P0 is inf-sup stable on
  tetrahedra, Boffi, Brezzi & Fortin, Mixed Finite Element Methods,
  Springer 2013, ch. 8). One constraint per
  cell instead of one per point: no locking. Degree 2 only.

`dimension` (section.py) gives the model's dimension: "3d", or a 2D
section, "axisymmetric" (every integral per radian, weighted by r; the
fibre families averaged over the azimuth, hgo.py) or "plane" (plane
strain, per unit thickness). On a section, F, N, v and x are 3D
(section.py), so the laws and loads below are the 3D ones.

`degree` (1 or 2), `quadrature_degree` of the cell integrals, `variant`
and `dimension` are its compile options (options.py, set by CMake's
nct_add_form). Facet integrals use 2 * degree, one more where r weighs
them.
"""
import basix
from ufl import (Coefficient, Constant, FacetNormal, FiniteElement, Measure,
                 SpatialCoordinate, TestFunction, TrialFunction, VectorElement, derivative,
                 det, diff, inner, sqrt, tr, Identity)

import cavity
import dynamics
import compressible_neo_hookean
import hgo
import kinematics
import neo_hookean
import saint_venant_kirchhoff
from options import degree, quadrature_degree, variant, dimension
import section
import support
import volumetric

# Integration tags (tags.py): cells by law, facets by load.
from tags import HGO, NEO_HOOKEAN, SAINT_VENANT_KIRCHHOFF, COMPRESSIBLE_NEO_HOOKEAN
from tags import CAVITY_1_WALL, PRESS, CAVITY_2_WALL, SUPPORT

cell = section.cell(dimension)
# The azimuths the fibre energy is averaged over (axisymmetric, hgo.py).
fibre_angles = 16
element = VectorElement("Lagrange", cell, degree)
cell_scalar = FiniteElement("DG", cell, 0)
# A fibre family per cell: its 3D direction; axisymmetric, its direction
# in (r, z, theta) at each of the fibre_angles azimuths.
cell_vector = VectorElement("DG", cell, 0,
                            dim=3 * fibre_angles if dimension == "axisymmetric" else 3)
nodal_scalar = FiniteElement("Lagrange", cell, 1)

v = TestFunction(element)
du = TrialFunction(element)
u = Coefficient(element)            # displacement [mm]

# Per-cell material fields
c10 = Coefficient(cell_scalar)      # matrix stiffness [MPa]
k1 = Coefficient(cell_scalar)       # fibre stiffness [MPa]
k2 = Coefficient(cell_scalar)       # fibre nonlinearity [-]
dispersion = Coefficient(cell_scalar)  # fibre dispersion kappa_f [-]
kappa = Coefficient(cell_scalar)    # bulk modulus [MPa]
youngs_modulus = Coefficient(cell_scalar)  # [MPa]
poisson_ratio = Coefficient(cell_scalar)   # [-]
fibre_1 = Coefficient(cell_vector)  # first fibre family (unit or zero)
fibre_2 = Coefficient(cell_vector)  # second fibre family (unit or zero)

# Loads [MPa]: up to two cavities (the merged one, or aqueous and vitreous)
p_cavity_1 = Constant(cell)
p_cavity_2 = Constant(cell)
p_press = Constant(cell)
press_profile = Coefficient(nodal_scalar)  # shape f of the press [-]
# The cut's lid per cavity, A_lid / A_cut (support.py; 0: no lid) [-]
lid_1 = Constant(cell)
lid_2 = Constant(cell)

# Fixed quadrature degrees: UFL's estimate explodes on exp() (docs/physics.md section 20).
dx = Measure("dx", metadata={"quadrature_degree": quadrature_degree})
# The volumetric energy's measure: one point (the centroid) when mixed.
dx_volume = Measure("dx", metadata={"quadrature_degree": 1 if variant == "mixed"
                                    else quadrature_degree})
# The weight r (axisymmetric; else 1) raises a facet integrand's degree by one.
r = section.weight(cell, dimension)
weighted = 0 if r == 1 else 1
ds = Measure("ds", metadata={"quadrature_degree": 2 * degree + weighted})

N = section.vector(FacetNormal(cell), dimension)
grad_v = section.gradient(v, dimension)


def as_3d(w):
    """w as a 3-vector (section.py). Inline: in 3D it is w itself, and
    FFCx names a coefficient after the last global bound to it."""
    return section.vector(w, dimension)


def deformation_gradient(w):
    """The 3x3 F of the displacement (expression) w."""
    return kinematics.deformation_gradient(w, dimension)


def hgo_isochoric_energy(F):
    """The HGO cornea's and limbus' Psi_iso; axisymmetric, its fibre energy
    averaged over the azimuth (hgo.py)."""
    if dimension == "axisymmetric":
        return hgo.azimuthal_isochoric_energy(F, c10, k1, k2, dispersion, fibre_1, fibre_2,
                                              fibre_angles)
    return hgo.isochoric_energy(F, c10, k1, k2, dispersion, fibre_1, fibre_2)


def balance(w):
    """Internal work and pressure loads at the displacement (expression) w."""
    Fw = deformation_gradient(w)
    Jw = det(Fw)
    P_volume = diff(volumetric.energy(Jw, kappa), Fw)
    P_cnh_volume = diff(compressible_neo_hookean.volumetric_energy(Jw, youngs_modulus,
                                                                   poisson_ratio), Fw)
    return (inner(diff(hgo_isochoric_energy(Fw), Fw), grad_v) * r * dx(HGO)
            + inner(diff(neo_hookean.isochoric_energy(Fw, c10), Fw), grad_v) * r
            * dx(NEO_HOOKEAN)
            + inner(P_volume, grad_v) * r * (dx_volume(HGO) + dx_volume(NEO_HOOKEAN))
            + inner(diff(saint_venant_kirchhoff.energy(Fw, youngs_modulus, poisson_ratio), Fw),
                    grad_v) * r * dx(SAINT_VENANT_KIRCHHOFF)
            + inner(diff(compressible_neo_hookean.shear_energy(Fw, Jw, youngs_modulus,
                                                               poisson_ratio), Fw), grad_v)
            * r * dx(COMPRESSIBLE_NEO_HOOKEAN)
            + inner(P_cnh_volume, grad_v) * r * dx_volume(COMPRESSIBLE_NEO_HOOKEAN)
            + cavity.follower_pressure(p_cavity_1, Fw, N, as_3d(v)) * r * ds(CAVITY_1_WALL)
            + cavity.follower_pressure(p_cavity_2, Fw, N, as_3d(v)) * r * ds(CAVITY_2_WALL)
            + (support.lid_pressure(p_cavity_1, lid_1, N, as_3d(v))
               + support.lid_pressure(p_cavity_2, lid_2, N, as_3d(v))) * r * ds(SUPPORT)
            + cavity.follower_pressure(p_press * press_profile, Fw, N, as_3d(v)) * r * ds(PRESS))


F = deformation_gradient(u)
psi_hgo = hgo_isochoric_energy(F)
psi_neo_hookean = neo_hookean.isochoric_energy(F, c10)
psi_volume = volumetric.energy(det(F), kappa)
psi_saint_venant_kirchhoff = saint_venant_kirchhoff.energy(F, youngs_modulus, poisson_ratio)
psi_cnh_shear = compressible_neo_hookean.shear_energy(F, det(F), youngs_modulus, poisson_ratio)
psi_cnh_volume = compressible_neo_hookean.volumetric_energy(det(F), youngs_modulus, poisson_ratio)

R = balance(u)
J = derivative(R, u, du)

# Enclosed cavity volumes (the meshed part, no symmetry factor) about x0,
# a point on the axis of a section.
x0 = Constant(cell, shape=(3 if dimension == "3d" else 2,))
x = section.vector(SpatialCoordinate(cell) + u, dimension)
d_space = section.space_dimension(dimension)
volume_1 = (cavity.volume(x, F, N, as_3d(x0), d_space) * r * ds(CAVITY_1_WALL)
            + support.lid_volume(lid_1, as_3d(u), N, d_space) * r * ds(SUPPORT))
volume_2 = (cavity.volume(x, F, N, as_3d(x0), d_space) * r * ds(CAVITY_2_WALL)
            + support.lid_volume(lid_2, as_3d(u), N, d_space) * r * ds(SUPPORT))

# The border of the closed-cavity system: dR/dp_c and dV_c/du.
cavity_load_1 = (cavity.follower_pressure(1.0, F, N, as_3d(v)) * r * ds(CAVITY_1_WALL)
                 + support.lid_pressure(1.0, lid_1, N, as_3d(v)) * r * ds(SUPPORT))
cavity_load_2 = (cavity.follower_pressure(1.0, F, N, as_3d(v)) * r * ds(CAVITY_2_WALL)
                 + support.lid_pressure(1.0, lid_2, N, as_3d(v)) * r * ds(SUPPORT))
dvolume_1 = derivative(volume_1, u, v)
dvolume_2 = derivative(volume_2, u, v)

# Von Mises equivalent of the Cauchy stress, per cell: the law indicators
# pick the stress of the cell's own law (1 on its cells, 0 elsewhere).
is_hgo = Coefficient(cell_scalar)
is_neo_hookean = Coefficient(cell_scalar)
is_saint_venant_kirchhoff = Coefficient(cell_scalar)
is_compressible_neo_hookean = Coefficient(cell_scalar)
P = (is_hgo * diff(psi_hgo + psi_volume, F) + is_neo_hookean * diff(psi_neo_hookean + psi_volume, F)
     + is_saint_venant_kirchhoff * diff(psi_saint_venant_kirchhoff, F)
     + is_compressible_neo_hookean * diff(psi_cnh_shear + psi_cnh_volume, F))
sigma = kinematics.cauchy_stress(P, F)
s = sigma - tr(sigma) / 3.0 * Identity(3)
von_mises = sqrt(1.5 * inner(s, s))

# Dynamics (generalised alpha, forms/dynamics.py): the balance at
# u_{n+1-alpha_f} plus inertia and mass-proportional damping,
# rho (a_{n+1-alpha_m} + damping v_{n+1-alpha_f}) . v. The mass is
# integrated exactly (degree 2 degree, with r's one more) whatever the
# cell quadrature.
u_old = Coefficient(element)        # u_n [mm]
v_old = Coefficient(element)        # v_n [mm/ms]
a_old = Coefficient(element)        # a_n [mm/ms^2]
density = Coefficient(cell_scalar)  # [g/mm^3]
dt = Constant(cell)          # [ms]
alpha_m = Constant(cell)
alpha_f = Constant(cell)
beta = Constant(cell)
gamma = Constant(cell)
damping = Constant(cell)     # mass-proportional [1/ms]
# The support on the cut (support.py), zero while clamped
support_stiffness = Constant(cell)  # k [MPa/mm]
support_damping = Constant(cell)    # c [MPa ms/mm]
u_support = Coefficient(element)           # u_0 [mm]
dx_mass = Measure("dx", metadata={"quadrature_degree": 2 * degree + weighted})

a_new = dynamics.acceleration(u, u_old, v_old, a_old, dt, beta)
v_new = dynamics.velocity(a_new, v_old, a_old, dt, gamma)
u_mid = dynamics.level(u, u_old, alpha_f)
R_dynamic = (density * inner(dynamics.level(a_new, a_old, alpha_m)
                             + damping * dynamics.level(v_new, v_old, alpha_f), v) * r
             * dx_mass
             + balance(u_mid)
             + support.spring_dashpot(support_stiffness, support_damping, u_mid, u_support,
                                      dynamics.level(v_new, v_old, alpha_f), v) * r * ds(SUPPORT))
J_dynamic = derivative(R_dynamic, u, du)
F_mid = deformation_gradient(u_mid)
cavity_load_dynamic_1 = (cavity.follower_pressure(1.0, F_mid, N, as_3d(v)) * r
                         * ds(CAVITY_1_WALL)
                         + support.lid_pressure(1.0, lid_1, N, as_3d(v)) * r * ds(SUPPORT))
cavity_load_dynamic_2 = (cavity.follower_pressure(1.0, F_mid, N, as_3d(v)) * r
                         * ds(CAVITY_2_WALL)
                         + support.lid_pressure(1.0, lid_2, N, as_3d(v)) * r * ds(SUPPORT))

# Energies (for checks): stored in the solid at u, kinetic at v_n.
strain_energy = (psi_hgo * r * dx(HGO) + psi_neo_hookean * r * dx(NEO_HOOKEAN)
                 + psi_volume * r * (dx_volume(HGO) + dx_volume(NEO_HOOKEAN))
                 + psi_saint_venant_kirchhoff * r * dx(SAINT_VENANT_KIRCHHOFF)
                 + psi_cnh_shear * r * dx(COMPRESSIBLE_NEO_HOOKEAN)
                 + psi_cnh_volume * r * dx_volume(COMPRESSIBLE_NEO_HOOKEAN))
kinetic_energy = 0.5 * density * inner(v_old, v_old) * r * dx_mass

# det F at the cell quadrature points and the vertices, to find inverted
# elements (det F <= 0, where ln J is undefined) and say where they are.
# Axisymmetric, the hoop stretch is 0/0 at a vertex on the axis: there the
# corners are taken 1 % of the way in towards the centroid.
if dimension == "3d":
    corners, reference_cell = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0],
                               [0.0, 0.0, 1.0]], basix.CellType.tetrahedron
else:
    corners, reference_cell = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]], basix.CellType.triangle
    if dimension == "axisymmetric":
        corners = [[0.99 * a + 0.01 / 3, 0.99 * b + 0.01 / 3] for a, b in corners]
jacobian_points = corners + basix.make_quadrature(reference_cell,
                                                  quadrature_degree)[0].tolist()
det_F = det(F)
centroid = [1.0 / (len(corners[0]) + 1)] * len(corners[0])

support_area = inner(N, N) * r * ds(SUPPORT)  # the cut's area (meshed part) [mm^2]

forms = [R, J, volume_1, volume_2, cavity_load_1, cavity_load_2, dvolume_1, dvolume_2,
         R_dynamic, J_dynamic, cavity_load_dynamic_1, cavity_load_dynamic_2,
         strain_energy, kinetic_energy, support_area]
expressions = [(von_mises, [centroid]), (det_F, jacobian_points)]
