"""The first contact time against an independent mpmath reference (tests/toss_reference.py).

The reference scans F = z - L at 40 digits with its own certificate, so it finds the first
root however thin the dip before it.  coincli.core.toss.flight must agree with it to within what a double
can resolve (:func:`toss_reference.allowed_error`: 4 ulps of t plus the time F takes to cross
its rounding band), one toss (:func:`coincli.core.toss.flight.toss`) and a batch (:func:`toss_many`) alike:
grazing contacts, huge spins, tiny launch speeds, psi at 0 and 180, both contact models.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import toss_reference as R

from coincli.core.toss import batch as TB
from coincli.core.toss import flight as T
from coincli.core.toss import launch as TL

FAIR = 1 / math.sqrt(3)
D = T.DEFAULT_DIAMETER
A = D / 2

CASES = [
    # (xi, psi, u, omega)
    (FAIR, math.pi / 2, 2.0, 40.0),  # the README's toss
    (0.577, math.pi / 2, 2.4, 238.7610416728243),  # a hand toss, 38 rev/s
    (FAIR, math.pi / 2, 1e-6, 1e6),  # dropped, spun very fast
    (FAIR, math.pi / 2, 2.0, 1e6),  # thrown, ~6e4 turns
    (FAIR, math.pi / 2, 20.0, 1e6),
    (0.0, math.pi / 2, 1e-6, 1e6),
    (0.0, 1.0, 3.0, 1e6),
    (1e6, 1.0, 2.0, 1e6),  # a coin much thicker than wide
    (FAIR, 0.0, 2.0, 1e6),  # psi = 0: no tilt, ever
    (FAIR, math.pi, 2.0, 1e6),  # psi = 180
    (FAIR, 0.0, 1e-6, 0.0),
    (FAIR, math.pi, 1e-6, 1e6),
    (0.3, 1e-9, 2.0, 1e6),
    (0.3, math.pi - 1e-9, 2.0, 1e6),
    (0.3, math.pi / 4, 2.0, 1e6),
    (0.3, math.pi / 4, 1e-6, 1e6),
    (5.0, 2.0, 1e-6, 1e-3),
    (FAIR, math.pi / 2, 0.0, 1e6),  # u = 0
    (FAIR, math.pi / 2, 1e-6, 1.0),
    (FAIR, math.pi / 2, 1e4, 1e-3),  # a long flight, almost no spin
    (0.2, 1.2, 0.05, 3000.0),  # a low toss, fast spin: contact in the first turns
]


def _check(t_f, args, contact, **kw):
    """t_f is the reference's first root to within what a double resolves; or, past it, the
    first root after a dip shallower than the rounding band of F (which no double evaluation
    of F can see for certain: the module documents that such a dip is not a contact)."""
    ref = R.ref_first_root(*args, contact=contact, **kw)
    err = abs(t_f - float(ref))
    allowed = R.allowed_error(ref, *args, contact=contact, **kw)
    if err > allowed and t_f > float(ref):
        band = R.band(t_f, *args, contact=contact, **kw)
        ts = np.linspace(float(ref), t_f, 2001)
        depth = -min(float(R.ref_f(t, *args, contact=contact, **kw)) for t in ts)
        at = abs(float(R.ref_f(t_f, *args, contact=contact, **kw)))
        assert depth <= band and at <= 2 * band, (args, contact, t_f, float(ref), depth, band)
        return 0.0
    assert err <= allowed, (args, contact, t_f, float(ref), err, allowed)
    return err / math.ulp(float(ref)) if ref > 0 else 0.0


@pytest.mark.slow
@pytest.mark.parametrize("contact", T.CONTACTS)
@pytest.mark.parametrize("args", CASES)
def test_first_contact_matches_the_mpmath_reference(args, contact):
    t_one = TB.toss(*args, contact=contact).t_f
    t_batch = float(TB.toss_many(*args, contact=contact).t_f)
    assert t_one == t_batch  # one toss is a batch of one: the same bits
    _check(t_one, args, contact)


@pytest.mark.slow
@pytest.mark.parametrize("contact", T.CONTACTS)
def test_random_tosses_match_the_mpmath_reference_in_a_batch(contact):
    rng = np.random.default_rng(2024)
    n = 40
    xi = np.where(rng.random(n) < 0.2, rng.choice([0.0, 3.0], n), rng.uniform(0, 1.5, n))
    psi = rng.uniform(0, math.pi, n)
    u = 10 ** rng.uniform(-3, 1, n)
    om = 10 ** rng.uniform(0, 4, n)
    v = TB.toss_many(xi, psi, u, om, contact=contact)
    worst = 0.0
    for i in range(n):
        args = (float(xi[i]), float(psi[i]), float(u[i]), float(om[i]))
        worst = max(worst, _check(float(v.t_f[i]), args, contact))
    assert worst <= 64  # in ulps of t: rounding of F, not a wrong root


@pytest.mark.slow
def test_hand_tosses_match_the_mpmath_reference():
    rng = np.random.default_rng(38)
    c = TL.sample_conditions(30, rng, **TL.HAND_TOSS)
    v = TB.toss_many(FAIR, c["psi"], c["u"], c["omega"])
    for i in range(30):
        args = (FAIR, float(c["psi"][i]), float(c["u"][i]), float(c["omega"][i]))
        _check(float(v.t_f[i]), args, "rim")


def _dip_z0(psi, xi, contact, u, om):
    """The launch height at which the toss dips 1e-11 a below the plane at a local minimum of
    F that is lower than F was before it (F moves by a constant with z0): found on a fine
    grid of the reference F and refined by golden-section search in mpmath."""
    from mpmath import mp, mpf

    thick = contact == "thick"
    z0 = math.sqrt(3) / 2 * A + (xi * A if thick else 0.0)
    t_end = (u + math.sqrt(u * u + 2 * 9.81 * z0)) / 9.81
    ts = np.linspace(0.0, t_end, 200_001)
    f = np.array([float(R.ref_f(t, xi, psi, u, om, contact=contact)) for t in ts[::10]])
    ts = ts[::10]
    before = np.minimum.accumulate(f)
    floor = xi * A if thick else 0.0
    for i in range(1, ts.size - 1):
        if f[i] < f[i - 1] and f[i] <= f[i + 1] and f[i] < before[i - 1] and \
                0 < f[i] < (z0 - floor) * 0.9:
            with mp.workdps(40):
                lo, hi = mpf(ts[i - 1]), mpf(ts[i + 1])
                phi = (mp.sqrt(5) - 1) / 2
                for _ in range(120):
                    m1, m2 = hi - phi * (hi - lo), lo + phi * (hi - lo)
                    if R.ref_f(m1, xi, psi, u, om, contact=contact) < \
                            R.ref_f(m2, xi, psi, u, om, contact=contact):
                        hi = m2
                    else:
                        lo = m1
                fm = R.ref_f((lo + hi) / 2, xi, psi, u, om, contact=contact)
            return float(mpf(z0) - fm - mpf(1e-11) * A), float((lo + hi) / 2)
    raise AssertionError("no grazing minimum")


@pytest.mark.slow
@pytest.mark.parametrize("contact,psi,xi", [("rim", math.pi / 2, 0.5), ("rim", 0.5, 0.2),
                                             ("thick", math.pi / 2, 0.3), ("thick", 1.3, 0.8)])
def test_a_grazing_dip_is_the_first_contact(contact, psi, xi):
    # A dip 1e-11 a deep lasting ~1e-5 rad of phase: the first root is its left edge, and the
    # module finds it where the reference does, one toss and in a batch.
    u, om = 2.0, 776.0
    z0, t_min = _dip_z0(psi, xi, contact, u, om)
    args = (xi, psi, u, om)
    t_f = TB.toss(*args, contact=contact, z0=z0).t_f
    assert t_f < t_min
    _check(t_f, args, contact, z0=z0)
    batch = TB.toss_many(np.full(3, xi), psi, u, om, contact=contact, z0=z0)
    assert np.all(batch.t_f == t_f)
