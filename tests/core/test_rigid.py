"""The free rigid body of ``coin book`` (the paper's Problem 1) against independent references.

- the Jacobi functions and K, F against mpmath at 50 digits, down to m1 = 1e-300;
- the exact motion (omega and the attitude) against scipy's DOP853 at rtol 1e-13 over many
  periods, for every order of the three moments, stable and unstable axes, the separatrix;
- the conservation of energy and |L| out to 10^6 periods;
- the paper's exercise: exact frequency against Gamma with the second-order term derived in
  coincli.core.rigid.paper_frequency_shift (computed again here in mpmath); the growth rate lambda;
  the time between flips against the separatrix asymptote; the logarithmic divergence of K;
- the geometric model (solid angles) against mpmath quadrature and a random-attitude toss;
- the catch model's limits (a spin about a stable axis keeps its faces).
"""

from __future__ import annotations

import math

import mpmath as mp
import numpy as np
import pytest
import rigid_reference  # tests/ is on sys.path under pytest
from scipy.integrate import solve_ivp

from coincli.core import rigid as R
from coincli.core._numerics import elliptic

EPS = 2.220446049250313e-16
PERMS = [(0, 1, 2), (0, 2, 1), (1, 0, 2), (1, 2, 0), (2, 0, 1), (2, 1, 0)]


# --------------------------------------------------------------------------- references


def _rhs(t, y, I):
    w, q = y[:3], y[3:]
    I1, I2, I3 = I
    dw = [(I2 - I3) * w[1] * w[2] / I1, (I3 - I1) * w[2] * w[0] / I2,
          (I1 - I2) * w[0] * w[1] / I3]
    qw, qx, qy, qz = q
    wx, wy, wz = w
    dq = [-qx * wx - qy * wy - qz * wz, qw * wx + qy * wz - qz * wy,
          qw * wy - qx * wz + qz * wx, qw * wz + qx * wy - qy * wx]
    return np.concatenate([dw, 0.5 * np.asarray(dq)])


def _dop853(I, w0, ts, q0=(1.0, 0.0, 0.0, 0.0)):
    sol = solve_ivp(_rhs, (0, ts[-1]), list(w0) + list(q0), method="DOP853", rtol=1e-13,
                    atol=1e-15 * max(1.0, float(np.abs(w0).max())), t_eval=ts, args=(I,))
    assert sol.success
    q = sol.y[3:].T
    return sol.y[:3].T, q / np.linalg.norm(q, axis=1, keepdims=True)


def _qdist(a, b):
    """Distance between attitudes (q and -q are the same rotation)."""
    return np.minimum(np.abs(a - b).max(axis=-1), np.abs(a + b).max(axis=-1))


def _energy_momentum(I, w):
    I = np.asarray(I, dtype=float)
    return (I * w * w).sum(axis=-1) / 2, np.sqrt(((I * w) ** 2).sum(axis=-1))


# --------------------------------------------------------------------------- elliptic functions

def _dps(m1):
    """Digits for mpmath to hold m = 1 - m1 exactly enough: 40 more than m1's exponent."""
    return 40 + int(max(0.0, -math.log10(m1)))


M1S = [0.5, 0.1, 1e-3, 1e-6, 1e-9, 1e-12, 1e-16, 1e-20, 1e-40, 1e-100, 1e-300]


@pytest.mark.parametrize("m1", M1S + [1.0, 0.9, 0.999999])
def test_k_and_f_against_mpmath(m1):
    mp.mp.dps = _dps(m1)
    m1m = mp.mpf(m1)
    m = 1 - m1m
    K = elliptic.ellip_k(float(m), m1)
    assert K == pytest.approx(float(mp.ellipk(m)), rel=4 * EPS)
    for phi in [1e-9, 0.3, 1.0, 1.5, 1.5707963267, math.pi / 2]:
        F = elliptic.ellip_f(math.sin(phi), math.cos(phi), m1)
        # the amplitude the two doubles represent
        phim = mp.atan2(mp.mpf(math.sin(phi)), mp.mpf(math.cos(phi)))
        ref = mp.ellipf(phim, m)
        assert F == pytest.approx(float(ref), rel=8 * EPS), phi
        Fa = elliptic.ellip_f(np.array([math.sin(phi)]), np.array([math.cos(phi)]), np.array([m1]))
        assert Fa[0] == pytest.approx(float(ref), rel=8 * EPS), phi


