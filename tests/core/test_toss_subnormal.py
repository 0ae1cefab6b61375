"""Tiny and subnormal inputs to the deterministic toss (issue 28, item 4).

``coin toss --xi 1 --psi 90 --u 0 --omega 1 --g 5e-324`` used to answer ``t_f 0, heads``: the
latest contact ``(u + sqrt(u^2 + 2 g z0)) / g`` underflowed to 0.  A subnormal ``g`` has a digit
or none (``g t^2 / 2`` cannot be computed), so ``g`` is refused below ``G_MIN``; the bound is
computed without a product of small numbers (:func:`coincli.core.toss.flight.fall_time`), so that
a tiny ``g z0`` from normal numbers is right.  Every other physical parameter, subnormal, gives
the answer of its limit, computed independently here (mpmath, or the closed form of the limit).
"""

from __future__ import annotations

import math

import mpmath
import numpy as np
import pytest

from coincli.core.toss import batch as TB
from coincli.core.toss import flight as T
from coincli.core.toss.batch import toss_many
from coincli.core.toss.simulate import simulate
from coincli.limits import G_MIN

SUB = 5e-324  # the smallest subnormal
D = T.DEFAULT_DIAMETER
A = D / 2


def _fall(u, g, z0):
    """The centre's fall time to the plane, in 60 digits."""
    mpmath.mp.dps = 60
    u, g, z0 = mpmath.mpf(u), mpmath.mpf(g), mpmath.mpf(z0)
    return float((u + mpmath.sqrt(u * u + 2 * g * z0)) / g)


def _rim(g, z0=None):
    """The first contact of the reference toss (rim, psi = 90 degrees, omega = 1, u = 0):
    the root of a sin(t) = z0 - g t^2 / 2 near pi/3, in 60 digits."""
    mpmath.mp.dps = 60
    a = mpmath.mpf(A)
    z0 = mpmath.sqrt(3) / 2 * a if z0 is None else mpmath.mpf(z0)
    return float(mpmath.findroot(lambda t: a * mpmath.sin(t) - z0 + g * t * t / 2,
                                 mpmath.asin(z0 / a)))


@pytest.mark.parametrize("u, g, z0", [(0.0, 1e-300, 1e-303), (1e-160, 1e-300, 1e-303),
                                      (0.0, 1e-10, 1e-303), (2.0, 1e-300, 0.01),
                                      (0.0, 1e-300, 0.01), (3.0, 9.81, 0.01)])
def test_fall_time_has_no_underflow(u, g, z0):
    for xp in (math, np):
        got = T.fall_time(xp if xp is np else T._M(), np.float64(u) if xp is np else u, g, z0)
        assert got == pytest.approx(_fall(u, g, z0), rel=1e-14)


@pytest.mark.parametrize("g", [SUB, 1e-310, 2.2e-308, 1e-301])
def test_g_below_the_normal_range_is_refused(g):
    with pytest.raises(ValueError, match="g must be"):
        TB.toss(1.0, math.pi / 2, 0.0, 1.0, g=g)
    with pytest.raises(ValueError, match="g must be"):
        simulate(10, 1, xi=1.0, u=0.0, omega=1.0, psi=math.pi / 2, g=g)


def test_the_reference_toss_at_a_tiny_g():
    """psi = 90 degrees, omega = 1: cos(alpha) = cos(t), and with g t^2 << z0 the rim touches
    when a sin(t) = z0 = (sqrt 3/2) a: t = pi/3, alpha = 60 degrees, beyond theta0 = 45: sides.
    At g = G_MIN the phase bound refuses it (the latest contact is 1e149 s away)."""
    r = TB.toss(1.0, math.pi / 2, 0.0, 1.0, g=1e-10)
    assert r.t_f == pytest.approx(_rim(1e-10), rel=1e-12) and r.outcome == "sides"
    assert abs(r.t_f - math.pi / 3) < 1e-8
    _, phase, problem = T.flight_limits(1.0, math.pi / 2, 0.0, 1.0, g=G_MIN)
    assert problem == 2 and phase == pytest.approx(_fall(0.0, G_MIN, math.sqrt(3) / 2 * A))


def test_a_tiny_g_with_a_tiny_z0():
    """g = 1e-300, z0 = 1e-303 m: 2 g z0 underflows to 0 (the old bound said the coin lands at
    once).  A flat coin (omega tiny) with thick contact and z0 just above h/2 lands when its
    centre has fallen z0 - h/2: t = sqrt(2 (z0 - h/2) / g)."""
    xi, z0 = 1e-300, 1e-280
    r = TB.toss(xi, math.pi / 2, 0.0, 1e-300, g=1e-300, contact="thick", z0=z0)
    assert r.t_f == pytest.approx(_fall(0.0, 1e-300, z0 - xi * D / 2), rel=1e-9)
    assert r.outcome == "heads"
    # rim contact, turning at 1 rad/s: a sin(t) = z0 first, t = asin(z0 / a) = z0 / a
    r = TB.toss(1.0, math.pi / 2, 0.0, 1.0, g=1e-300, z0=1e-303)
    assert r.t_f == pytest.approx(_rim(1e-300, 1e-303), rel=1e-12) and r.outcome == "heads"


@pytest.mark.parametrize("name", ["u", "omega", "psi", "xi"])
def test_subnormal_physical_parameters_give_their_limit(name):
    """Each parameter at 5e-324 answers as at 0 (u, omega, psi) or as a disc (xi: theta0 = 90
    degrees, so every landing tilt below 90 is heads), the others at the reference toss."""
    kw = {"xi": 1.0, "psi": math.pi / 2, "u": 0.0, "omega": 1.0}
    kw[name] = SUB
    r = TB.toss(kw["xi"], kw["psi"], kw["u"], kw["omega"], g=1e-10)
    many = toss_many(kw["xi"], np.array([kw["psi"]] * 2), kw["u"], kw["omega"], g=1e-10)
    assert many.t_f.tolist() == [r.t_f] * 2
    z0 = math.sqrt(3) / 2 * A
    if name in ("omega", "psi"):  # no tilt: the coin falls flat, the rim lands at the plane
        assert r.t_f == pytest.approx(_fall(0.0, 1e-10, z0), rel=1e-12) and r.outcome == "heads"
    else:  # the tilt reaches 60 degrees first (u = 5e-324 rises 1e-314 m)
        assert r.t_f == pytest.approx(_rim(1e-10), rel=1e-12)
        assert r.outcome == ("heads" if name == "xi" else "sides")


def test_the_commands_refuse_a_subnormal_g_naming_it():
    """`coin toss --g 5e-324` answered t_f 0, heads; --g 1e-10 answers the reference toss."""
    from coincli import api
    from coincli.errors import InputError

    for fn in (api.toss, api.simulate):
        with pytest.raises(InputError, match=r"--g must be a number from 1e-300 to 1e\+100 "
                                             r"m/s\^2, got '5e-324'"):
            fn(xi=1, psi=90, u=0, omega=1, g="5e-324")
    (row,) = api.toss(xi=1, psi=90, u=0, omega=1, g="1e-10")
    assert row["outcome"] == "sides" and row["t_f"] == pytest.approx(_rim(1e-10), rel=1e-12)
