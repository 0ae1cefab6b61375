"""``coin book``: the paper's Problem 1 from the command line."""

from __future__ import annotations

import csv
import io
import json
import math
import os
import subprocess
import sys

import numpy as np
import pytest
from cli_helpers import error, ok

from coincli.core import rigid as R

BOOK = ["book", "--size", "235x155x30"]


def _json(out):
    return json.loads(out)


def _moments_mm(a, b, c):
    """Moments per kg (m^2) of a uniform box, written out again here."""
    a, b, c = a / 1000, b / 1000, c / 1000
    return ((b * b + c * c) / 12, (c * c + a * a) / 12, (a * a + b * b) / 12)


# --------------------------------------------------------------------------- the motion table


def test_the_papers_case_spin_about_the_largest_axis(coin):
    row = _json(ok(coin(*BOOK, "--spin", "0,0,40", "-f", "json")))[0]
    I1, I2, I3 = _moments_mm(235, 155, 30)
    assert (row["I1"], row["I2"], row["I3"]) == pytest.approx((I1, I2, I3), rel=1e-15)
    gamma = 40 * math.sqrt((I3 - I1) * (I3 - I2) / (I1 * I2))
    assert row["gamma"] == pytest.approx(gamma, rel=1e-14)
    assert row["spin_axis"].startswith("3 (largest")
    assert row["motion"].startswith("steady")
    assert row["period"] == pytest.approx(2 * math.pi / gamma, rel=1e-14)
    assert row["lambda"] is None and row["flip_time"] is None


def test_a_perturbed_stable_spin_oscillates_at_nearly_gamma(coin):
    row = _json(ok(coin(*BOOK, "--spin", "0.4,0.3,40", "-f", "json")))[0]
    mo = R.motion(_moments_mm(235, 155, 30), (0.4, 0.3, 40))
    assert row["period"] == pytest.approx(mo.period, rel=1e-14)
    assert row["frequency"] == pytest.approx(mo.frequency, rel=1e-14)
    assert row["gamma_shift"] == pytest.approx(row["gamma_shift_2"], rel=1e-3)
    assert abs(row["gamma_shift"]) < 1e-4
    # omega_3 dips and rises a little: its top is sqrt(w3^2 + I2 (I2 - I1) w2^2 / (I3 (I3 - I1)))
    I1, I2, I3 = _moments_mm(235, 155, 30)
    top = math.sqrt(40**2 + I2 * (I2 - I1) * 0.3**2 / (I3 * (I3 - I1)))
    assert row["omega3_max"] == pytest.approx(top, rel=1e-14) and row["omega3_min"] > 39.99
    assert row["circulates_about"].startswith("3")


def test_a_spin_near_the_middle_axis_flips(coin):
    row = _json(ok(coin(*BOOK, "--spin", "0.4,40,0.3", "-f", "json")))[0]
    I1, I2, I3 = _moments_mm(235, 155, 30)
    lam = 40 * math.sqrt((I3 - I2) * (I2 - I1) / (I1 * I3))
    assert row["lambda"] == pytest.approx(lam, rel=1e-14)
    assert row["gamma"] is None
    assert row["flip_time"] == pytest.approx(row["period"] / 2, rel=1e-15)
    assert row["flip_asymptote"] == pytest.approx(row["flip_time"], rel=1e-3)
    assert 0 < row["first_flip"] < row["flip_time"]
    # the omega_2 swings all the way through: a flip, not a wobble
    assert row["omega2_min"] == pytest.approx(-row["omega2_max"]) and row["omega2_max"] >= 40


def test_quiet_is_the_period_or_the_time_between_flips(coin):
    stable = float(ok(coin(*BOOK, "--spin", "0.4,0.3,40", "-q")))
    flips = float(ok(coin(*BOOK, "--spin", "0.4,40,0.3", "-q")))
    I = _moments_mm(235, 155, 30)
    assert stable == pytest.approx(R.motion(I, (0.4, 0.3, 40)).period, rel=1e-14)
    assert flips == pytest.approx(R.motion(I, (0.4, 40, 0.3)).half_period, rel=1e-14)


def test_units_per_side_and_on_the_spin(coin):
    a = _json(ok(coin("book", "--size", "23.5cmx15.5cmx3cm", "--spin", "0,0,40", "-f", "json")))
    b = _json(ok(coin(*BOOK, "--spin", "0,0,40rad/s", "-f", "json")))
    assert a[0]["period"] == pytest.approx(b[0]["period"], rel=1e-15)
    c = _json(ok(coin(*BOOK, "--spin", "0,0,2400rpm", "-f", "json")))[0]
    assert c["omega3_0"] == pytest.approx(2400 * 2 * math.pi / 60, rel=1e-15)
    d = _json(ok(coin(*BOOK, "--spin", "0,0,6.5rev/s", "-f", "json")))[0]
    assert d["omega3_0"] == pytest.approx(6.5 * 2 * math.pi, rel=1e-15)


def test_moments_instead_of_a_size(coin):
    I = _moments_mm(235, 155, 30)
    text = ",".join(repr(v) for v in I)
    a = _json(ok(coin("book", "--moments", text, "--spin", "0.4,40,0.3", "-f", "json")))[0]
    b = _json(ok(coin(*BOOK, "--spin", "0.4,40,0.3", "-f", "json")))[0]
    assert a["flip_time"] == pytest.approx(b["flip_time"], rel=1e-14)


