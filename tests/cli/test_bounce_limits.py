"""The limits of ``--landing bounce``, checked before any simulation by every bouncing command
that takes the option, and named as typed with the range for that command (issue 28, items 5
to 10); MuJoCo's warnings kept off the terminal and out of files.  Nothing here simulates more
than the first sweep of one design (180 tosses, a few seconds)."""

from __future__ import annotations

import math
import os
import subprocess
import sys
import textwrap
from statistics import NormalDist

import pytest
from cli_helpers import error

pytest.importorskip("mujoco")

SIM = ["simulate", "--landing", "bounce", "-n", "2", "--seed", "1", "-j", "1"]
TOSS = ["toss", "--landing", "bounce", "--psi", "90", "--u", "2"]
DESIGN = ["design", "--landing", "bounce", "-p", "1/3"]
PLOT = ["plot", "sides", "--landing", "bounce", "--terminal"]


# ----------------------------------------------------------------------- --g (item 6)

@pytest.mark.parametrize("g", ["1000.1", "1e8", "1e100"])
@pytest.mark.parametrize("cmd", [SIM + ["--xi", "0.577"], TOSS + ["--xi", "0.577", "--omega",
                                                                  "40"]])
def test_g_beyond_the_bounce_limit_is_one_line_naming_g(coin, cmd, g):
    """It used to print hundreds of MuJoCo warnings, write MUJOCO_LOG.TXT and blame the
    restitution."""
    error(coin(*cmd, "--g", g), 2, "--g must be at most 1000 m/s^2 with --landing bounce",
          f"got '{g}'")


def test_mujoco_warnings_reach_neither_the_terminal_nor_a_file(tmp_path):
    """An unstable model makes MuJoCo warn ('Nan, Inf or huge value in QACC'); through
    coincli's engine nothing is printed and no MUJOCO_LOG.TXT is written (cwd: a temporary
    folder), and the warnings are kept in the engine's MUJOCO_WARNINGS."""
    script = textwrap.dedent("""
        from coincli.core.bounce import engine as B
        mujoco = B.require_mujoco()
        xml = ('<mujoco><option gravity="0 0 -1e300"/><worldbody><body><freejoint/>'
               '<geom size="0.1"/></body></worldbody></mujoco>')
        m = mujoco.MjModel.from_xml_string(xml)
        d = mujoco.MjData(m)
        for _ in range(5):
            mujoco.mj_step(m, d)
        assert d.warning[mujoco.mjtWarning.mjWARN_BADQACC].number > 0
        assert any("QACC" in w for w in B.MUJOCO_WARNINGS), B.MUJOCO_WARNINGS
    """)
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(p for p in sys.path if p)}
    p = subprocess.run([sys.executable, "-c", script], cwd=tmp_path, capture_output=True,
                       text=True, env=env, timeout=120)
    assert (p.returncode, p.stdout, p.stderr) == (0, "", "")
    assert os.listdir(tmp_path) == []


def test_g_limit_is_in_the_help(coin):
    for cmd in ("simulate", "toss"):
        out = " ".join(coin(cmd, "--help")[1].split())
        assert "at most 1000 with --landing bounce" in out, cmd


# ----------------------------------------------------------------------- --omega (item 7)

@pytest.mark.parametrize("cmd, omega", [
    (SIM + ["--xi", "0.577"], "2e4"),
    (SIM + ["--xi", "0.577"], "normal:9000:200"),
    (TOSS + ["--xi", "0.577"], "2e4"), (DESIGN, "2e4"), (DESIGN, "uniform:0:10001")])
def test_omega_above_ten_thousand_is_refused_by_every_bouncing_command(coin, cmd, omega):
    """simulate used to run it (every toss unsettled, NaN); toss and design refused it with
    two different messages."""
    error(coin(*cmd, "--omega", omega), 2,
          "--omega must be at most 10000 rad/s with --landing bounce", f"got '{omega}'")


def test_omega_limit_is_in_the_help(coin):
    for cmd in ("simulate", "toss", "design"):
        out = " ".join(coin(cmd, "--help")[1].split())
        assert "at most 10000 rad/s" in out.lower() and "--landing bounce" in out, cmd


# ----------------------------------------------------------------------- counts (items 8, 9)

@pytest.mark.parametrize("n", ["0", "1000001", "1e3", "-1"])
def test_bounce_simulate_n_quotes_the_bounce_limit(coin, n):
    msg = error(coin(*SIM[:3], "-n", n, "--xi", "0.577"), 2,
                "-n must be a whole number from 1 to 1000000 with --landing bounce",
                f"got '{n}'")
    assert "100000000" not in msg


def test_plot_sides_n_names_its_own_range(coin):
    error(coin(*PLOT, "-n", "0"), 2, "-n must be a whole number from 1 to 100000 with "
          "--landing bounce", "got '0'")


# ----------------------------------------------------------------------- coins (item 9)

