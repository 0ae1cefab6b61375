"""coincli.core.estimators and the --tol/--method/--seed options: Problem 2 of the paper, the three
estimators agreeing within their stated errors (hypothesis, across sd 1e-6..1e3 rad, means at 0
and pi, densities on a regime boundary), exact psi sampling, the chooser, errors.  No timing."""

from __future__ import annotations

import csv
import io
import math

import mpmath
import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from coincli.cli import run
from coincli.core import estimators as E
from coincli.core import models
from coincli.core.averages import error_bound, marginal, order_for_tol
from coincli.core.densities import Cosine, Normal, Table, Uniform

XI_FAIR = 1 / math.sqrt(3)
P2 = Normal(math.pi / 2, math.sqrt(0.1))  # Problem 2: mean pi/2, variance 0.1
TABLE = Table([0.0, 0.3, 0.9, 1.6, 2.2, math.pi], [0.0, 1.0, 0.5, 2.0, 0.25, 0.0], "stress")
XIS_P2 = np.round(np.arange(1, 21) * 0.1, 10)  # coin table --xi 0.1:2:0.1


def _within(est, exact, k):
    """Each chance within k standard errors (plus a count's worth for a zero s.e., and the
    quadrature bound when ``exact`` is the quadrature)."""
    for v, se, x in zip(est.value, est.error, exact, strict=True):
        v, se, x = (np.asarray(a, dtype=float) for a in (v, se, x))
        slack = k * se + k / est.n + 2 * error_bound(16)
        assert (np.abs(v - x) <= slack).all(), (est.detail, v, x, se)


# --------------------------------------------------------------------------- Problem 2


def test_problem_2_monte_carlo_agrees_with_quadrature_and_sits_above_dynamic():
    mc = E.monte_carlo(XIS_P2, P2, n=1 << 20, seed=2026)
    quad = marginal(XIS_P2, P2)
    dyn = models.dynamic(XIS_P2).sides
    # within its own 95% interval, for each xi (20 intervals from the same tosses)
    inside = [(lo <= q <= hi) for lo, q, hi in zip(mc.low.sides, quad.sides, mc.high.sides,
                                                   strict=True)]
    assert sum(inside) >= 18, inside  # 95% intervals: one or two of 20 may miss
    _within(mc, quad, 4.5)  # and every one within 4.5 s.e.
    assert (mc.low.sides > dyn).all()  # above the dynamic curve, beyond the noise


def test_problem_2_command(capsys):
    code = run(["table", "--xi", "0.1:2:0.1", "--psi-dist", "normal:90:18.12", "--method", "mc",
                "--seed", "7", "--tol", "2e-3", "-f", "csv"])
    out, err = capsys.readouterr()
    assert code == 0 and err == ""
    rows = list(csv.DictReader(io.StringIO(out)))
    assert len(rows) == 60
    dyn = {r["xi"]: float(r["p_sides"]) for r in rows if r["model"] == "dynamic"}
    mc = [r for r in rows if r["model"] == "normal:90:18.12"]
    assert len(mc) == 20
    d = Normal(math.radians(90), math.radians(18.12))
    for r in mc:
        xi, p, hw = float(r["xi"]), float(r["p_sides"]), float(r["err_sides"])
        assert r["method"].startswith("mc ") and hw <= 2e-3
        assert p - hw > dyn[r["xi"]]  # slightly above the dynamic curve
        assert abs(p - marginal(xi, d).sides) <= 2.5 * hw  # 95% half-width: 2.5 is ~4 s.e.
    assert rows[0]["method"] == "closed form" and rows[0]["err_sides"] == ""


# --------------------------------------------------------------------------- the estimators


@pytest.mark.parametrize("density", [Uniform(), Cosine(), Normal(), P2, TABLE])
def test_three_estimators_and_scipy_agree_at_the_fair_coin(density):
    exact = marginal(XI_FAIR, density)
    _within(E.monte_carlo(XI_FAIR, density, n=1 << 18, seed=1), exact, 5)
    _within(E.quasi_monte_carlo(XI_FAIR, density, n=1 << 16, seed=1), exact, 8)
    _within(E.quasi_monte_carlo(XI_FAIR, density, n=1 << 12, seed=1, phase="table1"), exact, 8)
    sq = E.scipy_quad(XI_FAIR, density, tol=1e-12)
    assert sq.met
    for a, b in zip(sq.value, exact, strict=True):
        assert abs(a - b) <= 1e-12