def test_equal_moments_are_handled_exactly(coin):
    cube = _json(ok(coin("book", "--size", "16x16x16", "--spin", "1,2,3", "-f", "json")))[0]
    assert cube["motion"].startswith("steady") and cube["omega1_min"] == 1.0
    square = _json(ok(coin("book", "--size", "20x20x5", "--spin", "0.5,0.2,30", "-f",
                           "json")))[0]
    # a square plate is a symmetric top: the exact frequency is Gamma, exactly
    assert square["gamma_shift"] == pytest.approx(0.0, abs=1e-15)
    plate = _json(ok(coin("book", "--moments", "1,2,3", "--spin", "0,0,1", "-f", "json")))[0]
    assert plate["I3"] == 3.0  # I3 = I1 + I2: a flat plate is a body too


def test_flight_adds_the_face_up_at_the_catch(coin):
    row = _json(ok(coin(*BOOK, "--spin", "0.4,40,0.3", "--flight", "0.7", "-f", "json")))[0]
    series = list(csv.DictReader(io.StringIO(ok(coin(*BOOK, "--spin", "0.4,40,0.3", "--times",
                                                     "0.7", "-f", "csv")))))
    assert row["face_up"] == series[0]["up"]
    assert ok(coin(*BOOK, "--spin", "0,0,40", "--flight", "0.5", "-q")) == "+3\n"
    assert ok(coin(*BOOK, "--spin", "0,0,40", "--flight", "0.5", "--start", "-3", "-q")) == "-3\n"
    # spun about a horizontal axis 3, the book turns through its four long faces
    faces = ok(coin(*BOOK, "--spin", "0,0,40", "--times", "0:0.16:0.01", "--start", "-2", "-q"))
    assert set(faces.split()) == {"+1", "-1", "+2", "-2"}


# --------------------------------------------------------------------------- time series


def test_times_give_omega_the_attitude_and_the_face_up(coin):
    out = ok(coin(*BOOK, "--spin", "0.4,40,0.3", "--times", "0:2:0.01", "-f", "csv"))
    rows = list(csv.DictReader(io.StringIO(out)))
    assert len(rows) == 201 and list(rows[0]) == ["t", "omega1", "omega2", "omega3", "qw",
                                                    "qx", "qy", "qz", "up"]
    t = np.array([float(r["t"]) for r in rows])
    w = np.array([[float(r[f"omega{i}"]) for i in (1, 2, 3)] for r in rows])
    ref = R.omega_at(R.orbit(_moments_mm(235, 155, 30), np.array([0.4, 40, 0.3])), t)
    assert np.abs(w - ref).max() < 1e-12  # the moments differ in rounding (mm -> m)
    I = np.array(_moments_mm(235, 155, 30))
    E = (I * w * w).sum(1)
    L = np.sqrt(((I * w) ** 2).sum(1))
    assert np.abs(E / E[0] - 1).max() < 1e-14 and np.abs(L / L[0] - 1).max() < 1e-14
    q = np.array([[float(r[k]) for k in ("qw", "qx", "qy", "qz")] for r in rows])
    assert np.abs(np.linalg.norm(q, axis=1) - 1).max() < 1e-15
    assert rows[0]["up"] == "+3" and {r["up"] for r in rows} >= {"+3", "-3"}


@pytest.mark.parametrize("fmt", ["csv", "tsv", "json", "jsonl", "markdown", "table"])
def test_every_format_of_the_time_series(coin, fmt):
    out = ok(coin(*BOOK, "--spin", "1,40,0", "--times", "0,0.1,0.2", "-f", fmt))
    if fmt == "json":
        assert len(json.loads(out)) == 3
    elif fmt == "jsonl":
        assert [json.loads(line)["t"] for line in out.splitlines()] == [0.0, 0.1, 0.2]
    elif fmt in ("csv", "tsv"):
        assert len(out.splitlines()) == 4
    else:
        assert "face up" in out and "nan" not in out.lower()


def test_times_from_stdin(coin):
    out = ok(coin(*BOOK, "--spin", "1,40,0", "--times", "-", "-f", "csv", stdin="0\n0.5\n1\n"))
    assert [r["t"] for r in csv.DictReader(io.StringIO(out))] == ["0.0", "0.5", "1.0"]


def test_quiet_time_series_prints_the_faces(coin):
    assert ok(coin(*BOOK, "--spin", "0,0,40", "--times", "0,1,2", "-q")) == "+3\n+3\n+3\n"


# --------------------------------------------------------------------------- tosses

TOSS = [*BOOK, "--toss", "-n", "20000", "--spin", "normal:0:20,normal:0:20,normal:0:20"]


def test_toss_is_reproducible_and_reports_its_seed(coin):
    a = ok(coin(*TOSS, "--seed", "7", "-f", "csv"))
    b = ok(coin(*TOSS, "--seed", "7", "-f", "csv"))
    assert a == b
    rows = list(csv.DictReader(io.StringIO(a)))
    assert {r["seed"] for r in rows} == {"7"}
    assert sum(int(r["count"]) for r in rows) == 20000
    geo = R.face_shares((1, 155 / 235, 30 / 235))
    for r, g in zip(rows, geo, strict=True):
        assert float(r["ci_low"]) <= float(r["frequency"]) <= float(r["ci_high"])
        assert float(r["geometric"]) == g
    # no seed given: one is drawn and printed, and it reproduces the run
    out = ok(coin(*TOSS, "-f", "json"))
    seed = json.loads(out)[0]["seed"]
    assert ok(coin(*TOSS, "-f", "json", "--seed", str(seed))) == out
    note = ok(coin(*TOSS, "--seed", "7"))
    assert "seed 7" in note


