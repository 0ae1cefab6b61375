"""The toss family from Python (:mod:`coincli.api`: toss, simulate, phase) is the command line's
``--format json``, row for row; a wrong input raises the command's message; the reports
(:mod:`coincli.reports.toss`, :mod:`coincli.reports.phase`, :mod:`coincli.reports.plot`) are
plain functions of the options as typed."""

from __future__ import annotations

import doctest
import json

import pytest

from coincli import api
from coincli.errors import InputError
from coincli.io.table import Result


def _cli_json(coin, *argv):
    rc, out, err = coin(*argv, "--format", "json")
    assert rc == 0, err
    return json.loads(out)


def _cli_error(coin, *argv) -> str:
    rc, out, err = coin(*argv, "--format", "json")
    assert rc == 2 and out == "" and err.startswith("coin: error: "), (rc, out, err)
    return err[len("coin: error: "):].rstrip("\n")


# --------------------------------------------------------------------------- coin toss

TOSSES = [
    (["--xi", "0.577", "--psi", "90", "--u", "2", "--omega", "40"],
     {"xi": "0.577", "psi": 90, "u": 2, "omega": 40}),
    (["--xi", "0.577", "--psi", "90", "--u", "2", "--omega", "38:40:1"],  # a range
     {"xi": 0.577, "psi": "90", "u": "2", "omega": "38:40:1"}),
    (["--xi", "0.5,0.6", "--psi", "80", "--u", "240cm/s", "--omega", "6rev/s"],  # a list, units
     {"xi": [0.5, 0.6], "psi": 80, "u": "240cm/s", "omega": "6rev/s"}),
    (["--coin", "quarter", "--seed", "3", "--u", "2"],  # drawn psi and omega: the seed
     {"coin": "quarter", "seed": 3, "u": 2}),
    (["--xi", "0.3", "--psi", "85", "--u", "2", "--omega", "40", "--contact", "thick", "--z0",
      "30", "--g", "9.7"],
     {"xi": 0.3, "psi": 85, "u": 2, "omega": 40, "contact": "thick", "z0": "30", "g": 9.7}),
]


@pytest.mark.parametrize("argv,kwargs", TOSSES)
def test_toss_is_the_cli_json(coin, argv, kwargs):
    assert api.toss(**kwargs) == _cli_json(coin, "toss", *argv)


def test_toss_error_is_the_cli_message(coin):
    message = _cli_error(coin, "toss", "--xi", "0.577", "--psi", "90", "--u", "2km", "--omega",
                         "40")
    with pytest.raises(InputError) as exc:
        api.toss(xi=0.577, psi=90, u="2km", omega=40)
    assert str(exc.value) == message


# --------------------------------------------------------------------------- coin simulate

RUNS = [
    (["--xi", "0.5", "-n", "2000", "--seed", "7"], {"xi": "0.5", "tosses": 2000, "seed": 7}),
    (["--xi", "0.577", "--tosses", "1000", "--seed", "1", "--omega", "normal:6:1rev/s"],
     {"xi": 0.577, "tosses": "1000", "seed": "1", "omega": "normal:6:1rev/s"}),
    (["--coin", "quarter", "-n", "500", "--seed", "2", "--u", "uniform:1:3", "--psi-dist",
      "cosine", "--g", "1.62"],
     {"coin": "quarter", "tosses": 500, "seed": 2, "u": "uniform:1:3", "psi_dist": "cosine",
      "g": 1.62}),
    (["--xi", "0.577", "-n", "300", "--seed", "4", "--psi", "90", "--contact", "thick"],
     {"xi": 0.577, "tosses": 300, "seed": 4, "psi": 90, "contact": "thick"}),
]


@pytest.mark.parametrize("argv,kwargs", RUNS)
def test_simulate_is_the_cli_json(coin, argv, kwargs):
    assert api.simulate(**kwargs) == _cli_json(coin, "simulate", *argv)


def test_simulate_error_is_the_cli_message(coin):
    message = _cli_error(coin, "simulate", "--xi", "0.577", "--u", "uniform:3:1")
    with pytest.raises(InputError) as exc:
        api.simulate(xi=0.577, u="uniform:3:1")
    assert str(exc.value) == message
    message = _cli_error(coin, "simulate", "--xi", "0.577", "-n", "10000000000")
    with pytest.raises(InputError) as exc:
        api.simulate(xi=0.577, tosses=10**10)
    assert str(exc.value) == message


# --------------------------------------------------------------------------- coin phase

GRIDS = [
    (["--cols", "5", "--rows", "4"], {"cols": 5, "rows": 4}),
    (["--xi", "0.3", "--u", "0:5", "--omega", "0:100", "--cols", "6", "--rows", "3",
      "--contact", "thick", "--exact", "--psi", "70"],
     {"xi": 0.3, "u": "0:5", "omega": "0:100", "cols": 6, "rows": 3, "contact": "thick",
      "exact": True, "psi": 70}),
    (["--quarters", "8", "--u", "0:300cm/s", "--omega", "0:10rev/s", "--cols", "4", "--rows",
      "4", "--no-curves"],
     {"quarters": 8, "u": "0:300cm/s", "omega": "0:10rev/s", "cols": 4, "rows": 4,
      "no_curves": True}),
]


@pytest.mark.parametrize("argv,kwargs", GRIDS)
def test_phase_is_the_cli_json(coin, argv, kwargs):
    assert api.phase(**kwargs) == _cli_json(coin, "phase", *argv)


