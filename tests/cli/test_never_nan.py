"""One rule for the empty results of the bouncing commands (issue 28, item 3).

When no toss settles, what only settled tosses give (a frequency, a time to settle, a final
tilt) is an empty cell in every format ('-' in a table and markdown, nothing in csv, tsv and
``-q``, null in json), never NaN; a note on stderr, after the output, says how many tosses did
not settle and why; and a design, whose answer is a fit, says so as one error line (exit 1).
Inputs that cannot settle by construction are refused before any simulation, by every command.
Each case costs a few tosses (about 2 s of CPU in all, with MuJoCo's calibration).
"""

from __future__ import annotations

import csv
import io
import json
import math

import pytest
from cli_helpers import error, ok

pytest.importorskip("mujoco")

#: sliding at 100 m/s on wood, no toss stops within --t-max 3 s
NONE_SETTLE = ["simulate", "--landing", "bounce", "-n", "2", "--seed", "1", "--xi", "0.577",
               "-j", "1", "--vx", "100", "--t-max", "3"]
#: a slow toss given 0.1 s: it lands at 0.033 s and is still bouncing at 0.1 s
TOSS = ["toss", "--landing", "bounce", "--xi", "0.577", "--psi", "90", "--u", "0.04",
        "--omega", "40", "--t-max", "0.1"]
FORMATS = ["table", "csv", "tsv", "markdown", "json", "jsonl"]


def _no_nan(out: str) -> None:
    assert "nan" not in out.lower(), out


def _rows(out: str, fmt: str) -> list[dict]:
    if fmt in ("csv", "tsv"):
        return list(csv.DictReader(io.StringIO(out), delimiter="," if fmt == "csv" else "\t"))
    if fmt == "json":
        return json.loads(out)
    return [json.loads(line) for line in out.splitlines()]


@pytest.mark.parametrize("fmt", FORMATS + ["quiet"])
def test_simulate_with_no_settled_toss_has_empty_cells_and_a_note(coin, fmt):
    args = ["-q"] if fmt == "quiet" else ["-f", fmt]
    rc, out, err = coin(*NONE_SETTLE, *args)
    assert rc == 0
    _no_nan(out)
    assert err == ("coin: note: 2 of 2 tosses did not settle (2 still moving at --t-max 3 s): "
                   "no frequency can be given (empty cells); raise --t-max, or land more gently "
                   "(a lower --u, --vx, --release-height or --restitution)\n")
    if fmt == "quiet":  # the three frequencies: three empty lines
        assert out == "\n\n\n"
    elif fmt in ("table", "markdown"):
        heads = next(line for line in out.splitlines() if "heads" in line)
        assert heads.replace("|", " ").split()[1:5] == ["0", "-", "-", "-"]
        assert "no toss settled" in out and "mean time to settle" not in out.split("\n\n")[-1]
    else:
        rows = _rows(out, fmt)
        empty = "" if fmt in ("csv", "tsv") else None
        for r in rows[:3]:
            assert [r["frequency"], r["ci_low"], r["ci_high"], r["mean_t_settle"]] == [empty] * 4
        assert rows[3]["outcome"] == "unsettled" and float(rows[3]["frequency"]) == 1.0


@pytest.mark.parametrize("fmt", FORMATS + ["quiet"])
def test_toss_that_does_not_settle_has_empty_cells_and_a_note(coin, fmt):
    args = ["-q"] if fmt == "quiet" else ["-f", fmt]
    rc, out, err = coin(*TOSS, *args)
    assert rc == 0
    _no_nan(out)
    assert err == ("coin: note: the toss did not settle (still moving at --t-max 0.1 s): its "
                   "time to settle and final tilt are empty; raise --t-max, or land more gently "
                   "(a lower --u, --vx, --release-height or --restitution)\n")
    if fmt == "quiet":
        assert out == "unsettled\n"
    elif fmt in ("table", "markdown"):
        cells = {line.replace("|", " ").rsplit(None, 1)[0].strip():
                 line.replace("|", " ").split()[-1] for line in out.splitlines()
                 if line.replace("|", " ").strip().startswith(("settled at", "final tilt"))}
        assert cells == {"settled at (s)": "-", "final tilt (deg)": "-"}
    else:
        (row,) = _rows(out, fmt)
        empty = "" if fmt in ("csv", "tsv") else None
        assert (row["t_settle"], row["tilt_deg"], row["outcome"]) == (empty, empty, "unsettled")