@pytest.mark.parametrize("m1", M1S)
def test_jacobi_functions_against_mpmath(m1):
    """sn, cn, dn over a whole period and beyond (u up to 4.6 K and 2000 K), each to 1e-13
    relative, or 1e-15 absolute near a zero (the position of a zero moves by eps K with K)."""
    mp.mp.dps = _dps(m1)
    m1m = mp.mpf(m1)
    m = 1 - m1m
    K = float(mp.ellipk(m))
    us = np.concatenate([np.linspace(0, 4.6 * K, 47), [K - 1e-6, K + 1e-6, 2 * K - 1e-3,
                                                       3 * K + 0.5, 2000 * K + 0.3]])
    s, c, d, _, _ = elliptic.ellip_j(us, np.float64(float(m)), np.float64(m1))
    for u, si, ci, di in zip(us, s, c, d, strict=True):
        for name, got in (("sn", si), ("cn", ci), ("dn", di)):
            ref = float(mp.ellipfun(name, mp.mpf(float(u)), m=m))
            # slope times the uncertainty of u's place in the period (eps per period count)
            slack = 4 * EPS * (1 + abs(float(u)) / K) * K
            assert abs(got - ref) <= 1e-13 * abs(ref) + slack, (name, u, got, ref)


def test_jacobi_near_zero_keeps_relative_accuracy():
    """cn(K - v) = k' sn v / dn v: next to the separatrix cn and dn near u = K are tiny; they
    keep ~1e-12 relative accuracy (scipy.special.ellipj, which takes m alone, cannot)."""
    mp.mp.dps = 60
    for m1 in [1e-12, 1e-20]:
        m = 1 - mp.mpf(m1)
        K = mp.ellipk(m)
        u = float(K) - 0.25
        s, c, d, _, _ = elliptic.ellip_j(np.array([u]), np.float64(float(m)), np.float64(m1))
        for name, got in (("cn", c[0]), ("dn", d[0])):
            ref = mp.ellipfun(name, mp.mpf(u), m=m)
            assert abs(got / float(ref) - 1) < 1e-12, (name, m1)


def test_carlson_rf_against_mpmath():
    mp.mp.dps = 40
    for x, y, z in [(0, 1e-300, 1), (1e-300, 1e-300, 1), (1e-20, 3e-18, 1), (0.5, 0.25, 1),
                    (1, 1, 1), (2, 3, 4), (1e-8, 1, 1e8), (0, 1, 1)]:
        ref = float(mp.elliprf(mp.mpf(x), mp.mpf(y), mp.mpf(z)))
        assert elliptic.ellip_rf(float(x), float(y), float(z)) == pytest.approx(ref, rel=6 * EPS)
        got = elliptic.ellip_rf(np.array([x], float), np.array([y], float), np.array([z], float))
        assert got[0] == pytest.approx(ref, rel=6 * EPS)


def test_agm_scalar_and_array_agree():
    for m1 in M1S:
        a = elliptic.ellip_k(1 - m1, m1)
        b = elliptic.ellip_k(np.array([1 - m1]), np.array([m1]))
        assert a == pytest.approx(float(b[0]), rel=2 * EPS)


# --------------------------------------------------------------------------- the exact motion

# DOP853 is a reliable reference only while the orbit keeps away from the separatrix: there
# m1 (the distance to it) is a small difference of E and L, and the integrator's drift in
# them, ~1e-13 relative, moves m1 by ~1e-13/m1 relative; near the separatrix the reference is
# mpmath's Taylor-series integrator at 20 digits (test_near_separatrix_against_mpmath_odefun).
CASES = [
    ("largest axis, stable", (0.1, 0.2, 3.0)),
    ("smallest axis, stable", (3.0, 0.1, 0.2)),
    ("middle axis, flips", (0.6, 3.0, 0.9)),
    ("middle axis, other side", (0.9, 3.0, 0.6)),
    ("generic", (1.0, -1.3, 0.7)),
    ("largest axis, wide", (1.5, -1.0, 2.0)),
]


@pytest.mark.parametrize("perm, name, w0", [(p, *c) for p, c in zip(PERMS, CASES,
                                                                       strict=True)])
def test_exact_motion_against_dop853(perm, name, w0):
    """omega and the attitude over 12 periods: within 1e-10 of |omega| (omega) and 1e-9 (the
    quaternion); DOP853's own error is most of it.  Each case with another order of the
    moments (the slow test below runs every case in every order)."""
    _against_dop853(perm, w0)


@pytest.mark.slow
@pytest.mark.parametrize("perm", PERMS)
@pytest.mark.parametrize("name, w0", CASES)
def test_exact_motion_against_dop853_every_order(perm, name, w0):
    _against_dop853(perm, w0)


def _against_dop853(perm, w0):
    base = (1.0, 2.0, 3.0)
    I = tuple(base[k] for k in perm)
    w = np.array([w0[k] for k in perm])
    o = R.orbit(I, w)
    mo = R.motion(I, w)
    T = 12 * mo.period if mo.period < 30 else 2.2 * mo.period
    ts = np.linspace(0, T, 241)
    wref, qref = _dop853(I, w, ts)
    got = R.omega_at(o, ts)
    err = np.abs(got - wref).max() / np.linalg.norm(w)
    assert err < 1e-10, err
    q = R.attitude_at(o, ts)
    assert _qdist(q, qref).max() < 1e-9