def test_phase_error_is_the_cli_message(coin):
    message = _cli_error(coin, "phase", "--u", "3:0")
    with pytest.raises(InputError) as exc:
        api.phase(u="3:0")
    assert str(exc.value) == message


# --------------------------------------------------------------------------- --landing bounce


def test_bouncing_toss_and_run_are_the_cli_json(coin):
    pytest.importorskip("mujoco")
    argv = ["--xi", "0.577", "--psi", "85", "--u", "2.4", "--omega", "38", "--landing",
            "bounce", "--surface", "felt"]
    one = api.toss(xi=0.577, psi=85, u=2.4, omega=38, landing="bounce", surface="felt")
    assert one == _cli_json(coin, "toss", *argv)
    assert one[0]["landing"] == "bounce" and one[0]["surface"] == "felt"
    argv = ["--xi", "0.577", "-n", "4", "--seed", "1", "--psi", "90", "--landing", "bounce",
            "--jobs", "1", "--release-height", "20"]
    rows = api.simulate(xi=0.577, tosses=4, seed=1, psi=90, landing="bounce", jobs=1,
                        release_height=20)
    assert rows == _cli_json(coin, "simulate", *argv)
    assert [r["outcome"] for r in rows] == ["heads", "sides", "tails", "unsettled"]
    assert sum(r["count"] for r in rows) == 4


def test_bouncing_error_is_the_cli_message(coin):
    pytest.importorskip("mujoco")
    argv = ["--xi", "0.577", "--psi", "85", "--u", "2.4", "--omega", "38", "--landing",
            "bounce", "--release-height", "normal:1:2"]
    message = _cli_error(coin, "toss", *argv)
    with pytest.raises(InputError) as exc:
        api.toss(xi=0.577, psi=85, u=2.4, omega=38, landing="bounce",
                 release_height="normal:1:2")
    assert str(exc.value) == message


# --------------------------------------------------------------------------- the reports


def test_toss_report_is_a_result_of_the_typed_options():
    from coincli.reports import toss as R

    r = R.toss(xi="0.577", psi="90", u="2", omega="40")
    assert isinstance(r, Result) and r.vertical and r.quiet == "tails"
    assert [c.name for c in r.columns][:4] == ["xi", "psi_deg", "u", "omega"]
    assert "seed" not in [c.name for c in r.columns]  # nothing drawn
    with pytest.raises(InputError, match="--seed seeds what is drawn"):
        R.toss(xi="0.577", psi="90", u="2", omega="40", seed="1")


def test_simulate_report_and_its_stream():
    import io

    from coincli.io.table import emit
    from coincli.reports import toss as R

    r = R.simulate(xi="0.5", tosses="100", seed="7", fmt="csv")
    assert [row[0] for row in r.rows] == ["heads", "sides", "tails"]
    assert sum(row[1] for row in r.rows) == 100 and r.rows[0][-1] == 7
    assert [c.name for c in R.simulate(xi="0.5", tosses="10", seed="7").columns][-1] == \
        "difference"  # the human table has no seed column
    s = R.simulate(xi="0.5", tosses="70000", seed="7", psi="90", stream=True)
    out = io.StringIO()
    emit(s, "table", True, out=out)  # one letter a line, in chunks, as coin simulate --stream
    letters = out.getvalue().split("\n")
    assert len(letters) == 70001 and letters[-1] == "" and set(letters[:-1]) <= set("HST")
    counts = [letters.count(c) for c in "HST"]
    assert counts == [row[1] for row in R.simulate(xi="0.5", tosses="70000", seed="7",
                                                   psi="90").rows]
    with pytest.raises(InputError, match="--stream prints one letter a line"):
        R.simulate(xi="0.5", stream=True, fmt="csv")


def test_phase_report_gives_cells_a_picture_or_a_figure(tmp_path):
    from coincli.reports import phase as R

    cells = R.phase(cols="3", rows="2", fmt="csv")
    assert isinstance(cells, Result) and len(cells.rows) == 6
    picture = R.phase(cols="12", rows="5")  # not a terminal: letters, a str
    assert isinstance(picture, str) and "H" in picture
    with pytest.raises(InputError, match="--out writes a figure; it takes no --format"):
        R.phase(out=str(tmp_path / "p.png"), fmt="json")


def test_plot_reports_return_the_text_plot(capsys):
    from coincli.reports import plot as R

    for report in (R.psi, R.map, R.phase):
        assert report(terminal=True) is not None
    assert R.sides(xi="0.5", p_sides="1/3") is not None  # no --out: a text plot
    assert capsys.readouterr() == ("", "")  # the reports print nothing: the cli does
    with pytest.raises(InputError, match="--style must be panels or ternary"):
        R.map(style="pie")


def test_bounce_design_warning_comes_after_the_table(capsys):
    from coincli.io.table import Column, emit_all
    from coincli.reports.bounce import DesignResult, warn_unmet

    r = DesignResult("t", [Column("x", "x")], [(1.0,)], warning="--max-tosses 5 reached")
    emit_all(r, "csv")
    warn_unmet(r)
    warn_unmet(Result("t", [Column("x", "x")], [(1.0,)]))  # no warning: nothing
    assert capsys.readouterr() == ("x\n1.0\n", "coin: warning: --max-tosses 5 reached\n")


# --------------------------------------------------------------------------- doctests


@pytest.mark.parametrize("name", ["toss", "simulate", "phase"])
def test_api_doctests(name):
    fn = getattr(api, name)
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS)
    for test in doctest.DocTestFinder().find(fn, name, globs={}):
        runner.run(test)
    result = runner.summarize(verbose=False)
    assert result.attempted > 0 and result.failed == 0
