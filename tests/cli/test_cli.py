"""Behaviour of the ``coin`` command, run in-process through :func:`coincli.cli.run`.

Every number printed in csv/tsv/json/jsonl is read back and compared, as a double, with what
:mod:`coincli.core.models` (or :mod:`coincli.core.coins`) computes: the output layer must not lose a bit.
Errors: one line on stderr, the documented exit code, nothing on stdout, never a traceback.
No timing here (speed lives in benchmarks/).
"""

from __future__ import annotations

import csv
import io
import json
import math
from fractions import Fraction

import pytest
from cli_helpers import error as _error
from cli_helpers import ok as _ok

from coincli.cli import run
from coincli.core import coins, models
from coincli.io.batches import FAST_MIN_BYTES

QUARTER = coins.CATALOG["quarter"]





def rows_csv(out: str, sep: str = ",") -> list[dict]:
    return list(csv.DictReader(io.StringIO(out), delimiter=sep))


def num(text: str):
    """A csv cell as the value it stands for: '' is None, everything else a float."""
    return None if text == "" else float(text)


def _strict_json(text: str):
    def no_constants(name):
        raise AssertionError(f"non-standard JSON constant {name}")

    return json.loads(text, parse_constant=no_constants)


DESIGN_COLUMNS = [
    "p_sides", "xi", "d_over_h", "diameter_mm", "thickness_mm", "p_heads", "p_tails", "coin",
    "stack_n", "stack_xi", "stack_p_sides", "stack_p_sides_minus1", "stack_p_sides_plus1",
]


# --------------------------------------------------------------------------- design


def core(fn, values):
    """What the CLI computes for ``values``: Python floats for one value, one numpy call for a
    list (numpy's SIMD atan/tan/hypot may differ from libm's in the last bit, so a value is
    compared with the path that produced it)."""
    import numpy as np

    if len(values) == 1:
        return [fn(float(values[0]))]
    out = fn(np.asarray(values, dtype=float))
    if isinstance(out, tuple):
        return [type(out)(*t) for t in zip(*(np.asarray(v).tolist() for v in out), strict=True)]
    return out.tolist()


@pytest.mark.parametrize("model", ["dynamic", "geometric"])
def test_design_every_column_is_the_core_value(coin, model):
    targets = [0.0, 1e-300, 0.01, 0.25, 1 / 3, 0.5, 0.9, 0.999999, 1.0]
    text = ",".join(repr(p) for p in targets)
    out = _ok(coin("design", "-p", text, "--model", model, "-f", "csv"))
    rows = rows_csv(out)
    other = "geometric" if model == "dynamic" else "dynamic"
    assert list(rows[0]) == DESIGN_COLUMNS + [f"{other}_p_sides"]
    forward = getattr(models, model)
    xis = core(getattr(models, f"{model}_inverse"), targets)
    outs = core(forward, xis)
    others = core(getattr(models, other), xis)
    assert [float(r["p_sides"]) for r in rows] == targets
    assert [float(r["xi"]) for r in rows] == xis
    for r, p, xi, o, ot in zip(rows, targets, xis, outs, others, strict=True):
        assert float(r["d_over_h"]) == (math.inf if xi == 0 else 1 / xi)
        assert float(r["diameter_mm"]) == QUARTER.diameter_mm
        assert float(r["thickness_mm"]) == QUARTER.diameter_mm * xi
        assert (float(r["p_heads"]), float(r["p_tails"])) == (o.heads, o.tails)
        assert float(r[f"{other}_p_sides"]) == ot.sides
        assert r["coin"] == "quarter"
        if p == 1.0:  # an infinitely tall stack: no stack columns
            assert all(r[k] == "" for k in DESIGN_COLUMNS[8:])
            continue
        n = coins.nearest_stack(QUARTER, p, lambda x: forward(x).sides).count
        assert int(r["stack_n"]) == n
        assert float(r["stack_xi"]) == coins.stack_xi(QUARTER, n)
        assert float(r["stack_p_sides"]) == pytest.approx(
            forward(coins.stack_xi(QUARTER, n)).sides, rel=1e-15, abs=0)
        minus = num(r["stack_p_sides_minus1"])
        if n == 1:
            assert minus is None
        else:
            assert minus == pytest.approx(forward(coins.stack_xi(QUARTER, n - 1)).sides,
                                          rel=1e-15)
        assert float(r["stack_p_sides_plus1"]) == pytest.approx(
            forward(coins.stack_xi(QUARTER, n + 1)).sides, rel=1e-15)


def test_design_single_value_is_the_scalar_core_bit_for_bit(coin):
    for model in ("dynamic", "geometric"):
        for p in (0.01, 0.28, 1 / 3, 0.77, 0.999):
            out = _ok(coin("design", "-p", repr(p), "--model", model, "-f", "json"))
            (r,) = _strict_json(out)
            xi = getattr(models, f"{model}_inverse")(p)
            o = getattr(models, model)(xi)
            ch = coins.nearest_stack(QUARTER, p, lambda x, m=model: getattr(models, m)(x).sides)
            assert (r["xi"], r["p_heads"], r["p_tails"]) == (xi, o.heads, o.tails)
            assert (r["stack_n"], r["stack_xi"], r["stack_p_sides"]) == (ch.count, ch.xi,
                                                                         ch.p_sides)


def test_design_default_is_dynamic_and_targets_spell_three_ways(coin):
    xi = {t: float(_ok(coin("design", "-p", t, "-q"))) for t in ("0.33", "33%", "1/3")}
    assert xi["0.33"] == xi["33%"] == models.dynamic_inverse(0.33)
    assert xi["1/3"] == models.dynamic_inverse(1 / 3) == pytest.approx(1 / math.sqrt(3), rel=1e-15)


