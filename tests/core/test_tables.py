"""The tables precomputed for the surface presets (coincli.core.bounce.tables, issue 25): that
they are the engine's as it is, agree with fresh tosses, apply to exactly the tosses they hold,
and that a design starting from one answers as the design it replaces does."""

from __future__ import annotations

import math

import pytest

B = pytest.importorskip("coincli.core.bounce.engine")
pytest.importorskip("mujoco")

from coincli.core.bounce import design as D  # noqa: E402
from coincli.core.bounce import runs as R  # noqa: E402
from coincli.core.bounce import tables as TB  # noqa: E402

REGENERATE = "regenerate it: python benchmarks/precompute_bounce_tables.py"


def test_every_preset_has_a_table_of_the_engine_as_it_is():
    """Fails when the engine's settings change until the tables are regenerated (a table of
    other settings is never used: the design would silently simulate everything)."""
    for name in B.SURFACES:
        t = TB.load(name)
        assert t is not None, f"no table of the engine as it is for {name}: {REGENERATE}"
        assert [(p[0], p[1]) for p in t.points] == [tuple(g) for g in TB.GRID]
        for _xi, n, heads, sides, tails, unsettled, never in t.points:
            assert heads + sides + tails + unsettled == n and 0 <= never <= unsettled
        assert t.seed == TB.TABLE_SEED


@pytest.mark.parametrize("name", list(B.SURFACES))
def test_the_table_is_what_its_seed_and_stream_give(name):
    """The table's last point (200 tosses at xi = 2.4, cheap) simulated again from the seed and
    stream the file records, as benchmarks/precompute_bounce_tables.py does: the same counts
    to the toss (MuJoCo is pinned), so the file is the script's output and nothing else."""
    t = TB.load(name)
    j = len(TB.GRID) - 1
    xi, n = TB.GRID[j]
    sim = R.simulate(n, t.seed, xi=xi, stream=(t.stream, j), jobs=1,
                     **TB.launch_kw(B.SURFACES[name]))
    assert t.points[j] == (xi, n, *sim.counts, n - sum(sim.catch_counts))


def _fresh(name, xi, n, seed):
    return R.simulate(n, seed, xi=xi, jobs=1, **TB.launch_kw(B.SURFACES[name]))


def _chi2_p(a, b):
    """p of the chi-square test that two (heads, sides, tails) counts share their chances
    (columns empty in both dropped)."""
    from scipy.stats import chi2_contingency

    cols = [j for j in range(3) if a[j] + b[j] > 0]
    if len(cols) < 2:
        return 1.0
    return float(chi2_contingency([[a[j] for j in cols], [b[j] for j in cols]],
                                  correction=False).pvalue)


@pytest.mark.slow
@pytest.mark.parametrize("name", list(B.SURFACES))
def test_the_table_agrees_with_fresh_tosses(name):
    """200 fresh tosses (another seed) at the grid point nearest the fair coin's 0.47 against
    the table's 2000 there: the chi-square test of heads, sides and tails is not rejected at
    0.1%, while the table's point two thirds as thick (xi = 0.3191) is (the test can tell
    points of the table apart)."""
    table = TB.load(name)
    row = next(p for p in table.points if p[0] == 0.4714)
    fresh = _fresh(name, 0.4714, 200, seed=7)
    assert _chi2_p(row[2:5], fresh.counts[:3]) > 1e-3, (name, row, fresh.counts)
    thinner = next(p for p in table.points if p[0] == 0.3191)
    assert _chi2_p(thinner[2:5], fresh.counts[:3]) < 1e-3, (name, thinner, fresh.counts)


@pytest.mark.slow
def test_half_the_default_step_agrees_with_the_wood_table_where_the_contact_matters():
    """The step sets the contact's stiffness (docs/bounce.md, "The step and the contact's
    stiffness"), and wood near xi = 0.7 is where the chance of a side depends on it most: 800
    fresh tosses at half the default step (a contact four times as stiff) are not rejected
    against the table there (chi-square, 0.1%).  The test has the power it needs: against the
    table made at 2e-4 s, whose softer contact gave P(sides) 0.6955 where 1e-4 gives about
    0.61, the same 800 tosses at 1e-4 gave p = 1.4e-7."""
    row = next(p for p in TB.load("wood").points if p[0] == 0.6965)
    fresh = R.simulate(800, 11, xi=0.6965, jobs=1,
                       **{**TB.launch_kw(B.SURFACES["wood"]), "dt": B.DEFAULT_DT / 2})
    assert fresh.counts[3] == 0
    assert _chi2_p(row[2:5], fresh.counts[:3]) > 1e-3, (row, fresh.counts)


