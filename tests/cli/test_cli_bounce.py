"""``--landing bounce`` from the command line: simulate, toss, design, plot sides; the install
hint without MuJoCo; no other command imports MuJoCo."""

from __future__ import annotations

import csv
import io
import json
import math
import re
import subprocess
import sys

import pytest
from cli_helpers import error, ok, sigint_default

pytest.importorskip("mujoco")

SIM = ["simulate", "-n", "64", "--seed", "3", "--xi", "0.577", "--u", "normal:2.4:0.3",
       "--omega", "normal:38:4", "--psi", "90", "--landing", "bounce", "--jobs", "1"]


@pytest.mark.slow
def test_simulate_bounce_table_and_machine_formats(coin):
    out = ok(coin(*SIM, "--surface", "wood"))
    assert out.startswith("coin simulate --landing bounce")
    assert "Simulated table (MuJoCo), not the paper's catch" in out and "seed 3" in out
    rows = list(csv.DictReader(io.StringIO(ok(coin(*SIM, "--surface", "wood", "-f", "csv")))))
    assert [r["outcome"] for r in rows] == ["heads", "sides", "tails", "unsettled"]
    assert sum(int(r["count"]) for r in rows) == 64
    settled = sum(int(r["count"]) for r in rows[:3])
    for r in rows[:3]:
        assert float(r["frequency"]) == int(r["count"]) / settled
        assert float(r["ci_low"]) <= float(r["frequency"]) <= float(r["ci_high"])
        assert r["landing"] == "bounce" and r["surface"] == "wood" and r["seed"] == "3"
    assert abs(sum(float(r["caught"]) for r in rows[:3]) - 1) < 1e-12
    data = json.loads(ok(coin(*SIM, "--surface", "wood", "-f", "json")))
    assert [d["count"] for d in data] == [int(r["count"]) for r in rows]  # same seed, same counts
    q = ok(coin(*SIM, "--surface", "wood", "-q")).split()
    assert [float(x) for x in q] == [float(r["frequency"]) for r in rows[:3]]


def test_simulate_bounce_custom_surface_and_workers(coin):
    one = ok(coin(*SIM, "--restitution", "0.4", "--friction", "0.3", "-f", "csv"))
    two = ok(coin(*[a if a != "1" else "2" for a in SIM], "--restitution", "0.4", "--friction",
                  "0.3", "-f", "csv"))
    assert one == two  # --jobs 2 gives the same bytes
    assert ",custom,0.4,0.3," in one


def test_landing_catch_is_the_default_and_unchanged(coin):
    base = ["simulate", "-n", "1000", "--seed", "7", "--xi", "0.577", "--u", "2.4", "--omega",
            "38", "--psi", "90", "-f", "csv"]
    assert ok(coin(*base)) == ok(coin(*base, "--landing", "catch"))


@pytest.mark.parametrize("argv, message", [
    (["--surface", "wood"], "--surface goes with --landing bounce"),
    (["--landing", "bounce", "--surface", "marble"], "--surface must be one of"),
    (["--landing", "bounce", "--restitution", "0.99", "--friction", "0.3"], "--restitution must"),
    (["--landing", "bounce", "--restitution", "0.5"], "needs --friction too"),
    (["--landing", "drop"], "--landing must be catch or bounce"),
    (["--landing", "bounce", "--jobs", "0"], "--jobs must be"),
    (["--landing", "bounce", "--stream"], "--stream goes with --landing catch"),
    (["--landing", "bounce", "--release-height", "-3"], "--release-height"),
])
def test_simulate_bounce_errors(coin, argv, message):
    base = ["simulate", "-n", "10", "--xi", "0.577", "--u", "2", "--omega", "38", "--psi", "90"]
    assert message in error(coin(*base, *argv), 2)