def test_design_p_zero_and_one_are_legal(coin):
    out = _ok(coin("design", "-p", "0,1", "-f", "csv"))
    zero, one = rows_csv(out)
    assert (float(zero["xi"]), float(zero["d_over_h"])) == (0.0, math.inf)
    assert (float(one["xi"]), float(one["d_over_h"])) == (math.inf, 0.0)
    assert _ok(coin("design", "-p", "0", "-q")) == "0.0\n"
    assert _ok(coin("design", "-p", "1", "-q")) == "inf\n"
    assert _ok(coin("design", "-p", "100%", "--model", "geometric", "-q")) == "inf\n"


def test_design_lengths_and_coin(coin):
    out = _ok(coin("design", "-p", "0.4", "--diameter", "0.955in", "-f", "csv"))
    (r,) = rows_csv(out)
    xi = models.dynamic_inverse(0.4)
    assert float(r["diameter_mm"]) == 24.257  # 0.955 * 25.4 exactly, then rounded once
    assert float(r["thickness_mm"]) == 24.257 * xi
    out = _ok(coin("design", "-p", "0.4", "--thickness", "2cm", "-f", "csv"))
    (r,) = rows_csv(out)
    assert float(r["thickness_mm"]) == 20.0 and float(r["diameter_mm"]) == 20.0 / xi
    out = _ok(coin("design", "-p", "0.4", "--coin", "nickel", "-f", "csv"))
    (r,) = rows_csv(out)
    nickel = coins.CATALOG["nickel"]
    assert r["coin"] == "nickel" and float(r["diameter_mm"]) == nickel.diameter_mm
    assert int(r["stack_n"]) == coins.nearest_stack(nickel, 0.4).count


def test_design_fixed_psi_solves_table_one(coin):
    out = _ok(coin("design", "-p", "0.33", "--model", "psi", "--psi", "80", "-f", "csv"))
    (r,) = rows_csv(out)
    xi, psi = float(r["xi"]), math.radians(80)
    o = models.conditional(xi, psi)
    assert o.sides == pytest.approx(0.33, abs=1e-12)
    assert (float(r["p_heads"]), float(r["p_tails"])) == (o.heads, o.tails)
    assert float(r["geometric_p_sides"]) == models.geometric(xi).sides
    # --psi alone implies the psi model
    assert float(_ok(coin("design", "-p", "0.33", "--psi", "80", "-q"))) == xi


def test_design_psi_distribution(coin):
    from coincli.core.averages import marginal
    from coincli.io.grammar import parse_density

    out = _ok(coin("design", "-p", "1/3", "--psi-dist", "normal:90:18", "-f", "json"))
    (r,) = _strict_json(out)
    o = marginal(r["xi"], parse_density("normal:90:18"))
    assert float(o.sides) == pytest.approx(1 / 3, abs=1e-10)
    assert r["p_heads"] == float(o.heads)


# --------------------------------------------------------------------------- formats


def test_formats_carry_the_same_doubles(coin):
    argv = ("table", "--xi", "0.2,0.577,1e-300,1e300,inf,0")
    by_fmt = {f: _ok(coin(*argv, "-f", f)) for f in ("csv", "tsv", "json", "jsonl")}
    rows_c = rows_csv(by_fmt["csv"])
    rows_t = rows_csv(by_fmt["tsv"], "\t")
    rows_j = _strict_json(by_fmt["json"])
    rows_l = [_strict_json(line) for line in by_fmt["jsonl"].splitlines()]
    assert len(rows_c) == len(rows_t) == len(rows_j) == len(rows_l) == 12
    names = ["xi", "model", "p_heads", "p_sides", "p_tails"]
    xis = [0.2, 0.577, 1e-300, 1e300, math.inf, 0.0]
    want_rows = [o for pair in zip(core(models.geometric, xis), core(models.dynamic, xis),
                                   strict=True) for o in pair]
    for rc, rt, rj, rl, o in zip(rows_c, rows_t, rows_j, rows_l, want_rows, strict=True):
        assert list(rc) == list(rt) == list(rj) == list(rl) == names
        assert rj == rl
        want = {"p_heads": o.heads, "p_sides": o.sides, "p_tails": o.tails}
        for k, v in want.items():
            assert float(rc[k]) == float(rt[k]) == float(rj[k]) == v
            assert rc[k] == repr(v)  # the shortest text that reads back
    inf_rows = [r for r in rows_j if r["xi"] == "inf"]
    assert len(inf_rows) == 2  # strict JSON: infinity as the string "inf"


def test_json_is_one_document_and_jsonl_one_object_a_line(coin):
    out = _ok(coin("design", "-p", "0.1,0.2,0.3", "-f", "json"))
    doc = _strict_json(out)
    assert isinstance(doc, list) and len(doc) == 3 and list(doc[0]) == DESIGN_COLUMNS + [
        "geometric_p_sides"]
    assert doc[0]["stack_n"] == 2 and isinstance(doc[0]["stack_n"], int)
    out = _ok(coin("design", "-p", "0.1,0.2,0.3", "-f", "jsonl"))
    assert out.count("\n") == 3
    assert [_strict_json(line) for line in out.splitlines()] == doc


def test_format_is_case_insensitive_and_checked(coin):
    assert _ok(coin("coins", "-f", "CSV")).startswith("name,label,")
    _error(coin("coins", "-f", "xml"), 2, "--format", "xml", "csv", "jsonl")


