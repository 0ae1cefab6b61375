"""``coin check --expect/--fair`` (stated chances) and ``coin check --landing bounce`` (a
simulated table): the exact multinomial p-value against an enumeration in exact rationals; the
table's row is the two-sample test of the user's counts and the counts ``coin simulate
--landing bounce`` makes with the same seed; the command line's json is ``coincli.api.check``;
bad input is one line."""

from __future__ import annotations

import json
from fractions import Fraction
from math import comb

import pytest

from coincli import api
from coincli.core.stats.homogeneity import homogeneity
from coincli.errors import InputError


def _json(coin, *argv):
    rc, out, err = coin("check", *argv, "--format", "json")
    assert rc == 0, err
    return json.loads(out)


def _exact_multinomial(x, p) -> float:
    """The exact test by enumeration of every (h, s, t) with h + s + t = n, in rationals:
    the total probability of the outcomes no more likely than the observed one."""
    n = sum(x)

    def prob(h, s, t):
        return Fraction(comb(n, h) * comb(n - h, s)) * p[0] ** h * p[1] ** s * p[2] ** t

    obs = prob(*x)
    return float(sum(q for h in range(n + 1) for s in range(n - h + 1)
                     if (q := prob(h, s, n - h - s)) <= obs * (1 + Fraction(1, 10**7))))


@pytest.mark.parametrize("argv, chances", [
    (["--fair"], (Fraction(1, 3),) * 3),
    (["--expect", "1/3,1/3,1/3"], (Fraction(1, 3),) * 3),
    (["--expect", "0.3,0.4,0.3"], (Fraction(3, 10), Fraction(4, 10), Fraction(3, 10))),
    (["--expect", "30%,40%,30%"], (Fraction(3, 10), Fraction(4, 10), Fraction(3, 10))),
    (["--expect", "0.25,0.5,0.25"], (Fraction(1, 4), Fraction(1, 2), Fraction(1, 4))),
])
@pytest.mark.parametrize("counts", [(45, 38, 37), (10, 30, 20), (0, 12, 3)])
def test_expect_is_the_exact_multinomial_test(coin, argv, chances, counts):
    h, s, t = counts
    rows = _json(coin, *argv, "--heads", h, "--sides", s, "--tails", t)
    assert [r["model"] for r in rows] == ["expected"]  # no coin: the stated chances only
    r = rows[0]
    assert (r["p_heads"], r["p_sides"], r["p_tails"]) == pytest.approx(
        [float(c) for c in chances], rel=1e-15)
    assert r["p_value"] == pytest.approx(_exact_multinomial(counts, chances), rel=1e-9)
    assert r["xi"] is None and r["test"] == "exact multinomial"


def test_expect_with_a_coin_adds_the_row_to_the_models(coin):
    rows = _json(coin, "--xi", "0.5", "--fair", "--heads", "45", "--sides", "38", "--tails",
                 "37")
    assert [r["model"] for r in rows] == ["geometric", "dynamic", "expected"]
    plain = _json(coin, "--xi", "0.5", "--heads", "45", "--sides", "38", "--tails", "37")
    assert rows[:2] == plain
    assert rows == api.check(xi=0.5, fair=True, heads=45, sides=38, tails=37)
    assert api.check(expect=[0.3, 0.4, 0.3], heads=45, sides=38, tails=37) == \
        _json(coin, "--expect", "0.3,0.4,0.3", "--heads", "45", "--sides", "38", "--tails", "37")


def test_fair_of_sides_and_n_is_the_binomial_of_a_third(coin):
    from scipy.stats import binomtest

    r = _json(coin, "--fair", "--sides", "38", "-n", "120")[0]
    assert r["test"] == "exact binomial"
    assert r["p_value"] == pytest.approx(binomtest(38, 120, 1 / 3).pvalue, rel=1e-9)


def test_fair_of_caught_flips_is_a_half_each_face(coin):
    from scipy.stats import binomtest

    r = _json(coin, "--fair", "--same", "5080", "--different", "4920")[0]
    assert r["p_value"] == pytest.approx(binomtest(5080, 10000, 0.5).pvalue, rel=1e-9)