def test_toss_bounce_and_trajectory(coin, tmp_path):
    path = tmp_path / "toss.csv"
    argv = ["toss", "--xi", "0.577", "--psi", "85", "--u", "2.4", "--omega", "38", "--landing",
            "bounce", "--surface", "wood"]
    out = ok(coin(*argv, "--trajectory", str(path)))
    assert "if caught (eq. 7)" in out and "bounces" in out and "settled at (s)" in out
    with path.open() as f:
        rows = list(csv.DictReader(f))
    assert rows and float(rows[0]["t"]) == 0.0
    assert [float(r["t"]) for r in rows] == sorted(float(r["t"]) for r in rows)
    assert [p.name for p in tmp_path.iterdir()] == ["toss.csv"]  # no temporary left behind
    one = json.loads(ok(coin(*argv, "-f", "json")))[0]
    assert one["outcome"] in ("heads", "sides", "tails") and one["landing"] == "bounce"
    assert ok(coin(*argv, "-q")).strip() == one["outcome"]
    assert "one toss" in error(coin("toss", "--xi", "0.577", "--psi", "85", "--u", "2.4",
                                    "--omega", "38,39", "--landing", "bounce"), 2)
    assert "--trajectory goes with --landing bounce" in error(
        coin(*argv[:9], "--trajectory", str(path)), 2)
    bad = tmp_path / "no" / "such" / "dir.csv"
    assert "cannot write" in error(coin(*argv, "--trajectory", str(bad)), 1)


@pytest.mark.slow
def test_design_bounce(coin):
    rc, out, warning = coin("design", "--p-sides", "1/3,0.2", "--landing", "bounce", "--seed",
                            "2", "--max-tosses", "1800", "--jobs", "2", "-f", "csv",
                            "--no-table")
    assert rc == 0 and re.fullmatch(
        r"coin: warning: --max-tosses 1800 reached before --tol 0\.01; the intervals are wider "
        r"than asked\n(coin: note: (\d+) of 1800 tosses did not settle \(\2 still moving at "
        r"--t-max 10 s\): they are left out of the frequencies; raise --t-max, or land more "
        r"gently \(a lower --u, --vx, --release-height or --restitution\)\n)?", warning), warning
    rows = list(csv.DictReader(io.StringIO(out)))
    assert [float(r["p_sides"]) for r in rows] == [1 / 3, 0.2]
    for r in rows:
        assert float(r["xi_low"]) < float(r["xi"]) < float(r["xi_high"])
        assert abs(float(r["fitted_p_sides"]) - float(r["p_sides"])) < 1e-9
        assert r["tosses"] == "1800" and r["seed"] == "2"
    assert float(rows[1]["xi"]) < float(rows[0]["xi"])  # monotone
    assert "--model, --method and --thickness go with --landing catch" in error(
        coin("design", "-p", "1/3", "--landing", "bounce", "--model", "geometric"), 2)
    assert "--seed goes with --landing bounce" in error(coin("design", "-p", "1/3", "--seed",
                                                           "1"), 2)


@pytest.mark.slow
def test_plot_sides_bounce_terminal(coin):
    rc, out, note = coin("plot", "sides", "--landing", "bounce", "--seed", "1", "-n", "40",
                         "--jobs", "1", "--terminal")
    assert rc == 0 and "seed 1" in note
    assert note.startswith("coin: note: simulated points: 40 tosses")
    assert "bounce on wood: fitted probit (simulated; " in out
    assert "s  simulated bounce on wood (8 points, " in out
    assert "omega ~ normal:38:4 rev/s, psi ~ normal:90:10 deg (hand toss" in note


def test_plot_sides_bounce_range_outside_the_simulated_window_is_one_line(coin):
    for rng in ("0:0.01", "200:300"):
        error(coin("plot", "sides", "--landing", "bounce", "--seed", "1", "-n", "5",
                   "--xi-range", rng, "--terminal"), 2, f"--xi-range '{rng}'",
              "holds no aspect ratio that --landing bounce simulates (0.05 to 100)")


@pytest.mark.slow
def test_plot_sides_bounce_without_a_curve_draws_the_points(coin):
    """Thin coins and few tosses: no side at all, so no probit can be fitted (it was 'coin:
    error: Singular matrix'); the points are drawn and the note says why there is no curve."""
    rc, out, note = coin("plot", "sides", "--landing", "bounce", "--seed", "1", "-n", "3",
                         "--jobs", "1", "--xi-range", "0.05:0.06", "--terminal")
    assert rc == 0 and "Traceback" not in note
    assert "at each of 8 xi from 0.05 to 0.06" in note
    assert "no curve: the simulated points do not determine a curve of P(sides)" in note
    assert "simulated bounce on wood (8 points, " in out and "fitted probit" not in out


