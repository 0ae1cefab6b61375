"""``coin design``, ``coin table``, ``coin stack``, ``coin coins``, ``coin fair``: their options
and help.  Each command calls its report in :mod:`coincli.reports.design`, which computes what
it prints, and writes that (:func:`coincli.io.table.emit_all`).
"""

from __future__ import annotations

from typing import Annotated

import typer

from coincli.cli import _accuracy, _options, app
from coincli.cli._bounce import BOUNCE, LAUNCH, RUNS
from coincli.cli._options import COINS, OUTPUT, Group, option, with_groups
from coincli.limits import BOUNCE_DESIGN_TOSSES, MAX_BOUNCE_TOSSES
from coincli.io import options
from coincli.io.table import emit_all
from coincli.render.progress import estimator_bar, simulating_bar
from coincli.reports import design as report

# --------------------------------------------------------------------------- models as options

ModelOpt = option("--model -m", "MODEL", "geometric, dynamic (default) or psi.")
PsiOpt = _options.PsiOpt
PsiDistOpt = _options.PsiDistOpt
CoinOpt = option("--coin -c", "NAME", "Catalog coin of the stack (see coin coins).", kind=str)


# --------------------------------------------------------------------------- design


PSidesOpt = option("--p-sides -p", "P", "Target chance of a side: 0.33, 1/3 or 33%; a list a,b; a "
                   "range lo:hi:step; or - (stdin).", kind=str)
SizedDiameterOpt = option("--diameter -d", "D", "Diameter (24.26, 2.4cm, 0.955in); the thickness "
                          "is computed.  Default: the --coin's.")
SizedThicknessOpt = option("--thickness -t", "H", "Thickness (mm or a unit); the diameter is "
                           "computed instead.")
#: ``--landing bounce`` of ``coin design``: the table, and the tosses simulated on it
DESIGN_TABLE = Group(
    BOUNCE.only("landing", "surface", "restitution", "friction", "torsional", "rolling"),
    LAUNCH.only("u", "omega"),
    BOUNCE.only("release_height", "vx"),
    LAUNCH.only("seed"),
    ("max_tosses", option("--max-tosses", "N", "With --landing bounce: stop before simulating "
                          f"more tosses than this (default {BOUNCE_DESIGN_TOSSES}, from 180 to "
                          f"{MAX_BOUNCE_TOSSES})."), None),
    ("time_limit", option("--time-limit", "S", "With --landing bounce: stop at the end of the "
                          "first round after this many seconds (default 300); the note gives "
                          "the --max-tosses that reproduces the result."), None),
    BOUNCE.only(*RUNS, "dt", "t_max", "calibration"),
    ("no_table", option("--no-table", None, "With --landing bounce: simulate every toss, "
                        "not starting from the table shipped for a surface preset with the "
                        "default launch and coin (see docs/bounce.md).", kind=bool), False),
)


@app.command()
@with_groups
def design(
    p_sides: PSidesOpt,
    model: ModelOpt = None,
    psi: PsiOpt = None,
    psi_dist: PsiDistOpt = None,
    diameter: SizedDiameterOpt = None,
    thickness: SizedThicknessOpt = None,
    coin: CoinOpt = "quarter",
    tol: _accuracy.TolOpt = None,
    method: _accuracy.DesignMethodOpt = None,
    table=DESIGN_TABLE,
    output=OUTPUT,
):
    """The aspect ratio (thickness/diameter) that lands on a side with the chance you want.

    Reports xi, D/h, the thickness for a diameter (or the diameter for a thickness), the
    nearest stack of a catalog coin with N-1, N and N+1 coins, and what the other model says.

    --landing bounce answers another question: the coin lands on a surface (--surface) and
    bounces; tosses are simulated (MuJoCo) at a sweep of xi, a probit curve in log xi is fitted,
    inverted for each target, and refined until its 95% interval is within --tol (in xi).

    Examples: coin design --p-sides 1/3 ;  coin design -p 25% --model geometric --diameter 30 ;
    seq 0.05 0.05 0.95 | coin design -p - --format csv ;
    coin design --p-sides 1/3 --landing bounce --surface wood --seed 1
    """
    result = report.design(
        p_sides, model=model, psi=psi, psi_dist=psi_dist, diameter=diameter,
        thickness=thickness, coin=coin, tol=tol, method=method, **table, **output,
        progress=simulating_bar)
    emit_all(result, **output)
    if table.landing.strip().lower() == "bounce":
        from coincli.reports.bounce import warn_unmet

        warn_unmet(result)  # after the table


# --------------------------------------------------------------------------- table

TABLE_OUTPUT = OUTPUT.but(quiet=option(
    "--quiet -q", None, "Print only P(sides), a line a row: each coin's geometric, then dynamic, "
    "then the other models.", kind=bool))


#: ``--landing bounce`` of ``coin table``: a parameter study of tables, a row per coin and
#: table (--restitution and --friction take lists and ranges as --xi does)
TABLE_TABLE = Group(
    BOUNCE.only("landing", "calibration", "surface", "restitution", "friction", "torsional",
                "rolling").but(
        restitution=option("--restitution", "E", "With --landing bounce: the surface's "
                           "coefficient of restitution, 0.06 to 0.95; a list or a range "
                           "(0.3:0.7:0.1) is a study, a row each."),
        friction=option("--friction", "MU", "With --landing bounce: the sliding friction "
                        "coefficient, 0 to 10; a list or a range is a study, a row each.")),
    LAUNCH.only("u", "omega"),
    ("tosses", option("-n --n --tosses", "N", "With --landing bounce: tosses simulated in each "
                      "cell (coin x restitution x friction), default 1000."), None),
    BOUNCE.only("release_height", "vx", *RUNS, "dt", "t_max"),
)
LayoutOpt = option("--layout", "long|wide", "long (default): a row per coin and model (per coin "
                   "and table with --landing bounce); wide: a row per coin, the models (tables) "
                   "side by side, for a spreadsheet.")


