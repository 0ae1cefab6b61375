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

from coincli.cli import _bounce as BO
from coincli.cli import _options, _phase, app
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

OutOpt = Annotated[
    str | None,
    typer.Option("--out", "-o", help="Figure file .png, .svg or .pdf; - or none: a text "
                 "plot.", metavar="FILE"),
]
TerminalOpt = Annotated[
    bool, typer.Option("--terminal", help="A text plot on stdout (needs no matplotlib).")
]
# Sizes are parsed by coincli.reports.plot, not by click: click's FloatRange lets nan through
# (nan < 1 is False) and its messages do not say what is allowed.  Limits:
# coincli.render.figures.FIGURE_INCHES, DPI_RANGE and MAX_PIXELS (width x dpi times height x
# dpi, so a figure cannot exhaust the memory).
DpiOpt = Annotated[str, typer.Option("--dpi", help="Dots per inch of a PNG, 10 to 2000 (50 "
                                     "Mpixel at most).", metavar="DPI")]
WidthOpt = Annotated[
    str | None, typer.Option("--width", help="Figure width, 1 to 100 inches.",
                             metavar="INCHES")
]
HeightOpt = Annotated[
    str | None, typer.Option("--height", help="Figure height, 1 to 100 inches.",
                             metavar="INCHES")
]
TitleOpt = Annotated[str | None, typer.Option("--title", help="Replace the figure's title.")]
LogOpt = Annotated[bool, typer.Option("--log", help="Logarithmic xi axis (0.01 to 100).")]
XiRangeOpt = Annotated[
    str | None, typer.Option("--xi-range", help="The xi axis LOW:HIGH (default: 0:2, widened "
                             "to show your marks).", metavar="LOW:HIGH")
]
PsiMarkOpt = Annotated[
    str | None, typer.Option("--psi", help="Mark tossing angles psi, degrees [0, 180]: a "
                             "value, a list a,b or a range.", metavar="DEG")
]


def _show(text_plot) -> None:
    """Print a report's text plot (None: it wrote a figure file)."""
    if text_plot is not None:
        from coincli.render.text import emit

        emit(text_plot)


# --------------------------------------------------------------------------- sides