def test_bounce_launch_defaults_are_the_hand_toss():
    """design and plot sides --landing bounce launch as simulate and toss do: the one hand toss
    of coincli.core.toss.launch, not a copy of it."""
    from coincli.core.toss import launch as T
    from coincli.reports.launch import bounce_launch

    u, w, psi, text = bounce_launch(None, None, None, None)
    assert (u, w, psi) == (T.HAND_TOSS["u"], T.HAND_TOSS["omega"], T.HAND_TOSS["psi"])
    assert u is T.HAND_TOSS["u"] and w is T.HAND_TOSS["omega"] and psi is T.HAND_TOSS["psi"]
    assert text.startswith(", ".join(f"{k} ~ {T.HAND_TOSS_TEXT[k]}" for k in ("u", "omega",
                                                                             "psi")))
    u, w, psi, text = bounce_launch("80", None, "2", None)
    assert psi == math.radians(80) and u.kind == "fixed" and w is T.HAND_TOSS["omega"]
    assert "psi = 80 deg" in text
    assert "hand toss, Diaconis, Holmes & Montgomery 2007: omega)" in text


# --------------------------------------------------------------------------- imports


_PROBE = r"""
import json, sys
from coincli.cli import run
report = []
for argv in json.loads(sys.argv[1]):
    code = run(argv)
    sys.stdout.flush()
    report.append([argv, code, "mujoco" in sys.modules])
print(json.dumps(report), file=sys.stderr)
"""


