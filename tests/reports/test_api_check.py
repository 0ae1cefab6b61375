"""coincli.api.check, fit and book give the rows ``--format json`` prints, and the same errors;
the reports behind them (coincli.reports.check, coincli.reports.book) return Results without
a command line."""

from __future__ import annotations

import doctest
import json
from pathlib import Path

import pytest

from coincli import api
from coincli.errors import InputError
from coincli.io.table import Result

TOSSES = Path(__file__).resolve().parent.parent / "data" / "tosses.csv"


def _cli_json(coin, *argv, stdin=None):
    rc, out, err = coin(*argv, "--format", "json", stdin=stdin)
    assert (rc, err) == (0, ""), err
    return json.loads(out)


def _cli_error(coin, *argv) -> str:
    rc, out, err = coin(*argv, "--format", "json")
    assert rc == 2 and out == "" and err.startswith("coin: error: "), (rc, out, err)
    return err.removeprefix("coin: error: ").rstrip("\n")


# --------------------------------------------------------------------------- check


@pytest.mark.parametrize("argv, kwargs", [
    (["--xi", "0.577", "--heads", "45", "--sides", "38", "--tails", "37"],
     dict(xi="0.577", heads=45, sides=38, tails=37)),
    (["--quarters", "8", "--sides", "33", "-n", "100"], dict(quarters=8, sides=33, tosses=100)),
    (["--coin", "nickel", "--count", "3", "--heads", "60", "--sides", "9", "--tails", "31",
      "--psi-dist", "normal:90:20,uniform"],
     dict(coin="nickel", count=3, heads=60, sides=9, tails=31,
          psi_dist=["normal:90:20", "uniform"])),
    (["--xi", "17/30", "--heads", "5", "--sides", "0", "--tails", "5", "--alpha", "1%",
      "--confidence", "0.99"],
     dict(xi="17/30", heads=5, sides=0, tails=5, alpha="1%", confidence=0.99)),
    (["--diameter", "24.26mm", "--thickness", "1.75mm", "--sides", "1", "-n", "1000"],
     dict(diameter="24.26mm", thickness="1.75mm", sides=1, tosses=1000)),
])
def test_check_rows_are_the_json_of_the_command(coin, argv, kwargs):
    assert api.check(**kwargs) == _cli_json(coin, "check", *argv)


@pytest.mark.parametrize("argv, kwargs", [
    (["--xi", "0.577", "--heads", "x", "--sides", "38", "--tails", "37"],
     dict(xi="0.577", heads="x", sides=38, tails=37)),
    (["--sides", "3", "-n", "9"], dict(sides=3, tosses=9)),
    (["--xi", "0.5", "--sides", "3", "-n", "9", "--alpha", "2"],
     dict(xi=0.5, sides=3, tosses=9, alpha=2)),
    (["--xi", "0.5", "--quarters", "3", "--sides", "1", "-n", "2"],
     dict(xi=0.5, quarters=3, sides=1, tosses=2)),
])
def test_check_errors_are_the_command_s(coin, argv, kwargs):
    message = _cli_error(coin, "check", *argv)
    with pytest.raises(InputError) as caught:
        api.check(**kwargs)
    assert str(caught.value) == message


# --------------------------------------------------------------------------- fit


@pytest.mark.parametrize("argv, kwargs", [
    ([], {}),
    (["--psi-dist", "uniform,cosine"], dict(psi_dist="uniform,cosine")),
    (["--no-spread", "--alpha", "0.01"], dict(no_spread=True, alpha=0.01)),
])
def test_fit_rows_are_the_json_of_the_command(coin, argv, kwargs):
    assert api.fit(str(TOSSES), **kwargs) == _cli_json(coin, "fit", str(TOSSES), *argv)


def test_fit_takes_a_path_and_reads_stdin_for_dash(coin, monkeypatch):
    import io
    import sys

    want = _cli_json(coin, "fit", "-", "--no-spread", stdin=TOSSES.read_text())
    monkeypatch.setattr(sys, "stdin", io.StringIO(TOSSES.read_text()))
    assert api.fit("-", no_spread=True) == want
    assert api.fit(TOSSES, no_spread=True) == want  # a path-like too


def test_fit_errors_are_the_command_s(coin, tmp_path):
    missing = str(tmp_path / "missing.csv")
    for argv, call in (([missing], lambda: api.fit(missing)),
                       ([str(TOSSES), "--delimiter", "pipe"],
                        lambda: api.fit(str(TOSSES), delimiter="pipe"))):
        message = _cli_error(coin, "fit", *argv)
        with pytest.raises(InputError) as caught:
            call()
        assert str(caught.value) == message


def test_an_option_the_command_lacks_is_refused_by_name():
    with pytest.raises(InputError, match=r"coincli\.api\.fit\(\) takes no 'xi'; it takes file, "
                       "psi_dist, "):
        api.fit(str(TOSSES), xi="0.5")


# --------------------------------------------------------------------------- book


