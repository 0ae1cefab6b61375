"""Caught flips (faces only, issue 27): the chance of the same side against mpmath (DHM's closed
form at xi -> 0, Table I integrated at xi 0.01 to 0.3), each row's fitted spread against an
independent optimizer (scipy.optimize), the coverage of its interval on synthetic tossers, the
file forms and the one-line errors.  About 6 s of one core."""

from __future__ import annotations

import io
import math
import sys
from pathlib import Path

import mpmath as mp
import numpy as np
import pytest

from coincli.cli import run
from coincli.core.stats import caught as cs
from coincli.core.stats.counts import Caught, CountsError, make_caught
from coincli.io.experiments import parse_experiments

DATA = Path(__file__).resolve().parents[1] / "data"


def _mp_same(xi, sigma, dps=30):
    """q = int P_H w / int (P_H + P_T) w over psi in [0, pi/2] (the problem is symmetric about
    pi/2), Table I in mpmath, w the normal density about pi/2 (its normalizer cancels)."""
    with mp.workdps(dps):
        xi = mp.mpf(xi)
        th0 = mp.atan2(1, xi)
        b1, b2 = mp.pi / 2 - th0 / 2, th0 / 2  # regime 3 above b1; regime 2 in [b2, b1)

        def w(psi):
            return mp.exp(-((psi - mp.pi / 2) ** 2) / (2 * mp.mpf(sigma) ** 2))

        def th(sign, psi):
            a, b = mp.cos(psi) ** 2, mp.sin(psi) ** 2
            return mp.acos(max(-1, min(1, (sign * mp.cos(th0) - a) / b)))

        def heads(psi):
            return 1 if psi < b2 else th(1, psi) / mp.pi

        def tails(psi):
            return 1 - th(-1, psi) / mp.pi if psi >= b1 else 0

        pts = [0, b2, b1, mp.pi / 2]
        h = mp.quad(lambda p: heads(p) * w(p), pts)
        t = mp.quad(lambda p: tails(p) * w(p), pts)
        return h / (h + t)


def _mp_dhm(sigma, dps=30):
    """DHM at xi = 0: P(same | psi) = 1/2 + asin(cot^2 psi)/pi for psi in [pi/4, pi/2]."""
    with mp.workdps(dps):
        def w(psi):
            return mp.exp(-((psi - mp.pi / 2) ** 2) / (2 * mp.mpf(sigma) ** 2))

        num = mp.quad(lambda p: w(p), [0, mp.pi / 4]) + mp.quad(
            lambda p: (mp.mpf(1) / 2 + mp.asin(min(1, mp.cot(p) ** 2)) / mp.pi) * w(p),
            [mp.pi / 4, mp.pi / 2])
        den = mp.quad(w, [0, mp.pi / 2])
        return num / den


@pytest.mark.parametrize("sigma_deg", [2.0, 10.0, 30.0, 90.0])
def test_dhm_closed_form_at_xi_zero(sigma_deg):
    s = math.radians(sigma_deg)
    ref = float(_mp_dhm(s))
    assert abs(float(cs.same_chance(0.0, s)) - ref) <= 1e-12
    # the limit is approached: q moves by O(xi) off it
    assert 0 < abs(float(cs.same_chance(1e-6, s)) - ref) <= 1e-6


@pytest.mark.parametrize("xi", [0.01, 0.075, 0.15, 0.3])
@pytest.mark.parametrize("sigma_deg", [3.0, 15.0, 60.0])
def test_table_one_integrated(xi, sigma_deg):
    ref = float(_mp_same(xi, math.radians(sigma_deg)))
    assert abs(float(cs.same_chance(xi, math.radians(sigma_deg))) - ref) <= 2e-13


def test_ends_and_interpolant():
    xs = np.array([0.02, 0.075, 0.3])
    assert np.all(cs.same_chance(xs, 0.0) == 0.5)
    ch = cs.SameChance(xs)
    rng = np.random.default_rng(5)
    u = rng.random(40)
    k = rng.integers(0, 3, 40)
    direct = np.array([cs.same_chance(xs[i], v / (1 - v)) for i, v in zip(k, u, strict=True)])
    assert np.max(np.abs(ch.at(k, u) - direct)) < 1e-13
    # the inverse lands back on u
    assert np.max(np.abs(ch.invert(k, direct) - u)) < 1e-9
    # monotone in sigma (the fit relies on it)
    assert np.all(np.diff(ch._dense, axis=1) >= -1e-15)


