"""The table calibration's statistics (coincli.core.bounce.calibrate) on a simulator whose
chances are known in closed form: the response surface, common random numbers, the estimate,
its intervals' coverage, the test of fit and the warning of parameters the data cannot tell
apart.  No MuJoCo: the engine's round trip is benchmarks/calibration_roundtrip.py, and
tests/cli/test_cli_calibrate.py runs the command on it."""

from __future__ import annotations

import math

import numpy as np
import pytest

from coincli.core.bounce import calibrate as C

NAMES = ("restitution", "friction")
PROTOTYPES = (0.45, 0.6)


def true_probs(xi, params):
    """A smooth table that is *not* a quadratic logit in the scaled coordinates (P(sides)
    grows with ln xi, friction and restitution; heads lead tails, more so on lively tables)."""
    e, mu = params["restitution"], params["friction"]
    a = (2.2 * math.log(xi / 0.5) + 1.3 * math.log(mu / 0.3) + 1.0 * (e - 0.5)
         + 0.3 * math.log(mu / 0.3) ** 2)
    ps = 1 / (1 + math.exp(-a))
    ph = (1 - ps) * (0.55 + 0.1 * (e - 0.5))
    return ph, ps, 1 - ph - ps


def fake(xi, params, n, seed, stream, kw):
    """n tosses with common random numbers: the uniforms depend on (seed, stream) only."""
    u = np.random.default_rng([seed, *stream]).uniform(size=n)
    ph, ps, _ = true_probs(xi, params)
    h, s = int(np.sum(u < ph)), int(np.sum((u >= ph) & (u < ph + ps)))
    return h, s, n - h - s, 0


@pytest.fixture(scope="module")
def design():
    pts = C.design_points(2, 4)
    return pts, C.run_design(PROTOTYPES, NAMES, pts, seed=1, per_group=16, simulate=fake)


def _data(rng, e, mu, n=1000, faces=True):
    out = []
    for xi in PROTOTYPES:
        c = rng.multinomial(n, true_probs(xi, {"restitution": e, "friction": mu}))
        out.append((int(c[0]), int(c[1]), int(c[2]), n) if faces else (None, int(c[1]), None, n))
    return out


def test_scaled_coordinates_span_the_ranges():
    for name, (lo, hi) in C.RANGES.items():
        assert C.to_coords(name, lo) == pytest.approx(-1) and C.to_coords(name, hi) == 1
        assert C.from_coords(name, C.to_coords(name, 0.5 * (lo + hi))) == pytest.approx(
            0.5 * (lo + hi), rel=1e-12)
    # friction is designed in ln: its midpoint is the geometric mean of the range's ends
    assert C.from_coords("friction", 0.0) == pytest.approx(math.sqrt(0.05 * 1.0), rel=1e-12)


def test_surface_recovers_a_quadratic_logit_exactly():
    pts = C.design_points(2, 4)
    rng = np.random.default_rng(3)
    coef = rng.normal(0, 0.5, (2, 6))
    p = C._probs(coef, C._terms(pts))
    fit = C.fit_surface(pts, 1e7 * p, ridge=0.0)  # expected counts, no noise
    np.testing.assert_allclose(fit.coef, coef, atol=1e-6)
    assert fit.deviance < 1e-6


def test_common_random_numbers_share_launches_across_tables_not_across_groups():
    seen = []

    def record(xi, params, n, seed, stream, kw):
        seen.append((xi, tuple(sorted(params.items())), seed, stream))
        return n, 0, 0, 0

    pts = C.design_points(2, 2)
    counts = C.run_design((0.3, 0.5), NAMES, pts, seed=7, per_group=3, groups=4, simulate=record)
    assert counts.shape == (2, 4, 4, 4) and counts[..., 0].sum() == 2 * 4 * 4 * 3
    for j, xi in enumerate((0.3, 0.5)):
        streams = {}
        for x, params, seed, stream in seen:
            if x == xi:
                assert seed == 7 and stream[0] == j
                streams.setdefault(params, []).append(stream)
        assert len(streams) == 4  # every designed table ...
        assert all(s == [(j, g) for g in range(4)] for s in streams.values())  # ... same launches


def test_round_trip_intervals_hold_the_truth(design):
    pts, counts = design
    rng = np.random.default_rng(5)
    hold = dict.fromkeys(NAMES, 0)
    tables = 6
    for _ in range(tables):
        e, mu = rng.uniform(0.15, 0.8), math.exp(rng.uniform(math.log(0.08), math.log(0.8)))
        f = C.fit_table(NAMES, pts, counts, _data(rng, e, mu))
        for n, v in zip(NAMES, (e, mu), strict=True):
            hold[n] += f.low[n] <= v <= f.high[n]
            assert f.low[n] <= f.estimate[n] <= f.high[n]
            # the surface's error widens the interval; it never narrows it
            assert f.high[n] - f.low[n] >= f.data_high[n] - f.data_low[n] - 1e-9
        assert f.df == 2 and 0 <= f.p_value <= 1
    assert hold["restitution"] >= tables - 1 and hold["friction"] >= tables - 1, hold