@pytest.mark.slow
def test_no_other_command_imports_mujoco():
    commands = [
        ["design", "--p-sides", "1/3"],
        ["table", "--xi", "0.577", "--all"],
        ["simulate", "-n", "1000", "--seed", "1", "--xi", "0.577", "--u", "2", "--omega", "38",
         "--psi", "90"],
        ["toss", "--xi", "0.577", "--psi", "90", "--u", "2", "--omega", "40"],
        ["phase", "--format", "csv", "--cols", "4", "--rows", "4"],
        ["plot", "sides", "--terminal"],
        ["check", "--xi", "0.5", "--sides", "3", "-n", "10"],
        ["toss", "--xi", "0.577", "--psi", "90", "--u", "2", "--omega", "40", "--landing",
         "bounce"],
    ]
    p = subprocess.run([sys.executable, "-c", _PROBE, json.dumps(commands)],
                       capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stderr
    report = json.loads(p.stderr.strip().splitlines()[-1])
    for argv, code, loaded in report[:-1]:
        assert code == 0, argv
        assert not loaded, f"coin {' '.join(argv)} imported mujoco"
    assert report[-1][1] == 0 and report[-1][2]  # control: a bounce does


_NO_MUJOCO = r"""
import sys
class Block:
    def find_spec(self, name, path=None, target=None):
        if name == "mujoco" or name.startswith("mujoco."):
            raise ImportError("No module named 'mujoco'")
sys.meta_path.insert(0, Block())
from coincli.cli import run
sys.exit(run(sys.argv[1:]))
"""


@pytest.mark.parametrize("argv", [
    ["simulate", "-n", "10", "--xi", "0.577", "--u", "2", "--omega", "38", "--psi", "90",
     "--landing", "bounce"],
    ["toss", "--xi", "0.577", "--psi", "90", "--u", "2", "--omega", "40", "--landing", "bounce"],
    ["design", "-p", "1/3", "--landing", "bounce"],
    ["plot", "sides", "--landing", "bounce", "--terminal"],
])
def test_without_mujoco_one_line_says_how_to_install(argv):
    p = subprocess.run([sys.executable, "-c", _NO_MUJOCO, *argv], capture_output=True,
                       text=True, timeout=120)
    assert p.returncode == 1 and p.stdout == ""
    assert p.stderr.count("\n") == 1 and "pip install -U 'thickcoin[physics]'" in p.stderr
    assert "Traceback" not in p.stderr


@pytest.mark.parametrize("u", ["25", "49", "100", "1e3", "1e7"])
def test_bounce_speed_beyond_the_flight_limit_is_refused(coin, u):
    """A launch at u > g t_max / 4 lands after half of --t-max: it cannot settle (a coin
    landing at u on wood bounces about as long again), or never reaches the surface at all
    (this used to end in an IndexError, then at u = 49 in NaN frequencies: issue 28)."""
    toss = ["toss", "--xi", "0.577", "--psi", "90", "--u", u, "--omega", "40", "--landing",
            "bounce", "-q"]
    error(coin(*toss), 2, "--u must be at most 24.5 m/s", "--t-max 10 s", repr(u),
          "within half of --t-max")
    sim = ["simulate", "-n", "10", "--xi", "0.577", "--psi", "90", "--u", u, "--landing",
           "bounce", "--jobs", "1"]
    error(coin(*sim), 2, "--u must be at most 24.5 m/s")
    error(coin("design", "-p", "1/3", "--landing", "bounce", "--u", u), 2, "--u must be at most")
    # a longer --t-max moves the limit; a lower surface is blamed when the speed alone is fine
    assert ok(coin(*toss[:6], "20", *toss[7:], "--t-max", "30")).strip() in SIDE_NAMES
    for cmd in (toss, sim):
        k = cmd.index("--u") + 1
        error(coin(*cmd[:k], "20", *cmd[k + 1:], "--release-height", "100m"), 2,
              "--release-height must be at most", "--t-max 10 s", "got '100m'")
    error(coin(*sim, "--t-max", "0.01"), 2, "--t-max must be at least 0.0534 s", "got 0.01 s")


SIDE_NAMES = ("heads", "sides", "tails", "unsettled")


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc")
def test_ctrl_c_ends_a_bounce_simulation_at_once():
    """SIGINT to `coin simulate --landing bounce` with worker processes: exit 130 with one line
    within a few seconds, the workers gone (the pool used to wait for every queued block)."""
    import os
    import signal
    import time

    p = subprocess.Popen([sys.executable, "-m", "coincli", "simulate", "-n", "20000", "--seed",
                          "1", "--xi", "0.577", "--landing", "bounce", "--jobs", "2"],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                         start_new_session=True, preexec_fn=sigint_default)
    try:
        kids, waited = [], 0.0
        while len(kids) < 2 and waited < 60 and p.poll() is None:  # the worker processes,
            time.sleep(0.2)  # however long a loaded machine takes to start them
            waited += 0.2
            with open(f"/proc/{p.pid}/task/{p.pid}/children") as f:
                kids = f.read().split()
        time.sleep(0.5)  # the workers at work
        p.send_signal(signal.SIGINT)
        # 20000 tosses take minutes of CPU: an answer within 20 s (a loaded machine's margin)
        # is one that did not wait for the queued blocks
        out, err = p.communicate(timeout=20)
    finally:
        if p.poll() is None:
            os.killpg(p.pid, signal.SIGKILL)
            p.wait()
    assert (p.returncode, out, err) == (130, "", "coin: error: interrupted\n")
    time.sleep(0.5)
    assert kids and not [k for k in kids if os.path.exists(f"/proc/{k}")]


def test_design_on_a_preset_starts_from_its_table(coin):
    """The defaults on a preset: the shipped table's points, its own fit (no toss simulated
    when the table gives --tol), the table named in the note; the same rows from the api; a
    changed launch or --no-table simulates (here with a fake engine: counts of a probit)."""
    from coincli import api
    from coincli.core.bounce import tables as TB

    table = TB.load("felt")
    argv = ["design", "-p", "1/3", "--landing", "bounce", "--surface", "felt", "--seed", "4",
            "--tol", "0.05"]
    rows = json.loads(ok(coin(*argv, "-f", "json")))
    assert rows[0]["table_tosses"] == table.tosses == rows[0]["tosses"]
    assert rows[0]["xi_low"] < rows[0]["xi"] < rows[0]["xi_high"]
    assert rows[0]["xi_high"] - rows[0]["xi"] <= 0.05 and rows[0]["seed"] == 4
    assert api.design(p_sides="1/3", landing="bounce", surface="felt", seed=4,
                      tol=0.05) == rows
    note = ok(coin(*argv))
    assert "Started from the table precomputed for felt with this launch and coin " \
           f"({table.tosses} tosses" in note
    assert "no toss simulated here: the table alone gave the intervals" in note
    # the same answer for any seed when the table is enough (the seed is still reported)
    other = json.loads(ok(coin(*argv[:-3], "9", "--tol", "0.05", "-f", "json")))
    assert {k: v for k, v in other[0].items() if k != "seed"} == {
        k: v for k, v in rows[0].items() if k != "seed"}
    error(coin("design", "-p", "1/3", "--no-table"), 2, "--no-table goes with --landing bounce")
    # cut short before any round: the note names a --max-tosses that is allowed and that
    # reproduces it (it said --max-tosses 0, its own simulated tosses)
    rc, out, err = coin(*argv[:-1], "0.001", "--max-tosses", "180")
    assert rc == 0 and "--max-tosses 180 reached before --tol 0.001" in err
    assert "no toss simulated here" in out and "--max-tosses 180 reproduces this result" in out


@pytest.mark.slow
def test_design_bounce_honours_a_small_max_tosses(coin):
    # a cut first sweep answers from points a factor 1.5 apart, never final however wide --tol
    # is: the cap stops it, and the warning after the table says so (issue 37)
    rc, out, err = coin("design", "-p", "1/3", "--landing", "bounce", "--seed", "1",
                        "--max-tosses", "200", "--tol", "0.5", "--jobs", "2", "--no-table")
    assert rc == 0 and err == ("coin: warning: --max-tosses 200 reached before --tol 0.5; the "
                               "intervals are wider than asked\n")
    assert "198 tosses" in out and "in 1 round." in out
    assert "--max-tosses 200 cut the first sweep to 22 tosses per aspect ratio, from 200" in out
    for n in ("100", "0", "1e3", "1000000000"):  # named, with its own range (not -n's)
        msg = error(coin("design", "-p", "1/3", "--landing", "bounce", "--max-tosses", n), 2,
                    "--max-tosses must be a whole number from 180 to 1000000 with --landing "
                    f"bounce", f"got '{n}'")
        assert "-n" not in msg and "20 seconds" not in msg


def test_zero_lengths_are_the_defaults_they_name(coin):
    """--release-height 0 is the default (help: 'Default 0'); --torsional/--rolling 0 are in
    their stated range 0 to 100 mm.  A negative or unitless-garbage length is still refused."""
    base = ["simulate", "-n", "10", "--seed", "1", "--xi", "0.577", "--psi", "90", "--landing",
            "bounce", "--jobs", "1", "-f", "csv"]
    default = ok(coin(*base))
    for h in ("0", "0mm", "0.0cm", "0in"):
        assert ok(coin(*base, "--release-height", h)) == default
    ok(coin(*base, "--torsional", "0", "--rolling", "0mm"))
    error(coin(*base, "--release-height", "-3"), 2, "--release-height must be a finite length "
          ">= 0", "'-3'")
    error(coin(*base, "--release-height", "0xx"), 2, "--release-height must be a length like")


@pytest.mark.slow
def test_coin_beyond_the_engines_limits_is_refused_naming_the_option(coin):
    """MuJoCo refuses a body lighter than mjMINVAL or a disc so thin that I1 + I1 >= I3 is lost
    to rounding (a two-line 'line 7' error used to leak); checked up front, one line naming the
    option as typed, the smallest allowed value, lengths in mm."""
    toss = ["toss", "--psi", "90", "--u", "2", "--omega", "40", "--landing", "bounce", "-q"]
    error(coin(*toss, "--xi", "1e-320"), 2, "--xi must be from 8.67e-07 to 100",
          "D = 24.26 mm", "got '1e-320'", longest=200)
    error(coin(*toss, "--diameter", "1e-300", "--thickness", "1e-300"), 2,
          "--diameter must be from 0.163 to 10000 mm", "got '1e-300'")
    error(coin(*toss, "--diameter", "20m", "--thickness", "1"), 2, "--diameter must be from",
          "got '20m'")
    error(coin(*toss, "--diameter", "24.26", "--thickness", "1e-7"), 2,
          "--thickness must be from 2.11e-05 to 2426 mm", "got '1e-7'")
    # the stated smallest values are themselves allowed (the triangle at 4.1e-9 used to leak)
    for coin_args in (["--xi", "8.67e-07"], ["--diameter", "24.26", "--thickness", "2.11e-5"],
                      ["--diameter", "0.163", "--xi", "99.3"]):
        assert ok(coin(*toss, *coin_args)).strip() in SIDE_NAMES
    error(coin("simulate", "-n", "5", "--xi", "1e-12", "--landing", "bounce"), 2,
          "--xi must be from 8.67e-07 to 100")
    # design sweeps xi down to 0.1: a diameter too small for that is refused up front (0.163
    # mm passed, then failed with an aspect ratio of the sweep the user never typed)
    for d in ("0.1mm", "0.163"):
        error(coin("design", "-p", "1/3", "--diameter", d, "--landing", "bounce"), 2,
              "--diameter must be from 0.743 to 10000 mm with coin design --landing bounce",
              f"got '{d}'")


def test_simulate_help_states_the_bounce_cost(coin):
    """A default bounce run takes minutes: --help says how many tosses a second, so that a
    user is not surprised."""
    out = " ".join(ok(coin("simulate", "--help")).split())
    assert "74-108 tosses a second on two idle cores" in out
    assert "10,000 tosses take some 4.5 CPU-minutes" in out
