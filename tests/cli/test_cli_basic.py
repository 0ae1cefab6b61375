"""End-to-end checks of the coin command: values, formats, batches, errors, import budget."""

from __future__ import annotations

import csv
import io
import json
import math
import subprocess
import sys

import pytest

from coincli.cli import run
from coincli.core import models


def test_design_csv_values_are_the_cores(coin):
    code, out, err = coin("design", "-p", "0.1,1/3,50%", "--format", "csv")
    assert code == 0 and err == ""
    rows = list(csv.DictReader(io.StringIO(out)))
    assert [float(r["p_sides"]) for r in rows] == [0.1, 1 / 3, 0.5]
    for r in rows:
        xi = float(r["xi"])
        assert xi == models.dynamic_inverse(float(r["p_sides"]))
        assert float(r["geometric_p_sides"]) == models.geometric(xi).sides
        assert float(r["thickness_mm"]) == 24.26 * xi


def test_quiet_and_json_round_trip(coin):
    code, out, _ = coin("design", "-p", "1/3", "-q")
    assert code == 0 and float(out) == models.dynamic_inverse(1 / 3)
    code, out, _ = coin("table", "--xi", "0.2,0.577", "--format", "json")
    rows = json.loads(out)
    assert len(rows) == 4 and rows[1]["model"] == "dynamic"
    assert rows[1]["p_sides"] == models.dynamic(0.2).sides


def test_stdin_batch_in_order_and_bad_line(coin):
    code, out, _ = coin("design", "-p", "-", "-f", "csv", stdin="0.3\n\n# c\n0.1\r\n")
    assert code == 0
    assert [float(r["p_sides"]) for r in csv.DictReader(io.StringIO(out))] == [0.3, 0.1]
    code, out, err = coin("design", "-p", "-", "-f", "csv", stdin="0.3\nabc\n")
    assert code == 2 and out == ""
    assert err.count("\n") == 1 and "stdin line 2" in err


def test_edges_p_zero_and_one(coin):
    code, out, _ = coin("design", "-p", "0,1", "-f", "csv")
    assert code == 0
    rows = list(csv.DictReader(io.StringIO(out)))
    assert float(rows[0]["xi"]) == 0.0 and math.isinf(float(rows[1]["xi"]))


@pytest.mark.parametrize("argv, code, words", [
    (["design", "-p", "1.5"], 2, "--p-sides"),
    (["design", "-p", "nan"], 2, "--p-sides"),
    (["design", "-p", "1/3", "--coin", "quater"], 2, "quarter"),
    (["design", "-p", "1/3", "--diameter", "1", "--thickness", "1"], 2, "not both"),
    (["design", "-p", "1/3", "--psi", "90", "--psi-dist", "uniform"], 2, "not both"),
    (["table", "--xi", "-1"], 2, "--xi"),
    (["table", "--xi", "0:1:0"], 2, "step"),
    (["table", "--xi", "0:1e12:1"], 2, "at most"),
    (["stack", "--coin", "quarter", "--count", "0"], 2, "--count"),
    (["design", "-p", "0.2", "--psi", "0"], 1, "only p_sides = 0"),
    (["nosuch"], 2, "No such command"),
])
def test_errors_are_one_line(coin, argv, code, words):
    got, out, err = coin(*argv)
    assert got == code
    assert out == ""
    assert err.startswith("coin: error: ") and err.count("\n") == 1 and words in err
    assert "Traceback" not in err


def _subprocess(code: str):
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          timeout=60)


def test_closed_form_paths_import_no_numpy_scipy_rich():
    probe = (
        "import sys\nfrom coincli.cli import run\n"
        "for argv in (['design','--p-sides','0.33'], ['table','--xi','0.577'], ['fair'],"
        " ['stack','--coin','quarter','--count','8'], ['design','-p','1/3','-m','geometric']):\n"
        "    assert run(argv) == 0\n"
        "print('LOADED', sorted(m for m in ('numpy','scipy','rich') if m in sys.modules))\n"
    )
    out = _subprocess(probe)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip().splitlines()[-1] == "LOADED []"


def test_closed_pipe_exits_quietly():
    p = subprocess.run(f"{sys.executable} -m coincli table --xi 0.01:100:0.001 | head -3",
                       shell=True, capture_output=True, text=True, timeout=120)
    assert p.stdout.count("\n") == 3
    assert p.stderr == ""


@pytest.mark.parametrize("argv", [["table", "--xi", "0.5"], ["design", "-p", "0.3"],
                                  ["check", "--xi", "0.583", "--heads", "35", "--sides", "33",
                                   "--tails", "32"]])
def test_ctrl_c_inside_a_command_says_interrupted(argv, capsys, monkeypatch):
    """typer turns KeyboardInterrupt into a silent Exit(130); coin still says what happened."""
    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(models, "dynamic", interrupted)
    monkeypatch.setattr(models, "dynamic_inverse", interrupted)
    assert run(argv) == 130
    out, err = capsys.readouterr()
    assert out == "" and err == "coin: error: interrupted\n"
