"""The batched engine of ``coin check``/``coin fit`` against the one-row-at-a-time scipy.stats
implementation it replaced (tests/stats_reference.py), on random files of experiments.

Every number a row reports is compared: p-values (exact tests and G-test), G, df,
log-likelihoods, verdicts, Wilson intervals to rounding; Clopper-Pearson ends to scipy's own
root-finding tolerance (the new ends are exact beta quantiles, tests/test_intervals.py); and the
fitted spread of psi and its interval to the optimizers' tolerances.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import stats_reference as old

from coincli.core.densities import Cosine, Normal
from coincli.core.models import dynamic, geometric
from coincli.core.stats import counts as stats_counts
from coincli.core.stats import fit as stats_fit
from coincli.core.stats import tests as stats


def _random_experiments(seed: int, rows: int) -> list[stats_counts.Experiment]:
    """Rows of a few shared coins and some coins of their own; 1 to 3000 tosses, drawn from a
    psi spread of 18 deg, some rows with sides only, some counts at the extremes."""
    from coincli.core.averages import marginal

    rng = np.random.default_rng(seed)
    shared = rng.uniform(0.05, 1.5, 4)
    out = []
    for i in range(rows):
        xi = float(shared[i % 4] if rng.random() < 0.6 else rng.uniform(0.02, 3.0))
        n = int(rng.choice([1, 2, 7, 30, 100, 100, 400, 3000]))
        p = np.array(marginal(xi, Normal(math.pi / 2, math.radians(18))))
        h, s, t = (int(v) for v in rng.multinomial(n, p / p.sum()))
        kind = rng.random()
        if kind < 0.05:
            h, s, t = n, 0, 0  # all heads
        elif kind < 0.1:
            h, s, t = 0, n, 0  # all sides
        if rng.random() < 0.25:
            counts = stats_counts.make_counts(sides=s, n=n)
        else:
            counts = stats_counts.make_counts(h, s, t)
        out.append(stats_counts.Experiment(i + 2, xi, counts, f"row{i}"))
    return out


def _close(a, b, rel, abs_=0.0):
    if a == b:
        return True
    return math.isfinite(a) and math.isfinite(b) and abs(a - b) <= max(rel * abs(b), abs_)


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_rows_match_the_one_at_a_time_engine(seed):
    exps = _random_experiments(seed, 40)
    dens = {"cosine": Cosine()}
    res = stats_fit.fit(exps, dens, spread=False)
    assert len(res.rows) == len(exps)
    for e, row in zip(exps, res.rows, strict=True):
        chances = {"geometric": geometric(e.xi), "dynamic": dynamic(e.xi)}
        from coincli.core.averages import marginal

        chances["cosine"] = marginal(e.xi, Cosine())
        for t in row.tests:
            ch = chances[t.model]
            assert _close(t.chances.sides, ch.sides, 1e-13), (e, t.model)
            ph, ps, pt = old.check_probs(ch, 3)
            x = e.counts.values
            probs = (ph, ps, pt) if e.counts.faces else (ps, ph + pt)
            want_p = old.exact_pvalue(x, probs)
            g, df, _ = old.g_test(x, probs)
            ll = old.log_likelihood(e.counts, (ph, ps, pt))
            where = (e.line, e.counts, t.model)
            assert _close(t.p_value, want_p, 1e-10, 1e-300), (where, t.p_value, want_p)
            # G is a small difference of terms of size n: its rounding is absolute, about n * 1e-16
            assert _close(t.g_statistic, g, 1e-12, 1e-14 * e.counts.n) and t.df == df, where
            assert _close(t.log_likelihood, ll, 1e-12, 1e-11), (where, t.log_likelihood, ll)
            assert t.verdict == stats.verdict(want_p, exact=True), where
        for prop in row.proportions:
            ref = old.proportion(prop.count, prop.n, prop.outcome)
            assert prop.estimate == ref.estimate
            for got, want in ((prop.wilson.low, ref.wilson.low),
                              (prop.wilson.high, ref.wilson.high)):
                assert _close(got, want, 1e-12, 1e-16), (e, prop.outcome, got, want)
            for got, want in ((prop.clopper_pearson.low, ref.clopper_pearson.low),
                              (prop.clopper_pearson.high, ref.clopper_pearson.high)):
                assert _close(got, want, 2e-7, 1e-16), (e, prop.outcome, got, want)


@pytest.mark.parametrize("seed", [4, 5])
def test_spread_fit_matches_the_scipy_optimize_one(seed):
    exps = _random_experiments(seed, 30)
    xi = [e.xi for e in exps]
    counts = [e.counts for e in exps]
    got = stats_fit.fit_spread(xi, counts)
    want = old.fit_spread(xi, counts)
    # u = sigma / (1 + sigma): bounded Brent stops within 2 (1.5e-8 u + 1e-9 / 3) of the
    # maximum, Brent's root finder within 1e-10 of each end
    for g, w, tol in ((got.sigma, want.sigma, 3e-8), (got.low, want.low, 3e-10),
                      (got.high, want.high, 3e-10)):
        assert g == w or abs(g / (1 + g) - w / (1 + w)) <= tol, (g, w)
    assert len(got.pieces) == len(want.pieces)
    assert got.log_likelihood == pytest.approx(want.log_likelihood, rel=1e-12, abs=1e-9)
    for a, b in zip(got.chances, want.chances, strict=True):
        assert np.allclose(a, b, rtol=1e-7, atol=0)


def test_a_file_of_repeated_rows_is_tested_once_per_distinct_row(monkeypatch):
    # a file of 2000 rows of 4 coins: the exact tests run on the distinct (counts, chances) only
    exps = _random_experiments(6, 40) * 50
    calls = []
    real = stats._trinomial_logp

    def spy(x, p):
        calls.append(len(x))
        return real(x, p)

    monkeypatch.setattr(stats, "_trinomial_logp", spy)
    res = stats_fit.fit(exps, spread=False)
    assert sum(calls) <= 2 * 40
    first = [t.p_value for t in res.rows[0].tests]
    assert [t.p_value for t in res.rows[40].tests] == first


@pytest.mark.slow
def test_a_million_tosses_match_the_one_at_a_time_engine():
    # the trinomial test at n = 10^6, where the old engine took seconds and the new one 0.02 s
    p = list(dynamic(0.583))
    for c in ([333000, 334000, 333000], [331000, 337500, 331500]):
        assert stats.exact_pvalue(c, p) == pytest.approx(old.exact_pvalue(c, p), rel=1e-11)
