"""``coin toss``, ``coin simulate``, ``coin phase`` run in-process through :func:`coincli.cli.run`.

Every printed number is read back and compared, as a double, with :mod:`coincli.core.toss`; bad
input is one line on stderr with exit 2 and nothing on stdout.  No timing here.
"""

from __future__ import annotations

import csv
import io
import json
import math
import re
import subprocess
import sys

import numpy as np
import pytest
from cli_helpers import error as _error
from cli_helpers import ok as _ok

from coincli.core.toss import batch as TB
from coincli.core.toss import flight as T
from coincli.core.toss import launch as TL
from coincli.core.toss import phase as TP
from coincli.core.toss import simulate as TS

FAIR = 0.577


# --------------------------------------------------------------------------- coin toss


def test_toss_json_is_the_core_bit_for_bit(coin):
    out = _ok(coin("toss", "--xi", "0.577", "--psi", "90", "--u", "2.0", "--omega", "40",
                   "--format", "json"))
    (row,) = json.loads(out)
    r = TB.toss(0.577, math.pi / 2, 2.0, 40.0)
    assert row["t_f"] == r.t_f
    assert row["turns"] == r.turns
    assert row["alpha_f_deg"] == math.degrees(r.alpha_f)
    assert row["theta0_deg"] == math.degrees(r.theta0)
    assert row["vigor"] == r.vigor
    assert row["outcome"] == r.outcome
    assert row["contact"] == "rim"
    assert row["z0_mm"] == pytest.approx(math.sqrt(3) / 2 * 12.13, rel=1e-14)


def test_toss_human_table_and_quiet(coin):
    out = _ok(coin("toss", "--xi", "0.577", "--psi", "90", "--u", "2", "--omega", "40"))
    for word in ("t_f (s)", "turns", "alpha_f (deg)", "theta0 (deg)", "vigor", "outcome",
                 "tails"):
        assert word in out
    assert _ok(coin("toss", "--xi", "0.577", "--psi", "90", "--u", "2", "--omega", "40",
                    "-q")) == "tails\n"


def test_toss_options_diameter_g_contact_z0(coin):
    out = _ok(coin("toss", "--xi", "0.4", "--psi", "70", "--u", "1.5", "--omega", "55",
                   "--diameter", "2.5cm", "--g", "9.8", "--contact", "thick", "--z0", "20",
                   "--format", "json"))
    (row,) = json.loads(out)
    r = TB.toss(0.4, math.radians(70), 1.5, 55.0, diameter=0.025, g=9.8, contact="thick",
                z0=0.02)
    assert row["t_f"] == r.t_f and row["outcome"] == r.outcome and row["contact"] == "thick"


def test_toss_lists_pair_up_and_match_toss_many(coin):
    out = _ok(coin("toss", "--xi", "0.577", "--psi", "90", "--u", "2", "--omega", "30:50:0.5",
                   "--format", "csv"))
    rows = list(csv.DictReader(io.StringIO(out)))
    assert len(rows) == 41
    w = np.array([float(r["omega"]) for r in rows])
    v = TB.toss_many(0.577, math.pi / 2, 2.0, w)
    assert [float(r["t_f"]) for r in rows] == v.t_f.tolist()
    assert [r["outcome"] for r in rows] == [T.NAMES[c] for c in v.code]
    for r in rows[::10]:
        s = TB.toss(0.577, math.pi / 2, 2.0, float(r["omega"]))
        assert float(r["t_f"]) == pytest.approx(s.t_f, rel=1e-12)


def test_toss_reads_stdin(coin):
    out = _ok(coin("toss", "--xi", "0.577", "--psi", "90", "--u", "-", "--omega", "40",
                   "--format", "csv", stdin="1\n2\n# a comment\n3\n"))
    assert [float(r["u"]) for r in csv.DictReader(io.StringIO(out))] == [1.0, 2.0, 3.0]


@pytest.mark.parametrize("argv,words", [
    (["--u", "-2"], ["--u"]),
    (["--omega", "-1"], ["--omega"]),
    (["--psi", "200"], ["--psi", "180"]),
    (["--xi", "-0.1"], ["--xi"]),
    (["--g", "0"], ["--g"]),
    (["--g", "-9.81"], ["--g"]),
    (["--diameter", "0"], ["--diameter"]),
    (["--contact", "edge"], ["--contact"]),
    (["--omega", "1e13"], ["omega", "1e+12"]),
    (["--u", "1,2", "--omega", "1,2,3"], ["one value or 3"]),
    (["--xi", "__import__('os')"], ["--xi"]),
    (["--z0", "1", "--contact", "thick", "--xi", "1"], ["z0"]),
])
def test_toss_bad_input_is_one_line_exit_2(coin, argv, words):
    base = {"--xi": "0.577", "--psi": "90", "--u": "2", "--omega": "40"}
    extra = []
    it = iter(argv)
    for k in it:
        v = next(it)
        if k in base:
            base[k] = v
        else:
            extra += [k, v]
    args = [x for kv in base.items() for x in kv] + extra
    _error(coin("toss", *args), 2, *words)