def test_human_table_has_no_escape_codes_when_piped(coin, monkeypatch):
    monkeypatch.delenv("NO_COLOR", raising=False)
    out = _ok(coin("design", "-p", "1/3"))
    assert "\x1b" not in out
    assert "xi = h/D" in out and "0.57735" in out and "model: dynamic" in out


def test_rich_table_honours_no_color(coin, monkeypatch):
    import coincli.io.table as common

    monkeypatch.setattr(common, "stdout_is_terminal", lambda: True)
    monkeypatch.setenv("FORCE_COLOR", "1")  # rich styles even a captured stream...
    monkeypatch.setenv("TERM", "xterm-256color")
    monkeypatch.delenv("NO_COLOR", raising=False)
    assert "\x1b[" in _ok(coin("table", "--xi", "0.577"))
    monkeypatch.setenv("NO_COLOR", "1")  # ...but not with NO_COLOR: no escape codes at all
    out = _ok(coin("table", "--xi", "0.577"))
    assert "\x1b" not in out and "geometric" in out and "0.499772" in out


def test_csv_quotes_text_cells_that_need_it(coin):
    out = _ok(coin("coins", "-f", "csv"))
    rows = rows_csv(out)
    assert [r["name"] for r in rows] == list(coins.CATALOG)
    for r in rows:
        c = coins.CATALOG[r["name"]]
        assert r["source"] == c.source and r["label"] == c.label  # commas survive quoting
        assert float(r["xi"]) == c.xi
        assert float(r["p_sides_dynamic"]) == models.dynamic(c.xi).sides
    assert '"Council Regulation (EC) No 975/98 as amended by No 423/1999, Annex' in out


# --------------------------------------------------------------------------- -q


def test_quiet_is_a_bare_number_per_row(coin):
    assert _ok(coin("design", "-p", "1/3", "-q")) == repr(models.dynamic_inverse(1 / 3)) + "\n"
    out = _ok(coin("design", "-p", "0.1:0.5:0.1", "-q"))
    assert [float(v) for v in out.split()] == core(
        models.dynamic_inverse, [0.1, 0.2, 0.3, 0.4, 0.5])  # the decimals, not 0.1 + 2 * 0.1
    # stack --p-sides: the count, as a whole number (was '8.0')
    assert _ok(coin("stack", "--coin", "quarter", "--p-sides", "1/3", "-q")) == "8\n"
    out = _ok(coin("stack", "--coin", "quarter", "--count", "8", "-q"))
    assert float(out) == models.dynamic(coins.stack_xi(QUARTER, 8)).sides
    out = _ok(coin("fair", "-q"))
    assert [float(v) for v in out.split()] == [models.FAIR_XI_GEOMETRIC,
                                               models.dynamic_inverse(1 / 3)]


# ---------------------------------------------------------------- table, stack, coins, fair


def test_table_lists_ranges_and_models(coin):
    out = _ok(coin("table", "--xi", "0.577", "-f", "csv"))
    g, d = rows_csv(out)
    assert (g["model"], d["model"]) == ("geometric", "dynamic")
    assert float(d["p_sides"]) == models.dynamic(0.577).sides
    out = _ok(coin("table", "--xi", "0.1:1:0.05", "-f", "csv"))
    xs = sorted({float(r["xi"]) for r in rows_csv(out)})
    assert len(xs) == 19 and xs[0] == 0.1 and xs[-1] == 1.0
    # each value is the double nearest the decimal (0.35, not 0.35000000000000003)
    assert xs == [float(Fraction(1, 10) + k * Fraction(1, 20)) for k in range(19)]


def test_table_psi_and_vs_psi(coin):
    out = _ok(coin("table", "--xi", "0.577", "--psi", "60", "-f", "csv"))
    r = rows_csv(out)[-1]
    o = models.conditional(0.577, math.radians(60))
    assert r["model"] == "psi=60"
    assert (float(r["p_heads"]), float(r["p_sides"]), float(r["p_tails"])) == tuple(o)
    out = _ok(coin("table", "--xi", "0.577", "--vs", "psi", "-f", "csv"))
    rows = rows_csv(out)
    assert [float(r["psi_deg"]) for r in rows] == [15.0 * k for k in range(13)]  # as typed
    for r in rows:
        deg = float(r["psi_deg"])
        # past 90 deg at the mirror angle, taken in degrees (exact): 180 deg is 0
        o = models.conditional(0.577, math.radians(180 - deg if deg > 90 else deg))
        assert float(r["p_sides"]) == o.sides
    assert rows[0]["regime"] == "heads only" and rows[6]["regime"] == "all three"


def test_table_stacks_of_coins(coin):
    out = _ok(coin("table", "--quarters", "8", "-f", "csv"))
    rows = rows_csv(out)
    assert [r["coin"] for r in rows] == ["quarter", "quarter"]
    assert [r["count"] for r in rows] == ["8", "8"]
    assert float(rows[0]["xi"]) == coins.stack_xi(QUARTER, 8)
    out = _ok(coin("table", "--coin", "nickel", "--count", "3", "-f", "csv"))
    nickel = coins.CATALOG["nickel"]
    r = rows_csv(out)[1]
    assert (r["coin"], r["count"]) == ("nickel", "3")
    assert float(r["p_sides"]) == models.dynamic(coins.stack_xi(nickel, 3)).sides