def _critical(delta, conf=0.95):
    """Feldman-Cousins' critical value for a normal mean ``delta`` >= 0 from a bound at 0,
    written out again with scipy.stats and brentq: P(accept) = Phi(sqrt c) - Phi(-(delta^2 +
    c) / (2 delta)) below delta = sqrt(chi2_1), chi2_1(conf) above."""
    from scipy.optimize import brentq
    from scipy.stats import chi2, norm

    full = chi2.ppf(conf, 1)
    if delta >= math.sqrt(full):
        return full
    if delta == 0:
        return norm.ppf(conf) ** 2
    return brentq(lambda c: norm.cdf(math.sqrt(c)) - norm.cdf(-(delta**2 + c) / (2 * delta))
                  - conf, norm.ppf(conf) ** 2, full, xtol=1e-13)


def test_boundary_cut():
    ds = [0.0, 0.3, 1.0, 1.9, 1.96, 3.0]
    assert 2 * cs.boundary_cut(np.array(ds), 0.95) == pytest.approx(
        [_critical(d) for d in ds], rel=1e-10)


def _independent(xi, s, n, conf=0.95):
    """The maximum-likelihood sigma and the ends of its confidence interval by scipy.optimize
    on the log-likelihood in sigma itself (same_chance straight from marginal), the critical
    value :func:`_critical` at each sigma's distance from q = 1/2."""
    from scipy.optimize import brentq, minimize_scalar

    def q_of(sig):
        return float(cs.same_chance(xi, sig))

    def ll(sig):
        q = q_of(sig)
        return s * math.log(q) + (n - s) * math.log1p(-q)

    hi_sig = 3.0
    r = minimize_scalar(lambda v: -ll(v), bounds=(0.0, hi_sig), method="bounded",
                        options={"xatol": 1e-10})
    top = max(-r.fun, ll(0.0))
    best = r.x if -r.fun >= ll(0.0) else 0.0

    def g(sig):
        q = q_of(sig)
        delta = (q - 0.5) / math.sqrt(q * (1 - q) / n)
        return top - ll(sig) - _critical(delta, conf) / 2

    lo = 0.0 if g(0.0) <= 0 else brentq(g, 0.0, best, xtol=1e-12)
    hi = brentq(g, best, hi_sig, xtol=1e-12)
    return best, lo, hi


@pytest.mark.parametrize("sd_deg", [0.0, 5.0, 12.0, 30.0])
def test_fit_against_independent_optimizer(sd_deg):
    xi = 0.075
    q = float(cs.same_chance(xi, math.radians(sd_deg)))
    rng = np.random.default_rng(int(sd_deg * 10))
    n = np.array([4000, 20000])
    s = rng.binomial(n, q)
    f = cs.fit_rows([xi, xi], s, n)
    for j in range(2):
        best, lo, hi = _independent(xi, int(s[j]), int(n[j]))
        if f.at_bound[j] == -1:
            assert f.sigma[j] == 0 and best < 1e-4
        else:
            assert abs(f.sigma[j] - best) < 2e-6
        assert abs(f.low[j] - lo) < 2e-6
        assert abs(f.high[j] - hi) < 2e-6


def test_coverage_small():
    """400 synthetic tossers at sd 12 deg, and 400 at sd 0 (the bound): the 95% intervals cover
    the truth 92-98% of the time (a 99.8% binomial band around 95% for 400 trials); the full
    study is in benchmarks/bench_faces.py."""
    rng = np.random.default_rng(27)
    xi, sig = 0.08, math.radians(12)
    q = float(cs.same_chance(xi, sig))
    n = np.full(400, 5000)
    s = rng.binomial(n, q)
    f = cs.fit_rows(np.full(400, xi), s, n)
    cover = np.mean((f.low <= sig) & (sig <= f.high))
    assert 0.92 <= cover <= 0.98
    s0 = rng.binomial(n, 0.5)
    f0 = cs.fit_rows(np.full(400, xi), s0, n)
    assert 0.92 <= np.mean(f0.low == 0) <= 0.98


def test_bounds_and_heterogeneity():
    f = cs.fit_rows([0.075] * 3, [40, 100, 60], [100, 100, 100])
    assert f.at_bound.tolist() == [-1, 1, 0]
    assert f.sigma[0] == 0 and math.isinf(f.sigma[1]) and math.isinf(f.high[1])
    # identical tossers: no heterogeneity; very different ones: clear
    same = cs.heterogeneity([0.075] * 4, [5100] * 4, [10000] * 4,
                            cs.fit_rows([0.075] * 4, [5100] * 4, [10000] * 4))
    assert same.statistic < 1e-6 and same.p_value > 0.99 and same.tau == 0.0
    s = [5000, 5000, 5400, 5400]
    diff = cs.heterogeneity([0.075] * 4, s, [10000] * 4, cs.fit_rows([0.075] * 4, s, [10000] * 4))
    assert diff.p_value < 1e-10 and diff.tau > 0.3


