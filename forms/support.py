"""The eye's support in the orbit: springs and dashpots on the cut, and its lid.

Springs and dashpots (a Robin condition). From the start of the dynamics
the cut face, clamped until then, is held by the traction

    t = -k (u - u_0) - c v,    k = K / A,  c = C / A,

u_0 the displacement when the springs take over (they take over the
clamp's reaction there as a dead load, cpp/solid/problem.cpp), and K
[N/mm], C [N ms/mm] the whole eye's stiffness and damping spread evenly
over the cut's area A (whole model). Its virtual work in the residual is

    R_s(u; v) = integral_cut (k (u - u_0) + c v) . v dA.

Reference: a spring and a damper for the whole eye's movement behind the
cornea, fitted to in-vivo Corvis deformations: S. Kling et al., PLoS ONE
9 (2014) e104904, table 3.

The lid. The model is cut by a plane through x0, and the cavity behind
the eye is closed there by a lid of area A_lid (docs/physics.md section 6)
that stands for the eye's posterior cap. The lid moves with the cut
face's mean displacement w, so a whole-eye translation neither changes
the cavity's volume nor lets the pressure push the model off its
support; the cap's share of the pressure p acts on the cut face. With
lid = A_lid / A_cut (both of the meshed part) and N the outward normal of
the cut face, w = -(1 / A_cut) integral_cut u . N dA, and the lid's term
of the volume about x0 (cavity.py) and its load are

    V_lid(u) = -1/3 w A_lid = 1/3 lid integral_cut u . N dA,
    R_lid(u; v) = -p lid integral_cut N . v dA   (the force p A_lid on the cap).

The wall's 1/3-formula is not closed while the cut moves: its derivative
carries the rim's terms, and with V_lid's they add up to the closed
surface's flux, -integral_wall v . J F^-T N dA - A_lid w(v), the
virtual volume change that R_lid's p A_lid works on (exactly for a
translation; the lid's area is held as the cut's rim moves radially).
Clamped, both vanish (u = v = 0 on the cut).
"""
from ufl import dot, inner


def spring_dashpot(stiffness, damping, u, u_0, velocity, v):
    """Virtual work integrand of the springs and dashpots, (k (u - u_0) + c v) . v."""
    return inner(stiffness * (u - u_0) + damping * velocity, v)


def lid_volume(lid, u, N, space_dimension=3):
    """Integrand of the lid's share of the cavity volume, 1/3 lid u . N (1/2 in 2D)."""
    return lid * dot(u, N) / float(space_dimension)


def lid_pressure(p, lid, N, v):
    """Virtual work integrand of the cavity pressure on the lid, -p lid N . v."""
    return -p * lid * dot(N, v)