def test_seed_reproduces_and_early_stop_meets_tol():
    a = E.monte_carlo(0.3, Normal(), tol=3e-3, seed=5)
    b = E.monte_carlo(0.3, Normal(), tol=3e-3, seed=5)
    assert a == b and a.met and a.half_width <= 3e-3
    assert a.n < 1 << 20  # stopped early: ~2e5 tosses give +-3e-3
    c = E.monte_carlo(0.3, Normal(), n=12345, seed=5)
    assert c.n == 12345 and c.tol is None and c.met
    q = E.quasi_monte_carlo(0.3, Normal(), tol=1e-4, seed=5)
    assert q.met and q.half_width <= 1e-4 and q.n % 16 == 0
    slow = E.monte_carlo(0.3, Normal(), tol=1e-7, seed=5, max_samples=1 << 16)
    assert not slow.met and slow.n == 1 << 16


def test_array_xi_shares_the_tosses_and_keeps_shape():
    xs = np.array([[0.1, 1.0], [math.inf, 0.0]])
    mc = E.monte_carlo(xs, Uniform(), n=1 << 14, seed=3)
    assert mc.value.sides.shape == (2, 2)
    assert mc.value.sides[1, 0] == 1.0 and mc.value.sides[1, 1] == 0.0
    one = E.monte_carlo(1.0, Uniform(), n=1 << 14, seed=3)
    assert one.value.sides == mc.value.sides[0, 1]  # same seed, same tosses
    big = E.monte_carlo(np.linspace(0.05, 3, 40), Uniform(), n=1 << 14, seed=3)  # sorted path
    assert big.value.sides[-1] == pytest.approx(
        E.monte_carlo(3.0, Uniform(), n=1 << 14, seed=3).value.sides, abs=0)


def test_toss_outcomes_are_table_i_in_the_vigorous_limit():
    rng = np.random.default_rng(9)
    psi = rng.uniform(0, math.pi, 4000)
    phase = rng.uniform(0, 2 * math.pi, 4000)
    out = E.toss_outcomes(XI_FAIR, psi, phase)
    # a phase grid integrates the indicator: the frequencies tend to Table I for each psi
    grid = (np.arange(20000) + 0.5) * (2 * math.pi / 20000)
    for p in (0.3, 0.8, 1.2, math.pi / 2, 2.0):
        f = np.bincount(E.toss_outcomes(XI_FAIR, np.full(grid.size, p), grid), minlength=3)
        assert np.allclose(f / grid.size, models.conditional(XI_FAIR, p), atol=2e-4)
    assert set(np.unique(out)) <= {0, 1, 2}


@pytest.mark.parametrize("density", [
    Uniform(), Cosine(), Normal(), Normal(0.0, 1e-6), Normal(math.pi, 1e-6), Normal(1.0, 1e3),
    Normal(-0.5, 0.2), Normal(4.0, 0.3), Normal(math.pi / 6, 1e-6), TABLE])
def test_psi_sampling_is_the_exact_inverse_distribution(density):
    """F(F^-1(u)) = u to 1e-12 at 40 digits, u from 1e-12 to 1 - 1e-12: the sampled
    distribution is within 1e-12 of the density in Kolmogorov distance, which no feasible
    number of tosses could detect.  (In a normal's window that is tiny in sd units the
    difference Phi(a + h) - Phi(a) limits it to ~1e-13; elsewhere it is ~1e-16.)"""
    u = np.concatenate([np.geomspace(1e-12, 0.5, 40), 1 - np.geomspace(1e-12, 0.5, 40),
                        np.linspace(0.01, 0.99, 21)])
    psi = E.sample_psi(density, u)
    assert ((psi >= 0) & (psi <= math.pi)).all() and (np.diff(psi[:40]) >= 0).all()
    cdf = _mp_cdf(density)
    pdf = _mp_pdf(density)
    worst = 0.0
    with mpmath.workdps(40):
        for ui, p in zip(u.tolist(), psi.tolist(), strict=True):
            x = mpmath.mpf(p)
            # a double psi is a multiple of its ulp: a narrow density cannot be sampled finer
            grain = 2 * pdf(x) * math.ulp(p)
            worst = max(worst, float(abs(cdf(x) - ui) - grain))
    assert worst <= 1e-12, (density.spec, worst)