def test_stack_count_list_range_and_nearest(coin):
    out = _ok(coin("stack", "--coin", "quarter", "--count", "8", "-f", "csv"))
    (r,) = rows_csv(out)
    assert list(r) == ["coin", "count", "height_mm", "xi", "p_heads", "p_sides", "p_tails", "mark"]
    assert float(r["xi"]) == coins.stack_xi(QUARTER, 8) and float(r["height_mm"]) == 8 * 1.75
    out = _ok(coin("stack", "--count", "1:12:1", "-f", "csv"))  # whole-number range
    assert [int(r["count"]) for r in rows_csv(out)] == list(range(1, 13))
    out = _ok(coin("stack", "--coin", "quarter", "--p-sides", "1/3", "-f", "csv"))
    rows = rows_csv(out)
    assert [int(r["count"]) for r in rows] == [7, 8, 9]
    assert [r["mark"] for r in rows] == ["", "nearest", ""]
    out = _ok(coin("stack", "--diameter", "25", "--thickness", "2", "--count", "3", "-f", "csv"))
    (r,) = rows_csv(out)
    assert r["coin"] == "custom" and float(r["xi"]) == 3 * 2 / 25  # 6 / 25, rounded once


def test_fair_is_both_models_fair_points(coin):
    rows = _strict_json(_ok(coin("fair", "-f", "json")))
    g, d = rows
    assert g["model"] == "geometric" and g["xi"] == models.geometric_inverse(1 / 3)
    assert g["xi"] == pytest.approx(models.FAIR_XI_GEOMETRIC, rel=1e-15)
    assert d["model"] == "dynamic" and d["xi"] == models.dynamic_inverse(1 / 3)
    assert d["dynamic_p_sides"] == models.dynamic(d["xi"]).sides
    assert g["dynamic_p_sides"] == models.dynamic(g["xi"]).sides
    assert (g["stack_n"], d["stack_n"]) == (5, 8)


# --------------------------------------------------------------------------- stdin batches


def test_stdin_batch_one_row_per_value_in_order(coin):
    values = [f"{k / 100:.2f}" for k in range(1, 100)]  # what `seq 0.01 0.01 0.99` prints
    out = _ok(coin("design", "--p-sides", "-", "--format", "csv", stdin="\n".join(values) + "\n"))
    rows = rows_csv(out)
    assert [r["p_sides"] for r in rows] == [repr(float(v)) for v in values]
    assert [float(r["xi"]) for r in rows] == core(models.dynamic_inverse, values)


def test_stdin_skips_blank_and_comment_lines_and_numbers_lines_from_one(coin):
    data = "# targets\n0.3\n\n  1/3  \r\n33%\n"
    out = _ok(coin("design", "-p", "-", "-q", stdin=data))
    assert [float(v) for v in out.split()] == core(models.dynamic_inverse, [0.3, 1 / 3, 0.33])
    err = _error(coin("design", "-p", "-", "-f", "csv", stdin=data + "\n0.5\nnope\n"), 2,
                 "stdin line 8", "nope")
    assert "--p-sides" in err


def _big_batch(n: int) -> list[str]:
    return [repr((k * 0.6180339887498949) % 1.0) for k in range(n)]


def test_long_stdin_batch_takes_the_fast_path_and_agrees(coin):
    values = _big_batch(3000)
    data = "\n".join(values) + "\n"
    assert len(data) >= FAST_MIN_BYTES
    fast = _ok(coin("design", "-p", "-", "-f", "csv", stdin=data))
    slow = _ok(coin("design", "-p", "-", "-f", "csv", stdin="# force the per-line path\n" + data))
    assert fast == slow
    rows = rows_csv(fast)
    assert [r["p_sides"] for r in rows] == [repr(float(v)) for v in values]
    crlf = _ok(coin("design", "-p", "-", "-f", "csv", stdin=data.replace("\n", "\r\n")))
    assert crlf == fast
    neg0 = _ok(coin("design", "-p", "-", "-q", stdin="-0.0\n" + data))
    assert neg0.split("\n", 1)[0] == "0.0"


@pytest.mark.parametrize("path", ["fast", "slow"])
def test_bad_line_in_a_long_batch_names_it_and_prints_nothing(coin, path):
    values = _big_batch(3000)
    values[1233] = "1.5"
    data = "\n".join(values) + "\n"
    if path == "slow":
        data += "50%\n"  # a value the fast path does not read: every line goes one by one
    err = _error(coin("design", "-p", "-", "-f", "csv", stdin=data), 2, "stdin line 1234",
                 "'1.5'", "[0, 1]")
    assert err == "coin: error: stdin line 1234: --p-sides must be in [0, 1] (or 0% to 100%), " \
                  "got '1.5'\n"


@pytest.mark.parametrize("data, words", [
    ("", ["read no values"]),
    ("\n# nothing\n", ["read no values"]),
    ("0.1\n0.1 0.2\n", ["stdin line 2"]),
    ("0.1\nnan\n", ["stdin line 2", "nan"]),
    (b"0.1\n\xff\n", ["stdin line 2", "UTF-8"]),
    (b"0.1\n0.2\x00\n", ["stdin line 2", "NUL"]),
    ("0.1\n" + "1" * 2000 + "\n", ["stdin line 2", "longer than 1000"]),
])
def test_bad_stdin(coin, data, words):
    _error(coin("design", "-p", "-", stdin=data), 2, *words)


def test_table_xi_from_stdin(coin):
    out = _ok(coin("table", "--xi", "-", "-f", "csv", stdin="0.5\ninf\n0\n"))
    assert [r["xi"] for r in rows_csv(out)][::2] == ["0.5", "inf", "0.0"]
    data = "\n".join(repr(0.001 * k) for k in range(4000)) + "\n"
    out = _ok(coin("table", "--xi", "-", "-f", "csv", stdin=data))
    rows = rows_csv(out)
    assert len(rows) == 8000
    assert [float(r["p_sides"]) for r in rows[1::2]] == [
        o.sides for o in core(models.dynamic, [0.001 * k for k in range(4000)])]