@pytest.mark.parametrize("cmd", [SIM, TOSS + ["--omega", "40"]])
@pytest.mark.parametrize("coin_args, words", [
    (["--xi", "100.0001"], ["--xi must be from 8.67e-07 to 100 with --landing bounce",
                            "got '100.0001'"]),
    (["--coin", "quarter", "--count", "10000"],
     ["--count must be from 1 to 1386 with --landing bounce", "quarter", "got '10000'"]),
    (["--quarters", "2000"], ["--quarters must be from 1 to 1386", "got '2000'"]),
    (["--diameter", "24.26", "--thickness", "2500"],
     ["--thickness must be from 2.11e-05 to 2426 mm", "got '2500'"]),
    (["--diameter", "20m", "--thickness", "1"], ["--diameter must be from 0.163 to 10000 mm",
                                                 "got '20m'"]),
])
def test_coins_past_the_engine_name_the_option_typed(coin, cmd, coin_args, words):
    """--xi 100.0001 used to say 'xi must be in (0, 100]', --count 10000 named nothing
    (simulate) or --xi (toss)."""
    msg = error(coin(*cmd, *coin_args), 2, *words)
    if "--xi" not in coin_args:
        assert "--xi" not in msg


# ----------------------------------------------------------------------- --z0 (item 10)

@pytest.mark.parametrize("z0, words", [
    ("0.001", ["h/2 = 6.999 mm", "got 0.001 mm"]),
    ("0.1cm", ["h/2 = 0.6999 cm", "got 0.1cm"]),
    ("0.001in", ["h/2 = 0.2756 in", "got 0.001in"]),
])
def test_z0_below_half_the_thickness_is_bad_input_in_the_users_unit(coin, z0, words):
    """It exited 1 with 'z0 must be > h/2 for thick contact', a contact the user did not
    choose."""
    msg = error(coin(*TOSS, "--xi", "0.577", "--omega", "40", "--z0", z0), 2,
                "--z0 must be above", "with --landing bounce", *words)
    assert "contact" not in msg


# ----------------------------------------------------------------------- design (item 5)

def _probit_runs(monkeypatch, alpha=-0.3, beta=1.5):
    """Replace the simulated tosses of a design with counts drawn from no engine: at each xi,
    ``round(n Phi(alpha + beta ln xi))`` of ``n`` land on a side, all settle (a design's
    arithmetic, tested without MuJoCo's seconds of tosses)."""
    from statistics import NormalDist

    from coincli.core.bounce import design as D
    from coincli.core.bounce.runs import BounceSimulation

    def simulate(n, seed, *, xi, **kw):
        k = round(n * NormalDist().cdf(alpha + beta * math.log(xi)))
        return BounceSimulation(n=n, counts=((n - k) // 2, k, n - k - (n - k) // 2, 0),
                                frequencies=[], catch_counts=(n, 0, 0), agree=0,
                                mean_bounces=0.0, mean_t_settle=1.0, steps=0, seed=seed,
                                landing="bounce", surface=None, damping=0.0, dt=1e-4)

    monkeypatch.setattr(D, "simulate", simulate)
    return D


def test_design_never_answers_an_xi_the_engine_cannot_simulate(coin, monkeypatch):
    """-p 1e-300 answered xi = 1.9e-10 'within --tol', below any simulated aspect ratio and
    below what MuJoCo can simulate (8.7e-7).  Refused, naming --p-sides and the range; as is
    an answer above xi = 100; an answer inside is given."""
    D = _probit_runs(monkeypatch)
    for p, beyond in (("1e-300", lambda x: x < 8.66e-07), ("0.999999999999", lambda x: x > 100)):
        msg = error(coin(*DESIGN[:4], p, "--seed", "1", "-j", "1", "--no-table"), 2,
                    f"--p-sides {p} needs xi = ", "outside the aspect ratios MuJoCo can "
                    "simulate for this coin (8.66e-07 to 100)")
        assert beyond(float(msg.split("needs xi = ")[1].split(",")[0])), msg
        assert "within" not in msg
    with pytest.raises(D.BeyondTheEngine):
        D.design([1e-300], seed=1, diameter=0.02426)
    r = D.design([1 / 3], seed=1, diameter=0.02426)  # the fake's exact answer, within --tol
    want = math.exp((NormalDist().inv_cdf(1 / 3) + 0.3) / 1.5)
    assert abs(r.xi[0] - want) < 0.01 and r.span[0] <= r.xi[0] <= r.span[1]


def test_a_design_answer_outside_the_simulated_range_is_called_an_extrapolation():
    """The report's rule (reports.bounce.design): an answer outside the span of the simulated
    aspect ratios is said to be extrapolated, in the note and in a warning.  Checked on a
    design record shaped as the core returns it, so that no run is needed."""
    from coincli.core.bounce import design as D
    from coincli.reports import bounce as bounce_report
    from coincli.reports.physics import bounce_physics

    fit = D.SidesFit(0.0, 1.0, ((0.01, 0.0), (0.0, 0.01)), [(0.5, 10, 3), (1.0, 10, 5)], 0.1,
                     0, float("nan"))
    rec = D.Design([0.9], [fit.inverse(0.9)], [3.0], [4.0], fit, 20, 0, False, "max_tosses", 1,
                   0, [fit], 200, (0.5, 1.0), 0)

    class _Run:  # design's core, replaced by the record
        @staticmethod
        def design(*a, **k):
            return rec

    p = bounce_physics()
    real = D.design
    D.design = _Run.design
    try:
        r = bounce_report.design(p, targets=[0.9], seed=1, tol=0.01, max_tosses=20,
                                 time_limit=1.0, u=2.0, omega=40.0, psi=1.0, diameter=0.02426,
                                 g=9.81, labels="")
    finally:
        D.design = real
    assert "xi = 3.602 for P(sides) = 0.9 extrapolated from the aspect ratios simulated (0.5 " \
           "to 1)" in r.note
    assert "1 answer extrapolated beyond the aspect ratios simulated (0.5 to 1)" in r.warning
