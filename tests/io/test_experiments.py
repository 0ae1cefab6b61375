"""The experiments file (coincli.io.experiments): an empty start cell is named as such
(issue 38, item 13), and caught rows are refused when a table's calibration reads the file
(item 1)."""

from __future__ import annotations

import pytest
from cli_helpers import error

from coincli.io.experiments import CSVError, parse_experiment_columns, parse_experiments


@pytest.mark.parametrize("text, words", [
    ("xi,heads,tails,start\n0.05,30,20,\n", "line 2, column 'start': start is required "
     "(heads or tails: the side every flip of the row started on)"),
    ("xi,heads,tails,start,sides\n0.2,3,1,,2\n0.05,30,20,,\n", "line 3, column 'start': start "
     "is required (heads or tails: the side every flip of the row started on), or give sides"),
])
def test_an_empty_start_cell_is_named(text, words):
    with pytest.raises(CSVError) as exc:
        parse_experiments(text)
    assert str(exc.value) == words or str(exc.value).startswith(words), str(exc.value)
    assert exc.value.column == "start"


def test_an_empty_start_cell_on_the_command_line(coin, tmp_path):
    data = tmp_path / "t.csv"
    data.write_text("xi,heads,tails,start\n0.05,30,20,heads\n0.1,30,20,\n")
    error(coin("fit", data), 2, f"{data.name} line 3, column 'start': start is required")


def test_rows_of_every_kind_with_a_start_column_still_read():
    """A start column does not make start required of a row of heads, sides and tails."""
    exps = parse_experiments("xi,heads,sides,tails,start\n0.2,3,1,2,\n0.05,30,,20,tails\n")
    assert [type(e.counts).__name__ for e in exps] == ["Counts", "Caught"]


CAUGHT = [
    ("xi,same,different\n0.05,60,40\n", 2, "same"),
    ("xi,same,n\n0.05,60,100\n", 2, "same"),
    ("xi,hsame,hdiff,tsame,tdiff\n0.05,30,20,30,20\n", 2, "hsame"),
    ("xi,heads,tails,start\n0.05,30,20,heads\n", 2, "start"),
    ("xi,heads,sides,tails,same,different\n0.2,10,2,10,,\n0.05,,,,60,40\n", 3, "same"),
]


@pytest.mark.parametrize("text, line, column", CAUGHT)
def test_caught_rows_refused_for_a_table(text, line, column):
    parse_experiment_columns(text)  # read as ever for the catch's fit
    with pytest.raises(CSVError) as exc:
        parse_experiment_columns(text, caught=False)
    assert str(exc.value).startswith(f"line {line}, column {column!r}: a row of caught flips")
    assert "never met a table" in str(exc.value)


@pytest.mark.parametrize("text, line, column", CAUGHT)
def test_caught_rows_refused_by_a_bouncing_fit_before_any_simulation(coin, tmp_path, text, line,
                                                                     column):
    """They simulated the whole design, then failed with `internal error: TypeError`."""
    pytest.importorskip("mujoco")
    data = tmp_path / "c.csv"
    data.write_text(text)
    error(coin("fit", data, "--landing", "bounce", "--fit", "friction", "--restitution", "0.5",
               "--design-tosses", "32", "--seed", "1", "--jobs", "1"), 2,
          f"c.csv line {line}, column {column!r}: a row of caught flips",
          "never met a table; --landing bounce fits tosses that landed on one")


def test_caught_rows_refused_by_the_api(tmp_path):
    pytest.importorskip("mujoco")
    from coincli import api
    from coincli.errors import InputError

    data = tmp_path / "c.csv"
    data.write_text(CAUGHT[0][0])
    with pytest.raises(InputError, match="line 2, column 'same': a row of caught flips"):
        api.fit(str(data), landing="bounce", fit="friction", restitution=0.5, design_tosses=32,
                seed=1, jobs=1)