def test_toss_with_a_random_start_matches_the_geometric_model(coin):
    from scipy.stats import chisquare

    out = ok(coin(*TOSS, "--seed", "2", "--start", "random", "-f", "json"))
    rows = json.loads(out)
    counts = [r["count"] for r in rows]
    expected = [r["geometric"] * 20000 for r in rows]
    assert chisquare(counts, expected).pvalue > 1e-4


def test_toss_shows_where_angular_momentum_disagrees_with_geometry(coin):
    """Spun about its long axis (stable) from lying flat, a book never shows its ends; spun
    flat about its thin axis it never turns over."""
    rows = json.loads(ok(coin(*BOOK, "--toss", "-n", "5000", "--seed", "1", "--spin",
                              "normal:40:2,normal:0:0.3,normal:0:0.3", "--flight",
                              "uniform:0.4:0.8", "-f", "json")))
    assert rows[0]["count"] == rows[1]["count"] == 0 and rows[0]["geometric"] > 0.02
    rows = json.loads(ok(coin(*BOOK, "--toss", "-n", "5000", "--seed", "1", "--spin",
                              "normal:0:0.3,normal:0:0.3,normal:40:4", "-f", "json")))
    assert rows[4]["count"] == 5000


def test_toss_distribution_units_and_quiet(coin):
    a = ok(coin(*BOOK, "--toss", "-n", "3000", "--seed", "3", "--spin",
                "normal:0:1rev/s,0,6rev/s", "--flight", "500ms", "-q"))
    b = ok(coin(*BOOK, "--toss", "-n", "3000", "--seed", "3", "--spin",
                f"normal:0:{2 * math.pi!r},0,{12 * math.pi!r}", "--flight", "0.5", "-q"))
    assert a == b and len(a.splitlines()) == 6
    assert sum(float(v) for v in a.split()) == pytest.approx(1.0)


def test_normal_rule_gives_a_sixth_to_every_face_geometrically(coin):
    rows = json.loads(ok(coin(*TOSS, "--seed", "1", "--rule", "normal", "-f", "json")))
    assert all(r["geometric"] == 1 / 6 for r in rows)


# --------------------------------------------------------------------------- files


@pytest.mark.slow
def test_out_writes_a_figure_atomically(coin, tmp_path):
    path = tmp_path / "book.png"
    rc, out, err = coin(*BOOK, "--spin", "0.4,40,0.3", "--out", str(path))
    # a figure written says so, as coin plot and coin phase do (the shared cli writer)
    assert (rc, out) == (0, "") and err == f"coin: wrote {path} (1125 x 780 pixels)\n", err
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert os.listdir(tmp_path) == ["book.png"]  # no temporary file left behind
    svg = tmp_path / "faces.svg"
    rc, out, err = coin(*TOSS, "--seed", "1", "-n", "2000", "--out", str(svg))
    assert rc == 0 and err.startswith(f"coin: wrote {svg} (") and err.endswith(" inches)\n")
    assert b"<svg" in svg.read_bytes()[:400]


def test_out_writes_the_table_in_its_format(coin, tmp_path):
    path = tmp_path / "series.csv"
    ok(coin(*BOOK, "--spin", "1,40,0", "--times", "0:1:0.5", "-f", "csv", "--out", str(path)))
    assert path.read_text() == ok(coin(*BOOK, "--spin", "1,40,0", "--times", "0:1:0.5", "-f",
                                       "csv"))


def test_out_to_a_missing_directory_fails_cleanly(coin, tmp_path):
    error(coin(*BOOK, "--spin", "1,40,0", "--out", str(tmp_path / "no" / "x.png")), 1,
          "cannot write")


# --------------------------------------------------------------------------- bad input

