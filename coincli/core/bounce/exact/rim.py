"""On one rim point: the coin rolling or slipping on the lowest point of its rim.

The state is the centre ``x``, the axis ``n`` (unit), the centre's velocity ``v`` and the
angular velocity ``w`` (world frame; the spin about the axis needs no angle of its own, the
body being symmetric).  The contact is the lowest rim point ``r(n)`` (:func:`.body.rim_point`),
which moves over the body as ``n`` turns: ``dr/dt = (dr/dn) (w x n)``.

Its height above the plane, ``z - hh |n_z| - a sqrt(1 - n_z^2)``, has the time derivative
``v_z + z.(w x r)`` and the second derivative ``z.(a_G + alpha x r + w x dr/dt)``; the velocity of
the body's point at the contact is ``v + w x r``, with the time derivative ``a_G + alpha x r + w
x dr/dt``.  With the contact force ``F`` (normal part ``N``), Newton and Euler give ``m a_G = F -
m g z`` and ``I alpha = r x F + M_res - w x I w``, so that contact acceleration is affine in
``F``; each mode is a linear solve:

- **rolling** (no slip): all three components vanish; ``F`` (3) follows.  It holds while ``N >=
  0`` and ``|F_t| <= mu N`` (static friction within the cone);
- **slipping**: Coulomb friction opposes the contact point's slip ``s``, ``F = N (z - mu s/|s|)``,
  and only the normal component vanishes; ``N`` follows.

``N < 0`` means the constraint would have to pull: the coin lifts off (unilateral contact; the
flight takes over).  The resistances are torques proportional to ``N``: rolling resistance
``-c N w_h / |w_h|`` (``w_h`` the horizontal part of ``w``, the rolling about tangent axes;
``c`` the surface's ``--rolling`` length) and spinning resistance ``-tau N sign(w_z) z``
(``--torsional``).  Both are the kinetic (sliding) forms; at ``w_h = 0`` or ``w_z = 0`` they
are taken as zero (their static, set-valued part is stage 2's).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .body import UP, Cylinder, cross, rim_point

G = 9.80665  #: m/s^2


def rim_rate(body: Cylinder, n, w):
    """``dr/dt``: how fast the contact point moves (world frame) as the axis turns."""
    n, w = np.asarray(n, float), np.asarray(w, float)
    ndot = cross(w, n)
    u = n[2] * n - UP
    norm = np.linalg.norm(u)
    e = u / norm
    udot = ndot[2] * n + n[2] * ndot
    edot = (udot - e * (e @ udot)) / norm
    sigma = 1.0 if n[2] >= 0 else -1.0
    return -sigma * body.hh * ndot + body.a * edot


def height(body: Cylinder, x, n):
    """The height of the lowest rim point above the plane."""
    return float(x[2] - body.hh * abs(n[2]) - body.a * math.sqrt(max(0.0, 1 - n[2] ** 2)))


@dataclass(frozen=True)
class RimContact:
    """The rim contact's solution at one instant: the centre's acceleration ``a_centre``, the
    angular acceleration ``alpha``, the contact force ``force`` (``N`` its normal part), the
    contact point's slip velocity ``slip`` (horizontal), the mode, whether the coin lifts
    (``N < 0``), and, rolling, whether static friction holds (``|F_t| <= mu N``)."""

    a_centre: tuple
    alpha: tuple
    force: tuple
    N: float
    slip: tuple
    mode: str
    lifts: bool
    rolling_holds: bool


def _resistance_axis(w, c, tau):
    """The resisting torque per unit normal force."""
    wh = np.array([w[0], w[1], 0.0])
    m = np.zeros(3)
    norm = np.linalg.norm(wh)
    if c > 0 and norm > 0:
        m -= c * wh / norm
    if tau > 0 and w[2] != 0:
        m -= tau * math.copysign(1.0, w[2]) * UP
    return m


def contact(body: Cylinder, n, v, w, mu, c=0.0, tau=0.0, mode="rolling", g=G) -> RimContact:
    """Solve the rim contact in ``mode`` (``"rolling"`` or ``"slipping"``)."""
    n, v, w = (np.asarray(x, float) for x in (n, v, w))
    r = rim_point(body, n)
    rdot = rim_rate(body, n, w)
    inertia, inv = body.inertia(n), body.inverse_inertia(n)
    gyro = -cross(w, inertia @ w)
    res = _resistance_axis(w, c, tau)
    gvec = -g * UP

    def motion(F):
        alpha = inv @ (cross(r, F) + F[2] * res + gyro)
        return F / body.m + gvec, alpha

    def accel(F):  # the contact point's acceleration (the body's point at the contact)
        aG, alpha = motion(F)
        return aG + cross(alpha, r) + cross(w, rdot)

    b = accel(np.zeros(3))
    J = np.column_stack([accel(np.eye(3)[j]) - b for j in range(3)])
    slip = (v + cross(w, r)) * np.array([1.0, 1.0, 0.0])
    if mode == "rolling":
        F = np.linalg.solve(J, -b)
    elif mode == "slipping":
        speed = np.linalg.norm(slip)
        d = UP - (mu * slip / speed if speed > 0 else 0.0)
        F = d * (-b[2] / (J[2] @ d))
    else:
        raise ValueError(f"mode must be 'rolling' or 'slipping', got {mode!r}")
    aG, alpha = motion(F)
    N = float(F[2])
    return RimContact(tuple(aG), tuple(alpha), tuple(F), N, tuple(slip[:2]), mode, N < 0,
                      bool(math.hypot(F[0], F[1]) <= mu * N * (1 + 1e-12)))


def rhs(body: Cylinder, mu, c=0.0, tau=0.0, mode="rolling", g=G):
    """The right-hand side ``f(t, y)`` of the rim mode for ``y = (x, n, v, w)`` (12)."""
    def f(_t, y):
        n, v, w = y[3:6], y[6:9], y[9:12]
        sol = contact(body, n, v, w, mu, c, tau, mode, g)
        return np.concatenate([v, cross(w, n), sol.a_centre, sol.alpha])
    return f


def energy(body: Cylinder, y, g=G):
    """Kinetic plus gravitational energy of the state ``y = (x, n, v, w)``."""
    x, n, v, w = (np.asarray(y[k:k + 3], float) for k in (0, 3, 6, 9))
    return 0.5 * body.m * v @ v + 0.5 * w @ body.inertia(n) @ w + body.m * g * x[2]
