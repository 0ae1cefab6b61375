"""``coin toss``, ``coin simulate``, ``coin phase``: real tosses of finite vigor (Sec. II, Fig. 3).

Their help, and the call of their report: :mod:`coincli.reports.toss` (toss, simulate, with
:mod:`coincli.reports.bounce` for ``--landing bounce``) and :mod:`coincli.reports.phase`.  Their
options are declared in :mod:`coincli.requests.toss`.  numpy loads only inside the commands,
rich only to draw on a terminal, scipy never.
"""

from __future__ import annotations

import sys

from coincli.cli import app
from coincli.cli._options import declared
from coincli.io.table import Result, emit_all
from coincli.render.progress import tossing_bar
from coincli.reports import phase as phase_report
from coincli.reports import toss as report
from coincli.reports.bounce import warn_unmet
from coincli.requests.toss import PHASE_PICTURE, SIMULATE, TOSS


@app.command("toss")
@declared(TOSS)
def toss_cmd(request):
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
    result = report.toss(**request)
    emit_all(result, **request.output)
    warn_unmet(result)  # a bounce that did not settle: the note, after the output


@app.command("simulate")
@declared(SIMULATE)
def simulate_cmd(request):
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
    result = report.simulate(**request, progress=tossing_bar)
    # --stream: the letters, one a line
    emit_all(result, request.fmt, request.quiet or request.stream)
    warn_unmet(result)  # bounces that did not settle: the note, after the output


@app.command("phase")
@declared(PHASE_PICTURE)
def phase_cmd(request):
    """The pre-images of heads, sides and tails over (u, omega): Fig. 3 of the paper.

    Each cell is one deterministic toss (as `coin toss`) from the cell's centre; the coin is
    the fair one (1/sqrt 3, a quarter's size) unless given.  On a terminal: coloured blocks,
    boundaries of eq. (10) as dots, round ticks.  In a pipe or with NO_COLOR: letters H, S,
    T, lower case where a boundary passes.  --format csv/json: one row per cell.  --out
    FILE: a figure.  coin plot phase takes the same options.

    Examples: coin phase ;  coin phase --xi 0.577 --psi 90 --u 0:3 --omega 0:60 ;
    coin phase --xi 0.3 --u 0:5 --omega 0:100 --out phase.png ;  coin phase -f csv
    """
    shown = phase_report.phase(**request)
    if isinstance(shown, (Result, list)):
        emit_all(shown, **request.output)
    elif isinstance(shown, str):  # letters (a pipe, NO_COLOR): no rich needed
        sys.stdout.write(shown)
    else:  # coloured blocks, a rich Text
        from rich.console import Console

        Console(file=sys.stdout, highlight=False, soft_wrap=True, emoji=False, markup=False,
                force_terminal=True).print(shown, end="")