BAD = [
    (["book", "--spin", "0,0,40"], "--size"),
    ([*BOOK, "--moments", "1,2,3", "--spin", "0,0,1"], "one of them"),
    (["book", "--size", "0x155x30", "--spin", "0,0,1"], "> 0"),
    (["book", "--size", "-235x155x30", "--spin", "0,0,1"], "side 1"),
    (["book", "--size", "infx155x30", "--spin", "0,0,1"], "side 1"),
    (["book", "--size", "nanx155x30", "--spin", "0,0,1"], "side 1"),
    (["book", "--size", "235x155", "--spin", "0,0,1"], "three lengths"),
    (["book", "--size", "235x155x30x4", "--spin", "0,0,1"], "three lengths"),
    (["book", "--moments", "1,2,4", "--spin", "0,0,1"], "no rigid body"),
    (["book", "--moments", "1,0,1", "--spin", "0,0,1"], "I2"),
    (["book", "--moments", "1,inf,1", "--spin", "0,0,1"], "I2"),
    ([*BOOK], "--spin"),
    ([*BOOK, "--spin", "0,40"], "three components"),
    ([*BOOK, "--spin", "0,40,nan"], "component 3"),
    ([*BOOK, "--spin", "0,40,inf"], "component 3"),
    ([*BOOK, "--spin", "0,40,1e999"], "component 3"),
    ([*BOOK, "--spin", "0,40,3furlongs"], "component 3"),
    ([*BOOK, "--spin", "normal:0:1,0,40"], "component 1"),
    ([*BOOK, "--spin", "0,0,40", "--times", "0:1e30:1e29"], "rad"),
    ([*BOOK, "--spin", "0,0,40", "--times", "-1"], ">= 0"),
    ([*BOOK, "--spin", "0,0,40", "--times", "0:1:0"], "step"),
    ([*BOOK, "--spin", "0,0,40", "--times", "0:1e9:1e-3"], "at most"),
    ([*BOOK, "--spin", "0,0,40", "--flight", "normal:1:0.1"], "--flight"),
    ([*BOOK, "--spin", "0,0,40", "--flight", "1e30"], "rad"),
    ([*BOOK, "--spin", "0,0,40", "--start", "top"], "--start"),
    ([*BOOK, "--spin", "0,0,40", "--start", "random"], "--toss"),
    ([*BOOK, "--spin", "0,0,40", "--rule", "nearest"], "--rule"),
    ([*BOOK, "--spin", "0,0,40", "-n", "5"], "--toss"),
    ([*BOOK, "--spin", "0,0,40", "--seed", "5"], "--toss"),
    ([*BOOK, "--spin", "0,0,40", "-f", "xml"], "--format"),
    ([*BOOK, "--spin", "0,0,40", "--out", "x.gif", "--times", "0"], ".png"),
    ([*BOOK, "--spin", "0,0,40", "--start", "+1"], "--start"),
    ([*BOOK, "--spin", "0,0,40", "--rule", "normal"], "--rule"),
    ([*TOSS, "-n", "0"], "-n"),
    ([*TOSS, "-n", "1e5"], "-n"),
    ([*TOSS, "-n", "10000001"], "10000000"),
    ([*TOSS, "--seed", "-1"], "--seed"),
    ([*TOSS, "--times", "0"], "--times"),
    ([*BOOK, "--toss", "--spin", "normal:0:-1,0,0"], "SD >= 0"),
    ([*BOOK, "--toss", "--spin", "gamma:1:2,0,0"], "unknown distribution"),
    ([*BOOK, "--toss", "--spin", "uniform:2:1,0,0"], "LOW <= HIGH"),
    ([*BOOK, "--toss", "--spin", "0,0,40", "--flight", "-0.5"], "--flight"),
    ([*BOOK, "--toss", "--spin", "0,0,40", "--flight", "normal:-50:1"], "no probability"),
    ([*BOOK, "--toss", "--spin", "normal:0:1e12,0,0", "--flight", "1"], "rad"),
    ([*BOOK, "--spin", "0,0,40", "--flight", "-1"], ">= 0"),  # was exit 1
    # found by fuzzing: moments 1e-316 of each other overflowed their ratios (nan in the table)
    (["book", "--size", "4.3e-307x4.2e-08x1.5e+150", "--spin", "2.7,0,-9e40"], "span"),
    (["book", "--size", "4.3e-307x4.2e-08x1.5e+150", "--spin", "2.7,0,-9e40", "--toss"], "span"),
    ([*BOOK, "--spin", "1e-200,40,0"], "middle axis"),  # was 'on the separatrix'
    ([*BOOK, "--spin", "1e-200,40,0", "--times", "0,1"], "middle axis"),
    ([*BOOK, "--spin", "0,40,1e-320", "--flight", "1"], "middle axis"),
    ([*BOOK, "--toss", "--spin", "1e-200,40,0"], "middle axis"),
    ([*BOOK, "--toss", "--spin", "normal:38rev/s:4,0,0"], "unit once at the end"),
    ([*BOOK, "--toss", "--spin", "0,0,40", "--flight", "uniform:400ms:0.6"], "unit once"),
]


