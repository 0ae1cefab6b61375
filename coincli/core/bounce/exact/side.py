"""Lying on the side: the cylinder's curved surface on the plane, a line contact.

The axis ``n = (cos psi, sin psi, 0)`` is horizontal and the centre at height ``a``; ``e = z x
n`` is the horizontal direction across the axis.  The coin can roll about its axis
(``wn``), turn about the vertical (``wz``) and slide (``v``, horizontal); a rotation about
``e`` would lift one end of the line, and the pressure along the line prevents it.  The point of
the line at ``s`` along the axis (``-hh <= s <= hh``) slips at ``u(s) = v_n n + (v_e + a wn + s wz)
e``.

- **Sliding**: Coulomb friction opposes each point's slip, with the load ``N / (2 hh)`` per unit
  length (uniform, as on the face, :mod:`.flat`).  The friction force ``F`` and its moment about
  the vertical ``M_z = int s f_e`` are line integrals (:func:`line_friction`); the moment about
  ``n`` is ``a F_e``.  ``N = m g`` (the centre keeps its height), ``m dv/dt = F``, ``I3 dwn/dt =
  a F_e - c N sign(wn)``, ``I1 dwz/dt = M_z - tau N sign(wz)``, ``dpsi/dt = wz``.
- **Rolling** (no point slips: ``v_n = 0``, ``wz = 0``, ``v_e = -a wn``): ``dwn/dt = -c N
  sign(wn) / (I3 + m a^2)``, so a coin rolling upright slows at ``c g / (a (1 + I3 / (m a^2))) =
  2 c g / (3 a)`` for any thickness (``I3 = m a^2 / 2``).  It holds while the friction it needs,
  ``|m dv_e/dt|``, is at most ``mu N``.

The moment about ``e``, ``I3 wn wz`` (the gyroscopic turn of the axis) with the friction's ``-a
F_n``, is carried by the pressure's centre moving to ``s_c = -(I3 wn wz + a F_n) / N``; the mode
holds while ``|s_c| <= hh`` (else the coin tips onto a rim).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .body import Cylinder

G = 9.80665  #: m/s^2
RTOL = 1e-12  #: the ODE's relative error control
STOP_TOL = 1e-12  #: slip below this fraction of the initial speeds has stopped


def line_friction(body: Cylinder, vn, ve, wn, wz, mu):
    """``(F_n, F_e, M_z)`` per unit normal force: the friction force along ``n`` and ``e`` and
    its moment about the vertical, integrated along the line at uniform load.

    The point at ``s`` slips at ``(A, B + C s)``, ``A = v_n``, ``B = v_e + a wn``, ``C = wz``;
    with ``y = B + C s`` and ``rho = sqrt(A^2 + y^2)`` the integrals are elementary:
    ``int A / rho ds = (A / C) asinh(y / |A|)``, ``int y / rho ds = rho / C``, ``int s y / rho ds
    = (y rho / 2 - A^2 asinh(y / |A|) / 2 - B rho) / C^2``.  Where the slip varies little along
    the line (``|C| hh < |A| + |B|``, the integrand smooth) a 24-point Gauss-Legendre rule is
    used instead, free of the closed form's cancellation."""
    A, B, C, hh = vn, ve + body.a * wn, wz, body.hh
    if A == 0 and B == 0 and C == 0:
        return 0.0, 0.0, 0.0
    if C == 0:
        rho = math.hypot(A, B)
        return -mu * A / rho, -mu * B / rho, 0.0
    if abs(C) * hh < abs(A) + abs(B):
        x, wts = np.polynomial.legendre.leggauss(24)
        sv = hh * x
        y = B + C * sv
        rho = np.hypot(A, y)
        return (-mu * float(wts @ (A / rho)) / 2, -mu * float(wts @ (y / rho)) / 2,
                -mu * float(wts @ (sv * y / rho)) / 2)
    if A == 0:  # every point slips across the axis: sign(B + C s)
        s0 = min(max(-B / C, -hh), hh)
        sg = math.copysign(1.0, C)
        return 0.0, mu * sg * s0 / hh, -mu * sg * (hh * hh - s0 * s0) / (2 * hh)
    y1, y2 = B - C * hh, B + C * hh
    r1, r2 = math.hypot(A, y1), math.hypot(A, y2)
    u1, u2 = y1 / abs(A), y2 / abs(A)
    dL = math.asinh(u2 * math.sqrt(1 + u1 * u1) - u1 * math.sqrt(1 + u2 * u2))
    i_n = A / C * dL
    i_e = 4 * hh * B / (r1 + r2)
    i_s = ((y2 * r2 - y1 * r1) / 2 - A * A * dL / 2 - B * (r2 - r1)) / (C * C)
    return -mu * i_n / (2 * hh), -mu * i_e / (2 * hh), -mu * i_s / (2 * hh)


@dataclass(frozen=True)
class SideRates:
    """The side contact at one instant: the time derivatives of ``(x, y, psi, vx, vy, wn,
    wz)``, the normal force ``N``, the friction force (world, 2), the pressure's centre
    ``s_c`` along the axis and whether it is on the line (``holds``), the mode, and, rolling,
    whether static friction holds."""

    rates: tuple
    N: float
    friction: tuple
    pressure_centre: float
    holds: bool
    mode: str
    rolling_holds: bool