def test_file_forms_agree():
    text = ("label,xi,same,different,n,heads,tails,start,hsame,hdiff,tsame,tdiff\n"
            "a,0.07,51,49,,,,,,,,\n"
            "b,0.07,51,,100,,,,,,,\n"
            "c,0.07,,,,51,49,heads,,,,\n"
            "d,0.07,,,,49,51,tails,,,,\n"
            "e,0.07,,,,,,,30,20,21,29\n")
    rows = parse_experiments(text)
    assert {r.counts for r in rows} == {Caught(100, 51, 49)}
    with pytest.raises(CountsError, match="same \\+ different = 100 but n = 99"):
        make_caught(51, 49, 99)


@pytest.mark.parametrize("argv, words", [
    (["check", "--xi", "0.07", "--same", "-1", "--different", "3"], "--same must be a whole"),
    (["check", "--xi", "0.07", "--same", "1.5", "--different", "3"], "--same must be a whole"),
    (["check", "--xi", "0.07", "--same", "5", "--different", "3", "-n", "9"],
     "--same + --different = 8 but -n = 9"),
    (["check", "--xi", "0.07", "--same", "5", "--sides", "3"], "cannot go with"),
])
def test_one_line_errors(argv, words, capsys):
    assert run(argv) == 2
    out, err = capsys.readouterr()
    assert out == "" and err.count("\n") == 1 and words in err


def test_thick_warning_and_check(capsys):
    assert run(["check", "--xi", "0.4", "--same", "60", "--different", "40", "-q"]) == 0
    out, err = capsys.readouterr()
    assert err.startswith("coin: warning: xi = 0.4 is above 0.3") and err.count("\n") == 1
    # the exact binomial p-value of 60 of 100 against 1/2, for both models
    from scipy.stats import binomtest

    p = binomtest(60, 100, 0.5).pvalue
    assert [float(v) for v in out.split()] == pytest.approx([p, p], rel=1e-12)


def test_fit_mixed_file(tmp_path, capsys, monkeypatch):
    path = tmp_path / "mixed.csv"
    path.write_text("label,xi,heads,sides,tails,same,different\n"
                    "stack,0.5,30,40,30,,\n"
                    "alice,0.075,,,,5200,4800\n"
                    "bob,0.075,,,,4990,5010\n")
    from coincli import api

    rows = api.fit(str(path), design="1/3")
    spread = [r for r in rows if r["scope"] == "experiment" and r["model"] == "psi-spread"]
    own = cs.fit_rows([0.075, 0.075], [5200, 4990], [10000, 10000])
    assert spread[1]["sigma_deg"] == pytest.approx(math.degrees(own.sigma[0]), rel=1e-12)
    assert spread[2]["sigma_deg"] == 0 and "bound sigma = 0" in spread[2]["sigma_note"]
    assert spread[0]["same"] is None and spread[1]["sides"] is None
    assert spread[1]["design_xi"] == pytest.approx(float(cs.fair_xi([own.sigma[0]])[0]))
    het = [r for r in rows if r["scope"] == "all"]
    assert len(het) == 1 and het[0]["heterogeneity_df"] == 1
    # the JSON rows are the CLI's
    monkeypatch.setattr(sys, "stdin", io.TextIOWrapper(io.BytesIO(b"")))
    assert run(["fit", str(path), "--design", "1/3", "--format", "json"]) == 0
    import json

    assert json.loads(capsys.readouterr().out) == rows


def test_synthetic_file_is_reproducible():
    """tests/data/caught.csv is what make_caught.py writes."""
    import subprocess

    out = subprocess.run([sys.executable, str(DATA / "make_caught.py")], capture_output=True,
                         text=True, check=True,
                         env={**__import__("os").environ,
                              "PYTHONPATH": str(DATA.parents[1])}).stdout
    assert out == (DATA / "caught.csv").read_text()


@pytest.mark.parametrize("text, words", [
    ("xi,same,different\n0.07,-5,3\n", "line 2, column 'same': same must be a whole number"),
    ("xi,same,different\n0.07,5.5,3\n", "line 2, column 'same': same must be a whole number"),
    ("xi,same,different,n\n0.07,5,3,9\n", "line 2, column 'n': same + different = 8 but n = 9"),
    ("xi,same,different,sides\n0.07,5,3,1\n", "column 'sides': a row of caught flips"),
    ("xi,heads,tails,start\n0.07,5,3,up\n", "start must be heads or tails, got 'up'"),
    ("xi,hsame,hdiff,tsame\n0.07,5,3,1\n", "column 'tdiff': hsame, hdiff, tsame and tdiff"),
])
def test_file_errors(text, words):
    with pytest.raises(ValueError, match=None) as info:
        parse_experiments(text)
    assert words in str(info.value) and "\n" not in str(info.value)


def test_plot_data_refuses_caught_rows(capsys):
    assert run(["plot", "sides", "--data", str(DATA / "caught.csv"), "--terminal"]) == 2
    out, err = capsys.readouterr()
    assert out == "" and "line 3 is caught flips" in err and err.count("\n") == 1
