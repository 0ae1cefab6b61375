"""coincli.api's design family (design, table, stack, coins, fair): the rows ``--format json``
prints, from Python; the same errors with the same messages; the reports themselves
(:mod:`coincli.reports.design`) called without an argv."""

from __future__ import annotations

import doctest
import json

import pytest
from cli_helpers import ok as _ok

from coincli import api
from coincli.errors import InputError, NotComputable
from coincli.io.table import Result, json_rows
from coincli.reports import design as R


def _cli_rows(coin, *argv):
    return json.loads(_ok(coin(*argv, "--format", "json")))


def _cli_error(coin, *argv) -> tuple[int, str]:
    """(exit code, message) of a command that fails in one line."""
    code, out, err = coin(*argv)
    assert code != 0 and out == "" and err.startswith("coin: error: ") and err.count("\n") == 1
    return code, err[len("coin: error: "):-1]


# (argv of the command, the same inputs as api keyword arguments: text as typed, and as Python
# values; each set of keyword arguments must give the rows the command prints)
DESIGN = [
    (["--p-sides", "1/3"], [{"p_sides": "1/3"}]),
    (["--p-sides", "0.3333333333333333"], [{"p_sides": 1 / 3}, {"p_sides": "0.3333333333333333"}]),
    (["--p-sides", "25%", "--model", "geometric", "--diameter", "30"],
     [{"p_sides": "25%", "model": "geometric", "diameter": "30"},
      {"p_sides": 0.25, "model": "geometric", "diameter": 30}]),
    (["--p-sides", "0.1,0.25,0.5"], [{"p_sides": "0.1,0.25,0.5"}, {"p_sides": [0.1, 0.25, 0.5]},
                                     {"p_sides": (0.1, 0.25, 0.5)}]),
    (["--p-sides", "0.1:0.9:0.1", "--thickness", "2cm"],
     [{"p_sides": "0.1:0.9:0.1", "thickness": "2cm"}]),
    (["--p-sides", "0.3", "--psi", "120", "--coin", "dime"],
     [{"p_sides": "0.3", "psi": "120", "coin": "dime"}, {"p_sides": 0.3, "psi": 120,
                                                         "coin": "dime"}]),
    (["--p-sides", "1/3", "--psi-dist", "normal:90:18", "--tol", "1e-6"],
     [{"p_sides": "1/3", "psi_dist": "normal:90:18", "tol": 1e-6}]),
    (["--p-sides", "0,1"], [{"p_sides": [0, 1]}]),
]
TABLE = [
    (["--xi", "0.577"], [{"xi": "0.577"}, {"xi": 0.577}]),
    (["--xi", "0.2,0.577", "--all"], [{"xi": "0.2,0.577", "all": True},
                                      {"xi": [0.2, 0.577], "all": True}]),
    (["--xi", "0.1:1:0.1"], [{"xi": "0.1:1:0.1"}]),
    (["--xi", "inf,0,1e300"], [{"xi": [float("inf"), 0, 1e300]}]),
    (["--quarters", "8", "--psi", "60,90,120"], [{"quarters": 8, "psi": [60, 90, 120]},
                                                 {"quarters": "8", "psi": "60,90,120"}]),
    (["--coin", "quarter", "--count", "1:4:1", "--psi-dist", "cosine"],
     [{"coin": "quarter", "count": "1:4:1", "psi_dist": "cosine"}]),
    (["--diameter", "30", "--thickness", "17", "--psi-dist", "uniform,normal:90:18"],
     [{"diameter": 30, "thickness": 17, "psi_dist": ["uniform", "normal:90:18"]}]),
    (["--xi", "17/30", "--vs", "psi", "--psi", "0:180:30"],
     [{"xi": "17/30", "vs": "psi", "psi": "0:180:30"}]),
    (["--xi", "0.577", "--all", "--tol", "1e-8"], [{"xi": 0.577, "all": True, "tol": 1e-8}]),
    (["--xi", "0.577", "--psi-dist", "uniform", "--method", "mc", "--seed", "1", "--tol",
      "1e-2"], [{"xi": 0.577, "psi_dist": "uniform", "method": "mc", "seed": 1, "tol": 0.01}]),
]
STACK = [
    (["--coin", "quarter", "--count", "8"], [{"coin": "quarter", "count": 8}, {"quarters": 8}]),
    (["--p-sides", "1/3"], [{"p_sides": "1/3"}]),
    (["--diameter", "25", "--thickness", "2", "--count", "1:12:1"],
     [{"diameter": 25, "thickness": 2, "count": "1:12:1"}]),
    (["--coin", "nickel", "--p-sides", "0.1,0.5,1"],
     [{"coin": "nickel", "p_sides": [0.1, 0.5, 1]}]),
    (["--p-sides", "0.1:0.9:0.1", "--model", "geometric"],
     [{"p_sides": "0.1:0.9:0.1", "model": "geometric"}]),
    (["--count", "3,5", "--psi", "60"], [{"count": [3, 5], "psi": 60}]),
    (["--count", "1:5:1", "--psi-dist", "uniform"], [{"count": "1:5:1", "psi_dist": "uniform"}]),
]
FAIR = [
    ([], [{}]),
    (["--diameter", "30"], [{"diameter": 30}, {"diameter": "30mm"}]),
    (["--coin", "dime", "--psi-dist", "normal:90:18"],
     [{"coin": "dime", "psi_dist": "normal:90:18"}]),
]


