"""Known answers of the exact impact law (issue 39, stage 1):
:mod:`coincli.core.bounce.exact.impact` against closed forms and against an independent
30-digit integration of the impulse equations.

The law (Keller, J. Appl. Mech. 53, 1, 1986; Stronge, *Impact Mechanics*, 2000, ch. 5): the
contact point's velocity is ``v_c0 + K P`` in the impulse ``P``; Coulomb friction ``dP_t/dp =
-mu s/|s|`` while it slips, stick or reversal when the slip halts; compression ends at ``v_n =
0``; the work of restitution is ``-e^2`` times that of compression (Stronge's energetic
coefficient).  The reference below (:func:`mp_impact`) shares no code with the engine: it builds
``K`` from the impulse-momentum laws, and integrates the same equations with a fixed-step RK4 in
mpmath at 30 digits, its events located by root finding on the RK4 step.
"""

from __future__ import annotations

import math

import mpmath as mp
import numpy as np
import pytest

from coincli.core.bounce.exact.body import Cylinder, rim_point
from coincli.core.bounce.exact.impact import face_impact, point_impact, rim_impact

D = 0.02426  #: m, a US quarter's diameter (the default coin)


def _coin(xi=0.1):
    return Cylinder.solid(D, xi)


def _axis(tilt, azimuth=0.0):
    """The coin's axis at ``tilt`` (rad) from the vertical."""
    return np.array([math.sin(tilt) * math.cos(azimuth), math.sin(tilt) * math.sin(azimuth),
                     math.cos(tilt)])


# --------------------------------------------------------------------------- the reference


def _mcross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def _solve2(A, b):
    det = A[0][0] * A[1][1] - A[0][1] * A[1][0]
    return [(A[1][1] * b[0] - A[0][1] * b[1]) / det, (A[0][0] * b[1] - A[1][0] * b[0]) / det]


