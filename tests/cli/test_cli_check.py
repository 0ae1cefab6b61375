"""End-to-end checks of `coin check` and `coin fit`: values against the core, every way of naming
the coin, formats, one-line errors with exit 2, extreme data, the import budget."""

from __future__ import annotations

import csv
import io
import json
import math
import subprocess
import sys
from pathlib import Path

import pytest

from coincli.core import coins
from coincli.core.models import dynamic, geometric
from coincli.core.stats import counts as stats_counts
from coincli.core.stats import fit as stats_fit
from coincli.core.stats import intervals as stats_intervals
from coincli.core.stats import tests as stats
from coincli.io import experiments

DATA = Path(__file__).resolve().parents[1] / "data"
TOSSES = DATA / "tosses.csv"


def _csv(out):
    return list(csv.DictReader(io.StringIO(out)))


def _f(text):
    return float(text) if text != "" else None


# --------------------------------------------------------------------------- check


def test_check_csv_is_the_core(coin):
    code, out, err = coin("check", "--xi", "0.583", "--heads", "35", "--sides", "33",
                          "--tails", "32", "--format", "csv")
    assert code == 0 and err == ""
    rows = _csv(out)
    ref = stats.check(stats_counts.make_counts(35, 33, 32), 0.583)
    assert [r["model"] for r in rows] == ["geometric", "dynamic"]
    for r, t in zip(rows, ref.tests, strict=True):
        assert r["scope"] == "experiment" and r["line"] == "" and int(r["n"]) == 100
        assert float(r["p_value"]) == t.p_value
        assert float(r["log_likelihood"]) == t.log_likelihood
        assert tuple(float(r[f"expected_{k}"]) for k in ("heads", "sides", "tails")) == \
            t.expected
        assert r["verdict"] == t.verdict and r["test"] == "exact multinomial"
        assert r["exact"] == "true"
        for p in ref.proportions:
            assert float(r[f"freq_{p.outcome}"]) == p.estimate
            assert float(r[f"{p.outcome}_wilson_low"]) == p.wilson.low
            assert float(r[f"{p.outcome}_cp_high"]) == p.clopper_pearson.high
    assert float(rows[1]["p_sides"]) == dynamic(0.583).sides
    assert float(rows[0]["p_heads"]) == geometric(0.583).heads
    assert rows[1]["verdict"].startswith("consistent at the 5% level")
    assert rows[0]["verdict"].startswith("rejected, p = ")


@pytest.mark.parametrize("coin_args, xi", [
    (["--quarters", "8"], coins.stack_xi(coins.get_coin("quarter"), 8)),
    (["--coin", "nickel", "--count", "3"], coins.stack_xi(coins.get_coin("nickel"), 3)),
    (["--diameter", "24mm", "--thickness", "1.4cm"], 14 / 24),
    (["-x", "0.5"], 0.5),
])
def test_check_coin_forms(coin, coin_args, xi):
    code, out, err = coin("check", *coin_args, "--sides", "33", "-n", "100", "-f", "csv")
    assert code == 0, err
    rows = _csv(out)
    assert float(rows[0]["xi"]) == pytest.approx(xi, rel=1e-15)
    assert rows[0]["test"] == "exact binomial"
    assert rows[0]["heads"] == rows[0]["tails"] == rows[0]["freq_heads"] == ""
    assert float(rows[1]["p_value"]) == pytest.approx(
        stats.exact_pvalue([33, 67], [dynamic(xi).sides, 1 - dynamic(xi).sides]), rel=1e-12)


def test_check_psi_dist_and_json(coin):
    from coincli.core.averages import marginal
    from coincli.core.densities import Normal, Uniform

    code, out, _ = coin("check", "--xi", "0.58", "--heads", "45", "--sides", "35", "--tails",
                        "20", "--psi-dist", "uniform,normal:90:20", "--format", "json")
    assert code == 0
    rows = json.loads(out)
    assert [r["model"] for r in rows] == ["geometric", "dynamic", "uniform", "normal:90:20"]
    assert rows[2]["p_sides"] == marginal(0.58, Uniform()).sides
    assert rows[3]["p_heads"] == marginal(0.58, Normal(math.pi / 2, math.radians(20))).heads
    assert all(0 <= r["p_value"] <= 1 for r in rows)


def test_check_quiet_prints_p_values(coin):
    code, out, _ = coin("check", "--xi", "0.583", "--heads", "35", "--sides", "33", "--tails",
                        "32", "-q")
    ref = stats.check(stats_counts.make_counts(35, 33, 32), 0.583)
    assert code == 0 and [float(v) for v in out.split()] == [t.p_value for t in ref.tests]


def test_check_human_table(coin):
    code, out, _ = coin("check", "--quarters", "8", "--heads", "35", "--sides", "33",
                        "--tails", "32")
    assert code == 0
    assert out.startswith("coin check: quarter x8 (xi = 0.577")
    assert "95% Wilson" in out and "95% Clopper-Pearson" in out
    assert "consistent at the 5% level" in out and "exact multinomial" in out


