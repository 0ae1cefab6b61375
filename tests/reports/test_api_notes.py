"""What the command line writes to stderr besides its rows, ``coincli.api`` returns with them
(``rows.notes``, ``rows.caption``) and, for a warning, issues as a ``CoinWarning``; nothing
reaches stderr from Python (issue 36)."""

from __future__ import annotations

import warnings

import pytest

from coincli import api
from coincli.errors import CoinWarning
from coincli.io.notes import Note


def test_a_warning_is_returned_and_issued_and_not_printed(capsys, coin):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        rows = api.check(xi=0.9, same=60, different=40)
    out, err = capsys.readouterr()
    assert out == "" and err == ""
    said = [n for n in rows.notes if n.kind == "warning"]
    assert len(said) == 1 and "xi = 0.9 is above" in said[0].text
    assert [str(w.message) for w in caught if w.category is CoinWarning] == [said[0].text]
    # the command line prints the same line on stderr
    code, _, cli_err = coin("check", "--xi", "0.9", "--same", "60", "--different", "40",
                            "-f", "json")
    assert code == 0 and cli_err == f"{said[0]}\n"


def test_a_warning_can_be_made_an_error():
    with warnings.catch_warnings():
        warnings.simplefilter("error", CoinWarning)
        with pytest.raises(CoinWarning, match="caught flips"):
            api.check(xi=0.9, same=60, different=40)


def test_rows_are_the_json_rows_with_a_caption(coin):
    import json

    rows = api.fair()
    code, out, _ = coin("fair", "-f", "json")
    assert code == 0 and rows == json.loads(out)
    assert rows.notes == [] and rows.caption.strip() != ""
    code, table, _ = coin("fair")
    # the caption is the paragraph a terminal table shows under the rows
    assert " ".join(rows.caption.split())[:60] in " ".join(table.split())


def test_a_note_is_the_line_the_command_line_prints():
    assert str(Note("warning", "w")) == "coin: warning: w"
    assert str(Note("note", "n")) == "coin: note: n"
    assert str(Note("seed", "seed 5 (--seed 5 repeats this run)")) == \
        "coin: seed 5 (--seed 5 repeats this run)"
