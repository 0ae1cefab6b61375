"""``coin plot sides|psi|map|phase``: the paper's figures with the user's design and data.

The typer declarations; :mod:`coincli.reports.plot` checks the options, computes the figure's
data and draws it into ``--out FILE`` (PNG, SVG or PDF by extension), or, with ``--terminal``,
``--out -`` or no ``--out``, returns a text plot that :func:`coincli.render.text.emit` prints.
Nothing heavy is imported at module level: numpy, scipy, matplotlib and rich load only when a
plot is made.
"""

from __future__ import annotations

from typing import Annotated

import typer

from coincli.cli import _options, _phase, app
from coincli.cli._bounce import BOUNCE, RUNS
from coincli.cli._options import COIN, COINS, Group, option, with_groups
from coincli.reports import plot as report

plot_app = typer.Typer(
    name="plot",
    help="Draw the paper's figures with your design and data on them: sides (Fig. 5a), psi "
    "(Fig. 2d), map (Fig. 2a-c), phase (Fig. 3).  PNG, SVG or PDF by the --out file's "
    "extension (needs matplotlib: pip install 'thickcoin\\[plot]'); a text plot in the terminal "
    "otherwise.  Example: coin plot sides --p-sides 1/3 --out sides.png",
    no_args_is_help=True,
    context_settings={"help_option_names": ["-h", "--help"]},
)
app.add_typer(plot_app, name="plot")

# --------------------------------------------------------------------------- shared options

OutOpt = option("--out -o", "FILE", "Figure file .png, .svg or .pdf; - or none: a text plot.")
TerminalOpt = option("--terminal", None, "A text plot on stdout (needs no matplotlib).", kind=bool)
# Sizes are parsed by coincli.reports.plot, not by click: click's FloatRange lets nan through
# (nan < 1 is False) and its messages do not say what is allowed.  Limits:
# coincli.render.figures.FIGURE_INCHES, DPI_RANGE and MAX_PIXELS (width x dpi times height x
# dpi, so a figure cannot exhaust the memory).
DpiOpt = option("--dpi", "DPI", "Dots per inch of a PNG, 10 to 2000 (50 Mpixel at most).", kind=str)
WidthOpt = option("--width", "INCHES", "Figure width, 1 to 100 inches.")
HeightOpt = option("--height", "INCHES", "Figure height, 1 to 100 inches.")
TitleOpt = option("--title", None, "Replace the figure's title.")
LogOpt = option("--log", None, "Logarithmic xi axis (0.01 to 100).", kind=bool)
XiRangeOpt = option("--xi-range", "LOW:HIGH", "The xi axis LOW:HIGH (default: 0:2, widened to "
                    "show your marks).")
PsiMarkOpt = option("--psi", "DEG", "Mark tossing angles psi, degrees [0, 180]: a value, a list "
                    "a,b or a range.")
#: the xi axis of ``sides`` and ``map``
XI_AXIS = Group(("log", LogOpt, False), ("xi_range", XiRangeOpt, None))
#: ``--landing bounce`` of ``coin plot sides``: the surface, and the tosses simulated on it
SIDES_TABLE = Group(BOUNCE.only("landing", "surface", "restitution", "friction"),
                    ("seed", _options.SeedOpt, None), ("tosses", _options.TossesOpt, None),
                    BOUNCE.only(*RUNS, "calibration"))
#: where the figure goes, and its size and title
FIGURE = Group(("out", OutOpt, None), ("terminal", TerminalOpt, False), ("dpi", DpiOpt, "150"),
               ("width", WidthOpt, None), ("height", HeightOpt, None), ("title", TitleOpt, None))


def _show(text_plot) -> None:
    """Print a report's text plot (None: it wrote a figure file)."""
    if text_plot is not None:
        from coincli.render.text import emit

        emit(text_plot)


# --------------------------------------------------------------------------- sides