# --------------------------------------------------------------------------- errors


ERRORS = [
    (["design", "-p", "1.5"], 2, ["--p-sides", "'1.5'", "[0, 1]"]),
    (["design", "-p", "abc"], 2, ["--p-sides", "'abc'", "0.33, 1/3 or 33%"]),
    (["design", "-p", "1/0"], 2, ["--p-sides", "divides by zero"]),
    (["design", "-p", "-5%"], 2, ["--p-sides", "[0, 1]"]),
    (["design", "-p", "1e99999999"], 2, ["--p-sides", "[0, 1]"]),
    (["design", "-p", "0.3", "--model", "foo"], 2, ["--model", "'foo'", "geometric, dynamic"]),
    (["design", "-p", "0.3", "--psi", "80", "--psi-dist", "uniform"], 2, ["--psi", "--psi-dist",
                                                                          "not both"]),
    (["design", "-p", "0.3", "--model", "geometric", "--psi", "80"], 2, ["--model geometric",
                                                                         "--psi"]),
    (["design", "-p", "0.3", "--model", "psi"], 2, ["--model psi", "--psi"]),
    (["design", "-p", "0.3", "--psi", "190"], 2, ["--psi", "'190'", "[0, 180]"]),
    (["design", "-p", "0.3", "--psi-dist", "bogus"], 2, ["--psi-dist", "'bogus'", "uniform"]),
    (["design", "-p", "0.3", "--diameter", "1", "--thickness", "1"], 2, ["--diameter",
                                                                         "--thickness"]),
    (["design", "-p", "0.3", "--diameter", "-3"], 2, ["--diameter", "'-3'", "> 0"]),
    (["design", "-p", "0.3", "--diameter", "3 furlongs"], 2, ["--diameter", "0.955in"]),
    (["design", "-p", "0.3", "-f", "xml"], 2, ["--format", "'xml'"]),
    (["design"], 2, ["--p-sides"]),
    (["design", "-p"], 2, ["-p"]),
    (["design", "-p", "0.3", "--bogus"], 2, ["--bogus"]),
    (["nosuchcommand"], 2, ["nosuchcommand"]),
    (["table"], 2, ["--xi", "--quarters", "--count"]),
    (["table", "--xi", "0.5", "--quarters", "8"], 2, ["both give the coin"]),
    (["table", "--xi", "0.5", "--coin", "nickel"], 2, ["--xi and --coin", "--count N"]),
    (["table", "--xi", "-1"], 2, ["--xi", "'-1'", ">= 0"]),
    (["table", "--xi", "0.01:100:0.0000001"], 2, ["--xi", "1000000"]),
    (["table", "--xi", "0:1e308:1e-308"], 2, ["--xi", "at most"]),
    (["table", "--xi", "1:0:0.1"], 2, ["--xi", "start <= stop"]),
    (["table", "--xi", "0:1:0"], 2, ["--xi", "step", "> 0"]),
    (["table", "--xi", "0.5", "--vs", "phi"], 2, ["--vs", "'phi'"]),
    (["table", "--xi", "0.5,0.6", "--vs", "psi"], 2, ["--vs psi", "single"]),
    (["stack"], 2, ["--count", "--p-sides"]),
    (["stack", "--count", "0"], 2, ["--count", "'0'", ">= 1"]),
    (["stack", "--count", "2.5"], 2, ["--count", "'2.5'", "whole number"]),
    (["stack", "--count", "9" * 30], 2, ["--count", "whole number from 1"]),
    (["stack", "--count", "8", "--p-sides", "1/3"], 2, ["--count", "--p-sides"]),
    (["stack", "--diameter", "25", "--count", "3"], 2, ["--diameter", "--thickness"]),
    (["stack", "--p-sides", "1"], 1, ["infinitely tall"]),
    (["stack", "--p-sides", "0.3", "--psi", "0"], 1, ["no stack", "0.3"]),
    (["design", "-p", "0.2", "--psi", "0"], 1, ["psi = 0", "p_sides = 0"]),
    (["fair", "--diameter", "0in"], 2, ["--diameter", "'0in'"]),
    (["fair", "--psi-dist", "table:/nonexistent/psi.csv"], 2, ["--psi-dist", "/nonexistent"]),
    (["coins", "--coin", "quarter"], 2, ["--coin"]),
]


@pytest.mark.parametrize("argv, code, words", ERRORS, ids=[" ".join(a)[:40] for a, _, _ in ERRORS])
def test_errors_are_one_line_with_exit_code(coin, argv, code, words):
    _error(coin(*argv), code, *words)


COIN_CONTRADICTIONS = [
    (["stack", "--coin", "dime", "--diameter", "24", "--thickness", "1.75", "--count", "8"],
     ["--coin and --diameter/--thickness both give the coin", "--diameter D --thickness H"]),
    # typing the default is still a choice of coin
    (["stack", "-c", "quarter", "-d", "24", "-t", "1.75", "--count", "8"],
     ["--coin and --diameter/--thickness both give the coin"]),
    # named before the custom coin is checked for its other half
    (["stack", "--coin=dime", "--thickness", "2", "--p-sides", "1/3"],
     ["--coin and --diameter/--thickness both give the coin"]),
    (["table", "--quarters", "8", "--coin", "dime"],
     ["--coin and --quarters both give the coin", "--count N"]),
    (["table", "--quarters", "8", "--coin", "quarter", "--vs", "psi"],
     ["--coin and --quarters both give the coin"]),
]