@pytest.mark.parametrize("I, w0", [
    ((1.0, 1.0, 2.0), (0.3, 0.2, 2.0)),  # symmetric top: k = 0, regular precession
    ((1.0, 2.0, 2.0), (2.0, 0.3, 0.2)),  # symmetric about axis 1
    ((1.0, 1.0, 2.0), (0.3, 0.2, 0.0)),  # spin in the symmetric plane: steady
    ((1.0, 2.0, 3.0), (0.0, 2.0, 0.0)),  # exactly about the middle axis: steady (unstable)
    ((1.0, 2.0, 3.0), (0.0, 0.0, 2.0)),
    ((1.0, 2.0, 3.0), (2.0, 0.0, 0.0)),
    ((1.0, 1.0, 1.0), (0.3, 1.0, 2.0)),  # a sphere
    ((1.0, 2.0, 3.0), (1e-9, 2.0, 1e-9)),  # the linear stage, before the first flip
])
def test_degenerate_motions_against_dop853(I, w0):
    w = np.array(w0)
    o = R.orbit(I, w)
    ts = np.linspace(0, 15.0, 151)
    wref, qref = _dop853(I, w, ts)
    got = R.omega_at(o, ts)
    assert np.isfinite(got).all()
    assert np.abs(got - wref).max() / np.linalg.norm(w) < 1e-10
    assert _qdist(R.attitude_at(o, ts), qref).max() < 1e-9


def test_near_separatrix_against_mpmath_odefun():
    """Next to (and on) the separatrix, over two periods (four flips) and more: omega within
    1e-10 of |omega| and the attitude within 1e-9 of a 20-digit Taylor-series integration
    (tests/rigid_reference.py, frozen in tests/data/rigid_reference.json)."""
    ref = rigid_reference.load()
    assert len(ref["cases"]) == len(rigid_reference.CASES)
    for case in ref["cases"]:
        I, w = tuple(case["moments"]), np.array(case["omega"])
        rows = np.array(case["rows"])
        ts = rows[:, 0]
        o = R.orbit(I, w)
        assert np.abs(R.omega_at(o, ts) - rows[:, 1:4]).max() / np.linalg.norm(w) < 1e-10
        q = rows[:, 4:]
        assert _qdist(R.attitude_at(o, ts), q / np.linalg.norm(q, axis=1, keepdims=True)
                      ).max() < 1e-9
    # the cases do what they say: flips, m1 small, the exact separatrix
    kinds = [R.motion(tuple(c["moments"]), c["omega"]) for c in ref["cases"]]
    assert kinds[0].m1 < 1e-5 and kinds[1].m1 < 1e-11 and kinds[3].kind == "separatrix"
    assert kinds[0].gamma_kind == kinds[1].gamma_kind == "growth"


@pytest.mark.slow
def test_frozen_separatrix_reference_recomputes():
    """The last frozen case (exactly on the separatrix) recomputed live."""
    I, w, T, n = rigid_reference.CASES[-1]
    rows = rigid_reference.solve(I, w, T, n)
    frozen = rigid_reference.load()["cases"][-1]["rows"]
    assert np.abs(np.array(rows) - np.array(frozen)).max() < 1e-15


def test_separatrix_is_recognized_exactly():
    o = R.orbit((2.0, 5.0, 8.0), (2.0, 1.0, 1.0))
    assert o.m1 == 0 and o.separatrix and not o.stationary
    mo = R.motion((2.0, 5.0, 8.0), (2.0, 1.0, 1.0))
    assert mo.kind == "separatrix" and mo.period == math.inf


def test_symmetric_top_is_regular_precession():
    I, w0 = (1.0, 1.0, 2.5), np.array([0.3, -0.4, 2.0])
    o = R.orbit(I, w0)
    t = np.linspace(0, 50, 101)
    W = (I[2] - I[0]) / I[0] * w0[2]  # the body-frame precession rate
    ref = np.stack([w0[0] * np.cos(W * t) - w0[1] * np.sin(W * t),
                    w0[0] * np.sin(W * t) + w0[1] * np.cos(W * t), np.full_like(t, w0[2])], 1)
    assert np.abs(R.omega_at(o, t) - ref).max() < 1e-13
    assert R.motion(I, w0).gamma_shift == pytest.approx(0.0, abs=4 * EPS)