def test_toss_draws_what_is_missing_from_a_hand_toss_and_reports_the_seed(coin):
    # was a usage error naming --omega; now a realistic hand toss fills the gap
    out = _ok(coin("toss", "--xi", "0.5", "--psi", "90", "--u", "2", "--seed", "4", "-f", "csv"))
    row = next(csv.DictReader(io.StringIO(out)))
    assert row["seed"] == "4" and row["psi_deg"] == "90.0" and row["u"] == "2.0"
    rng = np.random.default_rng(4)
    w = TL.HAND_TOSS["omega"].sample(rng, 1)
    assert float(row["omega"]) == float(w[0])
    assert _ok(coin("toss", "--xi", "0.5", "--psi", "90", "--u", "2", "--seed", "4", "-f",
                    "csv")) == out  # the same seed, the same bytes
    human = _ok(coin("toss", "--xi", "0.5"))
    assert "Drawn from a hand toss (Diaconis, Holmes & Montgomery 2007)" in human
    seed = int(human.split("; seed ")[1].split()[0])
    again = _ok(coin("toss", "--xi", "0.5", "--seed", str(seed)))
    assert again == human
    _error(coin("toss", "--xi", "0.5", "--psi", "90", "--u", "2", "--omega", "40", "--seed",
                "1"), 2, "--seed seeds what is drawn")


# --------------------------------------------------------------------------- coin simulate


SIM = ["simulate", "--xi", "0.577", "--u", "normal:2.4:0.3", "--omega", "normal:38:4"]


def test_simulate_csv_is_the_core(coin):
    out = _ok(coin(*SIM, "--psi-dist", "normal:90:10", "-n", "20000", "--seed", "7",
                   "--format", "csv"))
    rows = list(csv.DictReader(io.StringIO(out)))
    from coincli.io.grammar import parse_density

    psi = TL.Dist.from_density(parse_density("normal:90:10"))  # the grammar of coin design
    sim = TS.simulate(20000, 7, xi=0.577, u="normal:2.4:0.3", omega="normal:38:4", psi=psi)
    assert [r["outcome"] for r in rows] == ["heads", "sides", "tails"]
    assert tuple(int(r["count"]) for r in rows) == sim.counts
    for r, f, p in zip(rows, sim.frequencies, sim.vigorous, strict=True):
        assert float(r["frequency"]) == f.p
        assert float(r["ci_low"]) == f.lo and float(r["ci_high"]) == f.hi
        assert float(r["vigorous"]) == p


def test_simulate_seed_reproducible_and_note_names_it(coin):
    a = _ok(coin(*SIM, "--psi", "90", "-n", "3000", "--seed", "5"))
    b = _ok(coin(*SIM, "--psi", "90", "-n", "3000", "--seed", "5"))
    assert a == b and "seed 5" in a
    c = _ok(coin(*SIM, "--psi", "90", "-n", "3000"))
    assert "seed " in c  # a fresh seed, printed so the run can be repeated


def test_simulate_stream_letters_prefix_and_counts(coin):
    out = _ok(coin(*SIM, "--psi", "90", "-n", "100", "--seed", "3", "--stream"))
    lines = out.splitlines()
    assert len(lines) == 100 and set(lines) <= {"H", "S", "T"}
    short = _ok(coin(*SIM, "--psi", "90", "-n", "10", "--seed", "3", "--stream")).splitlines()
    assert short == lines[:10]
    codes = np.concatenate(list(TS.simulate_chunks(100, 3, xi=0.577, u="normal:2.4:0.3",
                                                   omega="normal:38:4", psi=math.pi / 2)))
    assert lines == [T.LETTERS[c] for c in codes]