def test_some_unsettled_tosses_are_noted_and_the_rest_counted(coin):
    """Part of a run settles: the frequencies are among the settled tosses, and the note says
    how many were left out (u = 2 m/s lands at 0.4 s, leaving 0.8 s of --t-max 1.2 to settle:
    some do, some are still rolling)."""
    rc, out, err = coin("simulate", "--landing", "bounce", "-n", "6", "--seed", "1", "--xi",
                        "0.577", "-j", "1", "--u", "2", "--t-max", "1.2", "-f", "csv")
    rows = _rows(out, "csv")
    unsettled = int(rows[3]["count"])
    assert rc == 0 and 0 < unsettled < 6, rows
    _no_nan(out)
    settled = 6 - unsettled
    assert [float(r["frequency"]) for r in rows[:3]] == [int(r["count"]) / settled
                                                         for r in rows[:3]]
    assert err.startswith(f"coin: note: {unsettled} of 6 tosses did not settle")
    assert "they are left out of the frequencies" in err


@pytest.mark.slow
def test_design_with_no_settled_toss_is_one_line(coin):
    """--diameter 10m: no toss of the sweep settles.  It used to say 'fitting P(sides) needs
    simulated tosses at two aspect ratios or more'; now it says that none settled, and why."""
    msg = error(coin("design", "-p", "1/3", "--landing", "bounce", "--diameter", "10m",
                     "--max-tosses", "180", "--seed", "1", "-j", "1"), 1,
                "no design: 180 of 180 tosses did not settle", "still moving at --t-max 10 s",
                "fitting P(sides) needs settled tosses at two aspect ratios or more")
    _no_nan(msg)


def test_plot_sides_leaves_out_aspect_ratios_with_no_settled_toss(coin, monkeypatch):
    """An aspect ratio where no toss settled is no point at all (it was a point at NaN), and
    the note says how many did not settle.  The tosses are counts from no engine (all settle
    below xi = 0.5, none above), the rule is the report's."""
    from coincli.core.bounce import runs
    from coincli.core.bounce.runs import BounceSimulation
    from coincli.core.toss.simulate import Frequency
    from coincli.reports import bounce as bounce_report
    from coincli.reports.physics import bounce_physics

    def simulate(n, seed, *, xi, **kw):
        k = n if xi < 0.5 else 0  # settled
        s = k // 2
        f = [Frequency(name, c, c / k if k else math.nan, 0.0, 1.0)
             for name, c in (("heads", k - s), ("sides", s), ("tails", 0))]
        return BounceSimulation(n=n, counts=(k - s, s, 0, n - k), frequencies=f,
                                catch_counts=(n, 0, 0), agree=0, mean_bounces=0.0,
                                mean_t_settle=math.nan, steps=0, seed=seed, landing="bounce",
                                surface=None, damping=0.0, dt=1e-4)

    monkeypatch.setattr(runs, "simulate", simulate)
    p = bounce_physics(jobs="1")
    pts, fitted, why = bounce_report.sides_points(p, seed=1, n=4, xis=[0.1, 0.2, 0.4, 0.8, 1.6],
                                                  u=2.0, omega=40.0, psi=1.0, diameter=0.02426,
                                                  g=9.81)
    assert [e.xi for e in pts] == [0.1, 0.2, 0.4] and all(e.n == 4 for e in pts)
    assert all(math.isfinite(e.frequency) for e in pts)
    assert "8 of 20 tosses did not settle (8 still moving at --t-max 10 s)" in why
    rc, out, err = coin("plot", "sides", "--landing", "bounce", "-n", "4", "--seed", "1",
                        "-j", "1", "--terminal")
    assert rc == 0
    _no_nan(out + err)
    assert "tosses did not settle" in err


@pytest.mark.parametrize("argv, words", [
    # the flight alone (launch height and speed) takes more than half of --t-max
    (["simulate", "-n", "2", "--xi", "0.577", "--t-max", "0.01"],
     ["--t-max must be at least 0.0534 s"]),
    (["simulate", "-n", "2", "--xi", "0.577", "--u", "49"], ["--u must be at most 24.5 m/s"]),
    (["toss", "--xi", "0.577", "--psi", "90", "--omega", "40", "--u", "49"],
     ["--u must be at most 24.5 m/s"]),
    (["design", "-p", "1/3", "--u", "49"], ["--u must be at most 24.5 m/s"]),
    (["simulate", "-n", "2", "--xi", "0.577", "--release-height", "100m"],
     ["--release-height must be at most 9.562e+04 mm", "got '100m'"]),
    (["toss", "--xi", "0.577", "--psi", "90", "--omega", "40", "--u", "2", "--t-max", "0.06"],
     ["--u must be at most 0.0305 m/s", "--t-max 0.06 s"]),
])
def test_inputs_that_cannot_settle_are_refused_before_any_simulation(coin, argv, words):
    error(coin(*argv, "--landing", "bounce"), 2, *words, "within half of --t-max")