def test_conservation_over_a_million_periods():
    """E and |L| from omega(t) at 10^4 times out to ~10^6 periods: relative drift ~ eps (the
    exact solution has none to accumulate)."""
    I = (0.4, 1.1, 1.3)
    for w0 in [(0.3, 5.0, 0.2), (4.0, 0.5, -0.7), (0.1, 0.2, 9.0), (1e-7, 3.0, 1e-7)]:
        w = np.array(w0)
        o = R.orbit(I, w)
        P = R.motion(I, w).period
        ts = np.concatenate([np.linspace(0, 3 * P, 5000), np.linspace(1e6 * P, 1e6 * P + 3 * P,
                                                                        5000)])
        E0, L0 = _energy_momentum(I, w)
        E, L = _energy_momentum(I, R.omega_at(o, ts))
        assert np.abs(E / E0 - 1).max() < 2e-14
        assert np.abs(L / L0 - 1).max() < 2e-14
        q = R.attitude_at(o, ts)
        assert np.abs(np.linalg.norm(q, axis=1) - 1).max() < 4 * EPS


def test_angular_momentum_is_fixed_in_space():
    """L in the lab (R(t) I omega(t)) stays put: a test of the attitude independent of any
    integrator, out to 1000 periods."""
    I = (0.4, 1.1, 1.3)
    w = np.array([0.3, 5.0, 0.2])
    o = R.orbit(I, w)
    ts = np.linspace(0, 1000 * R.motion(I, w).period, 20001)
    q = R.attitude_at(o, ts)
    Lb = np.asarray(I) * R.omega_at(o, ts)
    Llab = _rotate(q, Lb)
    assert np.abs(Llab - Llab[0]).max() / np.linalg.norm(Lb[0]) < 1e-11


def _rotate(q, v):
    w, x, y, z = (q[:, k] for k in range(4))
    Rm = np.stack([
        np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
        np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
        np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1)], 1)
    return np.einsum("nij,nj->ni", Rm, v)


def test_scalar_summary_matches_array_path():
    I = (0.4, 1.1, 1.3)
    for w0 in [(0.3, 5.0, 0.2), (4.0, 0.5, -0.7), (1e-7, 3.0, 1e-7)]:
        a = R.orbit(I, w0)
        b = R.orbit(I, np.array([w0]))
        for f in ("m", "m1", "r", "tau0", "K", "acn", "asn", "adn"):
            # one motion's m1 is exact (rationals); the array path's has the cancellation of
            # a difference of squares next to the separatrix (4e-14 relative at m1 = 1e-16)
            tol = 1e-12 if f == "m1" else 8 * EPS
            assert getattr(a, f) == pytest.approx(float(np.asarray(getattr(b, f))[0]),
                                                  rel=tol, abs=1e-300), f


def _m1_mp(I, w):
    """1 - m at 50 digits from E and L (Landau's form), independent of coincli.core.rigid."""
    mp.mp.dps = 50
    I = sorted(zip([mp.mpf(v) for v in I], [mp.mpf(v) for v in w]))
    (Ia, wa), (Ib, wb), (Ic, wc) = I
    E2 = Ia * wa**2 + Ib * wb**2 + Ic * wc**2
    L2 = (Ia * wa)**2 + (Ib * wb)**2 + (Ic * wc)**2
    if L2 >= E2 * Ib:
        m = (Ib - Ia) * (E2 * Ic - L2) / ((Ic - Ib) * (L2 - E2 * Ia))
    else:
        m = (Ic - Ib) * (L2 - E2 * Ia) / ((Ib - Ia) * (E2 * Ic - L2))
    return 1 - m


@pytest.mark.parametrize("I, w", [
    ((0.4, 1.1, 1.3), (1e-7, 3.0, 1e-7)),       # pushed along the separatrix's own direction
    ((0.4, 1.1, 1.3), (0.3, 5.0, 0.2)),
    ((3.0, 4.0, 6.0), (2.0, 1.0, 1.0 + 2**-40)),  # next to an exact separatrix, either side
    ((3.0, 4.0, 6.0), (2.0, 1.0, 1.0 - 2**-40)),
    ((0.3, 0.4, 0.6), (2.0, 1.0, 1.0)),          # 0.3, 0.4, 0.6 are not 3:4:6 as doubles
    ((2.0, 1.0, 3.0), (1e-140, 1.0, 3e-141)),
])
def test_one_motion_m1_is_correctly_rounded(I, w):
    ref = _m1_mp(I, w)
    assert R.orbit(I, w).m1 == float(ref)
    assert float(np.asarray(R.orbit(I, np.array(w)).m1)) == float(ref)
    assert R.motion(I, w).m1 == float(ref)


def test_a_separatrix_is_exact_however_the_moments_are_scaled():
    # 2 E I2 = L^2 exactly for moments 3, 4, 6 and omega 2, 1, 1; scaled by the largest moment
    # (4/6 is not a double) this was 'periodic' with a period of 99 s from rounding
    for scale in (1.0, 1 / 3, 1e-7, 7.0):
        I = tuple(v * scale for v in (3.0, 4.0, 6.0))
        if (I[0] * (I[0] - I[1]) * 4 + I[2] * (I[2] - I[1])) != 0:
            continue  # the scaling itself rounded: no longer on the separatrix
        mo = R.motion(I, (2.0, 1.0, 1.0))
        assert mo.kind == "separatrix" and mo.m1 == 0 and mo.period == math.inf
        assert R.orbit(I, np.array([2.0, 1.0, 1.0])).separatrix