def mp_impact(body, n, r, v, w, mu, e, steps=300, halt=mp.mpf("1e-16")):
    """The impact by a 30-digit RK4 in the rescaled impulse variable ``tau`` (``dp = |s| dtau``,
    which keeps the right-hand side smooth as the slip halts).  Returns the impulse ``P`` and
    the phases."""
    mp.mp.dps = 30
    m, i1, i3 = (mp.mpf(x) for x in (body.m, body.i1, body.i3))
    n, r, v, w = ([mp.mpf(float(x)) for x in y] for y in (n, r, v, w))
    mu, e = mp.mpf(mu), mp.mpf(e)

    def inv_inertia(x):  # I^-1 x for a symmetric top with axis n
        nx = sum(a * b for a, b in zip(n, x, strict=True))
        return [x[k] / i1 + (1 / i3 - 1 / i1) * nx * n[k] for k in range(3)]

    # K: the contact point's velocity change per unit impulse along each axis
    cols = []
    for j in range(3):
        ej = [mp.mpf(int(k == j)) for k in range(3)]
        dw = inv_inertia(_mcross(r, ej))
        cols.append([ej[k] / m + _mcross(dw, r)[k] for k in range(3)])
    K = [[cols[j][i] for j in range(3)] for i in range(3)]
    vc0 = [v[k] + _mcross(w, r)[k] for k in range(3)]
    speed = mp.sqrt(sum(x * x for x in vc0))

    def vc(y):  # y = [p, Px, Py, W]
        P = (y[1], y[2], y[0])
        return [vc0[i] + sum(K[i][j] * P[j] for j in range(3)) for i in range(3)]

    def g(y):
        u = vc(y)
        rho = mp.sqrt(u[0] ** 2 + u[1] ** 2)
        return [rho, -mu * u[0], -mu * u[1], rho * u[2]]

    def rk4(y, h):
        k1 = g(y)
        k2 = g([a + h / 2 * b for a, b in zip(y, k1, strict=True)])
        k3 = g([a + h / 2 * b for a, b in zip(y, k2, strict=True)])
        k4 = g([a + h * b for a, b in zip(y, k3, strict=True)])
        return [a + h / 6 * (b1 + 2 * b2 + 2 * b3 + b4)
                for a, b1, b2, b3, b4 in zip(y, k1, k2, k3, k4, strict=True)]

    y = [mp.mpf(0)] * 4
    phases, compressing, target = [], True, None
    hp = speed / K[2][2] / steps
    tail = mp.mpf(30) / steps  # the step in tau where the slip is small (dp = rho dtau)
    rate = abs(K[0][2]) + abs(K[1][2]) + mu * (abs(K[0][0]) + abs(K[1][1]) + 2 * abs(K[0][1]))
    while mu > 0:
        u = vc(y)
        rho = mp.sqrt(u[0] ** 2 + u[1] ** 2)
        if rho <= halt * speed:
            break
        if not phases:
            phases.append("slip")
        h = min(hp / rho, tail / rate)
        y1 = rk4(y, h)
        if compressing and vc(y1)[2] >= 0:
            hc = mp.findroot(lambda hh: vc(rk4(y, hh))[2], (0, h), solver="anderson")
            y = rk4(y, hc)
            compressing, wc = False, y[3]
            target = (1 - e * e) * wc
            if e == 0:
                return (y[1], y[2], y[0]), tuple(phases)
            continue
        if not compressing and y1[3] >= target:
            hr = mp.findroot(lambda hh: rk4(y, hh)[3] - target, (0, h), solver="anderson")
            y = rk4(y, hr)
            return (y[1], y[2], y[0]), tuple(phases)
        y = y1
    # the slip has halted (or there is no friction): linear in p to the end
    ktt = [[K[0][0], K[0][1]], [K[1][0], K[1][1]]]
    ktz = [K[0][2], K[1][2]]
    if mu == 0:
        d, kind = [0, 0], "slip"
    else:
        lam = [-x for x in _solve2(ktt, ktz)]
        if mp.sqrt(lam[0] ** 2 + lam[1] ** 2) <= mu * (1 + mp.mpf("1e-20")):
            d, kind = lam, "stick"
        else:
            def excess(k):
                u = _solve2([[k + mu * ktt[0][0], mu * ktt[0][1]],
                             [mu * ktt[1][0], k + mu * ktt[1][1]]], ktz)
                return mp.sqrt(u[0] ** 2 + u[1] ** 2) - 1
            k = mp.findroot(excess, (mp.mpf(0), mp.sqrt(ktz[0] ** 2 + ktz[1] ** 2)),
                            solver="anderson")
            u = _solve2([[k + mu * ktt[0][0], mu * ktt[0][1]],
                         [mu * ktt[1][0], k + mu * ktt[1][1]]], ktz)
            d, kind = [-mu * u[0], -mu * u[1]], "reversal"
    if not phases or phases[-1] != kind:
        phases.append(kind)
    kappa = K[2][2] + K[2][0] * d[0] + K[2][1] * d[1]
    vn, W, p, pt = vc(y)[2], y[3], y[0], [y[1], y[2]]
    if compressing:
        q = -vn / kappa
        W, p, vn = W + vn * q + kappa * q * q / 2, p + q, 0
        pt = [pt[0] + d[0] * q, pt[1] + d[1] * q]
        target = (1 - e * e) * W
    q = (-vn + mp.sqrt(vn * vn + 2 * kappa * (target - W))) / kappa
    return (pt[0] + d[0] * q, pt[1] + d[1] * q, p + q), tuple(phases)


# --------------------------------------------------------------------------- the grid

# (xi, tilt, v, w, mu, e): obliques with spin, planar, grazing, starting without slip; the
# extremes mu = 0, mu large (stick), e = 0 and e = 1
CASES = [
    (0.1, 0.5, (0.5, 0.3, -1.0), (3.0, -20.0, 40.0), 0.3, 0.5),   # 3-d slip throughout
    (0.1, 0.5, (0.5, 0.3, -1.0), (3.0, -20.0, 40.0), 5.0, 0.0),   # slip, stick; a catch
    (0.1, 0.5, (0.5, 0.3, -1.0), (3.0, -20.0, 40.0), 5.0, 1.0),   # slip, stick, e = 1
    (0.1, 0.5, (0.5, 0.3, -1.0), (3.0, -20.0, 40.0), 0.0, 1.0),   # frictionless, elastic
    (0.3, 1.2, (0.3, 0.2, -0.5), (10.0, 50.0, -100.0), 1.0, 0.7),  # slip direction turns
    (0.1, 0.5, (-0.15 * math.cos(0.3), -0.15 * math.sin(0.3), -1.0), (0.0, 0.0, 0.0), 0.3,
     0.5),                                                        # planar: halts, reverses
    (0.1, 0.5, (0.0, 0.0, -1.0), (0.0, 0.0, 0.0), 0.3, 0.5),      # no slip at first: reversal
    (0.1, 0.5, (3.0, 0.0, -0.01), (0.0, 0.0, 0.0), 0.3, 0.5),     # grazing
    (0.5, 0.05, (0.2, -0.4, -1.5), (5.0, 5.0, 30.0), 0.6, 0.3),   # nearly flat landing
    (0.7, 1.5, (0.4, 0.1, -0.8), (-30.0, 8.0, 0.0), 2.0, 0.9),    # nearly on edge
]