def rates(body: Cylinder, state, mu, c=0.0, tau=0.0, mode="sliding", g=G) -> SideRates:
    """The side contact's equations of motion at ``state = (x, y, psi, vx, vy, wn, wz)``."""
    x, y, psi, vx, vy, wn, wz = state
    n = np.array([math.cos(psi), math.sin(psi)])
    e = np.array([-n[1], n[0]])
    v = np.array([vx, vy])
    N = body.m * g
    if mode == "rolling":
        sign = math.copysign(1.0, wn) if wn != 0 else 0.0
        dwn = -c * N * sign / (body.i3 + body.m * body.a ** 2)
        Fe = -body.m * body.a * dwn
        F = Fe * e
        dv = F / body.m
        dwz, Fn = 0.0, 0.0
        rolling_holds = abs(Fe) <= mu * N
    elif mode == "sliding":
        fn, fe, mz = line_friction(body, v @ n, v @ e, wn, wz, mu)
        Fn, Fe = fn * N, fe * N
        F = Fn * n + Fe * e
        dv = F / body.m
        dwn = (body.a * Fe - c * N * (math.copysign(1.0, wn) if wn != 0 else 0.0)) / body.i3
        dwz = (mz * N - tau * N * (math.copysign(1.0, wz) if wz != 0 else 0.0)) / body.i1
        rolling_holds = False
    else:
        raise ValueError(f"mode must be 'sliding' or 'rolling', got {mode!r}")
    sc = -(body.i3 * wn * wz + body.a * Fn) / N
    return SideRates((vx, vy, wz, dv[0], dv[1], dwn, dwz), N, tuple(F), sc,
                     abs(sc) <= body.hh, mode, rolling_holds)


def slip_measure(body: Cylinder, state):
    """The largest slip speed along the line: ``|u(s)|`` at the worse end."""
    _, _, psi, vx, vy, wn, wz = state
    n = (math.cos(psi), math.sin(psi))
    vn, ve = vx * n[0] + vy * n[1], -vx * n[1] + vy * n[0]
    b = ve + body.a * wn
    return max(math.hypot(vn, b + body.hh * wz), math.hypot(vn, b - body.hh * wz))


@dataclass(frozen=True)
class SideRun:
    """The end of a side run: the state ``(x, y, psi, vx, vy, wn, wz)``, the time at which
    it began to roll (None if it did not) and the mode at the end."""

    state: tuple
    t_roll: float | None
    mode: str


def run(body: Cylinder, state, mu, c, tau, duration, g=G, *, rtol=RTOL,
        stop_tol=STOP_TOL) -> SideRun:
    """Integrate the side contact for ``duration`` s: sliding until no point of the line slips
    (an event), then rolling while static friction holds.

    The sliding phase is solved in ``tau`` with ``dt = sigma dtau``, ``sigma`` the largest slip
    speed along the line (:func:`slip_measure`): as the slip comes to a halt, where the
    friction's direction would jump, it then decays exponentially and smoothly, and the halt
    (``sigma`` below ``stop_tol`` of the initial speeds) is an event on a smooth solution."""
    from scipy.integrate import solve_ivp

    y = np.array(state, float)
    scale = slip_measure(body, y) + abs(y[3]) + abs(y[4]) + body.a * abs(y[5]) + 1e-300
    floor = stop_tol * scale
    t, t_roll = 0.0, None
    mode = "rolling" if slip_measure(body, y) <= floor else "sliding"
    # the fastest decay rate of the slip per unit slip (in tau)
    rate = mu * g * (1 + body.m * body.a ** 2 / body.i3 + body.m * body.hh ** 2 / body.i1)

    def f_slide(_tau, yy):
        sig = slip_measure(body, yy[1:])
        return [sig] + [sig * r for r in rates(body, yy[1:], mu, c, tau, "sliding", g).rates]

    def ev_end(_tau, yy):
        return yy[0] - duration

    def ev_roll(_tau, yy):
        return slip_measure(body, yy[1:]) - floor

    ev_end.terminal, ev_end.direction = True, 1
    ev_roll.terminal, ev_roll.direction = True, -1
    atol = rtol * np.array([duration, body.a, body.a, 1.0, scale, scale, scale / body.a,
                            scale / body.a])
    while mode == "sliding" and t < duration:
        sig = slip_measure(body, y)
        span = 2 * duration / sig + 60 * math.log(sig / floor + 2) / rate
        sol = solve_ivp(f_slide, (0.0, span), np.concatenate([[t], y]), method="DOP853",
                        rtol=rtol, atol=atol, events=(ev_end, ev_roll))
        if sol.status < 0:
            raise ArithmeticError(f"the side contact's ODE failed: {sol.message}")
        if sol.status == 0:
            t, y = float(sol.y[0, -1]), np.array(sol.y[1:, -1])
            continue
        hits = [(te[0], k) for k, te in enumerate(sol.t_events) if len(te)]
        k = min(hits)[1]
        yy = np.array(sol.y_events[k][0])
        t, y = float(yy[0]), yy[1:]
        if k == 0:
            t = duration
            break
        # no point slips: roll (the residual slip, below the floor, is set to zero)
        n = np.array([math.cos(y[2]), math.sin(y[2])])
        e = np.array([-n[1], n[0]])
        y[3:5] = -body.a * y[5] * e
        y[6] = 0.0
        mode, t_roll = "rolling", t
        if not rates(body, y, mu, c, tau, mode, g).rolling_holds:
            raise ArithmeticError("rolling needs more than mu N of friction")
    if mode == "rolling" and t < duration:
        def f_roll(_t, yy):
            return rates(body, yy, mu, c, tau, "rolling", g).rates

        sol = solve_ivp(f_roll, (t, duration), y, method="DOP853", rtol=rtol,
                        atol=atol[1:])
        if sol.status < 0:
            raise ArithmeticError(f"the side contact's ODE failed: {sol.message}")
        y = np.array(sol.y[:, -1])
    return SideRun(tuple(float(x) for x in y), t_roll, mode)