def test_a_perturbation_below_the_double_range_is_refused_not_a_separatrix():
    # m1 ~ 1e-400 would round to 0 and pass for the separatrix (one flip, never back), where
    # the body flips every 38 s: a one-line error instead, for one motion and for many
    for w in [(1e-200, 40.0, 0.0), (0.0, 40.0, 1e-320), (1e-160, 40.0, 1e-160)]:
        with pytest.raises(ValueError, match="too close to the middle axis"):
            R.motion((1.0, 2.0, 3.0), w)
        with pytest.raises(ValueError, match="too close to the middle axis"):
            R.orbit((1.0, 2.0, 3.0), np.array([w, (0.1, 1.0, 0.2)]))
    assert R.motion((1.0, 2.0, 3.0), (0.0, 40.0, 0.0)).kind == "steady"  # on the axis: exact
    mo = R.motion((1.0, 2.0, 3.0), (1e-140, 40.0, 1e-140))
    assert mo.kind == "periodic" and mo.half_period == pytest.approx(mo.flip_asymptote, rel=1e-12)


def test_huge_and_tiny_spins_scale():
    I = (0.4, 1.1, 1.3)
    w = np.array([0.3, 5.0, 0.2])
    base = R.motion(I, w)
    for s in [1e-300, 1e-100, 1e100, 1e300]:
        mo = R.motion(I, w * s)
        assert mo.period * s == pytest.approx(base.period, rel=1e-14)
        o = R.orbit(I, w * s)
        got = R.omega_at(o, np.array([0.0, base.period / s / 3])) / s
        ref = R.omega_at(R.orbit(I, w), np.array([0.0, base.period / 3]))
        assert np.abs(got - ref).max() < 1e-13


def test_perturbation_far_below_the_spin_still_counts():
    mo = R.motion((1.0, 2.0, 3.0), (1e300, 1.0, 1.0))
    assert mo.omega_max[1] > 1.0 and mo.omega_min[1] < -1.0  # omega_2 swings through +-1.5


# --------------------------------------------------------------------------- the paper's exercise


def _shift_mp(I, w, axis):
    """Omega / Gamma - 1 at 50 digits, from the exact period pi |r| / (2 K(m)) with m written
    from E and L (Landau's form), independent of coincli.core.rigid's formulas."""
    mp.mp.dps = 50
    I = [mp.mpf(v) for v in I]
    w = [mp.mpf(v) for v in w]
    c = axis
    a, b = sorted((k for k in range(3) if k != c), key=lambda k: abs(I[k] - I[c]), reverse=True)
    Ia, Ib, Ic = I[a], I[b], I[c]
    E2 = sum(I[k] * w[k] ** 2 for k in range(3))
    L2 = sum((I[k] * w[k]) ** 2 for k in range(3))
    m = (Ib - Ia) * (E2 * Ic - L2) / ((Ic - Ib) * (L2 - E2 * Ia))
    r = mp.sqrt((Ic - Ib) * (L2 - E2 * Ia) / (Ia * Ib * Ic))
    Omega = mp.pi * r / (2 * mp.ellipk(m))
    Gamma = abs(w[c]) * mp.sqrt((Ic - Ia) * (Ic - Ib) / (Ia * Ib))
    return Omega / Gamma - 1


@pytest.mark.parametrize("I, axis, dirs", [
    ((1.0, 2.0, 3.0), 2, (1.0, 0.0)),   # the paper's: spin about I3, push along axis 1
    ((1.0, 2.0, 3.0), 2, (0.0, 1.0)),   # ... along axis 2
    ((1.0, 2.0, 3.0), 2, (0.6, 0.8)),
    ((0.4, 1.1, 1.3), 0, (0.8, -0.6)),  # spin about the smallest axis
    ((2.0, 1.0, 2.5), 2, (0.3, 1.0)),
])
def test_exact_frequency_against_gamma_is_second_order(I, axis, dirs):
    """(Omega/Gamma - 1) = c2 eps^2 + O(eps^4), with c2 from paper_frequency_shift: checked
    against a 50-digit evaluation at eps = 1e-1 ... 1e-4 (the remainder / eps^4 stays bounded
    and settles), and the CLI path (motion) agrees with the mpmath value."""
    others = [k for k in range(3) if k != axis]
    remainders = []
    for eps in [1e-1, 1e-2, 1e-3, 1e-4]:
        w = [0.0, 0.0, 0.0]
        w[axis] = 40.0
        w[others[0]] = 40.0 * eps * dirs[0]
        w[others[1]] = 40.0 * eps * dirs[1]
        exact = _shift_mp(I, w, axis)
        pred = R.paper_frequency_shift(I, w)
        assert pred != 0
        rem = (exact - mp.mpf(pred)) / mp.mpf(eps) ** 4
        remainders.append(float(rem))
        assert float(exact) / pred - 1 == pytest.approx(0.0, abs=60 * eps**2)
        mo = R.motion(I, w)
        assert mo.gamma_kind == "oscillation" and mo.spin_axis == axis
        # the double-precision pipeline: Omega/Gamma - 1 to ~1e-15 absolute
        assert abs(mo.gamma_shift - float(exact)) < 2e-15 + 1e-9 * abs(float(exact))
    # O(eps^4): the scaled remainder converges (last two agree to 1%)
    assert abs(remainders[-1] - remainders[-2]) <= 0.01 * abs(remainders[-1]) + 1e-6