def _mp_pdf(d):
    if isinstance(d, Normal):
        mu, sd = mpmath.mpf(d.mean), mpmath.mpf(d.sd)
        z = _mp_norm_z(d)
        return lambda x: mpmath.npdf(x, mu, sd) / z
    return lambda x: mpmath.mpf(float(d.pdf(np.array([float(x)]))[0]))


def _mp_norm_z(d):
    mu, sd = mpmath.mpf(d.mean), mpmath.mpf(d.sd)
    pi = mpmath.mpf(math.pi)  # the density is normalized on [0, math.pi]
    a, b = -mu / sd, (pi - mu) / sd
    return mpmath.ncdf(-a) - mpmath.ncdf(-b) if a > 0 else mpmath.ncdf(b) - mpmath.ncdf(a)


def _mp_cdf(d):
    pi = mpmath.mpf(math.pi)
    if isinstance(d, Uniform):
        return lambda x: x / pi
    if isinstance(d, Cosine):
        return lambda x: (2 * x - mpmath.sin(2 * x)) / (2 * mpmath.pi)
    if isinstance(d, Normal):
        mu, sd = mpmath.mpf(d.mean), mpmath.mpf(d.sd)
        z = _mp_norm_z(d)
        a = -mu / sd
        if a > 0:
            return lambda x: (mpmath.ncdf(-a) - mpmath.ncdf(-(x - mu) / sd)) / z
        return lambda x: (mpmath.ncdf((x - mu) / sd) - mpmath.ncdf(a)) / z
    xs = [mpmath.mpf(float(v)) for v in d.psi]
    ws = [mpmath.mpf(float(v)) for v in d.w]
    cum = [mpmath.mpf(0)]
    for i in range(len(xs) - 1):
        cum.append(cum[-1] + (xs[i + 1] - xs[i]) * (ws[i] + ws[i + 1]) / 2)

    def cdf(x):
        i = max(j for j in range(len(xs) - 1) if xs[j] <= x) if x > xs[0] else 0
        dx = x - xs[i]
        slope = (ws[i + 1] - ws[i]) / (xs[i + 1] - xs[i])
        return (cum[i] + ws[i] * dx + slope * dx * dx / 2) / cum[-1]

    return cdf


# --------------------------------------------------------------------------- stress (hypothesis)


@st.composite
def _densities(draw):
    kind = draw(st.sampled_from(["normal", "normal", "normal", "uniform", "cosine", "table"]))
    if kind != "normal":
        return {"uniform": Uniform(), "cosine": Cosine(), "table": TABLE}[kind], None
    where = draw(st.sampled_from(["any", "zero", "pi", "boundary1", "boundary2"]))
    sd = 10 ** draw(st.floats(-6, 3))
    return where, sd


@settings(max_examples=40, deadline=None, derandomize=True,
          suppress_health_check=[HealthCheck.too_slow])
@given(spec=_densities(), lxi=st.floats(-3, 3), mean=st.floats(0, math.pi),
       seed=st.integers(0, 2**32))
def test_stress_three_estimators_agree_within_their_errors(spec, lxi, mean, seed):
    """sd from 1e-6 to 1e3 rad, means at 0 and pi, normals centred on a regime boundary."""
    xi = 10.0**lxi
    d, sd = spec
    if sd is not None:
        t = float(models.theta0(xi)) / 2
        centre = {"any": mean, "zero": 0.0, "pi": math.pi, "boundary1": t,
                  "boundary2": math.pi / 2 - t}[d]
        d = Normal(centre, sd)
    exact = marginal(xi, d)
    assert abs(sum(exact) - 1) <= 4e-16
    quad = E.quad(xi, d, tol=1e-6)
    for a, b in zip(quad.value, exact, strict=True):
        assert abs(a - b) <= quad.error[0] <= 1e-6
    _within(E.monte_carlo(xi, d, n=1 << 14, seed=seed), exact, 5.5)
    _within(E.quasi_monte_carlo(xi, d, n=1 << 13, seed=seed), exact, 9)