def test_a_table_applies_to_exactly_its_tosses():
    wood = B.SURFACES["wood"]
    kw = TB.launch_kw(wood)
    assert TB.for_design(kw).surface == "wood"
    assert TB.for_design({**kw, "surf": B.SURFACES["felt"]}).surface == "felt"
    from coincli.core.toss.launch import as_dist

    for change in ({"u": as_dist("normal:2.5:0.3", "u", 0, 20)}, {"omega": 240.0},
                   {"psi": math.pi / 2}, {"diameter": 0.03}, {"dt": 2 * B.DEFAULT_DT}, {"t_max": 5.0},
                   {"g": 9.8}, {"height": 0.1}, {"vx": 0.2}, {"density": 8000.0},
                   {"surf": B.surface("wood", restitution=0.6)}, {"z0": 0.01},
                   {"flight": "mujoco"}):
        assert TB.for_design({**kw, **change}) is None, change
    assert TB.for_design({**kw, "density": B.DEFAULT_DENSITY}).surface == "wood"


def _probit(x):
    from scipy.special import ndtr

    return float(ndtr(-0.1 + 2.4 * math.log(x / 0.55)))


def _fake(sims):
    import numpy as np

    def fake(n, seed, *, xi, stream=(), **kw):
        sims.append((n, seed, tuple(stream), xi))
        k = int(np.random.default_rng([seed, *stream]).binomial(n, _probit(xi)))
        return type("R", (), {"settled": n, "counts": (0, k, n - k, 0), "n": n,
                              "catch_counts": (n, 0, 0)})()
    return fake


def _table(per):
    """A table of the probit: binomial draws of ``per`` tosses at the grid's dense points."""
    import numpy as np

    rng = np.random.default_rng(5)
    pts = []
    for xi, n in TB.GRID:
        n = per if n > 200 else n
        k = int(rng.binomial(n, _probit(xi)))
        pts.append((xi, n, 0, k, n - k, 0, 0))
    return TB.Table("wood", 25, 1000, tuple(pts), {})


def test_a_design_from_a_dense_table_simulates_nothing_more(monkeypatch):
    from scipy.optimize import brentq

    sims = []
    monkeypatch.setattr(D, "simulate", _fake(sims))
    truth = brentq(lambda x: _probit(x) - 1 / 3, 0.1, 2.0)
    table = _table(4000)
    r = D.design([1 / 3], seed=3, tol=0.01, table=table)
    assert sims == [] and r.tosses == 0 and r.rounds == 0 and r.met and r.table is table
    assert r.low[0] <= truth <= r.high[0] and r.high[0] - r.low[0] <= 0.02
    # the answer is the design's own fit of the table's points (no other rule)
    fit = D._local_fit(table.design_points(), 1 / 3, D.fit_sides(
        [(x, n, k) for x, (n, k) in sorted(table.design_points().items())]).inverse(1 / 3))
    assert r.xi[0] == fit.inverse(1 / 3)


def test_a_design_from_a_sparse_table_adds_rounds_of_the_users_seed(monkeypatch):
    sims = []
    monkeypatch.setattr(D, "simulate", _fake(sims))
    table = _table(60)
    r = D.design([1 / 3], seed=3, tol=0.01, table=table)
    assert r.met and r.rounds >= 1 and r.tosses == sum(n for n, *_ in sims) > 0
    # every simulation is a round's, of the user's seed, on its own stream (never the table's)
    assert {s[1] for s in sims} == {3} and {s[2][0] for s in sims} == set(
        range(1, r.rounds + 1))
    assert all(n == D.DESIGN_ROUND for n, *_ in sims)
    # the table's tosses do not count against --max-tosses; the rounds' do
    sims.clear()
    capped = D.design([1 / 3], seed=3, tol=0.01, table=table, max_tosses=2 * 3 * D.DESIGN_ROUND)
    assert capped.tosses == sum(n for n, *_ in sims) <= 2 * 3 * D.DESIGN_ROUND