def test_exact_frequency_against_integrated_period():
    """Omega from the closed form against the period of omega_1 measured on DOP853's solution
    (zero crossings, 20 periods): independent of the elliptic functions altogether."""
    I, w = (1.0, 2.0, 3.0), np.array([2.0, 3.0, 40.0])
    mo = R.motion(I, w)
    ts = np.linspace(0, 20 * mo.period, 200001)
    wref, _ = _dop853(I, w, ts)
    x = wref[:, 1]  # omega_2 ~ sn: upward zero crossings
    j = np.nonzero((x[:-1] < 0) & (x[1:] >= 0))[0]
    tc = ts[j] - x[j] * (ts[j + 1] - ts[j]) / (x[j + 1] - x[j])
    period = np.diff(tc).mean()
    assert period == pytest.approx(mo.period, rel=1e-7)
    assert mo.gamma_shift == pytest.approx(2 * math.pi / period / mo.gamma - 1, abs=1e-7)


def test_middle_axis_growth_rate_is_lambda():
    """Starting next to the middle axis the perturbation grows like exp(lambda t): the slope of
    log|omega_3| over the linear stage matches lambda = omega0 sqrt((I3-I2)(I2-I1)/(I1 I3))."""
    I = (1.0, 2.0, 3.0)
    w0 = 40.0
    lam = w0 * math.sqrt((3 - 2) * (2 - 1) / (1 * 3))
    kind, val = R.gamma(I, w0, 1)
    assert kind == "growth" and val == pytest.approx(lam, rel=4 * EPS)
    o = R.orbit(I, np.array([1e-9 * w0, w0, 1e-9 * w0]))
    t1, t2 = 6 / lam, 12 / lam  # past the decaying mode, far before saturation
    w = R.omega_at(o, np.array([t1, t2]))
    slope = math.log(abs(w[1, 2] / w[0, 2])) / (t2 - t1)
    assert slope == pytest.approx(lam, rel=1e-5)


@pytest.mark.parametrize("ea, ec", [(1.0, 0.0), (0.0, 1.0), (0.7, 0.2), (0.2, 0.7)])
def test_flip_time_against_separatrix_asymptote(ea, ec):
    """Time between flips (half the period) against (1/lambda) ln(16 ...): the relative
    difference falls like eps^2 |ln eps| (checked: below 3 eps^2 |ln eps| down to 1e-7)."""
    I = (1.0, 2.0, 3.0)
    prev = prev_eps = None
    for eps in [1e-1, 1e-2, 1e-3, 1e-5, 1e-7]:
        w = (40 * eps * ea, 40.0, 40 * eps * ec)
        mo = R.motion(I, w)
        asym = R.flip_asymptote(I, w)
        rel = abs(mo.half_period / asym - 1)
        assert rel <= 3 * eps**2 * abs(math.log(eps)) + 1e-14, (eps, rel)
        assert mo.flip_asymptote == asym
        # the divergence is logarithmic: each factor 10 in eps adds ln(100)/lambda
        if prev is not None and prev_eps <= 1e-3:
            assert mo.half_period - prev == pytest.approx(
                math.log(100) * math.log10(prev_eps / eps) / mo.gamma, rel=1e-4)
        prev, prev_eps = mo.half_period, eps


def test_period_diverges_logarithmically_at_the_separatrix():
    """K(m) = (1/2) ln(16/m1) + (m1/4)((1/2) ln(16/m1) - 1) + O(m1^2 ln m1): the period
    4K/|r| of the motion, for m1 from 1e-2 to 1e-300, against that form (the O(m1^2) remainder
    / (m1^2 ln(1/m1)) bounded), and K itself against mpmath."""
    I = (1.0, 2.0, 3.0)
    for e in [1e-1, 1e-2, 1e-4, 1e-6, 1e-9, 1e-50, 1e-150]:
        w = (0.0, 1.0, e)
        o = R.orbit(I, w)
        mo = R.motion(I, w)
        m1 = o.m1
        L = math.log(16 / m1)
        asym = L / 2 + m1 / 4 * (L / 2 - 1)
        K = mo.period * mo.rate / 4
        assert abs(K - asym) <= 1.0 * m1**2 * L + 8 * EPS * K, (e, K - asym)
        mp.mp.dps = _dps(m1)
        assert K == pytest.approx(float(mp.ellipk(1 - mp.mpf(m1))), rel=1e-14)