@settings(max_examples=30, deadline=None, derandomize=True)
@given(mean=st.floats(0.01, math.pi - 0.01), lxi=st.floats(-2, 2))
def test_stress_narrow_normal_converges_to_table_i(mean, lxi):
    xi = 10.0**lxi
    t = float(models.theta0(xi)) / 2
    edge = min(abs(mean - b) for b in (t, math.pi / 2 - t, math.pi / 2 + t, math.pi - t))
    cond = models.conditional(xi, mean)
    prev = None
    for sd in (1e-3, 1e-5, 1e-6):
        got = marginal(xi, Normal(mean, sd))
        err = max(abs(g - c) for g, c in zip(got, cond, strict=True))
        assert err <= (1.5 * math.sqrt(sd) if edge < 8 * sd else 2e-13 + 50 * sd * sd / edge)
        if prev is not None and prev > 1e-12:
            assert err <= prev  # closer as the normal narrows
        prev = err


# --------------------------------------------------------------------------- the chooser


def test_auto_picks_quadrature_with_the_fewest_nodes():
    for tol in (0.1, 1e-3, 1e-6, 1e-9, 1e-12):
        e = E.estimate(XI_FAIR, Normal(), tol=tol)
        assert e.method == "quad" and e.n == order_for_tol(tol) and e.met
        assert max(e.error) <= tol
        assert max(abs(a - b) for a, b in zip(e.value, marginal(XI_FAIR, Normal()),
                                              strict=True)) <= tol
    full = E.estimate(XI_FAIR, Normal())
    assert full.value == marginal(XI_FAIR, Normal()) and full.n == 16
    deep = E.estimate(XI_FAIR, Normal(), tol=1e-16)
    assert not deep.met  # below double precision: the best there is, and says so


@pytest.mark.parametrize("call, match", [
    (lambda: E.estimate(0.5, tol=0.0), r"tol must be a number in \[1e-16, 0.5\]"),
    (lambda: E.estimate(0.5, tol=0.7), r"tol must be a number in \[1e-16, 0.5\]"),
    (lambda: E.estimate(0.5, method="mcmc"), "method must be one of auto, quad, mc, qmc"),
    (lambda: E.estimate(0.5, method="quad", n=10), "n .samples. applies to method mc or qmc"),
    (lambda: E.monte_carlo(0.5, n=0), r"n must be an integer in \[1, 2\^40\]"),
    (lambda: E.monte_carlo(0.5, n=1.5), r"n must be an integer in \[1, 2\^40\]"),
    (lambda: E.monte_carlo(-1.0), r"xi must be >= 0"),
    (lambda: E.monte_carlo(0.5, "normal"), "density must be a coincli.core.densities.Density"),
    (lambda: E.monte_carlo(0.5, seed=-1), "seed must be a whole number >= 0"),
    (lambda: E.quasi_monte_carlo(0.5, seed=1.5), "seed must be a whole number >= 0"),
    (lambda: E.quasi_monte_carlo(0.5, scrambles=1), r"scrambles must be an integer in \[2, 1024\]"),
    (lambda: E.quasi_monte_carlo(0.5, phase="x"), "phase must be 'toss' or 'table1'"),
])
def test_bad_arguments_name_themselves(call, match):
    with pytest.raises(ValueError, match=match):
        call()


# --------------------------------------------------------------------------- command line


def test_table_tol_adds_error_columns_and_keeps_quiet(coin):
    code, out, err = coin("table", "--xi", "0.577", "--all", "--tol", "1e-9", "-f", "csv")
    assert code == 0 and err == ""
    rows = list(csv.DictReader(io.StringIO(out)))
    quad = [r for r in rows if r["method"].startswith("quad")]
    assert len(quad) == 3 and all(r["method"] == f"quad n={order_for_tol(1e-9)}" for r in quad)
    assert all(float(r["err_sides"]) <= 1e-9 for r in quad)
    code, out, _ = coin("table", "--xi", "0.577", "--psi-dist", "uniform", "--tol", "1e-9",
                        "-q")
    assert code == 0
    assert [float(v) for v in out.split()] == [models.geometric(0.577).sides,
                                               models.dynamic(0.577).sides,
                                               pytest.approx(marginal(0.577, Uniform()).sides,
                                                             abs=1e-9)]


def test_table_qmc_rows(coin):
    code, out, err = coin("table", "--xi", "0.3,0.577", "--psi-dist", "uniform", "--method",
                          "qmc", "--seed", "4", "-f", "json")
    assert code == 0 and err == ""
    import json

    rows = [r for r in json.loads(out) if r["model"] == "uniform"]
    assert [r["method"] for r in rows] == ["qmc 1048576 points"] * 2
    for r in rows:
        exact = marginal(r["xi"], Uniform())
        assert abs(r["p_sides"] - exact.sides) <= 2 * r["err_sides"] + 1e-6
    assert json.loads(out)[0]["err_sides"] is None  # closed forms: no error column value