def test_simulate_psi_dist_accepts_the_design_densities(coin):
    for spec in ("cosine", "uniform", "normal", "normal:80:20", "uniform:60:120", "90"):
        out = _ok(coin(*SIM, "--psi-dist", spec, "-n", "2000", "--seed", "1", "--format",
                       "json"))
        rows = json.loads(out)
        assert sum(r["count"] for r in rows) == 2000
        assert sum(r["vigorous"] for r in rows) == pytest.approx(1.0, abs=1e-9)


def test_simulate_psi_table_file(coin, tmp_path):
    f = tmp_path / "psi.csv"
    f.write_text("psi,weight\n0,0\n90,1\n180,0\n")
    out = _ok(coin(*SIM, "--psi-dist", f"table:{f}", "-n", "2000", "--seed", "1", "--format",
                   "json"))
    assert sum(r["count"] for r in json.loads(out)) == 2000


def test_simulate_quiet_gives_the_three_frequencies(coin):
    out = _ok(coin(*SIM, "--psi", "90", "-n", "1000", "--seed", "2", "-q"))
    vals = [float(x) for x in out.split()]
    assert len(vals) == 3 and sum(vals) == pytest.approx(1.0)


@pytest.mark.parametrize("argv,words", [
    (["--u", "normal:2.4"], ["--u", "normal:MEAN:SD"]),
    (["--u", "normal:a:b"], ["--u"]),
    (["--u", "uniform:3:1"], ["--u", "LOW <= HIGH"]),
    (["--u", "-1"], ["--u"]),
    (["--u", "normal:-50:1"], ["--u", "no probability"]),
    # 9.9e-10 of the mass is in range: not "no probability" (it said so), the share and the rule
    (["--u", "normal:-6:1"], ["--u", "only 9.9e-10 of its probability", "at least 1e-9"]),
    (["--omega", "cauchy:1:2"], ["--omega", "unknown distribution"]),
    (["--omega", "normal:38:-4"], ["--omega", "SD >= 0"]),
    (["--psi-dist", "foo"], ["--psi-dist"]),
    (["--psi-dist", "uniform:0:200"], ["--psi-dist"]),
    (["--psi-dist", "normal:90"], ["--psi-dist"]),
    (["--psi", "90", "--psi-dist", "cosine"], ["--psi"]),
    (["-n", "0"], ["-n"]),
    (["-n", "1.5"], ["-n"]),
    (["--seed", "-3"], ["--seed"]),
    (["--g", "0"], ["--g"]),
    (["--xi", "0.1,0.2"], ["--xi must be a finite number >= 0"]),
    (["--stream", "--format", "csv"], ["--stream"]),
])
def test_simulate_bad_input_is_one_line_exit_2(coin, argv, words):
    base = {"--xi": "0.577", "--u": "normal:2.4:0.3", "--omega": "normal:38:4", "-n": "100"}
    extra = []
    flags = [a for a in argv if a == "--stream"]
    rest = [a for a in argv if a != "--stream"]
    it = iter(rest)
    for k in it:
        v = next(it)
        if k in base:
            base[k] = v
        else:
            extra += [k, v]
    if "--psi" not in extra and "--psi-dist" not in extra:
        extra += ["--psi", "90"]
    args = [x for kv in base.items() for x in kv] + extra + flags
    _error(coin("simulate", *args), 2, *words)


def test_simulate_without_psi_draws_the_hand_toss(coin):
    out = _ok(coin(*SIM, "-n", "10", "--seed", "1"))
    assert "psi ~ normal:90:10 deg (hand toss, Diaconis, Holmes & Montgomery 2007: psi)" in out
    out = _ok(coin("simulate", "--xi", "0.577", "-n", "10", "--seed", "1", "-f", "json"))
    rows = json.loads(out)
    assert [r["seed"] for r in rows] == [1, 1, 1] and sum(r["count"] for r in rows) == 10


def test_simulate_stream_survives_a_closed_pipe():
    p = subprocess.run(
        f"{sys.executable} -m coincli simulate -n 300000 --seed 1 --xi 0.577 --u 2.4 "
        "--omega normal:38:4 --psi 90 --stream | head -2", shell=True, capture_output=True,
        text=True, timeout=120)
    assert p.stdout.split() in (["H", "H"], ["H", "S"], ["H", "T"], ["S", "H"], ["S", "S"],
                                ["S", "T"], ["T", "H"], ["T", "S"], ["T", "T"])
    assert "Traceback" not in p.stderr and p.stderr == ""


# --------------------------------------------------------------------------- coin phase