@app.command()
@with_groups
def table(
    the_coin=COINS,
    psi: _options.PsisOpt = None,
    psi_dist: _options.PsiDistsOpt = None,
    all_models: Annotated[
        bool, typer.Option("--all", help="Also Table II's densities: uniform, cosine, normal.")
    ] = False,
    vs: Annotated[
        str | None, typer.Option("--vs", metavar="psi", help="psi: one row per --psi angle "
                                 "(default 0:180:15), regimes named.")
    ] = None,
    tol: _accuracy.TolOpt = None,
    method: _accuracy.MethodOpt = None,
    seed: _accuracy.SeedOpt = None,
    layout: LayoutOpt = None,
    bounce=TABLE_TABLE,
    output=TABLE_OUTPUT,
):
    """Chances of heads, sides and tails under every model, for one or more coins.

    One row per coin and model: geometric (eq. 11) and dynamic (eq. 12) always; Table I at
    each --psi angle; psi-averaged densities with --psi-dist or --all (Table II).

    --landing bounce answers another question: the coin lands on a table and bounces; -n
    tosses are simulated (MuJoCo) for each coin and each table (--restitution, --friction:
    lists or ranges make a parameter study), the same seeded launches in every cell, a row a
    cell with 95% intervals, printed as each cell completes.

    Examples: coin table --xi 0.577 ;  coin table --xi 0.1:1:0.1 --format csv ;
    coin table --quarters 8 --all ;  coin table --diameter 30 --thickness 17 --psi 60,90 ;
    coin table --xi 17/30 --vs psi --psi 0:180:10 ;  coin table --xi 0.5 --layout wide ;
    coin table --landing bounce --xi 0.3:0.7:0.1 --friction 0.2,0.4 --seed 1 -f csv
    """
    bouncing = bounce.landing.strip().lower() == "bounce"
    emit_all(report.table(
        **the_coin, psi=psi, psi_dist=psi_dist, all=all_models, vs=vs, tol=tol, method=method,
        seed=seed, layout=layout, **bounce, **output,
        progress=simulating_bar if bouncing else estimator_bar), **output)
    if output.quiet:  # the note that names a drawn seed (--method mc or qmc) is not shown
        options.report_drawn_seed()


# --------------------------------------------------------------------------- stack and coins

#: the coin group of ``coin stack``, around its --p-sides: the stack, then the coin
STACKED, STACKED_COIN = COINS.only("coin", "count"), COINS.only("quarters", "diameter", "thickness")


@app.command()
@with_groups
def stack(
    the_stack=STACKED,
    p_sides: Annotated[
        str | None, typer.Option("--p-sides", "-p", metavar="P", help="Find the stack nearest "
                                 "this chance of a side (0.33, 1/3, 33%), and its neighbours; "
                                 "a list, a range or - for one row each.")
    ] = None,
    the_coin=STACKED_COIN,
    xi: Annotated[str | None, typer.Option("--xi", "-x", hidden=True)] = None,
    model: ModelOpt = None,
    psi: PsiOpt = None,
    psi_dist: PsiDistOpt = None,
    output=OUTPUT,
    old_n: _options.OldCountOpt = None,
):
    """Stacks of real coins glued together: their xi = N h / D and chances.

    The coin is a US quarter unless --coin or --diameter/--thickness says otherwise.

    Examples: coin stack --coin quarter --count 8 ;  coin stack --coin quarter --p-sides 1/3 ;
    coin stack --diameter 25 --thickness 2 --count 1:12:1 ;
    seq 0.1 0.1 0.9 | coin stack --coin nickel --p-sides - --format csv
    """
    emit_all(report.stack(**the_stack, p_sides=p_sides, **the_coin, xi=xi, model=model, psi=psi,
                          psi_dist=psi_dist, **output, old_n=old_n), **output)


@app.command()
@with_groups
def coins(output=OUTPUT):
    """The catalog of real coins, with their dimensions and sources.

    Examples: coin coins ;  coin coins --format csv ;  coin coins -q
    """
    emit_all(report.coins(**output), **output)


# --------------------------------------------------------------------------- fair


@app.command()
@with_groups
def fair(
    diameter: Annotated[
        str | None, typer.Option("--diameter", "-d", metavar="D", help="Diameter for the "
                                 "thickness column (default: the --coin's).")
    ] = None,
    coin: CoinOpt = "quarter",
    psi_dist: PsiDistOpt = None,
    output=OUTPUT,
):
    """The fair three-sided coin under each model, and what the other model says of it.

    Bertrand's paradox in one screen: von Neumann's geometric answer xi = 1/(2 sqrt 2) and
    the dynamic answer xi = 1/sqrt 3 disagree: they assume different ways of tossing.  Under
    a --psi-dist only the sides are 1/3; heads and tails differ.

    Examples: coin fair ;  coin fair --diameter 30 ;  coin fair --psi-dist normal:90:18
    """
    emit_all(report.fair(diameter=diameter, coin=coin, psi_dist=psi_dist, **output), **output)