def _impact(case, **tols):
    xi, tilt, v, w, mu, e = case
    body = _coin(xi)
    n = _axis(tilt, 0.3)
    return body, n, rim_impact(body, n, v, w, mu, e, **tols)


def _rel(a, b):
    a, b = np.asarray(a, float), np.asarray(b, float)
    return float(np.linalg.norm(a - b) / np.linalg.norm(b))


def _reference(body, n, imp, case, steps):
    """The reference impulse: RK4 at ``steps`` and ``2 steps``, Richardson-extrapolated (RK4's
    error falls as ``h^4``); and the phases."""
    _, _, v, w, mu, e = case
    P1, _ = mp_impact(body, n, imp.r, v, w, mu, e, steps=steps)
    P2, phases = mp_impact(body, n, imp.r, v, w, mu, e, steps=2 * steps)
    return [float(b + (b - a) / 15) for a, b in zip(P1, P2, strict=True)], phases


@pytest.mark.parametrize("case", CASES)
def test_oblique_rim_impact_matches_a_30_digit_integration(case):
    """The engine's impulse (hence every post-impact velocity: ``v' = v + P/m``, ``w' = w +
    I^-1 (r x P)``) against the reference at 80 and 160 steps extrapolated; measured
    differences 1e-16 to 1.6e-10, the reference's own error (it falls 16-fold per halving of
    the step, the engine's self-convergence from rtol 1e-12 to 1e-14 is below 1e-12)."""
    body, n, imp = _impact(case)
    P_ref, phases_ref = _reference(body, n, imp, case, 80)
    assert imp.phases == phases_ref
    assert _rel(imp.impulse, P_ref) < 1e-9


@pytest.mark.slow
@pytest.mark.parametrize("case", CASES)
def test_oblique_rim_impact_matches_the_reference_at_fine_steps(case):
    body, n, imp = _impact(case)
    P_ref, phases_ref = _reference(body, n, imp, case, 320)
    assert imp.phases == phases_ref
    assert _rel(imp.impulse, P_ref) < 1e-11


# --------------------------------------------------------------------------- closed forms


def test_square_drop_on_a_face_rebounds_at_e_without_spin():
    """A coin falling flat onto its face: the normal impulse is ``m (1 + e) v``, the rebound
    ``e v``, no tangential impulse and no spin (by symmetry).  Both the face impact and the
    point impact at the face's centre (``K_tz = 0``: stick holds with a zero ratio)."""
    body = _coin(0.1)
    for e in (0.0, 0.3, 0.5, 1.0):
        f = face_impact(body, (0.0, 0.0, -1.2), 0.0, 0.3, e)
        assert f.v[2] == pytest.approx(1.2 * e, rel=1e-14, abs=1e-15)
        assert f.v[:2] == (0.0, 0.0) and f.wz == 0.0
        up = np.array([0.0, 0.0, 1.0])
        p = point_impact(body, up, (0.0, 0.0, -1.2), (0.0, 0.0, 0.0), (0.0, 0.0, -body.hh),
                         0.3, e)
        assert p.v[2] == pytest.approx(1.2 * e, rel=1e-12, abs=1e-15)
        assert np.abs(p.w).max() == 0.0 and np.abs(p.v[:2]).max() == 0.0
        assert p.p_final == pytest.approx(body.m * 1.2 * (1 + e), rel=1e-12)