@plot_app.command("sides")
def sides(
    xi: _options.XisOpt = None,
    coin: _options.CoinOpt = None,
    count: _options.CountsOpt = None,
    quarters: _options.QuartersManyOpt = None,
    diameter: _options.DiameterOpt = None,
    thickness: _options.ThicknessOpt = None,
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
    log: LogOpt = False,
    xi_range: XiRangeOpt = None,
    out: OutOpt = None,
    terminal: TerminalOpt = False,
    dpi: DpiOpt = "150",
    width: WidthOpt = None,
    height: HeightOpt = None,
    title: TitleOpt = None,
    landing: BO.LandingOpt = "catch",
    surface: BO.SurfaceOpt = None,
    restitution: BO.RestitutionOpt = None,
    friction: BO.FrictionOpt = None,
    seed: _options.SeedOpt = None,
    tosses: _options.TossesOpt = None,
    jobs: BO.JobsOpt = None,
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
    _show(report.sides(
        xi=xi, coin=coin, count=count, quarters=quarters, diameter=diameter,
        thickness=thickness, p_sides=p_sides, psi=psi, psi_dist=psi_dist, data=data, log=log,
        xi_range=xi_range, out=out, terminal=terminal, dpi=dpi, width=width, height=height,
        title=title, landing=landing, surface=surface, restitution=restitution,
        friction=friction, seed=seed, tosses=tosses, jobs=jobs))


# --------------------------------------------------------------------------- psi


@plot_app.command("psi")
def psi_cmd(
    xi: _options.XiOpt = None,
    coin: _options.CoinOpt = None,
    count: _options.CountOpt = None,
    quarters: _options.QuartersOpt = None,
    diameter: _options.DiameterOpt = None,
    thickness: _options.ThicknessOpt = None,
    psi: PsiMarkOpt = None,
    out: OutOpt = None,
    terminal: TerminalOpt = False,
    dpi: DpiOpt = "150",
    width: WidthOpt = None,
    height: HeightOpt = None,
    title: TitleOpt = None,
):
    """P(heads), P(sides), P(tails) against psi for one coin, regimes shaded (Fig. 2d).

    Below theta0/2 the coin always lands heads, up to 90 - theta0/2 heads or sides, within
    theta0/2 of 90 degrees all three.  The coin defaults to xi = 1/sqrt 3; --psi marks your
    tossing angles.

    Examples: coin plot psi --xi 0.577 --out psi.png ;
    coin plot psi --quarters 8 --psi 70 --terminal
    """
    _show(report.psi(xi=xi, coin=coin, count=count, quarters=quarters, diameter=diameter,
                     thickness=thickness, psi=psi, out=out, terminal=terminal, dpi=dpi,
                     width=width, height=height, title=title))


# --------------------------------------------------------------------------- map


@plot_app.command("map")
def map_cmd(
    style: Annotated[
        str, typer.Option("--style", help="panels (three maps, one per outcome) or ternary "
                          "(one map, colours mixed by the three chances).")
    ] = "panels",
    xi: _options.XisOpt = None,
    coin: _options.CoinOpt = None,
    count: _options.CountsOpt = None,
    quarters: _options.QuartersManyOpt = None,
    diameter: _options.DiameterOpt = None,
    thickness: _options.ThicknessOpt = None,
    psi: PsiMarkOpt = None,
    log: LogOpt = False,
    xi_range: XiRangeOpt = None,
    out: OutOpt = None,
    terminal: TerminalOpt = False,
    dpi: DpiOpt = "150",
    width: WidthOpt = None,
    height: HeightOpt = None,
    title: TitleOpt = None,
):
    """The chances of heads, sides and tails over the (xi, psi) plane (Fig. 2a-c).

    Table I on a grid; regime boundaries dashed, the white contour is 1/3, the star is the
    fair three-sided coin (xi = 1/sqrt 3, psi = 90).  The coin options and --psi mark your
    designs.

    Examples: coin plot map --out map.png ;
    coin plot map --style ternary --xi 0.5 --psi 80 --out map.pdf ;  coin plot map --terminal
    """
    _show(report.map(style=style, xi=xi, coin=coin, count=count, quarters=quarters,
                     diameter=diameter, thickness=thickness, psi=psi, log=log,
                     xi_range=xi_range, out=out, terminal=terminal, dpi=dpi, width=width,
                     height=height, title=title))


# --------------------------------------------------------------------------- phase


@plot_app.command("phase")
def phase_cmd(
    xi: _options.XiOpt = None,
    coin: _options.CoinOpt = None,
    count: _options.CountOpt = None,
    quarters: _options.QuartersOpt = None,
    diameter: _options.DiameterOpt = None,
    thickness: _options.ThicknessOpt = None,
    psi: _phase.PsiOpt = "90",
    u: _phase.URangeOpt = None,
    omega: _phase.OmegaRangeOpt = None,
    cols: _phase.ColsOpt = None,
    rows: _phase.RowsOpt = None,
    exact: _phase.ExactOpt = False,
    no_curves: _phase.NoCurvesOpt = False,
    toss: _phase.TossMarkOpt = None,
    g: _phase.GOpt = "9.81",
    contact: _phase.ContactOpt = "rim",
    u_range: _phase.OldURangeOpt = None,
    omega_range: _phase.OldOmegaRangeOpt = None,
    exact_curves: _phase.OldExactOpt = False,
    resolution: _phase.OldResolutionOpt = None,
    out: OutOpt = None,
    terminal: TerminalOpt = False,
    dpi: DpiOpt = "150",
    width: WidthOpt = None,
    height: HeightOpt = None,
    title: TitleOpt = None,
):
    """The outcome over launch speed and spin for one coin (Fig. 3): coin phase as a figure.

    The same picture and the same options as `coin phase` (which see): each cell is one
    finite toss; the dashed curves are eq. 10's hyperbolae omega = (2n +- theta0/pi) pi g /
    (2u).  Far from the origin the shares approach the vigorous limit of Table I.

    Examples: coin plot phase --out phase.png ;  coin plot phase --xi 0.3 --psi 70 --terminal ;
    coin plot phase --toss 1.2:40 --u 0:3 --omega 0:100 --out phase.svg
    """
    _show(report.phase(
        xi=xi, coin=coin, count=count, quarters=quarters, diameter=diameter,
        thickness=thickness, psi=psi, u=u, omega=omega, cols=cols, rows=rows, exact=exact,
        no_curves=no_curves, toss=toss, g=g, contact=contact, u_range=u_range,
        omega_range=omega_range, exact_curves=exact_curves, resolution=resolution, out=out,
        terminal=terminal, dpi=dpi, width=width, height=height, title=title))
