"""``coin toss``, ``coin simulate``, ``coin phase``: real tosses of finite vigor (Sec. II, Fig. 3).

The typer declarations; the reports are :mod:`coincli.reports.toss` (toss, simulate, with
:mod:`coincli.reports.bounce` for ``--landing bounce``) and :mod:`coincli.reports.phase`.
numpy loads only inside the commands, rich only to draw on a terminal, scipy never.
"""

from __future__ import annotations

import sys

from coincli.cli import _phase, app
from coincli.cli._bounce import BOUNCE, RUNS
from coincli.cli._options import COIN, OUTPUT, SeedOpt, TossesOpt, XisOpt, option, with_groups
from coincli.io.table import Result, emit_all
from coincli.limits import BOUNCE_OMEGA_MAX
from coincli.render.progress import tossing_bar
from coincli.reports import phase as phase_report
from coincli.reports import toss as report
from coincli.reports.bounce import warn_unmet
from coincli.reports.launch import HAND, SPEC_FORM

# --------------------------------------------------------------------------- coin toss

UValuesOpt = option("--u", "SPEED", "Launch speed: 2 (m/s), 240cm/s, 8.6km/h; a list, a range or "
                    "-.  Default: drawn (hand toss).")
OmegaValuesOpt = option("--omega", "SPIN", "Spin omega_N = M/I1 of eq. (2): 40 (rad/s), 38rev/s, "
                        "2300rpm; a list, a range or -.  Default: drawn.  At most "
                        f"{BOUNCE_OMEGA_MAX:.0f} rad/s with --landing bounce.")
PsiValuesOpt = option("--psi", "DEG", "Angle psi of the angular momentum to the normal, degrees "
                      "[0, 180]; a list, a range or -.  Default: drawn.")
Z0Opt = option("--z0", "MM", "Launch height of the centre, mm or with a unit (default: (sqrt 3/2) "
               "a, plus h/2 for thick contact).")


TrajectoryOpt = option("--trajectory", "FILE.csv", "With --landing bounce: write the time series "
                       "(time, position, quaternion, velocities, tilt, energy, contacts) to this "
                       "CSV file.")

#: one coin, or (--xi) several; the table of one toss (no worker processes)
TOSS_COIN, TOSS_TABLE = COIN.but(xi=XisOpt), BOUNCE.without(*RUNS)


@app.command("toss")
@with_groups
def toss_cmd(
    the_coin=TOSS_COIN,
    psi: PsiValuesOpt = None,
    u: UValuesOpt = None,
    omega: OmegaValuesOpt = None,
    seed: SeedOpt = None,
    flight=_phase.FLIGHT,
    z0: Z0Opt = None,
    table=TOSS_TABLE,
    trajectory: TrajectoryOpt = None,
    output=OUTPUT,
):
    """One deterministic toss: time of flight, turns, final tilt and outcome (eqs. 3-7).

    The coin starts heads up with its centre at z0 = (sqrt 3/2) a, flies up at u and spins at
    omega; it is caught at z = 0 the first time it touches (the smallest positive root of
    z(t) - a sin alpha(t) = 0, never skipping an earlier one).  Heads if alpha_f <= theta0,
    tails if alpha_f > 180 - theta0, sides between (eq. 7).  Whatever of --u, --omega, --psi
    is missing is drawn from a natural hand toss (see README; Diaconis, Holmes & Montgomery,
    SIAM Review 49 (2007) 211: u ~ normal:2.4:0.3 m/s, omega ~ normal:38:4 rev/s, psi ~
    normal:90:10 deg) with a seed that is reported.  Lists of equal length are paired.

    --landing bounce drops the coin onto a surface instead and follows it (MuJoCo, pip install
    'thickcoin[physics]') until it settles: its bounces, time to settle and final side;
    --trajectory FILE.csv writes the motion.

    Examples: coin toss --xi 0.577 ;  coin toss --xi 0.577 --psi 90 --u 2 --omega 40 ;
    coin toss --coin quarter --psi 90 --u 2 --omega 38:40:1 -f csv ;
    coin toss --xi 0.577 --psi 85 --u 2.4 --omega 38 --landing bounce --surface wood
    --trajectory toss.csv
    """
    result = report.toss(**the_coin, psi=psi, u=u, omega=omega, seed=seed, **flight, z0=z0,
                         **table, trajectory=trajectory, **output)
    emit_all(result, **output)
    warn_unmet(result)  # a bounce that did not settle: the note, after the output


# --------------------------------------------------------------------------- coin simulate


SpecUOpt = option(
    "--u", "SPEC", f"Launch speed: {SPEC_FORM}, in m/s or with a unit "
    f"(normal:240:30cm/s).  Default: {HAND['u']} (hand toss).")