def test_design_tol_sets_the_quadrature(coin):
    code, out, _ = coin("design", "-p", "1/3", "--psi-dist", "normal", "--tol", "1e-4", "-q")
    assert code == 0
    xi = float(out)
    assert marginal(xi, Normal()).sides == pytest.approx(1 / 3, abs=1e-4)


@pytest.mark.parametrize("argv, message", [
    (["table", "--xi", "0.5", "--tol", "1e-3"], "apply to psi-averaged chances"),
    (["table", "--xi", "0.5", "--psi-dist", "uniform", "--seed", "1"], "--seed goes with"),
    (["table", "--xi", "0.5", "--psi-dist", "uniform", "--method", "mc", "--seed", "-1"],
     "--seed must be a whole number"),
    (["table", "--xi", "0.5", "--psi-dist", "uniform", "--tol", "abc"], "--tol must be a number"),
    (["table", "--xi", "0.5", "--psi-dist", "uniform", "--tol", "1"], r"--tol must be in"),
    (["table", "--xi", "0.5", "--psi-dist", "uniform", "--method", "x"], "--method must be one"),
    (["design", "-p", "0.3", "--psi-dist", "uniform", "--method", "mc"], "cannot be inverted"),
    (["design", "-p", "0.3", "--tol", "1e-3"], "apply to psi-averaged chances"),
])
def test_option_errors_are_one_line_usage_errors(argv, message, coin):
    code, out, err = coin(*argv)
    assert code == 2 and out == "" and err.count("\n") == 1 and message in err


def test_no_progress_bar_off_a_terminal(coin, monkeypatch):
    """A long run with stderr not a terminal: no bar, nothing on stderr, clean stdout."""
    import coincli.render.progress as acc

    monkeypatch.setattr(acc, "stderr_is_terminal", lambda: False)
    code, out, err = coin("table", "--xi", "0.577", "--psi-dist", "uniform", "--method", "mc",
                          "--seed", "1", "--tol", "1e-3", "-f", "csv")
    assert code == 0 and err == "" and "\x1b" not in out


def test_the_run_budget_stops_quasi_monte_carlo_deterministically(coin, monkeypatch):
    # A --tol out of reach of qmc: the run stops at its budget of points (not on the clock),
    # warns, and the same seed gives the same bytes.
    import coincli.reports.accuracy as acc

    monkeypatch.setattr(acc, "RUN_BUDGET", 1 << 16)
    argv = ["table", "--xi", "0.577", "--psi-dist", "uniform", "--method", "qmc", "--seed", "1",
            "--tol", "1e-9", "-f", "csv"]
    code, out, err = coin(*argv)
    assert code == 0 and out.count("\n") == 4
    assert err.startswith("coin: warning: uniform: qmc reached") and "not --tol 1e-09" in err
    assert "--tol not met; it stopped at the run's limit of 65536 points" in err
    assert "qmc 65536 points" in out and out.splitlines()[0].endswith(",seed")
    assert out.splitlines()[-1].endswith(",1")
    assert coin(*argv)[1] == out


def test_monte_carlo_refuses_a_tol_beyond_the_run_limit_up_front(coin, monkeypatch):
    # The tosses a --tol needs follow from the chances: a --tol past the run's limit is a
    # one-line usage error before any toss, naming the smallest --tol that fits; that one runs
    # and meets it.
    import time

    import coincli.reports.accuracy as acc

    monkeypatch.setattr(acc, "RUN_BUDGET", 1 << 16)
    argv = ["table", "--xi", "0.577", "--psi-dist", "uniform", "--method", "mc", "--seed", "1",
            "-f", "csv", "--tol"]
    t0 = time.process_time()
    code, out, err = coin(*argv, "1e-5")
    assert time.process_time() - t0 < 5  # refused before simulating (2^16 tosses would not do)
    assert code == 2 and out == "" and err.count("\n") == 1
    assert err.startswith("coin: error: --tol 1e-05 needs about ")
    assert "over the run's limit of 65536 tosses" in err
    smallest = err.split("the smallest --tol that fits is ")[1].split()[0]
    assert 3e-3 < float(smallest) < 1e-2  # z sqrt(p (1 - p) / 2^16) with p(1 - p) near 1/4
    code, out, err = coin(*argv, smallest)
    assert code == 0 and err == "", err
    row = out.splitlines()[-1].split(",")
    assert int(row[5].split()[1]) <= 1 << 16
    assert max(float(v) for v in row[6:9]) <= float(smallest)
    # a tolerance a little below the smallest is refused (the figure is the limit, rounded up)
    code, _, err = coin(*argv, f"{float(smallest) * 0.97:.3g}")
    assert code == 2 and "the smallest --tol that fits is " + smallest in err