def test_first_flip_is_a_sign_change_of_the_middle_component():
    I = (1.0, 2.0, 3.0)
    for w in [(0.4, 40.0, 0.3), (0.3, -40.0, 0.4), (-0.4, 40.0, -0.1)]:
        mo = R.motion(I, w)
        o = R.orbit(I, np.array(w))
        t1 = mo.first_flip
        before, after = R.omega_at(o, np.array([t1 * (1 - 1e-9), t1 * (1 + 1e-9)]))[:, 1]
        assert before * after < 0 and np.sign(before) == np.sign(w[1])
        # and none earlier
        ts = np.linspace(0, t1 * (1 - 1e-6), 2001)
        assert (np.sign(R.omega_at(o, ts)[:, 1]) == np.sign(w[1])).all()


# --------------------------------------------------------------------------- faces


def _solid_angle_mp(a, b, c):
    """The solid angle of the face (sides a, b) at distance c/2 from the centre: the integral of
    d / r^3 over the rectangle, done in y by hand (C B / ((x^2 + C^2) sqrt(x^2 + B^2 + C^2)))
    and in x by quadrature."""
    mp.mp.dps = 30
    A, B, C = mp.mpf(a) / 2, mp.mpf(b) / 2, mp.mpf(c) / 2
    f = lambda x: C * B / ((x * x + C * C) * mp.sqrt(x * x + B * B + C * C))  # noqa: E731
    return 4 * mp.quad(f, mp.linspace(0, A, 9) if C < A / 100 else [0, A])


@pytest.mark.parametrize("sides", [(1, 1, 1), (235, 155, 30), (1, 2, 3), (16, 16, 16),
                                   (1, 1, 1e-3), (5, 0.2, 1)])
def test_face_shares_are_solid_angles(sides):
    shares = R.face_shares(sides)
    assert sum(shares) == pytest.approx(1.0, abs=4 * EPS)
    for k in range(3):
        i, j = (k + 1) % 3, (k + 2) % 3
        ref = _solid_angle_mp(sides[i], sides[j], sides[k]) / (4 * mp.pi)
        assert shares[2 * k] == pytest.approx(float(ref), rel=1e-13)
        assert shares[2 * k] == shares[2 * k + 1]


def test_cube_and_thin_plate_limits():
    assert all(abs(p - 1 / 6) < 4 * EPS for p in R.face_shares((2.0, 2.0, 2.0)))
    for h in [1e-3, 1e-6, 1e-12, 0.0]:
        s = R.face_shares((1.0, 1.0, h))
        assert s[4] + s[5] >= 1 - 2 * h  # the two large faces take almost everything
    assert R.face_shares((1.0, 1.0, 0.0))[4] == 0.5
    assert R.face_shares((1, 2, 3), "normal") == (1 / 6,) * 6


def test_box_sides_round_trip_and_impossible_moments():
    for s in [(235, 155, 30), (1, 1, 1), (3, 0.1, 2)]:
        got = R.box_sides(R.box_moments(s))
        assert got == pytest.approx(tuple(v / max(s) for v in s), rel=1e-13)
    with pytest.raises(ValueError, match="no rigid body"):
        R.box_sides((1, 2, 4))
    assert R.box_sides((1, 2, 3))[2] == 0.0  # I3 = I1 + I2: a flat plate
    for bad in [(0, 1, 1), (-1, 1, 1), (math.inf, 1, 1), (math.nan, 1, 1)]:
        with pytest.raises(ValueError):
            R.box_moments(bad)


class _Fixed:
    def __init__(self, v):
        self.v = v

    def sample(self, rng, k):
        return self.v


class _Normal:
    def __init__(self, mu, sd):
        self.mu, self.sd = mu, sd

    def sample(self, rng, k):
        return rng.normal(self.mu, self.sd, k)


class _Uniform:
    def __init__(self, a, b):
        self.a, self.b = a, b

    def sample(self, rng, k):
        return rng.uniform(self.a, self.b, k)


def _counts(n, seed, sides, spin, flight, start="+3", rule="centre"):
    m = R.box_moments(sides)
    s = tuple(v / max(sides) for v in sides)
    c = np.zeros(6, dtype=np.int64)
    for codes in R.toss_chunks(n, seed, moments=m, sides=s, spin=spin, flight=flight,
                               start=start, rule=rule):
        c += np.bincount(codes, minlength=6)
    return c


