"""Known answers of the exact sustained-contact modes (issue 39, stage 1):
:mod:`coincli.core.bounce.exact.flat`, :mod:`~coincli.core.bounce.exact.rim` and
:mod:`~coincli.core.bounce.exact.side`, each against a figure computed here independently.

The coin is the default quarter-sized one (diameter 24.26 mm, cupronickel 8920 kg/m^3) on
wood's coefficients (friction 0.3, rolling and torsional lengths 0.1 mm); tolerances are
relative errors.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from coincli.core.bounce.exact import flat, rim, side
from coincli.core.bounce.exact.body import Cylinder, rim_point

G = 9.80665
D = 0.02426
MU, ROLL, TORS = 0.3, 1e-4, 1e-4  #: wood


def _coin(xi):
    return Cylinder.solid(D, xi)


# --------------------------------------------------------------------------- flat on a face


@pytest.mark.parametrize("eps", [0.05, 0.3, 0.9, 1.0, 1.2, 3.0, 20.0])
def test_face_friction_is_the_integral_over_the_face(eps):
    """Farkas et al. (PRL 90, 248302, 2003): force and torque of Coulomb friction over a
    uniformly pressed disc; here the elliptic forms against a direct 2-d quadrature of the slip
    directions over the unit disc (``v = eps`` along x, ``wz = 1``)."""
    from scipy.integrate import dblquad

    def unit_slip(r, th):
        x, y = r * math.cos(th), r * math.sin(th)
        sx, sy = eps - y, x  # v + z x r
        q = math.hypot(sx, sy)
        return sx / q, (x * sy - y * sx) / q

    fx = dblquad(lambda r, th: unit_slip(r, th)[0] * r, 0, 2 * math.pi, 0, 1,
                 epsabs=1e-13, epsrel=1e-12)[0] / math.pi
    tz = dblquad(lambda r, th: unit_slip(r, th)[1] * r, 0, 2 * math.pi, 0, 1,
                 epsabs=1e-13, epsrel=1e-12)[0] / math.pi
    f, t = flat.face_friction(eps)
    assert f == pytest.approx(fx, rel=1e-9)
    assert t == pytest.approx(tz, rel=1e-9)


def test_face_friction_limits():
    assert flat.face_friction(0.0) == (0.0, pytest.approx(2 / 3, rel=1e-15))  # r_eff = 2a/3
    assert flat.face_friction(math.inf) == (1.0, 0.0)
    f, t = flat.face_friction(1e6)
    assert f == pytest.approx(1.0, rel=1e-12) and t == pytest.approx(0.25e-6, rel=1e-6)
    for eps in (0.2499, 0.25, 0.2501, 0.4999, 0.5, 0.5001, 0.9999, 1.0, 1.0001, 1.999, 2.001):
        # the series and the elliptic forms join continuously
        f1, t1 = flat.face_friction(eps)
        f2, t2 = flat.face_friction(eps * (1 + 1e-9))
        assert abs(f1 - f2) < 1e-8 and abs(t1 - t2) < 1e-8


def test_flat_slide_decelerates_at_mu_g_without_hop_or_tilt():
    """A coin flat, sliding at 0.5 m/s without spin: ``dv/dt = -mu g`` exactly, the normal
    force the weight (no hop), the pressure's centre ``mu hh`` ahead of the axis, inside the
    face (no tilt)."""
    body = _coin(0.1)
    run = flat.slide(body, (0.5, 0.0), 0.0, MU, TORS, 0.1)
    assert run.v[0] == pytest.approx(0.5 - MU * G * 0.1, rel=1e-12)
    assert run.v[1] == 0.0 and run.wz == 0.0
    c = flat.contact(body, (0.5, 0.0), 0.0, MU, TORS)
    assert c.N == pytest.approx(body.m * G, rel=1e-15)
    assert c.pressure_centre[0] == pytest.approx(MU * body.hh, rel=1e-12) and c.holds
    # it stops at v / (mu g)
    stop = flat.slide(body, (0.5, 0.0), 0.0, MU, TORS, 1.0)
    assert stop.p_slide_stop / (body.m * G) == pytest.approx(0.5 / (MU * G), rel=1e-10)
    # a tall coin on a rough floor cannot stay flat: the pressure would leave the face
    assert not flat.contact(_coin(1.5), (0.5, 0.0), 0.0, 0.8, 0.0).holds


def test_flat_spin_decays_linearly_without_tilt():
    """A coin flat, spinning at 5 rev/s: the torque is ``(mu 2a/3 + tau) m g`` (uniform
    pressure), constant, so the spin falls linearly; no force, so the centre stays and the
    pressure stays centred (no tilt)."""
    body = _coin(0.1)
    w0 = 2 * math.pi * 5
    rate = (MU * 2 * body.a / 3 + TORS) * body.m * G / body.i3
    for t in (0.01, 0.02, 0.04):
        run = flat.slide(body, (0.0, 0.0), w0, MU, TORS, t)
        assert run.wz == pytest.approx(w0 - rate * t, rel=1e-12)
        assert run.v == (0.0, 0.0)
    c = flat.contact(body, (0.0, 0.0), w0, MU, TORS)
    assert c.friction == (0.0, 0.0) and c.pressure_centre == (0.0, 0.0)


def test_farkas_slide_and_spin_stop_together():
    """Farkas et al. 2003: sliding and spinning on a flat face, both stop at the same instant,
    with ``eps = v / (a w)`` tending to the root ``eps*`` of ``f(eps) / eps = (m a^2 / I3)
    t(eps)`` (0.6530 for a solid coin; found here by bisection).  Measured: a millionth of the
    run before the end, the stop instants extrapolated linearly from the slide and from the spin
    agree to 1e-10 to 8e-9 of the run, and ``eps`` is within 1.3% of ``eps*``, four times nearer
    than at 1e-5 (it converges as a power of the time left).  With torsional resistance the spin
    stops first (a case where they do not stop together)."""
    from scipy.optimize import brentq

    body = _coin(0.1)
    k = body.m * body.a ** 2 / body.i3
    eps_star = brentq(lambda x: flat.face_friction(x)[0] / x - k * flat.face_friction(x)[1],
                      1e-3, 50, xtol=1e-15)
    for v0, w0 in ((0.3, 10.0), (0.1, 100.0), (1.0, 5.0)):
        end = flat.integrate(body, (v0, 0.0), w0, MU, 0.0, 1.0)
        assert end.p_slide_stop == end.p_spin_stop and end.v == (0.0, 0.0) and end.wz == 0.0
        gaps = []
        for frac in (1e-5, 1e-6):
            p = end.p_slide_stop * (1 - frac)
            near = flat.integrate(body, (v0, 0.0), w0, MU, 0.0, p)
            dv, dw = flat.rates(body, near.v, near.wz, MU, 0.0)
            p_v = p + math.hypot(*near.v) / math.hypot(*dv)
            p_w = p + abs(near.wz) / abs(dw)
            gaps.append(abs(math.hypot(*near.v) / (body.a * near.wz) / eps_star - 1))
        assert abs(p_v - p_w) < 2e-8 * end.p_slide_stop
        assert abs(p_v - end.p_slide_stop) < 2e-8 * end.p_slide_stop
        assert gaps[1] < 0.02 and gaps[1] < 0.3 * gaps[0]
    tors = flat.integrate(body, (0.3, 0.0), 10.0, MU, 1e-3, 1.0)
    assert tors.p_spin_stop < tors.p_slide_stop * (1 - 1e-3)


# --------------------------------------------------------------------------- on one rim point


def euler_omega(body, alpha):
    """The steady precession rate of a coin on its lower rim, centre at rest, tilt ``alpha``
    (tests/core/test_contact_known.py): ``Omega^2 sin(alpha) (I1 cos(alpha) - I3 (hh/a)
    sin(alpha)) = m g (a cos(alpha) - hh sin(alpha))``."""
    s, c = math.sin(alpha), math.cos(alpha)
    return math.sqrt(body.m * G * (body.a * c - body.hh * s)
                     / (s * (body.i1 * c - body.i3 * (body.hh / body.a) * s)))


@pytest.mark.parametrize("alpha", [0.4, 0.2, 0.1])
def test_euler_disk_steady_precession_solves_the_rolling_equations(alpha):
    """Moffatt (Nature 404, 833, 2000), Kessler & O'Reilly (2002): the steady motion at the
    rate of :func:`euler_omega` is a solution of the rim-rolling equations: the centre does not
    accelerate, ``dw/dt = Omega z x w`` (``w`` turns with the precession), ``N = m g``."""
    body = _coin(0.1)
    om = euler_omega(body, alpha)
    s, c = math.sin(alpha), math.cos(alpha)
    e, n = np.array([c, 0.0, -s]), np.array([s, 0.0, c])
    w = om * s * (-e + body.hh / body.a * n)
    sol = rim.contact(body, n, (0.0, 0.0, 0.0), w, MU)
    steady = om * np.cross([0.0, 0.0, 1.0], w)
    assert np.linalg.norm(sol.a_centre) < 1e-12 * G
    assert np.linalg.norm(np.array(sol.alpha) - steady) < 1e-12 * np.linalg.norm(steady)
    assert sol.N == pytest.approx(body.m * G, rel=1e-12)
    # the thin-disc limit is Moffatt's Omega^2 sin(alpha) = 4 g / a
    thin = _coin(1e-7)
    assert euler_omega(thin, alpha) ** 2 * s == pytest.approx(4 * G / thin.a, rel=1e-6)


@pytest.mark.parametrize("xi,tilt", [(0.1, 0.3), (0.5, 0.8), (1.0, 1.3)])
def test_coin_released_on_its_rim_pivots_or_slides_as_a_rigid_body(xi, tilt):
    """Released at rest on its rim, rolling (a pivot): the coin turns about the horizontal
    tangent through the contact, ``alpha = m g |r_x| / (I1 + m |r|^2)``, so ``N = m g (1 - m
    r_x^2 / (I1 + m |r|^2))``; frictionless: the centre falls straight, ``N = m g / (1 + m r_x^2
    / I1)`` (the falling ladder at its start)."""
    body = _coin(xi)
    n = np.array([math.sin(tilt), 0.0, math.cos(tilt)])
    r = rim_point(body, n)
    m, rx = body.m, r[0]
    roll = rim.contact(body, n, (0, 0, 0), (0, 0, 0), 10.0, mode="rolling")
    assert roll.N == pytest.approx(m * G * (1 - m * rx * rx / (body.i1 + m * r @ r)), rel=1e-12)
    free = rim.contact(body, n, (0, 0, 0), (0, 0, 0), 0.0, mode="slipping")
    assert free.N == pytest.approx(m * G / (1 + m * rx * rx / body.i1), rel=1e-12)
    assert abs(free.a_centre[0]) < 1e-15 and abs(free.a_centre[1]) < 1e-15


def test_rolling_upright_on_the_rim_slows_by_rolling_resistance():
    """A coin upright (axis along y) rolling along x on its lower corner: ``dv/dt = -a c N /
    (m (I3/m + I3 hh^2/I1 + a^2))`` with ``N`` from the tipping pair (derived by hand in
    docs/contact-models.md); ``-2 c g / (3 a)`` for a thin disc."""
    for xi in (1e-6, 0.1, 0.3):
        body = _coin(xi)
        a, hh, m, i1, i3 = body.a, body.hh, body.m, body.i1, body.i3
        v = 0.5
        sol = rim.contact(body, (0.0, 1.0, 0.0), (v, 0.0, 0.0), (0.0, v / a, 0.0), MU, ROLL)
        # y and z: Fy (1/m + a^2/I1) = a hh N / I1 and N (1/m + hh^2/I1) - a hh Fy / I1 = g
        A = np.array([[1 / m + a * a / i1, -a * hh / i1], [-a * hh / i1, 1 / m + hh * hh / i1]])
        Fy, N = np.linalg.solve(A, [0.0, G])
        dvdt = -(a * ROLL * N / i3) / (m * (1 / m + hh * hh / i1 + a * a / i3))
        assert sol.N == pytest.approx(N, rel=1e-12)
        assert sol.a_centre[0] == pytest.approx(dvdt, rel=1e-10)
        if xi < 1e-5:
            assert sol.a_centre[0] == pytest.approx(-2 * ROLL * G / (3 * a), rel=1e-5)


def _rolling_state(body, tilt, w):
    n = np.array([math.sin(tilt), 0.0, math.cos(tilt)])
    r = rim_point(body, n)
    x = -r  # the contact at the origin, on the plane
    return np.concatenate([x, n, -np.cross(w, r), w])


def test_rim_rolling_keeps_the_contact_on_the_plane_and_the_energy():
    """Integrating the rolling equations (no resistance) for 50 ms from a generic state: the
    lowest point stays on the plane, the contact point at rest, the energy constant (rolling
    without slip does no work)."""
    from scipy.integrate import solve_ivp

    body = _coin(0.2)
    y0 = _rolling_state(body, 0.3, np.array([2.0, 8.0, 20.0]))
    sol = solve_ivp(rim.rhs(body, 10.0), (0, 0.05), y0, method="DOP853", rtol=1e-12,
                    atol=1e-14, dense_output=True)
    e0 = rim.energy(body, y0)
    for t in np.linspace(0, 0.05, 11):
        y = sol.sol(t)
        n = y[3:6] / np.linalg.norm(y[3:6])
        assert abs(rim.height(body, y[:3], n)) < 1e-10 * body.a
        slip = y[6:9] + np.cross(y[9:12], rim_point(body, n))
        assert np.linalg.norm(slip) < 1e-9 * np.linalg.norm(y0[9:12]) * body.a
        assert rim.energy(body, y) == pytest.approx(e0, rel=1e-10)
        sol_t = rim.contact(body, n, y[6:9], y[9:12], 10.0)
        assert sol_t.N > 0 and sol_t.rolling_holds  # the mode holds throughout


def test_rim_slipping_dissipates_exactly_the_friction_power():
    """Slipping: ``dE/dt = -mu N |s| + N (resistance torque . w)``, from the accelerations; and
    the integrated motion keeps the lowest point on the plane."""
    from scipy.integrate import solve_ivp

    body = _coin(0.3)
    n = np.array([math.sin(0.7), 0.0, math.cos(0.7)])
    r = rim_point(body, n)
    w = np.array([3.0, -40.0, 12.0])
    v = np.array([0.2, -0.1, 0.0])
    v[2] = -np.cross(w, r)[2]  # no normal velocity at the contact
    sol = rim.contact(body, n, v, w, MU, ROLL, TORS, mode="slipping")
    aG, alpha = np.array(sol.a_centre), np.array(sol.alpha)
    power = body.m * v @ (aG + G * np.array([0, 0, 1])) + w @ body.inertia(n) @ alpha
    res = -ROLL * np.array([w[0], w[1], 0]) / math.hypot(w[0], w[1]) - TORS * np.array([0, 0, 1])
    expected = -MU * sol.N * math.hypot(*sol.slip) + sol.N * res @ w
    assert power == pytest.approx(expected, rel=1e-12)
    y0 = np.concatenate([-r, n, v, w])
    run = solve_ivp(rim.rhs(body, MU, mode="slipping"), (0, 0.01), y0, method="DOP853",
                    rtol=1e-12, atol=1e-14)
    y = run.y[:, -1]
    assert abs(rim.height(body, y[:3], y[3:6] / np.linalg.norm(y[3:6]))) < 1e-10 * body.a


def test_rim_contact_lifts_off_when_it_would_have_to_pull():
    """A coin tumbling fast about a horizontal axis through its centre: the contact point's
    centripetal acceleration points up, faster than gravity brings the coin down, so the
    constraint would need ``N < 0``: it lifts off (unilateral contact)."""
    body = _coin(0.1)
    n = np.array([math.sin(0.5), 0.0, math.cos(0.5)])
    slow = rim.contact(body, n, (0, 0, 0), (0.0, 1.0, 0.0), MU, mode="slipping")
    fast = rim.contact(body, n, (0, 0, 0), (0.0, 300.0, 0.0), MU, mode="slipping")
    assert not slow.lifts and fast.lifts and fast.N < 0


# --------------------------------------------------------------------------- on the side


def test_rolling_upright_on_the_side_slows_at_2cg_over_3a():
    """A thick coin (xi 0.5) rolling on its curved side at 0.5 m/s: ``dv/dt = -2 c g / (3 a)``
    for any thickness (``I3 = m a^2 / 2``; the rolling disc, O'Reilly 1996)."""
    body = _coin(0.5)
    a, v0 = body.a, 0.5
    state = (0.0, 0.0, math.pi / 2, v0, 0.0, v0 / a, 0.0)  # axis along y, e = -x
    r = side.rates(body, state, MU, ROLL, TORS, mode="rolling")
    assert r.rates[3] == pytest.approx(-2 * ROLL * G / (3 * a), rel=1e-14)
    assert r.rolling_holds and r.holds and r.pressure_centre == 0.0
    run = side.run(body, state, MU, ROLL, TORS, 0.4)
    assert run.mode == "rolling" and run.t_roll is None
    assert run.state[3] == pytest.approx(v0 - 2 * ROLL * G / (3 * a) * 0.4, rel=1e-12)
    assert abs(run.state[4]) < 1e-15 and run.state[2] == math.pi / 2


@pytest.mark.parametrize("c", [0.0, ROLL])
def test_wheel_set_down_spinning_slips_then_rolls_at_a_third(c):
    """The bowling-ball problem (Routh): set down spinning at 60 rad/s with its centre at rest,
    it slips, the centre speeding up at ``mu g`` and the spin slowing at ``(mu a + c) m g /
    I3``, until ``v = a w``: at ``t_s = a w0 / (g (3 mu + 2 c / a))``, ``v = mu g t_s`` (``a w0 /
    3`` without resistance, for any thickness: ``I3 = m a^2 / 2``); then it rolls, slowing at
    ``2 c g / (3 a)``."""
    body = _coin(0.5)
    a, w0 = body.a, 60.0
    run = side.run(body, (0.0, 0.0, math.pi / 2, 0.0, 0.0, w0, 0.0), MU, c, TORS, 0.1)
    ts = a * w0 / (G * (3 * MU + 2 * c / a))
    assert run.t_roll == pytest.approx(ts, rel=1e-10)
    v = MU * G * ts - 2 * c * G / (3 * a) * (0.1 - ts)
    assert run.state[3] == pytest.approx(v, rel=1e-10)
    if c == 0.0:
        assert run.state[3] == pytest.approx(a * w0 / 3, rel=1e-10)
    assert run.state[5] * a == pytest.approx(run.state[3], rel=1e-12)  # rolling: v = a w


def test_side_yaw_spin_feels_the_line_friction():
    """Spinning in place about the vertical on its side: each point of the line slips at ``s
    wz``, so the friction torque is ``mu N <|s|> = mu N hh / 2`` and the force zero."""
    body = _coin(0.5)
    fn, fe, mz = side.line_friction(body, 0.0, 0.0, 0.0, 7.0, MU)
    assert fn == 0.0 and abs(fe) < 1e-15
    assert mz == pytest.approx(-MU * body.hh / 2, rel=1e-12)


@pytest.mark.parametrize("state", [(0.0, 0.0, 0.3, 0.2, 0.1, 20.0, 30.0),
                                   (0.0, 0.0, -1.0, 0.0, 0.3, -5.0, -80.0),
                                   (0.0, 0.0, 2.0, 0.05, 0.0, 0.0, 10.0)])
def test_side_sliding_dissipates_exactly_the_friction_power(state):
    """Sliding on the side with yaw: the kinetic energy falls at the power of the friction,
    ``mu N <|u(s)|>`` (the mean slip speed along the line, by an independent quadrature), plus
    the resistances' ``c N |wn| + tau N |wz|``."""
    from scipy.integrate import quad

    body = _coin(0.5)
    _, _, psi, vx, vy, wn, wz = state
    r = side.rates(body, state, MU, ROLL, TORS)
    _, _, _, ax, ay, dwn, dwz = r.rates
    power = body.m * (vx * ax + vy * ay) + body.i3 * wn * dwn + body.i1 * wz * dwz
    n = np.array([math.cos(psi), math.sin(psi)])
    e = np.array([-n[1], n[0]])
    v = np.array([vx, vy])
    mean_slip = quad(lambda s: math.hypot(v @ n, v @ e + body.a * wn + s * wz), -body.hh,
                     body.hh, epsabs=0, epsrel=1e-13, limit=200)[0] / (2 * body.hh)
    expected = -r.N * (MU * mean_slip + ROLL * abs(wn) + TORS * abs(wz))
    assert power == pytest.approx(expected, rel=1e-11)


@pytest.mark.parametrize("A,B,C", [(0.1, 0.02, 7.0), (1e-6, 0.01, 7.0), (0.01, -0.02, -30.0),
                                   (0.3, 0.2, 1.0), (0.0, 0.01, 7.0), (0.05, 0.0, 3.0)])
def test_side_line_friction_is_the_integral_along_the_line(A, B, C):
    """The closed forms (and the Gauss-Legendre rule) of the line friction against an adaptive
    quadrature of the slip directions along the line."""
    from scipy.integrate import quad

    body = _coin(0.5)
    hh = body.hh
    pts = [-B / C] if -hh < -B / C < hh else None

    def mean(f):
        return quad(f, -hh, hh, epsabs=1e-16, epsrel=1e-13, limit=500, points=pts)[0] / (2 * hh)

    def rho(s):
        return math.hypot(A, B + C * s)

    want = (-MU * mean(lambda s: A / rho(s)) if A else 0.0,
            -MU * mean(lambda s: (B + C * s) / rho(s)),
            -MU * mean(lambda s: s * (B + C * s) / rho(s)))
    got = side.line_friction(body, A, B, 0.0, C, MU)
    for g_, w_ in zip(got, want, strict=True):
        assert g_ == pytest.approx(w_, rel=1e-11, abs=1e-17)


def test_refining_the_tolerances_tenfold_moves_no_contact_run():
    """The flat and side runs with ``rtol`` and ``stop_tol`` ten times tighter: nothing moves by
    more than 1e-10 of the speeds (measured 2e-12 flat, 8e-12 side)."""
    body = _coin(0.1)
    x = flat.integrate(body, (0.3, 0.1), 40.0, MU, TORS, 0.01)
    y = flat.integrate(body, (0.3, 0.1), 40.0, MU, TORS, 0.01, rtol=1e-13, stop_tol=1e-13)
    speed = math.hypot(*y.v) + body.a * abs(y.wz)
    assert math.hypot(x.v[0] - y.v[0], x.v[1] - y.v[1]) < 1e-10 * speed
    assert body.a * abs(x.wz - y.wz) < 1e-10 * speed
    body = _coin(0.5)
    start = (0.0, 0.0, 0.3, 0.2, 0.1, 20.0, 30.0)
    x = side.run(body, start, MU, ROLL, TORS, 0.25)
    y = side.run(body, start, MU, ROLL, TORS, 0.25, rtol=1e-13, stop_tol=1e-13)
    assert x.mode == y.mode == "rolling"
    assert x.t_roll == pytest.approx(y.t_roll, rel=1e-10)
    speed = math.hypot(y.state[3], y.state[4]) + body.a * abs(y.state[5])
    assert np.abs(np.subtract(x.state[3:5], y.state[3:5])).max() < 1e-10 * speed
    assert body.a * abs(x.state[5] - y.state[5]) < 1e-10 * speed
