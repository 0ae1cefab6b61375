"""Hypothesis properties of the closed forms in coincli.core.models.

Where a property holds exactly in real arithmetic but the outputs are rounded, the tolerance is
the one the 4-ulp accuracy bar (tests/test_accuracy.py) implies, and the largest deviation seen
is printed in the terminal summary ("properties: measured"), so that what is true is on record.
"""

from __future__ import annotations

import math

import mpmath
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from reference import ref_conditional, ref_dynamic

from coincli.core import models

BAR = 4  #: ulps per output (tests/test_accuracy.py)
EPS = 2.0**-52
SECTION = "properties: measured"
SETTINGS = settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])

_MEASURED: dict[str, float] = {}


def _measure(key, value):
    _MEASURED[key] = max(_MEASURED.get(key, 0.0), value)


@pytest.fixture(scope="module", autouse=True)
def _report_measured(report):
    yield
    for key, value in sorted(_MEASURED.items()):
        report(SECTION, f"{key}: {value:g}")


def _ulp(x):
    return math.ulp(x) if x != 0 else 2.0**-1074


# xi: log-uniform over the double range, plus the edges and ordinary values
xis = st.one_of(
    st.sampled_from([0.0, math.inf, 5e-324, 1e-300, 1 / math.sqrt(3), 1e300, 1.7e308]),
    st.floats(-320, 308).map(lambda e: 10.0**e),
    st.floats(0, 10),
)
finite_xis = xis.filter(math.isfinite)
psis = st.one_of(
    st.sampled_from([0.0, math.pi / 2, math.pi, 5e-324, math.pi / 4]),
    st.floats(0, math.pi),
)


def _outcomes(xi, psi):
    return [models.geometric(xi), models.dynamic(xi), models.conditional(xi, psi)]


@SETTINGS
@given(xis, psis)
def test_probabilities_in_unit_interval_and_sum_to_one(xi, psi):
    for out in _outcomes(xi, psi):
        assert all(0.0 <= v <= 1.0 for v in out), out
        # exact sum of the three rounded outputs; each is within BAR ulps of a value summing to 1
        dev = abs(math.fsum(out) - 1.0)
        _measure("|heads + sides + tails - 1| / eps (max)", dev / EPS)
        assert dev <= BAR * sum(_ulp(v) for v in out), (out, dev / EPS)


@SETTINGS
@given(xis, xis, psis)
def test_sides_nondecreasing_in_xi(a, b, psi):
    lo, hi = min(a, b), max(a, b)
    assert models.geometric(lo).sides <= models.geometric(hi).sides
    assert models.dynamic(lo).sides <= models.dynamic(hi).sides
    assert models.conditional(lo, psi).sides <= models.conditional(hi, psi).sides


@SETTINGS
@given(xis, psis)
def test_heads_at_least_tails(xi, psi):
    # theta1 + theta2 >= pi (cos theta1 + cos theta2 = -2 cos^2 psi / sin^2 psi <= 0)
    h, _, t = models.conditional(xi, psi)
    assert h >= t
    h, _, t = models.geometric(xi)
    assert h == t
    h, _, t = models.dynamic(xi)
    assert h == t


@SETTINGS
@given(xis, st.floats(math.pi / 2, math.pi))
def test_mirror_symmetry(xi, psi):
    """P(i | psi) = P(i | pi - psi).  pi - psi is not a double: math.pi - psi is exact here
    (Sterbenz) but is the mirror of psi - 1.22e-16, so the outputs may differ by as much as the
    exact values at the two angles do, plus the two 4-ulp bars."""
    mirror = math.pi - psi
    a, b = models.conditional(xi, psi), models.conditional(xi, mirror)
    ra, rb = ref_conditional(xi, psi), ref_conditional(xi, mirror)
    for x, y, rx, ry in zip(a, b, ra, rb, strict=True):
        slack = abs(float(rx - ry))
        _measure("mirror: |P(psi) - P(fl(pi - psi))| beyond the exact difference, ulps (max)",
                 max(0.0, abs(x - y) - slack) / _ulp(max(x, y)))
        assert abs(x - y) <= slack + BAR * (_ulp(x) + _ulp(y)), (x, y, float(rx), float(ry))