def test_check_levels(coin):
    code, out, _ = coin("check", "--xi", "0.583", "--heads", "35", "--sides", "33", "--tails",
                        "32", "--alpha", "0.001", "--confidence", "99%", "-f", "csv")
    rows = _csv(out)
    assert rows[0]["verdict"] == "consistent at the 0.1% level (p = 0.0017)"
    assert float(rows[0]["sides_cp_low"]) == stats_intervals.proportion(33, 100, confidence=0.99
                                                              ).clopper_pearson.low


@pytest.mark.parametrize("counts, words", [
    (["--heads", "-1", "--sides", "3", "--tails", "2"], "--heads must be a whole number >= 0"),
    (["--heads", "1", "--sides", "3.5", "--tails", "2"], "--sides must be a whole number >= 0"),
    (["--heads", "1", "--sides", "x", "--tails", "2"], "--sides must be a whole number"),
    (["--heads", "0", "--sides", "0", "--tails", "0"], "all zero"),
    (["--sides", "0", "-n", "0"], "-n must be a whole number from 1 to 9007199254740992, "
                                  "got '0'"),  # as every command says it (issue 28)
    (["--heads", "35", "--sides", "33", "--tails", "32", "-n", "99"], "= 100 but n = 99"),
    (["--sides", "101", "-n", "100"], "exceeds n = 100"),
    (["--sides", "3"], "give n"),
    (["--heads", "3", "--tails", "3"], "sides is required"),
])
def test_check_bad_counts_are_one_line_exit_2(coin, counts, words):
    code, out, err = coin("check", "--xi", "0.5", *counts)
    assert code == 2 and out == ""
    assert err.startswith("coin: error: ") and err.count("\n") == 1 and words in err


@pytest.mark.parametrize("argv, words", [
    (["check", "--sides", "3", "-n", "9"], "give a coin: --xi X"),
    (["check", "--xi", "0.5", "--quarters", "2", "--sides", "3", "-n", "9"],
     "--xi and --quarters both give the coin"),
    (["check", "--xi", "-1", "--sides", "3", "-n", "9"], "--xi must be a finite number >= 0"),
    (["check", "--xi", "inf", "--sides", "3", "-n", "9"], "--xi"),
    (["check", "--count", "2", "--sides", "3", "-n", "9"], "--count N needs the coin to stack"),
    (["check", "--coin", "nikel", "--count", "2", "--sides", "3", "-n", "9"], "nickel"),
    (["check", "--diameter", "24", "--sides", "3", "-n", "9"], "--diameter D needs --thickness"),
    (["check", "--xi", "0.5", "--sides", "3", "-n", "9", "--alpha", "0"], "--alpha"),
    (["check", "--xi", "0.5", "--sides", "3", "-n", "9", "--psi-dist", "nope"], "--psi-dist"),
    (["check", "--xi", "0.5", "--sides", "3", "-n", "9", "-f", "xml"], "--format"),
])
def test_check_usage_errors(coin, argv, words):
    code, out, err = coin(*argv)
    assert code == 2 and out == ""
    assert err.count("\n") == 1 and words in err


@pytest.mark.parametrize("counts", [
    ["--heads", "500000", "--sides", "0", "--tails", "500000"],
    ["--heads", "0", "--sides", "1000000", "--tails", "0"],
    ["--sides", "0", "-n", "1000000"],
    ["--sides", "1000000", "-n", "1000000"],
])
@pytest.mark.parametrize("xi", ["1e-6", "0.583", "1e6"])
def test_check_extreme_data(coin, counts, xi):
    code, out, err = coin("check", "--xi", xi, *counts, "-f", "csv")
    assert code == 0, err
    assert "nan" not in out.lower()
    for r in _csv(out):
        assert 0.0 <= float(r["p_value"]) <= 1.0
        assert math.isfinite(float(r["log_likelihood"]))
        for k in ("sides_wilson_low", "sides_wilson_high", "sides_cp_low", "sides_cp_high"):
            assert 0.0 <= float(r[k]) <= 1.0


# --------------------------------------------------------------------------- fit