SpecOmegaOpt = option(
    "--omega", "SPEC", f"Spin: {SPEC_FORM}, in rad/s or with a unit.  "
    f"Default: {HAND['omega']} (hand toss).  At most {BOUNCE_OMEGA_MAX:.0f} rad/s with --landing "
    "bounce.")
FixedPsiOpt = option("--psi", "DEG", "A fixed angle psi, degrees [0, 180].")
HandPsiDistOpt = option(
    "--psi-dist", "SPEC", "psi density: uniform[:LOW:HIGH], cosine, "
    f"normal[:MEAN:SD] (deg), table:FILE.  Default: {HAND['psi']}.")
StreamOpt = option("--stream", None, "Print one outcome a line (H, S or T) instead of the summary.",
                   kind=bool)


@app.command("simulate")
@with_groups
def simulate_cmd(
    the_coin=COIN,
    u: SpecUOpt = None,
    omega: SpecOmegaOpt = None,
    psi: FixedPsiOpt = None,
    psi_dist: HandPsiDistOpt = None,
    tosses: TossesOpt = None,
    seed: SeedOpt = None,
    stream: StreamOpt = False,
    flight=_phase.FLIGHT,
    table=BOUNCE,
    output=OUTPUT,
):
    """Many seeded tosses with random initial conditions: frequencies next to the vigorous limit.

    Draws u, omega and psi (by default a natural hand toss, after Diaconis, Holmes &
    Montgomery, SIAM Review 49 (2007) 211), tosses each coin as `coin toss` does, and reports
    the frequencies of heads, sides and tails with 95% Wilson intervals next to Table I
    averaged over the same psi (the vigorous limit).  -n is 10000 by default, at most 10^8
    (10^6 with --landing bounce).
    The seed is reported; the same seed gives the same tosses.

    --landing bounce tosses the coins onto a surface (--surface, or --restitution and
    --friction) and lets them bounce and settle, simulated with MuJoCo (pip install
    'thickcoin[physics]'): a simulated table, not the paper's catch.  It is slow: 20-30 ms of
    CPU a toss, 74-108 tosses a second on two idle cores (docs/performance.md), so the default
    10,000 tosses take some 4.5 CPU-minutes; a progress bar on a terminal shows the time left.

    Examples: coin simulate --xi 0.577 ;
    coin simulate -n 1000000 --seed 7 --xi 0.577 --omega normal:6:1rev/s ;
    coin simulate -n 5 --seed 1 --xi 0.577 --psi 90 --stream ;
    coin simulate -n 2000 --seed 1 --xi 0.577 --psi 90 --landing bounce --surface wood
    """
    result = report.simulate(
        **the_coin, u=u, omega=omega, psi=psi, psi_dist=psi_dist, tosses=tosses, seed=seed,
        stream=stream, **flight, **table, **output, progress=tossing_bar)
    emit_all(result, output.fmt, output.quiet or stream)  # --stream: the letters, one a line
    warn_unmet(result)  # bounces that did not settle: the note, after the output


# --------------------------------------------------------------------------- coin phase


FORMAT = OUTPUT.only("fmt")  #: a picture: no -q
PhaseOutOpt = option("--out -o", "FILE", "Write a figure: .png, .svg or .pdf (needs matplotlib: "
                     "pip install 'thickcoin\\[plot]').")


@app.command("phase")
@with_groups
def phase_cmd(the_coin=COIN, grid=_phase.PHASE, out: PhaseOutOpt = None, output=FORMAT):
    """The pre-images of heads, sides and tails over (u, omega): Fig. 3 of the paper.

    Each cell is one deterministic toss (as `coin toss`) from the cell's centre; the coin is
    the fair one (1/sqrt 3, a quarter's size) unless given.  On a terminal: coloured blocks,
    boundaries of eq. (10) as dots, round ticks.  In a pipe or with NO_COLOR: letters H, S,
    T, lower case where a boundary passes.  --format csv/json: one row per cell.  --out
    FILE: a figure.  coin plot phase takes the same options.

    Examples: coin phase ;  coin phase --xi 0.577 --psi 90 --u 0:3 --omega 0:60 ;
    coin phase --xi 0.3 --u 0:5 --omega 0:100 --out phase.png ;  coin phase -f csv
    """
    shown = phase_report.phase(**the_coin, **grid, out=out, **output)
    if isinstance(shown, (Result, list)):
        emit_all(shown, **output)
    elif isinstance(shown, str):  # letters (a pipe, NO_COLOR): no rich needed
        sys.stdout.write(shown)
    else:  # coloured blocks, a rich Text
        from rich.console import Console

        Console(file=sys.stdout, highlight=False, soft_wrap=True, emoji=False, markup=False,
                force_terminal=True).print(shown, end="")