@pytest.mark.parametrize("rule", ["centre", "normal"])
def test_random_start_reproduces_the_geometric_model(rule):
    """A uniformly random attitude at launch stays uniform: the tossed frequencies match the
    geometric model (chi-square at 1e-4, 6 cells)."""
    from scipy.stats import chisquare

    sides = (235.0, 155.0, 30.0)
    n = 60000
    c = _counts(n, 3, sides, [_Normal(0, 20)] * 3, _Uniform(0.3, 0.7), start="random",
                rule=rule)
    geo = np.array(R.face_shares(tuple(v / 235 for v in sides), rule))
    assert chisquare(c, geo * n).pvalue > 1e-4


def test_spin_about_the_long_axis_never_shows_its_ends():
    """A book spun about its long (smallest-moment, stable) axis, lying flat at launch: L is
    horizontal along that axis, which stays horizontal; the end faces never come up, and the
    four others share the turn by the angles their diagonals subtend: (2/pi) atan(155/30) for
    the covers together.  The geometric model gives the ends 4.4%: conservation of angular
    momentum is what it leaves out."""
    sides = (235.0, 155.0, 30.0)
    n = 40000
    c = _counts(n, 5, sides, [_Fixed(40.0), _Fixed(0.0), _Fixed(0.0)], _Uniform(0.4, 1.6))
    assert c[0] == c[1] == 0
    covers = (c[4] + c[5]) / n
    expect = 2 / math.pi * math.atan(155 / 30)
    assert covers == pytest.approx(expect, abs=4 * math.sqrt(expect * (1 - expect) / n))
    geo = R.face_shares(tuple(v / 235 for v in sides))
    assert geo[0] + geo[1] > 0.04


def test_flat_spin_keeps_the_cover_up():
    c = _counts(5000, 1, (235.0, 155.0, 30.0), [_Normal(0, 0.5), _Normal(0, 0.5), _Fixed(40)],
                _Uniform(0.2, 1.0))
    assert c[4] == 5000


def test_tosses_are_reproducible_and_prefixes():
    sides = (20.0, 15.0, 10.0)
    spin = [_Normal(0, 30)] * 3
    a = np.concatenate(list(R.toss_chunks(70000, 9, moments=R.box_moments(sides),
                                          sides=(1, .75, .5), spin=spin, flight=_Fixed(0.5))))
    b = np.concatenate(list(R.toss_chunks(70000, 9, moments=R.box_moments(sides),
                                          sides=(1, .75, .5), spin=spin, flight=_Fixed(0.5))))
    c = np.concatenate(list(R.toss_chunks(1000, 9, moments=R.box_moments(sides),
                                          sides=(1, .75, .5), spin=spin, flight=_Fixed(0.5))))
    assert (a == b).all() and (a[:1000] == c).all()


def test_catch_at_time_zero_is_the_start_face():
    for face in R.FACES:
        q = R.start_quaternion(face)
        code = R.catch((1, 2, 3), (1, 0.8, 0.5), np.array([[3.0, 4.0, 5.0]]), np.array([0.0]),
                       q)
        assert R.FACES[int(code[0])] == face


def test_catch_at_time_zero_needs_no_motion():
    # a spin whose motion cannot be followed (1e-303 of the spin off the middle axis) caught
    # at once: the start face, no error; caught later: refused
    w = np.array([[-4e5, 1e308, 3.0], [1.0, 2.0, 3.0]])
    q = R.start_quaternion("-2")
    codes = R.catch((1.0, 2.0, 3.0), (1, 1, 1), w, np.array([0.0, 0.0]), q)
    assert [R.FACES[int(c)] for c in codes] == ["-2", "-2"]
    with pytest.raises(ValueError, match="middle axis"):
        R.catch((1.0, 2.0, 3.0), (1, 1, 1), w, np.array([1e-297, 0.0]), q)


def test_omega_at_time_zero_is_the_launch_value_exactly():
    for I, w in [((1.0, 2.0, 3.0), (0.4, 40.0, 0.3)), ((235.0, 155.0, 30.0), (0.4, 0.3, 40.0)),
                 ((0.4, 1.1, 1.3), (-1e-7, 3.0, 1e-7)), ((1.0, 2.0, 3.0), (2.0, -1.0, 0.5))]:
        o = R.orbit(I, np.array(w))
        got = R.omega_at(o, np.array([0.0, 1e-3, 0.0]))
        assert got[0].tolist() == list(w) and got[2].tolist() == list(w)
        assert np.abs(got[1] - np.array(w)).max() < 1e-3 * np.abs(w).max() * 50
        many = R.orbit(I, np.array([w, w]))
        assert R.omega_at(many, 0.0).tolist() == [list(w), list(w)]


def test_catch_refuses_a_phase_beyond_the_limit():
    with pytest.raises(ValueError, match="rad"):
        R.catch((1, 2, 3), (1, 1, 1), np.array([[1e10, 0, 0]]), np.array([1e3]),
                R.start_quaternion("+3"))