@pytest.mark.parametrize("argv, words", COIN_CONTRADICTIONS,
                         ids=[" ".join(a)[:50] for a, _ in COIN_CONTRADICTIONS])
def test_contradictory_coin_options_are_usage_errors(coin, argv, words):
    _error(coin(*argv), 2, *words)  # exit 2, nothing on stdout, one line naming both options


def test_coin_left_at_its_default_is_no_contradiction(coin):
    out = _ok(coin("stack", "--diameter", "24", "--thickness", "1.75", "--count", "8", "-f", "csv"))
    (r,) = rows_csv(out)
    assert r["coin"] == "custom" and float(r["xi"]) == 8 * (1.75 / 24)
    # design and fair use both: the diameter sizes the design, the coin makes the stack column
    out = _ok(coin("design", "-p", "0.4", "--coin", "dime", "--diameter", "24", "-f", "csv"))
    (r,) = rows_csv(out)
    dime = coins.CATALOG["dime"]
    assert float(r["diameter_mm"]) == 24.0 and r["coin"] == "dime"
    assert int(r["stack_n"]) == coins.nearest_stack(dime, 0.4).count


def test_unknown_coin_suggests_the_nearest_names(coin):
    err = _error(coin("design", "-p", "1/3", "--coin", "quater"), 2, "--coin", "'quater'")
    assert "did you mean 'quarter'" in err and "coin coins" in err
    err = _error(coin("stack", "--coin", "euro2", "--count", "3"), 2, "'euro2'")
    assert "did you mean 'euro-2'" in err
    _error(coin("stack", "--coin", "zzzzzz", "--count", "3"), 2, "unknown coin 'zzzzzz'",
           "known: cent")
    # aliases and case are accepted
    assert _ok(coin("stack", "--coin", "Penny", "--count", "1", "-q")) == _ok(
        coin("stack", "--coin", "cent", "--count", "1", "-q"))


def test_no_arguments_prints_help_and_exits_2_without_an_error_line(coin):
    code, out, err = coin()
    assert code == 2 and "Usage" in out and "design" in out and err == ""


def test_version_and_help_exit_0(coin):
    from coincli import __version__

    assert _ok(coin("--version")) == f"coin {__version__}\n"
    out = _ok(coin("design", "--help"))
    assert "--p-sides" in out and "Examples" in out


def test_ctrl_c_exits_130(coin, monkeypatch):
    def interrupted(p):
        raise KeyboardInterrupt

    monkeypatch.setattr(models, "dynamic_inverse", interrupted)
    code, out, err = coin("design", "-p", "0.3")
    assert code == 130 and out == "" and "Traceback" not in err


def test_an_internal_bug_is_one_line_exit_1_and_traceback_on_request(coin, monkeypatch):
    def broken(p):
        raise RuntimeError("boom")

    monkeypatch.setattr(models, "dynamic_inverse", broken)
    _error(coin("design", "-p", "0.3"), 1, "internal error", "RuntimeError", "boom",
           "--traceback")
    with pytest.raises(RuntimeError):
        run(["--traceback", "design", "-p", "0.3"])
    import os

    assert "COIN_TRACEBACK" not in os.environ  # --traceback lasts one run
    _error(coin("design", "-p", "0.3"), 1, "internal error")


def test_output_is_written_only_after_everything_is_computed(coin, monkeypatch):
    # a failure while computing the last value leaves stdout empty
    real = models.dynamic

    def fails_late(xi):
        if not isinstance(xi, float) and len(xi) == 2:
            raise ValueError("late failure")
        return real(xi)

    monkeypatch.setattr(models, "dynamic", fails_late)
    _error(coin("table", "--xi", "0.1,0.2", "-f", "csv"), 1, "late failure")


# --------------------------------------------------------------------------- review fixes


def test_design_past_the_stack_cap_still_designs_the_coin(coin):
    from coincli.core.averages import conditional_inverse

    psi = math.radians(1e-10)
    out = _ok(coin("design", "-p", "0.5", "--model", "psi", "--psi", "1e-10", "-f", "csv"))
    (r,) = rows_csv(out)
    xi = conditional_inverse(0.5, psi)
    assert float(r["xi"]) == xi and xi > coins.MAX_STACK * QUARTER.xi  # ~4e11: past the cap
    assert float(r["d_over_h"]) == 1 / xi
    assert float(r["thickness_mm"]) == QUARTER.diameter_mm * xi
    o = models.conditional(xi, psi)
    assert (float(r["p_heads"]), float(r["p_tails"])) == (o.heads, o.tails)
    assert r["coin"] == "quarter"
    assert all(r[k] == "" for k in DESIGN_COLUMNS[8:])  # no stack: empty, as at p = 1
    # the human table shows them as '-' and the run succeeds; a list keeps one row per target
    human = _ok(coin("design", "-p", "0.5", "--psi", "1e-10"))
    assert "coins in nearest stack     -" in human
    rows = rows_csv(_ok(coin("design", "-p", "0.5,0", "--psi", "1e-10", "-f", "csv")))
    assert [r["stack_n"] for r in rows] == ["", "1"]
    # within the cap the stack is still found
    (r,) = rows_csv(_ok(coin("design", "-p", "0.5", "--psi", "0.001", "-f", "csv")))
    assert int(r["stack_n"]) > 1 and float(r["stack_xi"]) == coins.stack_xi(
        QUARTER, int(r["stack_n"]))
    # coin stack has nothing to show there: still a computation error, one line
    _error(coin("stack", "-p", "0.5", "--psi", "1e-10"), 1, "no stack", "2^40 (about 1.1 x 10^12)")