def test_phase_csv_is_phase_map(coin):
    out = _ok(coin("phase", "--xi", "0.577", "--psi", "90", "--u", "0:3", "--omega", "0:60",
                   "--cols", "12", "--rows", "8", "--format", "csv"))
    rows = list(csv.DictReader(io.StringIO(out)))
    pm = TP.phase_map(0.577, math.pi / 2, (0, 3), (0, 60), (12, 8))
    assert len(rows) == 96
    assert [int(r["code"]) for r in rows] == pm.codes.ravel().tolist()
    assert [float(r["u"]) for r in rows[:12]] == pm.u.tolist()
    assert float(rows[12]["omega"]) == pm.omega[1]
    assert {r["outcome"] for r in rows} <= set(T.NAMES)


def test_phase_text_in_a_pipe_is_letters_with_legend(coin):
    out = _ok(coin("phase", "--cols", "40", "--rows", "12"))
    lines = out.splitlines()
    grid = [line[4:44] for line in lines[2:14]]
    assert all(len(g) == 40 and set(g) <= set("HSThst") for g in grid)
    assert grid[-1].upper().startswith("H")  # the strip next to the omega = 0 axis: heads
    assert "H heads" in out and "S sides" in out and "T tails" in out
    assert "eq. 10" in out and "vigorous limit" in out
    # round ticks: 0 to 60 rad/s in steps of 20 on the left, 0 to 3 m/s below
    assert [line[:4] for line in lines[2:14] if line[:4] != "   |"] == \
        ["60 +", "40 +", "20 +", " 0 +"]
    assert lines[14] == "   ++" + "-" * 12 + "+" + "-" * 12 + "+" + "-" * 12 + "+"
    assert lines[15].split() == ["0", "1", "2", "3"]
    plain = _ok(coin("phase", "--cols", "40", "--rows", "12", "--no-curves"))
    assert not any(c in "hst" for line in plain.splitlines()[2:14] for c in line[4:44])
    # the letters are the map, whatever the marks
    pm = TP.phase_map(0.5773502691896257, math.pi / 2, (0, 3), (0, 60), (40, 12))
    top = plain.splitlines()[2][4:44]
    assert top == "".join(T.LETTERS[c] for c in pm.codes[-1])


def test_phase_colour_on_a_terminal(coin, monkeypatch):
    import coincli.reports.phase as C

    monkeypatch.setattr(C, "stdout_is_terminal", lambda: True)
    monkeypatch.delenv("NO_COLOR", raising=False)
    out = _ok(coin("phase", "--cols", "30", "--rows", "10"))
    assert "\x1b[" in out and "heads" in out and "boundary" in out
    # mid-tone blocks, never a black or a white one (sides were black: invisible on a dark
    # terminal), whatever the colour system rich finds
    import re

    backs = set(re.findall(r"\x1b\[(?:[0-9;]*;)?(4[0-7]|10[0-7]|48;5;[0-9]+|48;2;[0-9;]+)m",
                           out))
    assert backs and not backs & {"40", "47", "100", "107", "48;5;0", "48;5;16", "48;5;231",
                                  "48;5;15"}
    monkeypatch.setenv("NO_COLOR", "1")
    out = _ok(coin("phase", "--cols", "30", "--rows", "10"))
    assert "\x1b[" not in out


def test_phase_figure_file(coin, tmp_path):
    pytest.importorskip("matplotlib")
    for ext in ("png", "svg"):
        path = tmp_path / f"phase.{ext}"
        rc, out, err = coin("phase", "--u", "0:3", "--omega", "0:60", "--cols", "60", "--rows",
                            "60", "--out", str(path))
        assert rc == 0 and out == "" and err.startswith(f"coin: wrote {path} (")
        assert path.stat().st_size > 1000
    _error(coin("phase", "--out", str(tmp_path / "phase.txt")), 2, "--out")
    _error(coin("phase", "--out", str(tmp_path / "p.png"), "--format", "csv"), 2, "--out")


def test_phase_figure_without_matplotlib_says_how_to_install(coin, tmp_path, monkeypatch):
    import builtins

    real = builtins.__import__

    def no_mpl(name, *a, **k):
        if name == "matplotlib" or name.startswith("matplotlib."):
            raise ImportError("no matplotlib")
        return real(name, *a, **k)

    monkeypatch.setattr(builtins, "__import__", no_mpl)
    _error(coin("phase", "--out", str(tmp_path / "p.png")), 1, "matplotlib", "pip install")
    assert not (tmp_path / "p.png").exists()