@pytest.mark.parametrize("spec, xi", [("uniform", 0.577), ("normal", 0.3), ("cosine", 2.0),
                                      ("normal:30:5", 0.05), ("uniform", 40.0)])
def test_the_planned_tosses_meet_the_tolerance(spec, xi):
    # the prediction is an upper bound: seeded runs stop by the planned tosses, having met tol
    from coincli.io.grammar import parse_density

    d = parse_density(spec)
    spread = E.chance_spread(E.quad(xi, d).value)
    for tol in (3e-3, 1e-3):
        need = E.mc_tosses_for_tol(spread, tol)
        for seed in range(4):
            r = E.monte_carlo(xi, d, tol=tol, seed=seed, max_samples=need)
            assert r.met, (spec, xi, tol, seed, r.n, need)
    # and it is not wasteful where it matters (tosses in the millions): within 3% of the
    # tosses a half-width of tol takes
    need = E.mc_tosses_for_tol(spread, 1e-4)
    assert spread < 0.01 or E.wilson_half_width(spread, int(need / 1.03)) > 1e-4


def test_smallest_tol_is_the_limit():
    # the figure, rounded up to two digits, fits; one unit of its second digit less does not
    for spreads, budget in (([0.25], 1 << 26), ([0.25, 0.1, 0.2], 1 << 26), ([1e-9], 1 << 20),
                            ([0.0], 1 << 20), ([0.01, 1e-5], 1 << 16)):
        t = E.mc_smallest_tol(spreads, budget)
        assert float(f"{t:.2g}") == t
        assert sum(E.mc_tosses_for_tol(s, t) for s in spreads) <= budget
        less = t - 10.0 ** (math.floor(math.log10(t)) - 1)
        assert sum(E.mc_tosses_for_tol(s, less) for s in spreads) > budget, (spreads, t)
    assert E.mc_smallest_tol([0.25], 1) == 0.5


def test_the_budget_is_one_per_run_shared_by_the_densities(coin, monkeypatch):
    import coincli.reports.accuracy as acc

    monkeypatch.setattr(acc, "RUN_BUDGET", 1 << 16)
    code, out, err = coin("table", "--xi", "0.577", "--all", "--method", "qmc", "--seed",
                          "2", "--tol", "1e-9", "-f", "csv")
    assert code == 0 and err.count("coin: warning:") == 3
    assert "limit of 65536 points, shared by 3 densities" in err
    used = [int(line.split(",")[5].split()[1]) for line in out.splitlines()[3:]]
    assert len(used) == 3 and sum(used) <= 1 << 16, used
    argv = ["table", "--xi", "0.577", "--all", "--method", "mc", "--seed", "2", "-f", "csv",
            "--tol"]
    code, out, err = coin(*argv, "1e-3")
    assert code == 2 and "over the run's limit of 65536 tosses shared by 3 densities" in err
    smallest = err.split("the smallest --tol that fits is ")[1].split()[0]
    code, out, err = coin(*argv, smallest)
    assert code == 0 and err == ""
    rows = [line.split(",") for line in out.splitlines()[3:]]
    assert sum(int(r[5].split()[1]) for r in rows) <= 1 << 16
    assert max(float(v) for r in rows for v in r[6:9]) <= float(smallest)
    budget = acc.Budget(3, total=90)
    assert budget.share() == 30
    budget.used(10)  # the first met its tolerance early: the others share the rest
    assert budget.share() == 40
    budget.used(40)
    assert budget.share() == 40
    budget = acc.Budget(3, total=90)
    budget.plan([20, 30, 25])  # planned: each may use all but what the later ones need
    assert budget.share() == 35
    budget.used(22)
    assert budget.share() == 43
    budget.used(30)
    assert budget.share() == 38