def test_psi_180_is_psi_0_the_coin_never_precesses(coin):
    at0 = coin("design", "-p", "0.5", "--model", "psi", "--psi", "0")
    err = _error(at0, 1, "never precesses", "p_sides = 0")
    assert coin("design", "-p", "0.5", "--model", "psi", "--psi", "180") == at0
    assert _error(coin("design", "-p", "0.5", "--psi", "180.0"), 1) == err
    assert _ok(coin("design", "-p", "0", "--psi", "180", "-q")) == "0.0\n"
    # Table I at 180 deg is the table at 0 deg for every coin, the thickest included
    for xi in ("0.577", "1e16", "1e300", "inf"):
        r180 = rows_csv(_ok(coin("table", "--xi", xi, "--psi", "180", "-f", "csv")))[-1]
        r0 = rows_csv(_ok(coin("table", "--xi", xi, "--psi", "0", "-f", "csv")))[-1]
        assert r180["model"] == "psi=180" and r0["model"] == "psi=0"
        assert [r180[k] for k in ("p_heads", "p_sides", "p_tails")] == ["1.0", "0.0", "0.0"]
        assert [r180[k] for k in ("p_heads", "p_sides", "p_tails")] == [
            r0[k] for k in ("p_heads", "p_sides", "p_tails")]
    rows = rows_csv(_ok(coin("table", "--xi", "1e17", "--vs", "psi", "--psi", "0,180", "-f",
                             "csv")))
    assert [(r["regime"], r["p_sides"]) for r in rows] == [("heads only", "0.0")] * 2
    _error(coin("stack", "-p", "0.5", "--psi", "180"), 1, "no stack")
    # just short of 180 the coin precesses, as just past 0 does
    out = _ok(coin("design", "-p", "0.5", "--psi", "179", "-q"))
    assert float(out) == pytest.approx(float(_ok(coin("design", "-p", "0.5", "--psi", "1", "-q"))),
                                       rel=1e-12)


def _stack_q(coin, p, *extra):
    """The count `coin stack --p-sides p` marks nearest, as a single value."""
    return int(_ok(coin("stack", "--p-sides", p, *extra, "-q")))


STACK_BATCH_COLUMNS = ["target_p_sides", "coin", "count", "height_mm", "xi", "p_heads", "p_sides",
                       "p_tails"]


def test_stack_p_sides_from_stdin_one_row_per_line(coin):
    lines = ["0.05", "1/3", "# a comment", "", "33%", "0.5", "0", "0.9"]
    data = "\n".join(lines) + "\n"
    targets = [t for t in lines if t and not t.startswith("#")]
    rows = rows_csv(_ok(coin("stack", "--coin", "nickel", "--p-sides", "-", "-f", "csv",
                             stdin=data)))
    assert list(rows[0]) == STACK_BATCH_COLUMNS
    assert len(rows) == len(targets)
    nickel = coins.CATALOG["nickel"]
    from coincli.io.grammar import parse_probability

    for r, t in zip(rows, targets, strict=True):
        p = parse_probability(t)
        assert float(r["target_p_sides"]) == p and r["coin"] == "nickel"
        n = _stack_q(coin, t, "--coin", "nickel")  # the same count as the single value
        assert int(r["count"]) == n == coins.nearest_stack(nickel, p).count
        assert float(r["xi"]) == coins.stack_xi(nickel, n)
        assert float(r["height_mm"]) == n * nickel.thickness_mm
    # several lines take the vectorized path; the chances are the model's at that xi
    xs = [float(r["xi"]) for r in rows]
    got = [(float(r["p_heads"]), float(r["p_sides"]), float(r["p_tails"])) for r in rows]
    assert got == [tuple(o) for o in core(models.dynamic, xs)]
    # -q: one count per target; P(sides) = 1 (no finite stack) is an empty line, not an error
    out = _ok(coin("stack", "-p", "-", "-q", stdin="0.2\n1\n0.4\n"))
    assert out == f"{_stack_q(coin, '0.2')}\n\n{_stack_q(coin, '0.4')}\n"
    (one,) = rows_csv(_ok(coin("stack", "-p", "-", "-f", "csv", stdin="100%\n")))
    assert [one[k] for k in STACK_BATCH_COLUMNS[2:]] == [""] * 6
    # one line from stdin is still a batch of one: one row, the closed-form scalar path
    (r,) = rows_csv(_ok(coin("stack", "-p", "-", "-f", "csv", stdin="1/3\n")))
    assert int(r["count"]) == 8 and float(r["xi"]) == coins.stack_xi(QUARTER, 8)


@pytest.mark.parametrize("extra", [("--model", "geometric"), ("--psi", "70"),
                                   ("--psi", "1e-10")])
def test_stack_p_sides_batch_agrees_with_single_values_under_every_model(coin, extra):
    targets = ["0.01", "0.2", "0.45", "0.7"]
    rows = rows_csv(_ok(coin("stack", "-p", "-", *extra, "-f", "csv",
                             stdin="\n".join(targets) + "\n")))
    assert [r["target_p_sides"] for r in rows] == [repr(float(t)) for t in targets]
    for r, t in zip(rows, targets, strict=True):
        code, out, _ = coin("stack", "-p", t, *extra, "-q")
        if code == 1:  # no stack reaches it (psi = 1e-10): an empty row in a batch
            assert r["count"] == "" and r["xi"] == ""
            continue
        assert int(r["count"]) == int(out)
        assert float(r["xi"]) == coins.stack_xi(QUARTER, int(out))
    # a list and a range are batches too
    lst = rows_csv(_ok(coin("stack", "-p", ",".join(targets), *extra, "-f", "csv")))
    assert lst == rows
    rng = rows_csv(_ok(coin("stack", "-p", "0.1:0.3:0.1", *extra, "-f", "csv")))
    assert len(rng) == 3