@pytest.mark.parametrize("argv, kwargs", [
    (["--moments", "1,2,3", "--spin", "0,0,40"], dict(moments=(1, 2, 3), spin=(0, 0, 40))),
    (["--moments", "3,4,6", "--spin", "2,-1,1"], dict(moments="3,4,6", spin=[2, -1, 1])),
    (["--size", "235x155x30", "--spin", "0.4,40,0.3", "--flight", "0.5", "--rule", "normal",
      "--start", "-2"],
     dict(size="235x155x30", spin="0.4,40,0.3", flight=0.5, rule="normal", start="-2")),
    (["--moments", "1,2,3", "--spin", "0.1,6rev/s,0.1", "--times", "0:600:100ms"],
     dict(moments=[1, 2, 3], spin="0.1,6rev/s,0.1", times="0:600:100ms")),
    (["--size", "235x155x30", "--spin", "0.4,40,0.3", "--times", "0,0.25,1"],
     dict(size="235x155x30", spin=(0.4, 40, 0.3), times=[0, 0.25, 1])),
    (["--size", "16x16x16", "--toss", "-n", "300", "--seed", "7", "--spin",
      "normal:0:30,normal:0:30,normal:0:30", "--flight", "uniform:0.4:0.6", "--start", "random"],
     dict(size="16x16x16", toss=True, tosses=300, seed=7,
          spin="normal:0:30,normal:0:30,normal:0:30", flight="uniform:0.4:0.6",
          start="random")),
])
def test_book_rows_are_the_json_of_the_command(coin, argv, kwargs):
    assert api.book(**kwargs) == _cli_json(coin, "book", *argv)


@pytest.mark.parametrize("argv, kwargs", [
    (["--moments", "1,2,3"], dict(moments=(1, 2, 3))),
    (["--moments", "1,2,9", "--spin", "0,0,40"], dict(moments=(1, 2, 9), spin=(0, 0, 40))),
    (["--size", "235x155x30", "--spin", "0,0,40", "-n", "3"],
     dict(size="235x155x30", spin="0,0,40", tosses=3)),
    (["--size", "235x155x30", "--spin", "0,0,40", "--toss", "--times", "0:1:0.1"],
     dict(size="235x155x30", spin="0,0,40", toss=True, times="0:1:0.1")),
    (["--size", "235x155x30", "--spin", "0,0,40", "--out", "x.gif"],
     dict(size="235x155x30", spin="0,0,40", out="x.gif")),
])
def test_book_errors_are_the_command_s(coin, argv, kwargs):
    message = _cli_error(coin, "book", *argv)
    with pytest.raises(InputError) as caught:
        api.book(**kwargs)
    assert str(caught.value) == message


def test_book_out_a_figure_is_written_and_a_table_path_only_checked(tmp_path):
    pytest.importorskip("matplotlib")
    png = tmp_path / "book.png"
    assert api.book(moments=(1, 2, 3), spin=(0.1, 6, 0.1), out=str(png)) == []
    assert png.read_bytes().startswith(b"\x89PNG")
    table = tmp_path / "book.csv"
    rows = api.book(moments=(1, 2, 3), spin=(0.1, 6, 0.1), out=str(table))
    assert len(rows) == 1 and not table.exists()


# --------------------------------------------------------------------------- the reports


def test_the_check_report_returns_human_tables_or_the_machine_table():
    from coincli.reports import check as R

    human = R.check(xi="0.5", sides="3", tosses="9")
    assert [r.title for r in human] == ["coin check: xi = 0.5, 9 tosses", "models"]
    machine = R.check(xi="0.5", sides="3", tosses="9", fmt="csv")
    assert isinstance(machine, Result) and machine.columns == R.MACHINE_COLUMNS
    assert [row[8] for row in machine.rows] == ["geometric", "dynamic"]
    assert len(R.check(xi="0.5", sides="3", tosses="9", quiet=True).quiet) == 2
    with pytest.raises(InputError, match="--format must be one of"):
        R.check(xi="0.5", sides="3", tosses="9", fmt="xml")


def test_the_fit_report_streams_its_machine_table():
    from coincli.reports import fit as R

    tables = R.fit(str(TOSSES), no_spread=True)
    assert [r.title for r in tables][1:] == ["models, each experiment",
                                             "model comparison, all experiments"]
    machine = R.fit(str(TOSSES), fmt="json")
    assert machine.columns == R.FIT_COLUMNS and machine.chunks is not None
    rows = [row for data in machine.chunks for row in zip(*data)]
    assert {row[0] for row in rows} == {"experiment", "model"}
    spread = R.fit(str(TOSSES), quiet=True).quiet
    assert 0 < spread < 180


def test_the_book_report_returns_the_motion_the_series_or_the_faces():
    from coincli.reports import book as R

    motion = R.book(moments="1,2,3", spin="0,40,0.1")
    assert motion.title == "coin book" and motion.vertical and len(motion.rows) == 1
    series = R.book(moments="1,2,3", spin="0,40,0.1", times="0:1:0.25")
    rows = [row for data in series.chunks for row in zip(*data)]
    assert [float(r[0]) for r in rows] == [0.0, 0.25, 0.5, 0.75, 1.0]
    ticks = []

    class Bar:
        def __init__(self, total):
            ticks.append(("total", total))

        def __enter__(self):
            return ticks.append

        def __exit__(self, *exc):
            return False

    faces = R.book(size="16x16x16", toss=True, tosses="100", seed="1", spin="30,0,0",
                   progress=Bar)
    assert faces.title == "coin book --toss" and [r[0] for r in faces.rows] == list(R.FACES)
    assert ticks[0] == ("total", 100) and ticks[-1] == 100


def test_the_api_doctests_pass():
    for fn in (api.check, api.fit, api.book):
        finder = doctest.DocTestFinder()
        runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS)
        for test in finder.find(fn, fn.__name__, globs={}):
            runner.run(test)
        assert runner.failures == 0, fn.__name__
        assert runner.tries > 0, fn.__name__
