"""Checkpoint records are validated after their checksum matches (issue 38, item 3): a record of
the wrong types, field count or outcome, and a line too deeply nested for the JSON reader, are
dropped and their chunk computed again, as a torn line is; a header of the wrong types is a
damaged header (coincli.io.checkpoint)."""

from __future__ import annotations

import json

import pytest

from cli_helpers import error
from coincli.io.checkpoint import Checkpoint, _line

pytest.importorskip("mujoco")

RUN = ["simulate", "--landing", "bounce", "-n", "64", "--seed", "1", "--xi", "0.5",
       "--jobs", "1"]


@pytest.fixture(scope="module")
def written(tmp_path_factory):
    """A checkpoint of RUN and RUN's output (computed once, in a subprocess-free run)."""
    from coincli.cli import run

    path = tmp_path_factory.mktemp("ck") / "run.ck"
    import contextlib
    import io

    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        assert run([*RUN, "--checkpoint", str(path)]) == 0
    return path.read_text(), out.getvalue()


def _fields(line):
    rec = json.loads(line)
    rec.pop("sum")
    return rec


def _bad_row(rec, how):
    rows = rec["rows"]
    if how == "outcome 7":
        rows[0][0] = 7
    elif how == "catch -1":
        rows[0][1] = -1
    elif how == "four fields":
        rows[0] = rows[0][:4]
    elif how == "six fields":
        rows[0] = [*rows[0], 0]
    elif how == "a text row":
        rows[0] = "abc"
    elif how == "float bounces":
        rows[0][2] = 1.5
    elif how == "bool outcome":
        rows[0][0] = True
    elif how == "text steps":
        rows[0][4] = "266"
    elif how == "negative steps":
        rows[0][4] = -1
    elif how == "settled at nan":
        rows[0][3] = float("nan")
    elif how == "text time":
        rows[0][3] = "1.2"
    elif how == "an extra field":
        rec["junk"] = 1
    elif how == "start a text":
        rec["start"] = "0"
    elif how == "start a bool":
        rec["start"] = False
    elif how == "no rows":
        rec["rows"] = []
    elif how == "rows a dict":
        rec["rows"] = {"0": rows[0]}
    elif how == "key not hex":
        rec["key"] = "x" * 64
    return rec


BAD_ROWS = ["outcome 7", "catch -1", "four fields", "six fields", "a text row",
            "float bounces", "bool outcome", "text steps", "negative steps", "settled at nan",
            "text time", "an extra field", "start a text", "start a bool", "no rows",
            "rows a dict", "key not hex"]


@pytest.mark.parametrize("how", [*BAD_ROWS, "200,000 brackets", "a torn line"])
def test_a_bad_record_is_dropped_and_its_chunk_computed_again(coin, written, tmp_path, how):
    text, reference = written
    lines = text.splitlines(keepends=True)
    if how == "200,000 brackets":
        lines[1] = "[" * 200_000 + "]" * 200_000 + "\n"
    elif how == "a torn line":
        lines[1] = lines[1][:50] + "\n"
    else:
        lines[1] = _line(_bad_row(_fields(lines[1]), how))  # with a matching checksum
    ck = tmp_path / "c.ck"
    ck.write_text("".join(lines))
    rc, out, err = coin(*RUN, "--checkpoint", ck)
    assert (rc, err) == (0, "") and out == reference
    again = ck.read_text().splitlines(keepends=True)  # the bad line dropped, its chunk
    assert again[0] == lines[0] and sorted(again) == sorted(text.splitlines(keepends=True))


@pytest.mark.parametrize("field, value", [
    ("versions", "0.2.0"), ("versions", {"coin": 2}), ("options", ["-n"]),
    ("options", {"-n": 64}), ("command", 1), ("format", None)])
def test_a_header_of_the_wrong_types_is_a_damaged_header(coin, written, tmp_path, field, value):
    text, _ = written
    lines = text.splitlines(keepends=True)
    head = _fields(lines[0])
    head[field] = value
    ck = tmp_path / "c.ck"
    ck.write_text(_line(head) + "".join(lines[1:]))
    error(coin(*RUN, "--checkpoint", ck), 2, "is not a checkpoint of coin",
          "first line is damaged")


def test_a_nested_header_is_a_damaged_header(coin, tmp_path):
    ck = tmp_path / "c.ck"
    ck.write_text("[" * 200_000 + "]" * 200_000 + "\n")
    error(coin(*RUN, "--checkpoint", ck), 2, "is not a checkpoint of coin")


def _point(n):
    return [n] * 2


def _point_fits(task, result):
    return len(result) == 2 and all(sum(g) == task for g in result)


_point.fits = _point_fits


@pytest.mark.parametrize("rows", [
    [[1, 2, 3]], [[1, 2, 3, 4.0]], [[1, 2, 3, -4]], [[1, 2, 3, 4], [1, 2, 3, 5]], [],
    [[1, 2, 3, True]], "1,2,3,4", [[1, 2, 3, 4]] * 3])
def test_a_bad_design_point_is_computed_again(tmp_path, rows):
    """A calibration's design point (a task): groups of four counts >= 0 of one total, as many
    as the task has (``fits``); any other is not taken from the file."""
    head = {"versions": {"coin": "0"}, "command": "test", "options": {}}
    path = tmp_path / "t.ck"
    with Checkpoint(str(path), head) as ck:
        assert list(ck.tasks(_point, [(0, 10)])) == []
        ck.keep(0, [[1, 2, 3, 4], [4, 3, 2, 1]])
    with Checkpoint(str(path), head) as ck:
        assert list(ck.tasks(_point, [(0, 10)])) == [(0, [[1, 2, 3, 4], [4, 3, 2, 1]])]
    lines = path.read_text().splitlines(keepends=True)
    rec = _fields(lines[1])
    rec["rows"] = rows
    path.write_text(lines[0] + _line(rec))
    with Checkpoint(str(path), head) as ck:
        assert list(ck.tasks(_point, [(0, 10)])) == [] and ck.held in (0, 1)
