"""Generalised-alpha time integration of M a + C v + f(u) = 0.

The unknown is u_{n+1}; the Newmark updates give

    a_{n+1} = (u_{n+1} - u_n - dt v_n) / (beta dt^2) - (1 - 2 beta) / (2 beta) a_n,
    v_{n+1} = v_n + dt ((1 - gamma) a_n + gamma a_{n+1}),

and the balance holds at the intermediate levels

    M a_{n+1-alpha_m} + C v_{n+1-alpha_f} + f(u_{n+1-alpha_f}, t_{n+1-alpha_f}) = 0,
    x_{n+1-alpha} = (1 - alpha) x_{n+1} + alpha x_n.

From the spectral radius at infinite frequency rho (1: no numerical
dissipation, the trapezoidal rule; 0: the highest modes killed in a step),
alpha_m = (2 rho - 1) / (rho + 1), alpha_f = rho / (rho + 1),
gamma = 1/2 - alpha_m + alpha_f, beta = (1 - alpha_m + alpha_f)^2 / 4:
second order for every rho in [0, 1], unconditionally stable.

Reference: J. Chung, G. M. Hulbert, J. Appl. Mech. 60 (1993) 371-375.
"""


def acceleration(u, u_old, v_old, a_old, dt, beta):
    """a_{n+1} from the Newmark displacement update."""
    return (u - u_old - dt * v_old) / (beta * dt**2) - (1 - 2 * beta) / (2 * beta) * a_old


def velocity(a, v_old, a_old, dt, gamma):
    """v_{n+1} from the Newmark velocity update."""
    return v_old + dt * ((1 - gamma) * a_old + gamma * a)


def level(new, old, alpha):
    """x_{n+1-alpha} = (1 - alpha) x_{n+1} + alpha x_n."""
    return (1 - alpha) * new + alpha * old
