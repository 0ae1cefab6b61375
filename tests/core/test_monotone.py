"""Monotone to the last bit (issue 38, item 17).

P(sides) never decreases as xi grows, and P(heads), P(tails) never increase, over runs of
consecutive doubles: 2000 on each side of the aspect ratios where the regimes change
(xi = 1/(2 sqrt 2), 1/sqrt 3, 1, and 1.4617, where theta0/2 = 0.3 rad), for Table I at psi
from 45 to 115 deg and for every density of psi averaged (eq. 15).  The double formulas
stepped the wrong way there by 1 to 6 ulps; the numpy path of Table I and the averages now sum
in 64-bit long double and round once (coincli.core.models._extended_finish,
coincli.core.averages._working), which needs a long double of 64 bits (x86).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from coincli.core import models
from coincli.core.averages import marginal
from coincli.core.densities import Cosine, Normal, Table, Uniform
from coincli.core.modelspec import table_i_deg

pytestmark = pytest.mark.skipif(np.finfo(np.longdouble).nmant + 1 < 64,
                                reason="monotone to the last bit needs a 64-bit long double")

BOUNDARIES = {
    "1/(2 sqrt 2)": 1 / (2 * math.sqrt(2)),
    "1/sqrt 3": 1 / math.sqrt(3),
    "1": 1.0,
    "1.4617": 1 / math.tan(0.6),
}
RUN = 2000  #: consecutive doubles on each side
PSI_DEG = list(range(45, 116, 5))
DENSITIES = {
    "uniform": Uniform(),
    "cosine": Cosine(),
    "normal": Normal(),
    "normal:60:10": Normal(math.radians(60), math.radians(10)),
    "table": Table([0.0, 0.5, 1.2, 2.0, math.pi], [0.2, 1.0, 0.4, 1.5, 0.1]),
}


def _run(x: float) -> np.ndarray:
    """x and the RUN doubles on each side of it, ascending."""
    out = [x]
    lo = hi = x
    for _ in range(RUN):
        lo, hi = math.nextafter(lo, 0.0), math.nextafter(hi, math.inf)
        out += [lo, hi]
    return np.array(sorted(out))


def _wrong_steps(xi, outcome):
    """Where each output steps the wrong way: (label, xi before, xi after, size in ulps)."""
    bad = []
    for label, v, sign in (("heads", outcome.heads, -1), ("sides", outcome.sides, 1),
                           ("tails", outcome.tails, -1)):
        v = np.asarray(v, dtype=float)
        d = sign * np.diff(v)
        for i in np.flatnonzero(d < 0)[:3]:
            bad.append((label, float(xi[i]), float(xi[i + 1]),
                        float(-d[i] / np.spacing(max(abs(v[i]), abs(v[i + 1]))))))
    return bad


@pytest.mark.parametrize("name", BOUNDARIES)
def test_table_i_is_monotone_over_consecutive_doubles(name):
    xi = _run(BOUNDARIES[name])
    bad = {}
    for deg in PSI_DEG:
        for how, o in (("radians", models.conditional(xi, math.radians(deg))),
                       ("degrees", table_i_deg(xi, float(deg)))):
            steps = _wrong_steps(xi, o)
            if steps:
                bad[(deg, how)] = steps
    assert not bad, f"Table I steps the wrong way near xi = {name}: {bad}"


@pytest.mark.parametrize("density", DENSITIES)
@pytest.mark.parametrize("name", BOUNDARIES)
def test_every_average_is_monotone_over_consecutive_doubles(name, density):
    xi = _run(BOUNDARIES[name])
    steps = _wrong_steps(xi, marginal(xi, DENSITIES[density]))
    assert not steps, f"{density} steps the wrong way near xi = {name}: {steps}"


@pytest.mark.parametrize("density", ["uniform", "normal"])
def test_one_xi_at_a_time_is_the_array_path(density):
    """The scalar path of the averages sums as the array path does: the same bits."""
    xi = _run(1 / math.sqrt(3))[RUN - 20:RUN + 21]
    d = DENSITIES[density]
    arr = marginal(xi, d)
    for i, x in enumerate(xi.tolist()):
        assert tuple(marginal(x, d)) == (arr.heads[i], arr.sides[i], arr.tails[i])