@pytest.mark.parametrize("command, argv, calls", [
    *[("design", a, c) for a, c in DESIGN], *[("table", a, c) for a, c in TABLE],
    *[("stack", a, c) for a, c in STACK], *[("fair", a, c) for a, c in FAIR],
    ("coins", [], [{}]),
])
def test_the_api_returns_the_rows_the_command_prints(coin, command, argv, calls):
    rows = _cli_rows(coin, command, *argv)
    assert rows
    for kwargs in calls:
        assert getattr(api, command)(**kwargs) == rows, kwargs


# an input each command refuses: (argv, api call, exit code)
ERRORS = [
    (["design", "--p-sides", "2"], lambda: api.design(p_sides=2), 2),
    (["design", "--p-sides", "1/3", "--seed", "1"], lambda: api.design(p_sides="1/3", seed=1), 2),
    (["design", "--p-sides", "1/3", "--psi", "30", "--psi-dist", "uniform"],
     lambda: api.design(p_sides="1/3", psi=30, psi_dist="uniform"), 2),
    (["design", "--p-sides", "1/3", "--surface", "wood"],
     lambda: api.design(p_sides="1/3", surface="wood"), 2),
    (["table", "--xi", "0.5", "--psi", "200"], lambda: api.table(xi=0.5, psi=200), 2),
    (["table", "--xi", "0.5", "--tol", "1e-6"], lambda: api.table(xi=0.5, tol=1e-6), 2),
    (["table", "--xi", "0.5,0.6", "--vs", "psi"], lambda: api.table(xi=[0.5, 0.6], vs="psi"), 2),
    (["stack", "--quarters", "8", "--p-sides", "1/3"],
     lambda: api.stack(quarters=8, p_sides="1/3"), 2),
    (["stack", "--coin", "zzz", "--count", "2"], lambda: api.stack(coin="zzz", count=2), 2),
    (["stack", "--p-sides", "1"], lambda: api.stack(p_sides=1), 1),
    (["fair", "--coin", "nope"], lambda: api.fair(coin="nope"), 2),
    (["fair", "--diameter", "-3"], lambda: api.fair(diameter=-3), 2),
]


@pytest.mark.parametrize("argv, call, code", ERRORS, ids=[" ".join(a) for a, _, _ in ERRORS])
def test_a_wrong_input_raises_the_commands_error(coin, argv, call, code):
    got_code, message = _cli_error(coin, *argv)
    assert got_code == code
    with pytest.raises(InputError if code == 2 else NotComputable) as exc:
        call()
    assert str(exc.value) == message


def test_an_option_of_the_wrong_type_is_an_input_error():
    with pytest.raises(InputError, match="xi: a number, a string or a list of them; got set"):
        api.table(xi={0.5})


# --------------------------------------------------------------------------- the reports


def test_the_reports_return_results_and_print_nothing(capsys):
    r = R.design("1/3")
    assert isinstance(r, Result) and r.title == "coin design"
    assert [c.name for c in r.columns][:2] == ["p_sides", "xi"]
    assert r.quiet == [pytest.approx(3 ** -0.5, rel=1e-15)] and r.vertical
    batch = R.design("0.1:0.9:0.1")  # a batch under a closed form: streamed
    assert batch.chunks is not None and batch.quiet == 1
    assert len(json_rows(batch)) == 9
    t = R.table(xi="0.2,0.577", all=True, fmt="json")
    assert [row["model"] for row in json_rows(t)][:5] == ["geometric", "dynamic", "uniform",
                                                          "cosine", "normal"]
    human = R.table(xi="0.5", psi_dist="normal", fmt="table")  # the density's title by people
    assert [row[1] for row in human.rows] == ["geometric", "dynamic", "normal (paper)"]
    vs = R.table(xi="17/30", vs="psi")
    assert vs.title == "coin table --vs psi" and len(vs.rows) == 13
    s = R.stack(p_sides="1/3")
    assert s.quiet == 8 and [row[-1] for row in s.rows] == ["", "nearest", ""]
    c = R.coins()
    assert c.quiet[:3] == ["cent", "nickel", "dime"]
    f = R.fair(psi_dist="normal:90:18")
    assert f.title.startswith("coin fair: P(sides) = 1/3") and len(f.rows) == 3
    assert capsys.readouterr() == ("", "")


def test_the_reports_raise_the_commands_errors():
    with pytest.raises(InputError, match="--format must be one of"):
        R.coins(fmt="xml")
    with pytest.raises(InputError, match="--model must be geometric, dynamic or psi"):
        R.stack(count="3", model="flat")
    with pytest.raises(InputError, match="-n is a number of tosses"):
        R.table(tosses="8")
    with pytest.raises(NotComputable, match="infinitely tall stack"):
        R.stack(p_sides="1")


def test_a_sampled_table_reports_its_progress_to_the_bar_it_is_given():
    bars = []

    class Bar:
        def __init__(self, label):
            self.label, self.calls, self.closed = label, 0, False
            bars.append(self)

        def __call__(self, done, total):
            self.calls += 1

        def close(self):
            self.closed = True

    r = R.table(xi="0.577", psi_dist="uniform", method="mc", seed="1", tol="1e-2",
                fmt="csv", progress=Bar)
    assert [b.label for b in bars] == ["mc uniform"]
    assert bars[0].calls > 0 and bars[0].closed
    assert r.rows[-1][-1] == 1  # the seed column


def test_the_api_examples_run():
    finder, runner = doctest.DocTestFinder(), doctest.DocTestRunner()
    for fn in (api.design, api.table, api.stack, api.coins, api.fair):
        for test in finder.find(fn, fn.__name__, globs={}):
            runner.run(test)
    assert runner.summarize(verbose=False).failed == 0
