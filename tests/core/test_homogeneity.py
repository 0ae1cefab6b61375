"""The two-sample test of ``coin check --landing bounce`` (experiment against simulated counts):
the exact conditional test against Fisher's exact test (two outcomes, scipy) and against a
brute-force enumeration in exact rational arithmetic (three outcomes); the G-test against
scipy's chi2_contingency."""

from __future__ import annotations

import itertools
import math
from fractions import Fraction

import pytest
from scipy import stats as ss

from coincli.core.stats.homogeneity import g_statistic, homogeneity, tables


def _brute(a, b) -> float:
    """Freeman-Halton by enumeration of every first row, in exact rationals."""
    col = [x + y for x, y in zip(a, b, strict=True)]
    n1, n = sum(a), sum(col)

    def prob(row):
        num = 1
        for c, x in zip(col, row, strict=True):
            num *= math.comb(c, x)
        return Fraction(num, math.comb(n, n1))

    obs = prob(a)
    total = Fraction(0)
    for row in itertools.product(*(range(c + 1) for c in col)):
        if sum(row) == n1:
            p = prob(row)
            if p <= obs * (1 + Fraction(1, 10**7)):
                total += p
    return float(total)


@pytest.mark.parametrize("a, b", [((3, 7), (10, 2)), ((0, 5), (5, 0)), ((12, 30), (40, 200)),
                                  ((1, 1), (1, 1)), ((50, 50), (45, 55)), ((0, 9), (2, 30))])
def test_two_outcomes_is_fishers_exact(a, b):
    want = ss.fisher_exact([list(a), list(b)]).pvalue
    assert homogeneity(a, b).p_value == pytest.approx(want, rel=1e-9)


@pytest.mark.parametrize("a, b", [((3, 2, 5), (10, 4, 6)), ((0, 0, 7), (3, 4, 2)),
                                  ((5, 5, 5), (5, 5, 5)), ((9, 1, 0), (2, 3, 8)),
                                  ((4, 0, 4), (20, 1, 19)), ((1, 6, 2), (30, 3, 25))])
def test_three_outcomes_is_the_enumeration(a, b):
    got = homogeneity(a, b, method="exact")
    assert got.exact and got.method.startswith("exact conditional")
    assert got.p_value == pytest.approx(_brute(a, b), rel=1e-9)


@pytest.mark.parametrize("a, b", [((45, 38, 37), (4000, 2100, 3900)), ((3, 2, 5), (10, 4, 6)),
                                  ((0, 12, 30), (5, 80, 210))])
def test_g_test_is_scipys(a, b):
    seen = [j for j in range(3) if a[j] + b[j]]
    obs = [[a[j] for j in seen], [b[j] for j in seen]]
    g, p, df, _ = ss.chi2_contingency(obs, correction=False, lambda_="log-likelihood")
    got = homogeneity(a, b, method="g")
    assert not got.exact and got.df == df
    assert got.g == pytest.approx(g, rel=1e-10) and got.p_value == pytest.approx(p, rel=1e-9)
    assert g_statistic(a, b) == (pytest.approx(g, rel=1e-10), df)


def test_auto_switches_to_g_beyond_the_table_budget(monkeypatch):
    from coincli.core.stats import homogeneity as H

    a, b = (40, 30, 30), (400, 300, 300)
    assert tables(a, b) == len([r for r in itertools.product(range(441), range(331))
                                if 0 <= 100 - r[0] - r[1] <= 330])
    assert H.homogeneity(a, b).exact
    monkeypatch.setattr(H, "EXACT_MAX_TABLES", 10)
    assert not H.homogeneity(a, b).exact


def test_one_outcome_seen_cannot_differ_and_bad_input_is_named():
    assert homogeneity((0, 5, 0), (0, 9, 0)).p_value == 1.0
    for a, b in [((1, 2), (1, 2, 3)), ((-1, 2, 3), (1, 2, 3)), ((0, 0, 0), (1, 2, 3))]:
        with pytest.raises(ValueError, match="homogeneity"):
            homogeneity(a, b)