def test_fit_csv_is_the_core(coin):
    code, out, err = coin("fit", str(TOSSES), "--format", "csv")
    assert code == 0 and err == ""
    rows = _csv(out)
    exps = experiments.parse_experiments(TOSSES.read_text())
    ref = stats_fit.fit(exps)
    per_row = [r for r in rows if r["scope"] == "experiment"]
    models = [r for r in rows if r["scope"] == "model"]
    assert len(per_row) == 3 * len(exps)
    assert [r["model"] for r in models] == ["geometric", "dynamic", "psi-spread"]
    assert [int(r["line"]) for r in per_row[::3]] == [e.line for e in exps]
    for r, m in zip(models, ref.models, strict=True):
        assert float(r["aic"]) == m.aic and float(r["sse_sides"]) == m.sse_sides
        assert float(r["log_likelihood"]) == m.log_likelihood
        assert int(r["n_params"]) == m.n_params and float(r["delta_aic"]) == m.delta_aic
    spread = models[2]
    assert float(spread["sigma_deg"]) == math.degrees(ref.spread.sigma)
    assert float(spread["sigma_low_deg"]) < 18 < float(spread["sigma_high_deg"])  # the truth
    side_only = [r for r in per_row if r["label"] == "2-coin"]
    assert side_only[0]["test"] == "exact binomial" and side_only[0]["heads"] == ""


def test_fit_human_tables_and_quiet(coin):
    code, out, _ = coin("fit", str(TOSSES))
    assert code == 0
    assert "model comparison, all experiments" in out
    assert "profile-likelihood interval" in out and "SSE" in out
    code, out, _ = coin("fit", str(TOSSES), "-q")
    ref = stats_fit.fit(experiments.parse_experiments(TOSSES.read_text()))
    assert float(out) == math.degrees(ref.spread.sigma)


def test_fit_from_stdin_json_and_densities(coin):
    code, out, _ = coin("fit", "-", "--psi-dist", "uniform", "--no-spread", "-f", "json",
                        stdin=TOSSES.read_text())
    assert code == 0
    rows = json.loads(out)
    assert [r["model"] for r in rows if r["scope"] == "model"] == ["geometric", "dynamic",
                                                                    "uniform"]


@pytest.mark.parametrize("text, words", [
    ("xi,heads,sides,tails\n0.5,1,2,3\n0.5,1,-2,3\n", "line 3, column 'sides'"),
    ("xi,heads,sides,tails\n0.5,1,2,3\n0.5,1,2.5,3\n", "line 3, column 'sides'"),
    ("xi,heads,sides,tails\n0.5,0,0,0\n", "line 2, column 'n': heads, sides and tails are all"),
    ("xi,heads,sides,tails,n\n0.5,1,2,3,7\n", "line 2, column 'n'"),
    ("xi,sides,n\n0.5,11,10\n", "line 2, column 'sides'"),
    ("xi,hedas,sides,tails\n", "line 1, column 'hedas': unknown column"),
    ("coin,count,sides,n\nquater,2,1,10\n", "line 2, column 'coin'"),
    ("# only a comment\n", "line 1: the file is empty"),
])
def test_fit_malformed_rows(coin, tmp_path, text, words):
    path = tmp_path / "tosses.csv"
    path.write_text(text)
    for fmt in ("table", "csv", "json"):
        code, out, err = coin("fit", str(path), "-f", fmt)
        assert code == 2 and out == ""
        assert err == f"coin: error: {path} {err.split(str(path) + ' ', 1)[1]}"
        assert err.count("\n") == 1 and words in err


def test_fit_file_errors(coin, tmp_path):
    code, out, err = coin("fit", str(tmp_path / "missing.csv"))
    assert code == 2 and out == "" and "cannot read" in err
    p = tmp_path / "bin.csv"
    p.write_bytes(b"xi,sides,n\n\xff\xfe\n")
    code, out, err = coin("fit", str(p))
    assert code == 2 and "not UTF-8" in err
    code, out, err = coin("fit", str(TOSSES), "-q", "--no-spread")
    assert code == 2 and "--no-spread" in err


# --------------------------------------------------------------------------- import budget


def test_importing_the_commands_loads_no_numpy_scipy_rich():
    probe = (
        "import sys\nimport coincli.cli.check\nimport coincli.core.stats.tests\n"
        "import coincli.core.stats.fit\nimport coincli.io.experiments\n"
        "from coincli.cli import run\n"
        "assert run(['check', '--sides', '3', '-n', '9']) == 2\n"
        "assert run(['fit', 'no-such-file.csv']) == 2\n"
        "print('LOADED', sorted(m for m in ('numpy','scipy','rich') if m in sys.modules))\n"
    )
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True,
                         timeout=60)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip().splitlines()[-1] == "LOADED []"


def test_check_takes_xi_0_as_the_other_coin_commands_do(coin):
    """A coin of no thickness: never a side.  Counts with no side are certain under both models
    (p = 1); one side is impossible (p = 0, log-likelihood -inf, 'impossible' verdict)."""
    rc, out, err = coin("check", "--xi", "0", "--heads", "5", "--sides", "0", "--tails", "5", "-q")
    assert (rc, err) == (0, "") and [float(v) for v in out.split()] == [1.0, 1.0]
    rc, out, err = coin("check", "--xi", "0", "--heads", "5", "--sides", "1", "--tails", "5",
                        "-q")
    assert (rc, err) == (0, "") and [float(v) for v in out.split()] == [0.0, 0.0]