def test_stack_p_sides_long_batch_is_vectorized_and_exact(coin):
    values = [repr(float(v)) for v in _big_batch(3000)]
    data = "\n".join(values) + "\n"
    assert len(data) >= FAST_MIN_BYTES
    rows = rows_csv(_ok(coin("stack", "--coin", "cent", "-p", "-", "-f", "csv", stdin=data)))
    assert [r["target_p_sides"] for r in rows] == values
    cent = coins.CATALOG["cent"]
    for r, v in list(zip(rows, values, strict=True))[::97]:
        ch = coins.nearest_stack(cent, float(v))
        assert (int(r["count"]), float(r["xi"])) == (ch.count, ch.xi)
    slow = _ok(coin("stack", "--coin", "cent", "-p", "-", "-f", "csv", stdin="#\n" + data))
    assert rows_csv(slow) == rows


@pytest.mark.parametrize("data, line, words", [
    ("0.2\nx\n0.3\n", 2, ["'x'"]),
    ("0.2\n\n# c\n1.5\n", 4, ["'1.5'", "[0, 1]"]),
    ("0.2\n1/3%\n", 2, ["'1/3%'"]),
])
def test_stack_p_sides_bad_line_stops_with_its_number(coin, data, line, words):
    _error(coin("stack", "-p", "-", "-f", "csv", stdin=data), 2, f"stdin line {line}",
           "--p-sides", *words)


def test_every_command_agrees_on_a_stacks_xi(coin):
    for name, n in (("quarter", 9), ("quarter", 8), ("cent", 7), ("nickel", 3), ("euro-2", 11),
                    ("dime", 13)):
        c = coins.CATALOG[name]
        exact = float(Fraction(n) * Fraction(c.thickness_mm) / Fraction(c.diameter_mm))
        assert coins.stack_xi(c, n) == exact
        (s,) = rows_csv(_ok(coin("stack", "--coin", name, "--count", n, "-f", "csv")))
        t = rows_csv(_ok(coin("table", "--coin", name, "--count", n, "-f", "csv")))[0]
        chk = rows_csv(_ok(coin("check", "--coin", name, "--count", n, "--sides", "3", "-n", "10",
                                "-f", "csv")))[0]
        # design: a target that n coins reach exactly, so its nearest stack is n
        p = repr(models.dynamic(exact).sides)
        (d,) = rows_csv(_ok(coin("design", "-p", p, "--coin", name, "-f", "csv")))
        d2 = rows_csv(_ok(coin("design", "-p", f"{p},0.5", "--coin", name, "-f", "csv")))[0]
        assert int(d["stack_n"]) == int(d2["stack_n"]) == n
        assert {s["xi"], t["xi"], chk["xi"], d["stack_xi"], d2["stack_xi"]} == {repr(exact)}
    # the reviewer's case: 9 quarters, 9 * 1.75 / 24.26 correctly rounded
    assert coins.stack_xi(QUARTER, 9) == 0.6492168178070898


def _help_words(out: str) -> str:
    """--help text as one line of words, the box drawing of rich's panels taken out."""
    return " ".join(w for w in out.split() if not set(w) <= set("│╭╮╰╯─"))


def test_coins_help_has_an_example_like_every_command(coin):
    for cmd in ("design", "table", "stack", "coins", "fair"):
        assert "Examples: coin " + cmd in _help_words(_ok(coin(cmd, "--help"))), cmd


def test_a_bad_target_quotes_what_the_user_typed(coin):
    for bad in ("1/3%", "1/3/4", "%", "x%", "1/x"):
        err = _error(coin("design", "-p", bad), 2, "--p-sides")
        assert err == (f"coin: error: --p-sides must be a number like 0.33, 1/3 or 33%, "
                       f"got {bad!r}\n")


@pytest.mark.slow
def test_a_too_long_range_states_its_exact_count(coin):
    err = _error(coin("table", "--xi", "0.5", "--vs", "psi", "--psi", "0:100:0.0001"), 2)
    assert err == ("coin: error: --psi range '0:100:0.0001' has 1000001 values; at most 1000000 "
                   "are allowed\n")
    _error(coin("table", "--xi", "0:1e12:1"), 2, "has 1000000000001 values", "at most 1000000")
    _error(coin("table", "--xi", "0:1e308:1e-308"), 2, "more than 1000000 values")
    # exactly the limit is allowed (it was refused as '1e+06 values')
    out = _ok(coin("stack", "--count", "1:1000000:1", "-q"))
    assert out.count("\n") == 1_000_000


def test_table_quiet_is_p_sides_of_every_row_in_table_order(coin):
    argv = ("table", "--xi", "0.3,0.577", "--psi", "60")
    rows = rows_csv(_ok(coin(*argv, "-f", "csv")))
    assert [r["model"] for r in rows] == ["geometric", "dynamic", "psi=60"] * 2
    assert _ok(coin(*argv, "-q")).split() == [r["p_sides"] for r in rows]
    assert "geometric, then dynamic" in _help_words(_ok(coin("table", "--help")))