@pytest.mark.parametrize("argv,words", [
    (["--u", "3:0"], ["--u"]), (["--u", "0"], ["--u"]), (["--omega", "-1:60"], ["--omega"]),
    (["--cols", "1"], ["--cols"]), (["--rows", "99999"], ["--rows"]),
    (["--psi", "-5"], ["--psi"]), (["--xi", "x"], ["--xi"]), (["--g", "0"], ["--g"]),
    (["--omega", "0:1e14"], ["omega"]),
])
def test_phase_bad_input_is_one_line_exit_2(coin, argv, words):
    _error(coin("phase", *argv, "--format", "csv"), 2, *words)


# --------------------------------------------------------------------------- limits, messages


BASE = ["--xi", "0.577", "--psi", "90", "--u", "2", "--omega", "38"]


def _error_without(result, code, words, absent=()):
    """_error, and none of ``absent`` in the message (a wrong value, unit or interval)."""
    _error(result, code, *words)
    for w in absent:
        assert w not in result[2], (w, result[2])


def test_simulate_n_is_capped_and_the_message_names_the_cap_and_the_way_out(coin, monkeypatch):
    import time

    import coincli.reports.launch as C

    assert C.MAX_TOSSES == T.MAX_TOSSES == 10**8
    # was: no cap; 10^10 tosses ran for about 3 hours (and --stream as long)
    for extra in ([], ["--stream"]):
        start = time.monotonic()
        _error(coin("simulate", "-n", "10000000000", "--seed", "7", *BASE, *extra), 2,
               "-n 10000000000", "100000000", "--seed")
        assert time.monotonic() - start < 5
    _error(coin("simulate", "-n", "100000001", *BASE), 2, "-n 100000001", "100000000")
    _error(coin("simulate", "-n", "9" * 5000, *BASE), 2, "-n", "(5000 digits)")
    _error(coin("simulate", "-n", "0", *BASE), 2, "-n", "from 1 to 100000000")
    _error(coin("simulate", "-n", "1e5", *BASE), 2, "-n", "whole number")
    # the cap itself is allowed (the run is not made: the core is stubbed)
    seen, real = [], TS.simulate
    monkeypatch.setattr(TS, "simulate", lambda n, *a, **k: seen.append(n) or real(3, *a, **k))
    _ok(coin("simulate", "-n", "100000000", "--seed", "1", *BASE, "-q"))
    assert seen == [10**8]
    with pytest.raises(ValueError, match="n must be"):
        TS.simulate_chunks(10**8 + 1, 1, xi=FAIR, u=2.0, omega=38.0, psi=1.0).__next__()


@pytest.mark.parametrize("cmd", ["toss", "simulate"])
def test_a_too_long_flight_blames_the_option_at_fault_with_the_users_values(coin, cmd):
    # was (simulate): "lower omega (got 1 rad/s) or u (got 1 m/s)", a geometry check's values
    _error_without(coin(cmd, *BASE, "--g", "1e-300"), 2,
                   ["raise --g (got 1e-300 m/s^2)", "1e+12 rad"], ["got 1 rad/s", "--omega"])
    # was (toss): "lower omega (got 38 rad/s) or u (got 2 m/s)" for a launch height of 1e300 mm
    if cmd == "toss":
        _error_without(coin(cmd, *BASE, "--z0", "1e300"), 2, ["lower --z0 (got 1e300 mm)"],
                       ["--omega", "--u"])
        _error(coin(cmd, *BASE, "--z0", "1e300", "--g", "1e-300"), 2,
               "raise --g (got 1e-300 m/s^2) and lower --z0 (got 1e300 mm)")
    _error_without(coin(cmd, *BASE, "--diameter", "1e50"), 2, ["lower --diameter (got 1e50 mm)"],
                   ["--omega"])
    _error(coin(cmd, *BASE[:6], "--omega", "1e300"), 2,
           "lower --omega (got 1e", "rad/s) or --u (got 2 m/s)")
    _error(coin(cmd, *BASE, "--xi", "1e90", "--contact", "thick"), 2, "lower --xi")


def test_toss_names_the_row_of_a_list_that_cannot_be_followed(coin):
    _error(coin("toss", *BASE[:6], "--omega", "1,2,1e300"), 2, "(row 3)", "--omega",
           "1e+300 rad/s")


def test_simulate_checks_the_top_of_a_normal_before_tossing(coin):
    # a draw beyond the limit would have failed a batch halfway through a --stream
    _error(coin("simulate", "--xi", "0.577", "--psi", "90", "--u", "2", "--omega",
                "normal:1e13:1e11", "--stream"), 2,
           "--omega (got normal:1e13:1e11 rad/s, which reaches 1.1e+13 at MEAN + 10 SD)")