def test_oblique_flat_impact_takes_mu_times_the_normal_impulse():
    """Known answer 4 of tests/core/test_contact_known.py: flat, 1 m/s down and 1 m/s sliding,
    ``mu`` 0.3, ``e`` 0.5: it slides throughout (``1 > mu (1 + e)``), ``dv_t = mu dv_n``, the
    rebound is ``e``."""
    body = _coin(0.1)
    f = face_impact(body, (1.0, 0.0, -1.0), 0.0, 0.3, 0.5)
    dvn, dvt = f.v[2] + 1.0, 1.0 - f.v[0]
    assert dvt / dvn == pytest.approx(0.3, rel=1e-12)
    assert f.v[2] == pytest.approx(0.5, rel=1e-14)
    assert f.wz == 0.0 and f.v[1] == 0.0
    # sliding slower than mu (1 + e) v_n: the face stops sliding within the impact
    g = face_impact(body, (0.2, 0.0, -1.0), 0.0, 0.3, 0.5)
    assert abs(g.v[0]) < 1e-12 * 0.2


def test_mu_zero_keeps_the_tangential_velocity_and_e_one_the_energy():
    for case in CASES:
        xi, tilt, v, w, _, _ = case
        body = _coin(xi)
        n = _axis(tilt, 0.3)
        imp = rim_impact(body, n, v, w, 0.0, 1.0)
        assert imp.impulse[0] == 0.0 and imp.impulse[1] == 0.0
        assert imp.v[:2] == pytest.approx(v[:2], rel=0, abs=0)
        assert imp.energy_after == pytest.approx(imp.energy_before, rel=1e-12)
        # frictionless: Newton's law at the contact, v_n' = -v_n
        assert imp.contact_velocity_after[2] == pytest.approx(
            -imp.contact_velocity_before[2], rel=1e-12)


def test_energy_never_increases():
    """Stronge's energetic coefficient never creates energy, with any friction: 150 seeded
    random impacts (tilt, velocities, spins, mu up to 3, e from 0 to 1)."""
    rng = np.random.default_rng(39)
    worst = -math.inf
    for _ in range(150):
        xi = rng.uniform(0.05, 1.0)
        body = _coin(xi)
        n = _axis(rng.uniform(0.02, math.pi / 2 - 0.02), rng.uniform(0, 2 * math.pi))
        v = rng.normal(0, 1, 3)
        w = rng.normal(0, 60, 3)
        mu, e = rng.uniform(0, 3) * (rng.random() > 0.1), rng.choice([0.0, 1.0, rng.random()])
        r = rim_point(body, n)
        if (v + np.cross(w, r))[2] >= 0:
            v[2] -= (v + np.cross(w, r))[2] + 0.1
        imp = rim_impact(body, n, v, w, mu, e)
        assert imp.work_restitution == pytest.approx(-e * e * imp.work_compression, rel=1e-9,
                                                     abs=1e-15)
        worst = max(worst, (imp.energy_after - imp.energy_before) / imp.energy_before)
        assert imp.energy_after <= imp.energy_before * (1 + 1e-12)
    assert worst <= 1e-12


def test_face_impact_with_spin_never_gains_energy():
    body = _coin(0.2)
    for vt, wz in ((0.5, 80.0), (0.0, 200.0), (2.0, -30.0)):
        f = face_impact(body, (vt, 0.1, -0.7), wz, 0.4, 0.6, tau=1e-4)
        assert f.energy_after < f.energy_before
        assert abs(f.wz) < abs(wz) or wz == 0


def test_catch_limit_stops_the_contact_point_dead():
    """``e = 0`` and friction high: the contact point ends at rest (the paper's catch), and the
    impact ends in stick."""
    for case in CASES:
        xi, tilt, v, w, _, _ = case
        body = _coin(xi)
        n = _axis(tilt, 0.3)
        imp = rim_impact(body, n, v, w, 50.0, 0.0)
        assert imp.phases[-1] == "stick"
        speed = np.linalg.norm(imp.contact_velocity_before)
        assert np.linalg.norm(imp.contact_velocity_after) < 2e-12 * speed


def test_refining_the_tolerances_tenfold_moves_no_impact():
    """Converged by construction (issue 39, point 2, for the impact alone): the ODE's ``rtol``
    and the slip floor ``slip_tol`` each ten times tighter move no impulse by more than 1e-10
    (measured: 8.6e-13 at most over the grid)."""
    for case in CASES:
        _, _, a = _impact(case)
        _, _, b = _impact(case, rtol=1e-13, slip_tol=1e-13)
        assert a.phases == b.phases
        assert _rel(a.impulse, b.impulse) < 1e-10