@plot_app.command("sides")
@with_groups
def sides(
    the_coin=COINS,
    p_sides: Annotated[
        str | None, typer.Option("--p-sides", "-p", metavar="P", help="Mark target chances of "
                                 "a side (0.33, 1/3, 33%; a list a,b).")
    ] = None,
    psi: _options.PsisOpt = None,
    psi_dist: _options.PsiDistsOpt = None,
    data: Annotated[
        str | None, typer.Option("--data", help="Your tosses, a coin fit CSV, or - (stdin).",
                                 metavar="FILE")
    ] = None,
    axis=XI_AXIS,
    figure=FIGURE,
    table=SIDES_TABLE,
):
    """P(sides) against the aspect ratio for the geometric and dynamic models (Fig. 5a).

    The fair coins of both models are marked; the coin options (--xi, --coin/--count,
    --quarters, --diameter/--thickness) and --p-sides mark your designs, --data your tosses
    with 95% Wilson intervals; --psi and --psi-dist add curves.

    --landing bounce adds tosses simulated onto a surface (MuJoCo; the hand toss of coin
    simulate: u ~ normal:2.4:0.3 m/s, omega ~ normal:38:4 rev/s, psi ~ normal:90:10 deg):
    points with 95% intervals at 8 aspect ratios and the probit curve fitted to them.

    Examples: coin plot sides --out sides.png ;  coin plot sides --p-sides 1/3 --log --terminal ;
    coin plot sides --quarters 6:10:1 --psi-dist normal:90:18 --out sides.svg ;
    coin plot sides --landing bounce --surface wood --seed 1 --out bounce.png
    """
    _show(report.sides(**the_coin, p_sides=p_sides, psi=psi, psi_dist=psi_dist, data=data,
                       **axis, **figure, **table))


# --------------------------------------------------------------------------- psi


@plot_app.command("psi")
@with_groups
def psi_cmd(the_coin=COIN, psi: PsiMarkOpt = None, figure=FIGURE):
    """P(heads), P(sides), P(tails) against psi for one coin, regimes shaded (Fig. 2d).

    Below theta0/2 the coin always lands heads, up to 90 - theta0/2 heads or sides, within
    theta0/2 of 90 degrees all three.  The coin defaults to xi = 1/sqrt 3; --psi marks your
    tossing angles.

    Examples: coin plot psi --xi 0.577 --out psi.png ;
    coin plot psi --quarters 8 --psi 70 --terminal
    """
    _show(report.psi(**the_coin, psi=psi, **figure))


# --------------------------------------------------------------------------- map


@plot_app.command("map")
@with_groups
def map_cmd(
    style: Annotated[
        str, typer.Option("--style", help="panels (three maps, one per outcome) or ternary "
                          "(one map, colours mixed by the three chances).")
    ] = "panels",
    the_coin=COINS,
    psi: PsiMarkOpt = None,
    axis=XI_AXIS,
    figure=FIGURE,
):
    """The chances of heads, sides and tails over the (xi, psi) plane (Fig. 2a-c).

    Table I on a grid; regime boundaries dashed, the white contour is 1/3, the star is the
    fair three-sided coin (xi = 1/sqrt 3, psi = 90).  The coin options and --psi mark your
    designs.

    Examples: coin plot map --out map.png ;
    coin plot map --style ternary --xi 0.5 --psi 80 --out map.pdf ;  coin plot map --terminal
    """
    _show(report.map(style=style, **the_coin, psi=psi, **axis, **figure))


# --------------------------------------------------------------------------- phase


@plot_app.command("phase")
@with_groups
def phase_cmd(the_coin=COIN, grid=_phase.PHASE, old=_phase.OLD, figure=FIGURE):
    """The outcome over launch speed and spin for one coin (Fig. 3): coin phase as a figure.

    The same picture and the same options as `coin phase` (which see): each cell is one
    finite toss; the dashed curves are eq. 10's hyperbolae omega = (2n +- theta0/pi) pi g /
    (2u).  Far from the origin the shares approach the vigorous limit of Table I.

    Examples: coin plot phase --out phase.png ;  coin plot phase --xi 0.3 --psi 70 --terminal ;
    coin plot phase --toss 1.2:40 --u 0:3 --omega 0:100 --out phase.svg
    """
    _show(report.phase(**the_coin, **grid, **old, **figure))