def test_a_spin_whose_square_overflows_is_refused_not_a_hang():
    # was: omega^2 * a overflowed to inf, no cell was ever excluded and the scan ran forever
    p = subprocess.run([sys.executable, "-m", "coincli", "toss", "--xi", "0.577", "--psi", "90",
                        "--u", "0", "--omega", "5e158", "--z0", "1e-290"], capture_output=True,
                       text=True, timeout=60)
    assert p.returncode == 2 and p.stdout == ""
    assert p.stderr == ("coin: error: the spin is too fast to follow: omega^2 * a overflows a "
                        "double; lower --omega (got 5e+158 rad/s)\n")


def test_simulate_refuses_a_huge_omega_in_one_line_without_warnings(coin):
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")  # was: two numpy RuntimeWarnings (overflow) on stderr
        _error(coin("simulate", *BASE[:6], "--omega", "1e300"), 2, "--omega (got 1e300 rad/s)")


@pytest.mark.parametrize("cmd", ["toss", "simulate", "phase"])
def test_g_states_its_open_interval(coin, cmd):
    args = BASE if cmd != "phase" else ["--format", "csv"]
    # was: "--g must be in [0, 1e+100], got '0'", though 0 is refused
    _error_without(coin(cmd, *args, "--g", "0"), 2,
                   ["--g must be a number from 1e-300 to 1e+100 m/s^2, got '0'"], ["[0,"])


@pytest.mark.parametrize("cmd", ["toss", "simulate", "phase"])
def test_diameter_out_of_range_speaks_mm(coin, cmd):
    args = BASE if cmd != "phase" else ["--xi", "0.577", "--format", "csv"]
    # was: "diameter must be in (0, 1e+100] m, got 1e+297"
    _error_without(coin(cmd, *args, "--diameter", "1e300"), 2,
                   ["--diameter must be a length from 1e-300 mm to 1e103 mm (1e100 m), got "
                    "'1e300'"],
                   ["1e+297", "] m"])
    _error(coin(cmd, *args, "--diameter", "5e-324"), 2, "--diameter", "1e-300 mm")


def test_thick_z0_and_xi_messages_name_the_option_in_mm(coin):
    # was: "z0 must be > h/2 = 0.01213 m ..., got 0.001" (metres, no option name)
    _error(coin("toss", *BASE[2:], "--xi", "1", "--contact", "thick", "--z0", "1"), 2,
           "--z0 must be above h/2 = 12.13 mm", "got 1 mm")
    _error(coin("toss", *BASE[2:], "--xi", "1,2", "--contact", "thick", "--z0", "1cm"), 2,
           "h/2 = 24.26 mm", "--xi 2", "got 1cm")
    # was: "xi must be in [0, 1e+100], got 1e+200"
    for cmd in ("toss", "simulate"):
        _error(coin(cmd, *BASE[2:], "--xi", "1e200", "--contact", "thick"), 2,
               "--xi must be at most 1e100 with --contact thick", "1e+200")


def test_phase_range_errors_name_the_option_and_the_typed_range(coin):
    # was: "u must be in [0, 1e+08] m/s, got 105633802.81690142" (a grid cell's value)
    _error_without(coin("phase", "--xi", "0.577", "--psi", "90", "--u", "0:1e9", "--omega",
                        "0:1e9"), 2, ["--u must be LOW:HIGH", "<= 1e8", "'0:1e9'"],
                   ["105633802"])
    _error(coin("phase", "--u", "0:3", "--omega", "0:1e14", "--format", "csv"), 2,
           "--omega must be LOW:HIGH", "<= 1e12", "'0:1e14'")
    _error_without(coin("phase", "--u", "0:1e8", "--omega", "0:1e12", "--format", "csv"), 2,
                   ["lower --omega (got 0:1e12) or --u (got 0:1e8)",
                    "top of the --u and --omega ranges"], ["2.94118e+12"])


def test_a_range_over_the_row_limit_reports_its_exact_count(coin):
    # was: "has 1e+06 values" for 1,000,001
    _error(coin("toss", *BASE[:4], "--u", "0:100:0.0001", "--omega", "38"), 2,
           "--u range '0:100:0.0001' has 1000001 values")