def test_one_prototype_counting_sides_cannot_pin_two_parameters(design):
    pts, counts = design
    rng = np.random.default_rng(11)
    data = _data(rng, 0.5, 0.3, faces=False)[:1]
    f = C.fit_table(NAMES, pts, counts[:1], data)
    assert f.df == -1 and math.isnan(f.p_value)  # one count, two parameters: no test
    assert len(f.pinned) < 2 and len(f.ridge) >= 2
    # the curve of equally good tables: each predicts the observed chance of a side
    obs = data[0][1] / data[0][3]
    for e, mu in f.ridge:
        u = np.array([[C.to_coords("restitution", e), C.to_coords("friction", mu)]])
        p = f.surfaces[0].probs(u)[0][1]
        assert abs(p - obs) < 0.06, (e, mu, p, obs)


def test_counts_no_table_gives_are_rejected(design):
    pts, counts = design
    # tails three times as often as heads: every table of true_probs has heads ahead
    data = [(100, 300, 600, 1000), (80, 420, 500, 1000)]
    f = C.fit_table(NAMES, pts, counts, data)
    assert f.p_value < 1e-6
    assert f.p_value <= f.reach_p < 1e-6  # the bound on every cell is the weaker test
    # one prototype, heads/sides/tails: two cells for two parameters leave no df, but a table
    # that gave the counts would leave Q ~ chi-square(2), and the nearest leaves far more
    one = C.fit_table(NAMES, pts, counts[:1], data[:1])
    assert one.df == 0 and math.isnan(one.p_value) and one.reach_p < 1e-6
    from coincli.reports.calibrate import fit_warnings
    assert "no table in the designed range gives your counts" in fit_warnings(one, [None])
    # counts a table does give: no df, no rejection
    fine = C.fit_table(NAMES, pts, counts[:1], _data(np.random.default_rng(4), 0.5, 0.3)[:1])
    assert fine.df == 0 and fine.reach_p > 0.05
    assert "no test of fit" in fit_warnings(fine, [None])



def biased(xi, params, n, seed, stream, kw):
    """:func:`fake` at a table whose chance of a side is off by a fixed amount that changes
    from one designed table to the next (a bias no launch group shows: the jackknife cannot
    see it): the shape the surface then follows is wrong between its points."""
    rng = np.random.default_rng([99, round(1e6 * params["restitution"]),
                                 round(1e6 * params["friction"]), round(1e3 * xi)])
    shift = rng.normal(0.0, 0.35)
    ph, ps, pt = true_probs(xi, params)
    z = math.log(ps / (1 - ps)) + shift
    ps2 = 1 / (1 + math.exp(-z))
    ph, pt = ph * (1 - ps2) / (1 - ps), pt * (1 - ps2) / (1 - ps)
    u = np.random.default_rng([seed, *stream]).uniform(size=n)
    h, s = int(np.sum(u < ph)), int(np.sum((u >= ph) & (u < ph + ps2)))
    return h, s, n - h - s, 0


def test_a_surface_that_fits_carries_no_lack_of_fit(design):
    pts, counts = design
    pooled = counts.sum(axis=2)
    for j in range(2):
        s = C.fit_surface(pts, pooled[j], degree=3)
        assert s.deviance < s.df  # common random numbers: well under its df
        assert C.discrepancy(s, 256.0) == 0.0
    data = _data(np.random.default_rng(2), 0.5, 0.3)
    f, f0 = C.fit_table(NAMES, pts, counts, data), C.fit_table(NAMES, pts, counts, data,
                                                               lack_of_fit=False)
    assert f.tau2 == [0.0, 0.0] and (f.low, f.high) == (f0.low, f0.high)


@pytest.mark.slow
def test_the_surfaces_lack_of_fit_is_measured_and_carried():
    pts = C.design_points(2, 4)
    counts = C.run_design(PROTOTYPES, NAMES, pts, seed=1, per_group=16, simulate=biased)
    pooled = counts.sum(axis=2)
    surfaces = [C.fit_surface(pts, pooled[j], degree=3) for j in range(2)]
    for s in surfaces:  # the dispersion, read as 1 + m tau2 (m = 256 tosses a design point)
        phi = s.deviance / s.df
        assert phi > 2
        assert C.discrepancy(s, 256.0) == pytest.approx((phi - 1) / 256, rel=1e-12)
    rng = np.random.default_rng(5)
    tables, hold, hold0 = 12, dict.fromkeys(NAMES, 0), dict.fromkeys(NAMES, 0)
    for _ in range(tables):
        e, mu = rng.uniform(0.15, 0.8), math.exp(rng.uniform(math.log(0.08), math.log(0.8)))
        data = _data(rng, e, mu)
        f = C.fit_table(NAMES, pts, counts, data)
        f0 = C.fit_table(NAMES, pts, counts, data, lack_of_fit=False)
        assert f.tau2 == pytest.approx([C.discrepancy(s, 256.0) for s in surfaces], rel=1e-12)
        for n, v in zip(NAMES, (e, mu), strict=True):
            hold[n] += f.low[n] <= v <= f.high[n]
            hold0[n] += f0.low[n] <= v <= f0.high[n]
            # carried, the lack of fit widens the interval
            assert f.high[n] - f.low[n] >= f0.high[n] - f0.low[n] - 1e-9
    # the jackknife alone misses the truth where the surface is wrong; carried, it holds it
    assert sum(hold0.values()) < sum(hold.values()), (hold0, hold)
    assert min(hold.values()) >= tables - 1, hold