@pytest.mark.parametrize("argv, word", BAD)
def test_bad_input_is_one_line_and_exit_2(coin, argv, word, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    error(coin(*argv), 2, *([word] if word else []))
    assert os.listdir(tmp_path) == []


@pytest.mark.parametrize("argv", [
    [*BOOK, "--spin", "1e300,1,1"],
    [*BOOK, "--spin", "1e-300,1e-300,1e-300"],
    [*BOOK, "--spin", "5e-324,0,0"],
    [*BOOK, "--spin", "0,0,0"],
    [*BOOK, "--spin", "0,40,0"],
    ["book", "--size", "1e-300x1x1", "--spin", "1,2,3"],
    ["book", "--size", "1e150x1x1e-150", "--spin", "1,2,3"],
    ["book", "--moments", "1,1,1", "--spin", "1,2,3"],
    ["book", "--moments", "1,1,2", "--spin", "0,1,1"],
    ["book", "--moments", "2,5,7", "--spin", "2,1,1"],
    # found by fuzzing: two moments 1e-17 apart (tied in doubles), spins near the double range
    ["book", "--size", "1.1e-05x30527288.7x0.2073", "--spin", "7.5e-08,-19587759.5,1e308"],
    ["book", "--size", "841481.36x0.00012014x0.00052486", "--spin", "-0.5,8.3e-06,-1e300"],
    # a spin of 5e-324 (I * omega underflowed: 'float division by zero'), and a needle whose
    # smallest moment is 1e-300 of the others spun off its axis (the attitude was nan)
    ["book", "--size", "3x4x5", "--spin", "0,5e-324,-0"],
    ["book", "--size", "1e150x1x1e-150", "--spin", "1e-8,3,0.4"],
    ["book", "--moments", "3.6,3.1,5.1", "--spin", "0,0,0"],  # at rest, axis 1 the middle one
    # a steady spin of 5e300 rad/s (|omega| overflowed in the attitude's rotation: nan)
    ["book", "--size", "3.7e-09x3.5e+40x6.9e-08", "--spin", "-4.9e300,3.6e-300,4.4e-08"],
])
def test_extreme_but_valid_inputs_print_no_nan(coin, argv):
    for fmt in ("table", "csv", "json"):
        out = ok(coin(*argv, "-f", fmt))
        assert "nan" not in out.lower()
    spin = [float(v) for v in argv[argv.index("--spin") + 1].split(",")]
    t = 1 / max(max(abs(v) for v in spin), 1e-300)
    out = ok(coin(*argv, "--times", f"0,{t!r}", "-f", "csv"))
    assert "nan" not in out.lower() and len(out.splitlines()) == 3


def test_toss_with_a_spin_near_the_double_range(coin):
    out = ok(coin("book", "--moments", "4028.55,55030457.9,55033076.0", "--toss", "-n", "300",
                  "--seed", "1", "--spin", "-419208.97,uniform:0:1e308,3", "--flight", "0",
                  "-f", "csv"))
    assert "nan" not in out and out.count("\n") == 7
    error(coin("book", "--moments", "4028.55,55030457.9,55033076.0", "--toss", "-n", "300",
               "--spin", "-419208.97,1e308,1e308", "--flight", "0.5"), 2, "rad")


def test_help_names_the_examples(coin):
    out = ok(coin("book", "--help"))
    for word in ("--size", "--moments", "--spin", "--times", "--toss", "--flight", "--start",
                 "--rule", "Examples"):
        assert word in out


# --------------------------------------------------------------------------- imports

_PROBE = r"""
import json, sys
from coincli.cli import run
code = run(json.loads(sys.argv[1]))
sys.stdout.flush()
mods = sorted(m for m in sys.modules if m.split(".")[0] in ("numpy", "scipy", "rich",
                                                            "matplotlib"))
print(json.dumps([code, mods]), file=sys.stderr)
"""


def _loaded(argv):
    p = subprocess.run([sys.executable, "-c", _PROBE, json.dumps(argv)], capture_output=True,
                       text=True, timeout=120)
    code, mods = json.loads(p.stderr.strip().splitlines()[-1])
    assert code == 0, p.stderr
    return {m for m in mods}


def test_the_motion_table_imports_neither_numpy_scipy_rich_nor_matplotlib():
    mods = _loaded([*BOOK, "--spin", "0.4,40,0.3"])
    assert not mods, sorted(mods)[:5]


@pytest.mark.slow
def test_series_and_tosses_import_only_numpy_and_scipy_special(tmp_path):
    for argv in ([*BOOK, "--spin", "0.4,40,0.3", "--times", "0:1:0.1", "-f", "csv"],
                 [*BOOK, "--spin", "0.4,40,0.3", "--flight", "0.5"],
                 [*TOSS, "-n", "100", "--seed", "1"],
                 [*BOOK, "--spin", "0,0,40", "--times", "0,1", "--out",
                  str(tmp_path / "x.csv")]):
        mods = _loaded(argv)
        assert "numpy" in mods
        assert not {m for m in mods if m.startswith("matplotlib")}, argv
        scipy = {m.split(".")[1] for m in mods if m.startswith("scipy.") and
                 not m.split(".")[1].startswith("_")}
        assert scipy <= {"special", "linalg", "sparse", "version", "__config__", "constants"}, \
            (argv, scipy)
        assert not {m for m in mods if m.startswith(("scipy.stats", "scipy.integrate"))}


@pytest.mark.slow
def test_a_figure_imports_matplotlib(tmp_path):
    mods = _loaded([*BOOK, "--spin", "0.4,40,0.3", "--out", str(tmp_path / "b.png")])
    assert "matplotlib" in mods


def test_out_refuses_a_directory_before_computing(coin, tmp_path):
    error(coin(*BOOK, "--spin", "1,40,0", "--times", "0", "-f", "csv", "--out", str(tmp_path)),
          2, "--out")


def test_no_headers_and_negative_spins_with_units(coin):
    out = ok(coin(*BOOK, "--spin", "-0.4,-6.4rev/s,90deg/s", "--times", "0", "-f", "csv",
                  "--no-headers"))
    w = [float(v) for v in out.split(",")[1:4]]
    assert w == pytest.approx([-0.4, -6.4 * 2 * math.pi, math.pi / 2], rel=1e-15)


def test_a_unit_at_the_end_of_a_distribution_applies_to_every_number(coin):
    # as coin simulate --omega reads normal:38:4rev/s: both numbers in rev/s
    toss = [*BOOK, "--toss", "-n", "2000", "--seed", "4", "-f", "csv"]
    once = ok(coin(*toss, "--spin", "normal:6:1rev/s,0.5,uniform:-1:1rpm", "--flight",
                   "normal:500:50ms"))
    every = ok(coin(*toss, "--spin", "normal:6rev/s:1rev/s,0.5,uniform:-1rpm:1rpm", "--flight",
                    "normal:500ms:50ms"))
    assert once == every
    si = ok(coin(*toss, "--spin", f"normal:{12 * math.pi!r}:{2 * math.pi!r},0.5,"
                 f"uniform:{-math.pi / 30!r}:{math.pi / 30!r}", "--flight", "normal:0.5:0.05"))
    assert once == si


def test_a_spin_exactly_on_the_separatrix(coin):
    # 2 E I2 = L^2 exactly: one flip, never back (was 'periodic', period 99 s, from rounding)
    d = _json(ok(coin("book", "--moments", "3,4,6", "--spin", "2,1,1", "-f", "json")))[0]
    assert d["motion"].startswith("on the separatrix") and d["period"] == "inf"
    assert d["m"] == 1.0
    assert d["flip_time"] == "inf" and d["first_flip"] == "inf"  # omega2 > 0 ever after
    # launched the other way round it flips once, when omega2 changes sign: an independent
    # integration (DOP853) puts that at 0.5826649...s
    d = _json(ok(coin("book", "--moments", "3,4,6", "--spin", "2,-1,1", "-f", "json")))[0]
    assert d["first_flip"] == pytest.approx(0.58266494, abs=1e-8)
    out = ok(coin("book", "--moments", "3,4,6", "--spin", "2,-1,1"))
    assert "Exactly on the separatrix" in out and "is stable" not in out


def test_the_time_series_starts_at_the_launch_values_exactly(coin):
    rows = list(csv.reader(io.StringIO(ok(coin(*BOOK, "--spin", "0.4,40,0.3", "--times",
                                                    "0,0.1", "-f", "csv")))))
    assert rows[1][:8] == ["0.0", "0.4", "40.0", "0.3", "1.0", "0.0", "0.0", "0.0"]


def test_a_figure_without_matplotlib_fails_before_any_toss(coin, tmp_path, monkeypatch):
    for name in list(sys.modules):
        if name == "matplotlib" or name.startswith("matplotlib."):
            monkeypatch.delitem(sys.modules, name)
    monkeypatch.setitem(sys.modules, "matplotlib", None)

    def no_tosses(*args, **kwargs):
        raise AssertionError("tossed before finding that the figure cannot be drawn")

    monkeypatch.setattr(R, "toss_chunks", no_tosses)
    monkeypatch.setattr(R, "attitude_at", no_tosses)
    png = tmp_path / "b.png"
    for argv in ([*BOOK, "--toss", "-n", "10000000", "--spin", "1,2,40"],
                 [*BOOK, "--spin", "0.4,40,0.3"]):
        error(coin(*argv, "--out", str(png)), 1, "matplotlib")
    assert os.listdir(tmp_path) == []


def test_times_take_units_in_ranges_as_in_lists(coin):
    def ts(spec):
        out = ok(coin(*BOOK, "--spin", "0.4,40,0.3", "--times", spec, "-f", "csv"))
        return [float(r.split(",")[0]) for r in out.splitlines()[1:]]

    ref = ts("0,0.1,0.2,0.3")
    for spec in ("0:300:100ms", "0ms:300ms:100ms", "0,100ms,200ms,300ms", "0:0.3:0.1s"):
        assert ts(spec) == pytest.approx(ref, abs=1e-15), spec
    error(coin(*BOOK, "--spin", "0.4,40,0.3", "--times", "0s:500ms:0.1"), 2, "unit once")


@pytest.mark.parametrize("spec, unit", [("0:2:0.01", ""), ("0:1:0.3", ""), ("0:600:100", "ms"),
                                        ("1/3:3:1/7", ""), ("0.5:0.5:1", "s"),
                                        ("0:0.99999:0.00001", "")])
def test_a_range_of_times_is_the_shared_grammar_s_values(spec, unit):
    # the vectorized range gives exactly what coincli.io.grammar.parse_values gives item by item
    from coincli.io import grammar as parse
    from coincli.reports import book as B

    factor = B._TIME_UNITS[unit or "s"]
    ref = parse.parse_values(spec, "--times", lambda s, w: float(s) * factor if "/" not in s
                             else parse.parse_ratio(s) * factor)
    got = B._times(spec + unit) if unit else B._times(spec)
    assert np.asarray(got).tolist() == ref


@pytest.mark.slow
def test_times_out_file_is_the_stdout_bytes(coin, tmp_path):
    argv = [*BOOK, "--spin", "0.4,40,0.3", "--times", "0:3:0.0001"]
    for fmt in ("csv", "jsonl", "table"):
        out = ok(coin(*argv, "-f", fmt))
        path = tmp_path / f"s.{fmt}"
        ok(coin(*argv, "-f", fmt, "--out", str(path)))
        assert path.read_text(encoding="utf-8") == out
    assert len(out.splitlines()) > 30001


@pytest.mark.slow
def test_a_long_time_series_is_streamed_in_flat_memory(tmp_path):
    """Peak memory of --times with 2e4 and 2e5 rows differs by far less than the rows' text
    (a buffered run held ~1 kB a row: 944 MB at 10^6 rows; streamed, ~80 MB at any count)."""
    code = ("import resource, sys; from coincli.cli import main; sys.argv = ['coin', 'book', "
            "'--size', '235x155x30', '--spin', '0.4,40,0.3', '--times', sys.argv[1], '-f', "
            "'csv', '--out', sys.argv[2]]\n"
            "try: main()\nexcept SystemExit: pass\n"
            "print(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss)")
    peaks = []
    for spec in ("0:1.9999:0.0001", "0:1.99999:0.00001"):
        r = subprocess.run([sys.executable, "-c", code, spec, str(tmp_path / "s.csv")],
                           capture_output=True, text=True, check=True)
        peaks.append(int(r.stdout.split()[-1]))  # kB
    with open(tmp_path / "s.csv") as f:  # every row of the longer run was written
        rows = [line for line in f if line.strip() and not line.startswith("#")]
    assert len(rows) == 1 + 200_000 and rows[-1].startswith("1.99999,")
    assert peaks[1] - peaks[0] < 40_000, peaks


def test_the_figure_of_a_separatrix_marks_its_one_flip():
    pytest.importorskip("matplotlib")
    from coincli.render import book_figures as bookplot

    I, w = (3.0, 4.0, 6.0), (2.0, -1.0, 1.0)
    mo = R.motion(I, w)
    o = R.orbit(I, np.array(w))
    t = np.linspace(0.0, 20.0, 2001)
    q = R.attitude_at(o, t)
    up = R.face_up(R.up_vector(q), R.box_sides(I))
    fig = bookplot.omega_figure(t, R.omega_at(o, t), up, mo, "moments 3, 4, 6", "+3", "centre")
    flips = [a for a in fig.findobj(lambda a: a.get_gid() == "flip")]
    assert len(flips) == 1 and flips[0].get_xdata()[0] == pytest.approx(0.58266494, abs=1e-4)
    assert "separatrix" in fig.axes[0].get_title()


def test_toss_quiet_reports_a_drawn_seed_that_repeats_the_bytes(coin):
    import re

    argv = ["book", "--size", "16x16x16", "--toss", "-n", "200", "--spin", "normal:30:1,0,0", "-q"]
    rc, out, err = coin(*argv)
    assert rc == 0
    m = re.fullmatch(r"coin: seed (\d+) \(--seed \1 repeats this run\)\n", err)
    assert m, err
    assert coin(*argv, "--seed", m.group(1)) == (0, out, "")


def test_a_body_at_rest_has_no_spin_axis_and_no_gamma(coin):
    rows = _json(ok(coin("book", "--moments", "1,2,3", "--spin", "0,0,0", "-f", "json")))
    row = rows[0] if isinstance(rows, list) else rows
    for key in ("spin_axis", "gamma", "gamma_shift", "lambda"):
        assert row[key] is None, (key, row[key])


def test_times_from_stdin_name_the_bad_line(coin):
    error(coin("book", "--size", "235x155x30", "--spin", "0.4,40,0.3", "--times", "-",
               stdin="0\n0.1\nabc\n"), 2, "stdin line 3", "--times", "'abc'")


@pytest.mark.parametrize("moments", [(1.0, 2.0, 3.0), (1.0, 1.7, 2.2)])
def test_the_faces_figure_ticks_do_not_overlap(moments):
    # a box from --moments labels its faces "0.7071 x 0 (relative)": six such ticks side by
    # side overlapped in the 7-inch figure until the size went on lines of its own
    pytest.importorskip("matplotlib")
    from types import SimpleNamespace

    from coincli.render import book_figures as bookplot
    from coincli.reports.book import face_size

    box = SimpleNamespace(size_mm=None, sides=R.box_sides(moments))
    rows = [(f"{s}{k // 2 + 1}", face_size(box, k), 0, 1 / 6, 0.1, 0.2, 1 / 6)
            for k, s in zip(range(6), "+-+-+-")]
    assert all(r[1].endswith("(relative)") for r in rows)
    fig = bookplot.faces_figure(rows, "moments", 1000, 1, "centre")
    fig.canvas.draw()
    boxes = [t.get_window_extent() for t in fig.axes[0].get_xticklabels()]
    assert len(boxes) == 6
    for a, b in zip(boxes, boxes[1:]):
        assert a.x1 < b.x0, (a, b)


# --------------------------------------------------------------------------- issue 28, item 15


@pytest.mark.parametrize("size", ["1e-300x1e-300x1e-300", "1e-151x1e-151x1e-151",
                                  "1e-200x1e-200x1"])
def test_a_box_too_small_for_doubles_names_size(coin, size):
    """Its moments underflow to 0 (or a subnormal): the message names --size as typed and says
    why, not 'moments ... got 0, 0, 0' (options the user did not type)."""
    err = error(coin("book", "--size", size, "--spin", "1,2,3"), 2,
                "--size: the sides are too small for double precision",
                "at least 3.7e-151 mm", f"got '{size}'")
    assert "got 0, 0, 0" not in err


def test_the_smallest_cube_is_the_bound_the_message_states(coin):
    side = R.SMALLEST_CUBE  # the moments 2 s^2 / 12 of a cube of this side are normal doubles
    assert min(R.box_moments((side,) * 3)) >= sys.float_info.min
    with pytest.raises(ValueError, match="too small"):
        R.box_moments((side * 0.99,) * 3)
    ok(coin("book", "--size", f"{side * 1000 * 1.01!r}x{side * 1000 * 1.01!r}x"
            f"{side * 1000 * 1.01!r}", "--spin", "1,2,3", "-f", "csv"))


@pytest.mark.parametrize("moments, shown", [
    ("1,1,2.0000001", "(I3 = 2.0000001 > I1 + I2 = 2)"),
    ("1,1,2.000000000001", "(I3 = 2.000000000001 > I1 + I2 = 2)"),
    ("3,1,1", "(I1 = 3 > I2 + I3 = 2)"),
    ("0.1,0.2,0.30000001", "(I3 = 0.30000001 > I1 + I2 = 0.3)"),
])
def test_moments_that_belong_to_no_body_are_shown_with_digits_that_differ(coin, moments,
                                                                         shown):
    """The two sides of the inequality printed with the fewest digits (6 at least) that tell
    them apart: never '2 > 2'."""
    err = error(coin("book", "--moments", moments, "--spin", "1,2,3"), 2, shown,
                "belong to no rigid body")
    lhs, rhs = err.split("(I")[1].rstrip(")\n").split(" > ")
    assert float(lhs.split(" = ")[1]) > float(rhs.split(" = ")[1])


# --------------------------------------------------------------------------- issue 28, item 14


def _columns_of(t, t0, t1, columns):
    return np.clip(np.floor((t - t0) * (columns / (t1 - t0))), 0, columns - 1).astype(int)


@pytest.mark.slow
def test_a_long_series_is_thinned_to_its_pixel_columns_keeping_the_envelope():
    """10^6 samples of three curves (a chirp, noise-like, a step) drawn as at most four points
    per pixel column each: in every column the thinned curve has the whole series' first and
    last point and its smallest and largest value (the M4 rule), so the line covers the same
    pixels; the face-up curve likewise."""
    pytest.importorskip("matplotlib")
    from coincli.render import book_figures as bookplot

    n, cols = 1_000_000, bookplot.PIXEL_COLUMNS
    ts = np.linspace(0.0, 50.0, n)

    def omega_up(t):  # independent of coin's physics: any curves must keep their envelope
        w = np.column_stack([np.sin(0.01 * t * t), np.sin(1e4 * t) * np.cos(7 * t),
                             np.floor(t) % 3 - 1.0])
        return w, (np.floor(t * 3) % 6).astype(int)

    mo = R.motion((1.0, 2.0, 3.0), (0.0, 0.0, 1.0))
    fig = bookplot.omega_figure_of(ts, omega_up, mo, "test", "+3", "centre", chunk=70_001)
    full_w, full_up = omega_up(ts)
    col = _columns_of(ts, 0.0, 50.0, cols)
    lines = {a.get_gid(): a for a in fig.findobj(lambda a: a.get_gid() is not None)}
    for gid, full in [("omega:1", full_w[:, 0]), ("omega:2", full_w[:, 1]),
                      ("omega:3", full_w[:, 2]), ("face-up", full_up)]:
        x, y = (np.asarray(v, dtype=float) for v in lines[gid].get_data())
        if gid == "face-up":  # a step line: matplotlib's own data are the points given
            x, y = np.asarray(lines[gid].get_xdata()), np.asarray(lines[gid].get_ydata())
        assert x.size <= 4 * cols and np.all(np.diff(x) >= 0), (gid, x.size)
        c = _columns_of(x, 0.0, 50.0, cols)
        assert np.array_equal(np.unique(c), np.unique(col))
        lo = np.full(cols, np.inf)
        hi = np.full(cols, -np.inf)
        np.minimum.at(lo, col, full)
        np.maximum.at(hi, col, full)
        tlo = np.full(cols, np.inf)
        thi = np.full(cols, -np.inf)
        np.minimum.at(tlo, c, y)
        np.maximum.at(thi, c, y)
        assert np.array_equal(tlo, lo) and np.array_equal(thi, hi), gid
        starts = np.flatnonzero(np.r_[True, col[1:] != col[:-1]])
        assert set(ts[starts]) <= set(x) and set(ts[np.r_[starts[1:] - 1, n - 1]]) <= set(x)


def test_a_short_series_is_drawn_as_it_is():
    """Up to THIN_ABOVE times the figure is the unthinned one (the default 2001 samples)."""
    pytest.importorskip("matplotlib")
    from coincli.render import book_figures as bookplot

    I, w = (3.0, 4.0, 6.0), (2.0, -1.0, 1.0)
    mo, o = R.motion(I, w), R.orbit(I, np.array(w))
    t = np.linspace(0.0, 20.0, bookplot.THIN_ABOVE)

    def omega_up(t):
        return R.omega_at(o, t), R.face_up(R.up_vector(R.attitude_at(o, t)), R.box_sides(I))

    fig = bookplot.omega_figure_of(t, omega_up, mo, "m", "+3", "centre")
    (line,) = fig.findobj(lambda a: a.get_gid() == "omega:2")
    assert np.array_equal(line.get_xdata(), t)
    flips = fig.findobj(lambda a: a.get_gid() == "flip")
    assert len(flips) == 1 and flips[0].get_xdata()[0] == pytest.approx(0.58266494, abs=1e-4)


def test_the_figure_of_a_long_times_series_has_a_bounded_file(coin, tmp_path):
    """`--times 0:999999:1 --out x.png` peaked at 2.4 GB and failed in Agg; the SVG of 10^6
    points was 120 MB.  Thinned, 3 x 10^4 times make a file of the size 10^6 make (figures in
    docs/book.md, from benchmarks/bench_book_figure.py)."""
    pytest.importorskip("matplotlib")
    out = tmp_path / "x.svg"
    rc, _, err = coin("book", "--moments", "1,2,3", "--spin", "1,2,3", "--times", "0:29999:1",
                      "--out", str(out))
    assert (rc, err) == (0, f"coin: wrote {out} (7.5 x 5.2 inches)\n")
    assert out.stat().st_size < 1_200_000  # 3.6 MB unthinned


def test_a_figure_error_is_one_line(coin, tmp_path, monkeypatch):
    """matplotlib's errors run over lines ("Exceeded cell block limit in Agg.\\n\\nPlease
    reduce..."): one line, exit 1, nothing written."""
    pytest.importorskip("matplotlib")
    from coincli.render import figures

    def fail(*_a, **_k):
        raise OverflowError("Exceeded cell block limit in Agg.\n\nPlease reduce the value of "
                            "rcParams['agg.path.chunksize'] (currently 0) or increase the\n"
                            "path simplification threshold")

    monkeypatch.setattr(figures, "save_figure", fail)
    out = tmp_path / "x.png"
    err = error(coin("book", "--moments", "1,2,3", "--spin", "1,2,3", "--out", str(out)), 1,
                "cannot draw", "Exceeded cell block limit in Agg. Please reduce", "increase the "
                "path simplification")
    assert not out.exists() and os.listdir(tmp_path) == []
    assert "\n" not in err[:-1]