@SETTINGS
@given(xis)
def test_keller_flip_is_dynamic(xi):
    """conditional(xi, pi/2) = dynamic(xi).  math.pi/2 is 6.1e-17 short of pi/2, which matters
    only once theta0/2 is that small (xi > 1e15); the exact difference is allowed for."""
    c, d = models.conditional(xi, math.pi / 2), models.dynamic(xi)
    rc, rd = ref_conditional(xi, math.pi / 2), ref_dynamic(xi)
    for x, y, rx, ry in zip(c, d, rc, rd, strict=True):
        slack = abs(float(rx - ry))
        _measure("conditional(xi, pi/2) vs dynamic(xi) beyond the exact difference, ulps (max)",
                 max(0.0, abs(x - y) - slack) / _ulp(y))
        assert abs(x - y) <= slack + BAR * (_ulp(x) + _ulp(y)), (x, y)
    if xi <= 1e6:
        assert all(abs(x - y) <= 2 * BAR * _ulp(y) for x, y in zip(c, d, strict=True))


# the doubles in [pi/4, 3pi/4] (math.pi/4 itself is 3e-17 below pi/4)
_QUARTER = math.nextafter(math.pi / 4, 4.0)
_THREE_QUARTERS = math.nextafter(3 * math.pi / 4, 0.0)


def _dhm_heads(psi):
    with mpmath.workdps(60):
        p = mpmath.mpf(psi)
        return mpmath.mpf(1) / 2 + mpmath.asin(mpmath.cot(p) ** 2) / mpmath.pi


@SETTINGS
@given(st.floats(_QUARTER, _THREE_QUARTERS))
def test_zero_thickness_is_diaconis_holmes_montgomery(psi):
    """xi = 0: P(heads) = 1/2 + asin(cot^2 psi)/pi on [pi/4, 3pi/4], no sides, tails the rest."""
    assert mpmath.cot(mpmath.mpf(psi)) ** 2 <= 1  # the strategy stays inside the interval
    h, s, t = models.conditional(0.0, psi)
    ref = _dhm_heads(psi)
    err = abs(mpmath.mpf(h) - ref) / mpmath.mpf(_ulp(float(ref)))
    _measure("xi = 0 heads vs Diaconis-Holmes-Montgomery, ulps (max)", float(err))
    assert err <= BAR
    assert s == 0.0
    terr = abs(mpmath.mpf(t) - (1 - ref)) / mpmath.mpf(_ulp(float(1 - ref)))
    assert terr <= BAR


def _round_trip_bound(xi, p, dlnxi_dlnp):
    # p carries up to BAR ulps (forward bar), amplified by the condition number of the inverse,
    # and the inverse adds its own BAR ulps
    return xi * dlnxi_dlnp * BAR * _ulp(p) / p + BAR * _ulp(xi)


@SETTINGS
@given(st.floats(-300, 7.5).map(lambda e: 10.0**e))
def test_geometric_round_trip(xi):
    p = models.geometric(xi).sides
    back = models.geometric_inverse(p)
    kappa = 1 / ((1 - p) * (1 + p))  # d ln xi / d ln p for xi = p / sqrt(1 - p^2)
    err = abs(back - xi)
    _measure("geometric_inverse(geometric(xi)) error / bound (max)",
             err / _round_trip_bound(xi, p, kappa))
    assert err <= _round_trip_bound(xi, p, kappa), (xi, p, back)


@SETTINGS
@given(st.floats(-300, 15).map(lambda e: 10.0**e))
def test_dynamic_round_trip(xi):
    p = models.dynamic(xi).sides
    back = models.dynamic_inverse(p)
    # xi = tan(pi p / 2): d ln xi / d ln p = (pi p / 2)(1 + xi^2)/xi
    kappa = (math.pi * p / 2) * (1 / xi + xi)
    err = abs(back - xi)
    _measure("dynamic_inverse(dynamic(xi)) error / bound (max)",
             err / _round_trip_bound(xi, p, kappa))
    assert err <= _round_trip_bound(xi, p, kappa), (xi, p, back)
