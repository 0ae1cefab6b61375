"""``coin plot sides|psi|map|phase``: the paper's figures with the user's design and data.

Their help, and the call of their report: :mod:`coincli.reports.plot` checks the options,
computes the figure's data and draws it into ``--out FILE`` (PNG, SVG or PDF by extension), or,
with ``--terminal``, ``--out -`` or no ``--out``, returns a text plot that
:func:`coincli.render.text.emit` prints.  Their options are declared in
:mod:`coincli.requests.plot`.  Nothing heavy is imported at module level: numpy, scipy,
matplotlib and rich load only when a plot is made.
"""

from __future__ import annotations

import typer

from coincli.cli import app
from coincli.cli._options import declared
from coincli.reports import plot as report
from coincli.requests.plot import MAP, PHASE_FIGURE, PSI, SIDES

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


def _show(text_plot) -> None:
    """Print a report's text plot (None: it wrote a figure file)."""
    if text_plot is not None:
        from coincli.render.text import emit

        emit(text_plot)


# --------------------------------------------------------------------------- the figures


@plot_app.command("sides")
@declared(SIDES)
def sides(request):
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
    _show(report.sides(**request))


@plot_app.command("psi")
@declared(PSI)
def psi_cmd(request):
    """P(heads), P(sides), P(tails) against psi for one coin, regimes shaded (Fig. 2d).

    Below theta0/2 the coin always lands heads, up to 90 - theta0/2 heads or sides, within
    theta0/2 of 90 degrees all three.  The coin defaults to xi = 1/sqrt 3; --psi marks your
    tossing angles.

    Examples: coin plot psi --xi 0.577 --out psi.png ;
    coin plot psi --quarters 8 --psi 70 --terminal
    """
    _show(report.psi(**request))


@plot_app.command("map")
@declared(MAP)
def map_cmd(request):
    """The chances of heads, sides and tails over the (xi, psi) plane (Fig. 2a-c).

    Table I on a grid; regime boundaries dashed, the white contour is 1/3, the star is the
    fair three-sided coin (xi = 1/sqrt 3, psi = 90).  The coin options and --psi mark your
    designs.

    Examples: coin plot map --out map.png ;
    coin plot map --style ternary --xi 0.5 --psi 80 --out map.pdf ;  coin plot map --terminal
    """
    _show(report.map(**request))


@plot_app.command("phase")
@declared(PHASE_FIGURE)
def phase_cmd(request):
    """The outcome over launch speed and spin for one coin (Fig. 3): coin phase as a figure.

    The same picture and the same options as `coin phase` (which see): each cell is one
    finite toss; the dashed curves are eq. 10's hyperbolae omega = (2n +- theta0/pi) pi g /
    (2u).  Far from the origin the shares approach the vigorous limit of Table I.

    Examples: coin plot phase --out phase.png ;  coin plot phase --xi 0.3 --psi 70 --terminal ;
    coin plot phase --toss 1.2:40 --u 0:3 --omega 0:100 --out phase.svg
    """
    _show(report.phase(**request))