@pytest.mark.parametrize("cmd", ["toss", "simulate", "phase"])
@pytest.mark.parametrize("xi", ["inf", "nan", "-1", "1e400"])
def test_xi_says_what_is_allowed(coin, cmd, xi):
    args = ["--psi", "90", "--u", "2", "--omega", "38"] if cmd != "phase" else []
    # was: "--xi must be a number, got 'inf'"
    _error(coin(cmd, "--xi", xi, *args), 2, f"--xi must be a finite number >= 0 like 0.577 "
           f"or 17/30, got {xi!r}")


def test_toss_stdin_of_an_overflowing_number_is_refused_by_name(coin):
    vals = "".join(f"{0.5 + k / 1e4}\n" for k in range(5000)) + "1e400\n"  # the fast path
    _error(coin("toss", "--xi", "-", *BASE[2:], stdin=vals), 2, "stdin line 5001",
           "--xi must be a finite number >= 0")


@pytest.mark.parametrize("stream", [False, True])
def test_ctrl_c_in_simulate_says_interrupted(coin, monkeypatch, stream):
    def interrupted(*args, **kwargs):
        yield np.zeros(3, dtype=np.int8)
        raise KeyboardInterrupt

    monkeypatch.setattr(TS, "simulate_chunks", interrupted)
    from coincli.io import options

    # a seed drawn by an earlier run in this process is not this run's (it was reported)
    monkeypatch.setattr(options, "DRAWN_SEED", 12345)
    rc, out, err = coin("simulate", "-n", "1000", "--seed", "3", *BASE,
                        *(["--stream"] if stream else []))
    assert rc == 130 and err == "coin: error: interrupted\n"
    assert out == ("H\nH\nH\n" if stream else "")


# --------------------------------------------------------------------------- start-up budget


