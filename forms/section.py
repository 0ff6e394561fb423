"""The dimension of a model: the 3D fields of a 3D mesh or of a 2D section.

`dimension` is "3d", "axisymmetric" or "plane". On a 2D mesh every
kinematic quantity is still the 3D one, so that each material law works
unchanged on a 3x3 deformation gradient:

- axisymmetric, without swirl (r = x[0], z = x[1], components ordered
  r, z, theta): a displacement u = (u_r, u_z) has the gradient

      Grad u = [[du_r/dr, du_r/dz, 0], [du_z/dr, du_z/dz, 0], [0, 0, u_r/r]],

  so that F_thth = 1 + u_r/r is the hoop stretch, J = det F_2D F_thth and
  I1 = tr C_2D + F_thth^2 (the 2x2 J and I1 are the classic error). The
  volume element is dV = r dr dz dtheta: every integral is taken per
  radian, weighted by the reference radius r (the whole body is 2 pi
  times it). 1/r is evaluated only at quadrature points, strictly inside
  the cells; the integrands are rational in r, so every measure states
  its quadrature degree.
- plane (plane strain, per unit thickness): F_33 = 1, weight 1.

Reference: T. J. R. Hughes, The Finite Element Method, Dover 2000, sec.
2.12 (axisymmetric kinematics and weights); J. Bonet, R. D. Wood,
Nonlinear Continuum Mechanics for Finite Element Analysis, 2nd ed. 2008,
sec. 4.13 (F of a section); docs/physics.md section 21.
"""
from ufl import SpatialCoordinate, as_matrix, as_vector, grad

DIMENSIONS = ("3d", "axisymmetric", "plane")


def cell(dimension):
    """The mesh's cell: tetrahedron in 3D, triangle for a section."""
    from ufl import tetrahedron, triangle
    return tetrahedron if dimension == "3d" else triangle


def vector(w, dimension):
    """A vector of the mesh's dimension as a 3-vector (zero out of plane)."""
    if dimension == "3d":
        return w
    return as_vector([w[0], w[1], 0.0])


def gradient(u, dimension):
    """Grad u as a 3x3 tensor (above)."""
    g = grad(u)
    if dimension == "3d":
        return g
    hoop = u[0] / SpatialCoordinate(u.ufl_domain())[0] if dimension == "axisymmetric" else 0.0
    return as_matrix([[g[0, 0], g[0, 1], 0.0], [g[1, 0], g[1, 1], 0.0], [0.0, 0.0, hoop]])


def weight(domain, dimension):
    """The volume element's weight: the reference radius r, else 1."""
    return SpatialCoordinate(domain)[0] if dimension == "axisymmetric" else 1


def space_dimension(dimension):
    """The dimension the divergence theorem works in: 2 for a plane section
    (a cavity's "volume" is its area per unit thickness), else 3."""
    return 2 if dimension == "plane" else 3
