"""Lying flat on a face: sliding and spinning with the friction integrated over the face.

The face (radius ``a``) is pressed on the plane by ``N`` spread uniformly over it (Farkas,
Bartels, Unger & Wolf, PRL 90, 248302, 2003).  The centre slides at ``v`` (horizontal) and the
coin spins at ``wz`` about the vertical; the point of the face at ``r`` slides at ``v + wz z x
r``, and Coulomb friction ``mu`` opposes each point's own slip.  Integrated over the face, with
``eps = |v| / (a |wz|)``:

- the force is ``-mu N f(eps) v/|v|``, along the slide;
- the torque about the vertical is ``-mu N a t(eps) sign(wz)``;

with (``K``, ``E`` the complete elliptic integrals of parameter ``m``; derived in
:func:`face_friction`) for ``eps <= 1``, ``m = eps^2``: ``f = (4 eps / pi) J(m)``, ``t = (4 / (9
pi)) (2 (2 - m) E - (1 - m) K)``; for ``eps >= 1``, ``m = 1/eps^2``: ``f = (4 / pi) J(m)``, ``t =
(4 / (3 pi eps)) C(m)``; ``J(m) = int_0^(pi/2) cos^2 sqrt(1 - m sin^2) = ((1 + m) E - (1 - m) K)
/ (3 m)``, ``C(m) = int_0^(pi/2) cos^4 / sqrt(1 - m sin^2)``.  ``f(0) = 0``, ``t(0) = 2/3`` (a
pure spin: the effective radius ``2a/3``), ``f(inf) = 1``, ``t(inf) = 0`` (a pure slide).
Torsional resistance (the surface's ``--torsional`` length ``tau``) adds ``-tau N sign(wz)``.

The face stays flat: the normal force is the weight, ``N = m g`` (nothing in the friction has
a vertical component: no hop), and the friction's moment about horizontal axes, ``-hh z x F``
at the face, is carried by the pressure's centre moving to ``-hh F / N`` (towards the leading
edge).  The mode holds while that centre is on the face, ``mu f hh < a``; beyond it the coin
tips (:func:`contact`).  The friction is integrated at uniform pressure while the pressure's
first moment carries that moment: an approximation of order ``mu hh / a`` in the torque when the
coin both slides and spins (exact for a pure slide, where every point slips alike).

Both motions are integrated in the normal impulse ``p`` (``dp = N dt``), so that the same
function gives a flat slide in time (:func:`slide`, ``p = m g t``) and the friction of a square
face impact (:func:`coincli.core.bounce.exact.impact.face_impact`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .body import Cylinder

G = 9.80665  #: m/s^2, standard gravity (as the rest of coincli)
RTOL = 1e-12  #: the ODE's relative error control
STOP_TOL = 1e-12  #: slide and spin below this fraction of the initial speeds have stopped


def _series(m, first, ratio, coeff_ratio):
    """``sum_k b_k m^k I_k`` with ``I_0 = first``, ``I_k / I_(k-1) = ratio(k)``, ``b_0 = 1``,
    ``b_k / b_(k-1) = coeff_ratio(k)`` (for ``m < 1/4``: 60 terms reach 1e-36)."""
    total, term_i, b, mk = first, first, 1.0, 1.0
    for k in range(1, 60):
        term_i *= ratio(k)
        b *= coeff_ratio(k)
        mk *= m
        total += b * mk * term_i
    return total


def _j(m):
    """``int_0^(pi/2) cos^2 sqrt(1 - m sin^2)``."""
    from scipy.special import ellipe, ellipk

    if m < 0.25:  # (1 - x)^(1/2) = sum a_k x^k, a_k / a_(k-1) = (2k - 3) / (2k)
        return _series(m, math.pi / 4, lambda k: (2 * k - 1) / (2 * k + 2),
                       lambda k: (2 * k - 3) / (2 * k))
    if m >= 1.0:
        return 2.0 / 3.0
    return ((1 + m) * ellipe(m) - (1 - m) * ellipk(m)) / (3 * m)


def _d3(m):
    """``int_0^(pi/2) (1 - m sin^2)^(3/2)``."""
    from scipy.special import ellipe, ellipk

    if m >= 1.0:
        return 2.0 / 3.0
    return (2 * (2 - m) * ellipe(m) - (1 - m) * ellipk(m)) / 3


def _c4(m):
    """``int_0^(pi/2) cos^4 / sqrt(1 - m sin^2)``."""
    from scipy.special import ellipe, ellipk

    if m < 0.25:  # (1 - x)^(-1/2) = sum b_k x^k, b_k / b_(k-1) = (2k - 1) / (2k)
        return _series(m, 3 * math.pi / 16, lambda k: (2 * k - 1) / (2 * k + 4),
                       lambda k: (2 * k - 1) / (2 * k))
    if m >= 1.0:
        return 2.0 / 3.0
    K, E = ellipk(m), ellipe(m)
    return K - 2 * (K - E) / m + ((2 + m) * K - 2 * (1 + m) * E) / (3 * m * m)


def face_friction(eps):
    """``(f, t)``: the force and the torque of Coulomb friction over a uniformly pressed face,
    in units of ``mu N`` and ``mu N a``, at ``eps = |v| / (a |wz|)`` (``inf`` for no spin).

    Derivation: the face's velocity field is a rotation about the point ``c = z x v / wz`` at
    the distance ``eps a`` from the centre, so each point's slip direction is ``z x (r - c) /
    |r - c|``.  In polar coordinates about ``c`` the radial integral is elementary: with ``S =
    sqrt(a^2 - d^2 sin^2)``, ``d = eps a``, the force is ``mu N / (pi a^2)`` times ``d int_0^(2
    pi) cos^2 S`` (``d < a``) or ``2 d int_(-th)^(th) cos^2 S`` (``d > a``, ``sin th = a / d``),
    the torque ``mu N / (pi a^2)`` times ``(1/3) int_0^(2 pi) S^3`` or ``(2/3) int_(-th)^(th)
    S^3``; the substitution ``d sin = a sin phi`` turns the second pair into the first's
    complete elliptic integrals."""
    if eps == math.inf:
        return 1.0, 0.0
    if eps <= 1.0:
        m = eps * eps
        return 4 * eps / math.pi * _j(m), 4 / (3 * math.pi) * _d3(m)
    m = 1.0 / (eps * eps)
    return 4 / math.pi * _j(m), 4 / (3 * math.pi * eps) * _c4(m)


def rates(body: Cylinder, v, wz, mu, tau):
    """``(dv/dp, dwz/dp)``: the change of the centre's horizontal velocity ``v`` (2) and of the
    spin ``wz`` per unit normal impulse ``p`` (``dp = N dt``)."""
    v = np.asarray(v, float)
    speed = float(np.hypot(v[0], v[1]))
    if wz == 0.0:
        eps = math.inf
    else:
        eps = speed / (body.a * abs(wz))
    f, t = face_friction(eps)
    dv = -mu * f / body.m * (v / speed) if speed > 0 else np.zeros(2)
    dw = -(mu * body.a * t + tau) / body.i3 * math.copysign(1.0, wz) if wz != 0.0 else 0.0
    return dv, dw


@dataclass(frozen=True)
class FlatContact:
    """The flat contact's forces: the normal force ``N`` (the weight), the friction force
    ``friction`` (horizontal, 2), the torque about the vertical ``torque``, the pressure's centre
    ``pressure_centre`` (2, from the axis) and whether it lies on the face (``holds``)."""

    N: float
    friction: tuple
    torque: float
    pressure_centre: tuple
    holds: bool


def contact(body: Cylinder, v, wz, mu, tau, g=G) -> FlatContact:
    """The forces on a coin flat on a face, sliding at ``v`` and spinning at ``wz``."""
    N = body.m * g
    dv, dw = rates(body, v, wz, mu, tau)
    F = body.m * dv * N
    centre = -body.hh * F / N
    return FlatContact(N, tuple(F), body.i3 * dw * N, tuple(centre),
                       bool(np.hypot(*centre) <= body.a))


@dataclass(frozen=True)
class FlatRun:
    """The end of a flat run: the centre's velocity ``v`` (2), the spin ``wz``, the impulse
    ``p`` reached, and the impulses at which the slide and the spin stopped (None if not)."""

    v: tuple
    wz: float
    p: float
    p_slide_stop: float | None
    p_spin_stop: float | None


def integrate(body: Cylinder, v, wz, mu, tau, impulse, *, rtol=RTOL,
              stop_tol=STOP_TOL) -> FlatRun:
    """Slide and spin under the face's friction over the normal impulse ``impulse``.

    The ODE is solved in ``tau`` with ``dp = (|v| + a |wz|) dtau``: near a stop, where the
    friction's direction would jump, the motion then decays exponentially and smoothly, and the
    stop (both speeds below ``stop_tol`` of the initial ones) is an event on a smooth solution.
    """
    from scipy.integrate import solve_ivp

    v = np.asarray(v, float)
    scale = float(np.hypot(v[0], v[1]) + body.a * abs(wz))
    if scale == 0.0 or mu == 0.0 and tau == 0.0:
        return FlatRun(tuple(v), float(wz), float(impulse), None, None)
    floor = stop_tol * scale
    y = np.array([0.0, v[0], v[1], wz])
    slide_stop = spin_stop = None
    # the fastest decay rate in tau: the friction's per-impulse rates times the speed scale
    rate = (mu + (mu * body.a + tau) * body.a * body.m / body.i3) / body.m

    def sigma(yy):
        return math.hypot(yy[1], yy[2]) + body.a * abs(yy[3])

    def rhs(_t, yy):
        dv, dw = rates(body, yy[1:3], yy[3], mu, tau)
        s = sigma(yy)
        return [s, s * dv[0], s * dv[1], s * dw]

    def ev_end(_t, yy):
        return yy[0] - impulse

    def ev_rest(_t, yy):
        return sigma(yy) - floor

    def ev_spin(_t, yy):
        return yy[3]

    for ev, direction in ((ev_end, 1), (ev_rest, -1), (ev_spin, 0)):
        ev.terminal, ev.direction = True, direction
    atol = rtol * np.array([impulse, scale, scale, scale / body.a])
    while True:
        if sigma(y) <= floor:
            slide_stop = y[0] if slide_stop is None else slide_stop
            spin_stop = y[0] if spin_stop is None else spin_stop
            y[1:] = 0.0
            break
        span = 2 * impulse / sigma(y) + 60 * math.log(sigma(y) / floor + 2) / rate
        events = (ev_end, ev_rest, ev_spin) if y[3] != 0.0 else (ev_end, ev_rest)
        sol = solve_ivp(rhs, (0.0, span), y, method="DOP853", rtol=rtol, atol=atol,
                        events=events)
        if sol.status < 0:
            raise ArithmeticError(f"the flat contact's ODE failed: {sol.message}")
        if sol.status == 0:
            y = np.array(sol.y[:, -1])
            continue
        hits = [(te[0], k) for k, te in enumerate(sol.t_events) if len(te)]
        k = min(hits)[1]
        y = np.array(sol.y_events[k][0])
        if k == 0:
            y[0] = impulse
            break
        if k == 1:
            slide_stop = y[0] if slide_stop is None else slide_stop
            spin_stop = y[0] if spin_stop is None else spin_stop
            y[1:] = 0.0
            break
        y[3] = 0.0  # the spin stopped (torsional resistance); the slide goes on
        spin_stop = y[0]
    return FlatRun((float(y[1]), float(y[2])), float(y[3]), float(y[0]), slide_stop, spin_stop)


def slide(body: Cylinder, v, wz, mu, tau, duration, g=G, **tols) -> FlatRun:
    """A coin flat on a face, sliding at ``v`` (2) and spinning at ``wz``, after ``duration``
    seconds: :func:`integrate` over the impulse ``m g duration`` (the impulses of the record
    are then ``m g`` times the times)."""
    return integrate(body, v, wz, mu, tau, body.m * g * duration, **tols)