def test_importing_the_command_module_loads_no_numpy_scipy_rich():
    code = ("import sys, coincli.cli.toss; "
            "print(sorted(m for m in ('numpy', 'scipy', 'rich') if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         timeout=60)
    assert out.stdout.strip() == "[]", out.stdout + out.stderr


# --------------------------------------------------------------------------- extremes

_EXTREME_TOSS = [
    ["--xi", "1e-300", "--psi", "0", "--u", "5e-324", "--omega", "1e12"],
    ["--xi", "1e300", "--psi", "180", "--u", "1e8", "--omega", "5e-324"],
    ["--xi", "0", "--psi", "179.9999999", "--u", "100000km/s", "--omega", "1e-300"],
    ["--xi", "1e100", "--psi", "90", "--u", "0", "--omega", "1e6", "--contact", "thick"],
    ["--xi", "0.577", "--psi", "1e-300", "--u", "1e-300cm/s", "--omega", "1e300rpm"],
    ["--xi", "0.577", "--psi", "90", "--u", "2", "--omega", "40", "--g", "1e-300"],
    ["--xi", "0.577", "--psi", "90", "--u", "2", "--omega", "40", "--g", "1e100"],
    ["--xi", "0.5", "--diameter", "1e-300", "--psi", "45", "--u", "1e-6", "--omega", "1e6"],
    ["--xi", "0.5", "--diameter", "1e103", "--psi", "45", "--u", "2", "--omega", "1e-6"],
    ["--xi", "0.577", "--psi", "90", "--u", "2", "--omega", "40", "--z0", "1e-300"],
    ["--xi", "0.577", "--psi", "90", "--u", "2", "--omega", "40", "--z0", "1e300"],
    ["--xi", "1e-300"],
]
_EXTREME_SIMULATE = [
    ["--xi", "1e-300", "--u", "normal:5e-324:5e-324", "--omega", "1e-300"],
    ["--xi", "0.05"],  # a thin coin, the hand toss's narrow normal psi
    ["--xi", "1e-20", "--u", "1e8", "--omega", "normal:1e6:1e6", "--g", "1e100"],
    ["--xi", "1e300", "--u", "uniform:1e-300:2e-300", "--omega", "uniform:0:1e300", "--g", "1e-300"],
    ["--xi", "0.577", "--psi-dist", "normal:0:1e-300"],
    ["--xi", "0.577", "--psi-dist", "uniform:179:180", "--u", "normal:-1e300:1e300"],
    ["--xi", "0.577", "--psi", "180", "--omega", "normal:0:5e-324", "--contact", "thick"],
]
_EXTREME_PHASE = [
    ["--u", "0:1e8", "--omega", "0:1e-6"], ["--u", "1e-300:2e-300"], ["--psi", "0"],
    ["--psi", "180", "--contact", "thick", "--xi", "1e100"], ["--xi", "1e300"],
    ["--g", "1e-300"], ["--g", "1e100"], ["--xi", "0.5", "--diameter", "1e-300"],
    ["--cols", "2", "--rows", "2"], ["--omega", "1e11:1e12", "--u", "1e7:1e8"],
    ["--toss", "1e300:1e300"], ["--exact", "--u", "0:1e8", "--omega", "0:1"],
]


@pytest.mark.parametrize("argv", [["toss", *a] for a in _EXTREME_TOSS]
                         + [["simulate", "-n", "300", "--seed", "1", *a] for a in _EXTREME_SIMULATE]
                         + [["phase", *a] for a in _EXTREME_PHASE])
@pytest.mark.parametrize("fmt", [["-f", "csv"], []])
def test_every_option_at_its_extremes_prints_no_nan_or_one_line(coin, argv, fmt):
    rc, out, err = coin(*argv, *fmt)
    if rc == 0:
        assert not re.search(r"\b(nan|inf)\b", out, re.I), out[-400:]
    else:
        assert rc == 2 and out == "" and err.startswith("coin: error: "), (rc, err)
        assert len(err.strip().splitlines()) == 1 and "Traceback" not in err


def test_a_drawn_seed_is_reported_and_repeats_the_same_bytes(coin):
    # simulate: the note, the csv column, stderr with -q and --stream
    human = _ok(coin("simulate", "--xi", "0.577", "-n", "500"))
    seed = human.split(" tosses, seed ")[1].split(":")[0]
    assert _ok(coin("simulate", "--xi", "0.577", "-n", "500", "--seed", seed)) == human
    rc, out, err = coin("simulate", "--xi", "0.577", "-n", "500", "-f", "csv")
    assert rc == 0 and out.splitlines()[0].endswith(",seed")
    seed = out.splitlines()[1].rsplit(",", 1)[1]
    assert _ok(coin("simulate", "--xi", "0.577", "-n", "500", "-f", "csv", "--seed", seed)) == out
    for extra in (["-q"], ["--stream"]):
        rc, out, err = coin("simulate", "--xi", "0.577", "-n", "20", *extra)
        assert rc == 0 and err.startswith("coin: seed ") and "repeats this run" in err
        seed = err.split()[2]
        assert _ok(coin("simulate", "--xi", "0.577", "-n", "20", "--seed", seed, *extra)) == out
    # toss: only when something is drawn
    rc, out, err = coin("toss", "--xi", "0.577", "-q")
    assert rc == 0 and out.strip() in ("heads", "sides", "tails") and err.startswith("coin: seed")
    assert coin("toss", "--xi", "0.577", "--psi", "90", "--u", "2", "--omega", "40", "-q")[2] == ""


@pytest.mark.parametrize("once, every", [
    (["--omega", "2000:2400:100rpm"], ["--omega", "2000rpm:2400rpm:100rpm"]),
    (["--u", "100:300:50cm/s"], ["--u", "100cm/s:300cm/s:50cm/s"]),
])
def test_a_range_takes_its_unit_once_or_after_every_number(coin, once, every):
    """One grammar for a range with a unit, as `coin book --times` takes it."""
    base = ["toss", "--xi", "0.577", "--psi", "90", "-f", "csv"]
    fill = {"--omega": ["--u", "2"], "--u": ["--omega", "38rev/s"]}[once[0]]
    assert _ok(coin(*base, *fill, *once)) == _ok(coin(*base, *fill, *every))


@pytest.mark.parametrize("value, words", [
    ("2000rpm:2400:100rpm", "give a range's unit once at the end (38:40:1rev/s) or the same "
                            "after every number, got '2000rpm:2400:100rpm'"),
    ("2000rpm:2400rpm:100rad/s", "or the same after every number"),
    ("2400:2000:100rpm", "--omega range must have start <= stop, got '2400:2000:100rpm'"),
])
def test_a_range_with_a_unit_is_refused_as_typed(coin, value, words):
    _error(coin("toss", "--xi", "0.577", "--psi", "90", "--u", "2", "--omega", value), 2, words)


def test_distribution_bounds_are_stated_as_they_are(coin):
    _error(coin("simulate", "--xi", "0.5", "--omega", "uniform:3:1"), 2,
           "uniform:LOW:HIGH needs LOW <= HIGH, both >= 0 rad/s; got 'uniform:3:1'")
    _error(coin("book", "--size", "235x155x30", "--toss", "-n", "5", "--spin",
                "uniform:3:1,1,1"), 2, "needs LOW <= HIGH, both finite rad/s")