@pytest.mark.parametrize("argv, words", [
    (["--expect", "0.3,0.3,0.3"], ["must add up to 1", "sum 0.9"]),
    (["--expect", "0.5,0.5"], ["three numbers", "'0.5,0.5'"]),
    (["--expect", "0.5,x,0.5"], ["--expect"]),
    (["--fair", "--expect", "0.3,0.4,0.3"], ["--fair is --expect 1/3,1/3,1/3"]),
    (["--landing", "bounce", "--xi", "0.5", "--same", "3", "--different", "4"],
     ["caught flips", "--landing bounce"]),
    (["--xi", "0.5", "--u", "2"], ["--u goes with --landing bounce"]),
    (["--xi", "0.5", "--surface", "wood"], ["--surface goes with --landing bounce"]),
    (["--heads", "1", "--sides", "2", "--tails", "3"], ["--xi"]),  # no coin, no expectation
])
def test_bad_input_is_one_line(coin, argv, words):
    rc, out, err = coin("check", *argv, *([] if "--heads" in argv or "--same" in argv else
                                         ["--heads", "1", "--sides", "2", "--tails", "3"]))
    assert rc == 2 and out == "" and err.count("\n") == 1 and err.startswith("coin: error: "), \
        (rc, out, err)
    for w in words:
        assert w in err, err


# --------------------------------------------------------------------------- --landing bounce


@pytest.fixture
def few_sims(monkeypatch):
    """Simulate 60 tosses for the table (the command's rule is 10x the user's, at least 4000)."""
    from coincli.reports import check as R

    monkeypatch.setattr(R, "SIM_TOSSES", (60, 1, 60))


def test_bounce_row_is_the_two_sample_test_against_simulate(coin, few_sims):
    argv = ["--landing", "bounce", "--xi", "0.5", "--surface", "felt", "--seed", "5", "--jobs",
            "1"]
    rows = _json(coin, *argv, "--heads", "15", "--sides", "25", "--tails", "10")
    assert [r["model"] for r in rows] == ["geometric", "dynamic", "bounce on felt"]
    rc, out, err = coin("simulate", "--landing", "bounce", "--xi", "0.5", "--surface", "felt",
                        "--seed", "5", "--jobs", "1", "-n", "60", "-f", "json")
    sim = {r["outcome"]: r["count"] for r in json.loads(out)}
    settled = sim["heads"] + sim["sides"] + sim["tails"]
    row = rows[2]
    assert row["p_sides"] == pytest.approx(sim["sides"] / settled, rel=1e-15)
    want = homogeneity((15, 25, 10), (sim["heads"], sim["sides"], sim["tails"]))
    assert want.exact and row["p_value"] == pytest.approx(want.p_value, rel=1e-12)
    assert row["test"].startswith("exact conditional (Freeman-Halton)")
    assert rows == api.check(landing="bounce", xi=0.5, surface="felt", seed=5, jobs=1,
                             heads=15, sides=25, tails=10)


def test_bounce_check_of_sides_and_n_tests_sides_against_faces(coin, few_sims):
    argv = ["--landing", "bounce", "--xi", "0.5", "--surface", "felt", "--seed", "5", "--jobs",
            "1", "--sides", "25", "-n", "50"]
    row = _json(coin, *argv)[-1]
    full = _json(coin, "--landing", "bounce", "--xi", "0.5", "--surface", "felt", "--seed", "5",
                 "--jobs", "1", "--heads", "15", "--sides", "25", "--tails", "10")[-1]
    s = round(full["p_sides"] * 60)  # every toss of felt settles at xi 0.5 (checked above)
    assert row["p_value"] == pytest.approx(homogeneity((25, 25), (s, 60 - s)).p_value, rel=1e-12)


def test_bounce_check_reports_a_drawn_seed_in_machine_formats(coin, few_sims):
    rc, out, err = coin("check", "--landing", "bounce", "--xi", "0.5", "--surface", "felt",
                        "--jobs", "1", "--heads", "1", "--sides", "2", "--tails", "3", "-q")
    assert rc == 0 and "coin: seed " in err and "--seed" in err


def test_api_check_bounce_error_is_the_cli_message(coin):
    rc, out, err = coin("check", "--xi", "0.5", "--u", "2", "--heads", "1", "--sides", "2",
                        "--tails", "3")
    with pytest.raises(InputError) as exc:
        api.check(xi=0.5, u=2, heads=1, sides=2, tails=3)
    assert err == f"coin: error: {exc.value}\n"
