"""``coin design``, ``coin table``, ``coin stack``, ``coin coins``, ``coin fair``: their help, and
the call of their report in :mod:`coincli.reports.design`, which computes what it prints, written
by :func:`coincli.io.table.emit_all`.  Their options are declared in
:mod:`coincli.requests.design`.
"""

from __future__ import annotations

from coincli.cli import app
from coincli.cli._options import declared
from coincli.io import options
from coincli.io.table import emit_all
from coincli.render.progress import estimator_bar, simulating_bar
from coincli.reports import design as report
from coincli.requests.design import COINS_LIST, DESIGN, FAIR, STACK, TABLE


@app.command()
@declared(DESIGN)
def design(request):
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
    result = report.design(**request, progress=simulating_bar)
    emit_all(result, **request.output)
    if request.landing.strip().lower() == "bounce":
        from coincli.reports.bounce import warn_unmet

        warn_unmet(result)  # after the table


@app.command()
@declared(TABLE)
def table(request):
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
    bouncing = request.landing.strip().lower() == "bounce"
    result = report.table(**request, progress=simulating_bar if bouncing else estimator_bar)
    emit_all(result, **request.output)
    if bouncing:
        from coincli.reports.bounce import warn_unmet

        warn_unmet(result)  # tosses that did not settle: the note, after the table
    if request.quiet:  # the note that names a drawn seed (--method mc or qmc) is not shown
        options.report_drawn_seed()


@app.command()
@declared(STACK)
def stack(request):
    """Stacks of real coins glued together: their xi = N h / D and chances.

    The coin is a US quarter unless --coin or --diameter/--thickness says otherwise.

    Examples: coin stack --coin quarter --count 8 ;  coin stack --coin quarter --p-sides 1/3 ;
    coin stack --diameter 25 --thickness 2 --count 1:12:1 ;
    seq 0.1 0.1 0.9 | coin stack --coin nickel --p-sides - --format csv
    """
    emit_all(report.stack(**request), **request.output)


@app.command()
@declared(COINS_LIST)
def coins(request):
    """The catalog of real coins, with their dimensions and sources.

    Examples: coin coins ;  coin coins --format csv ;  coin coins -q
    """
    emit_all(report.coins(**request), **request.output)


@app.command()
@declared(FAIR)
def fair(request):
    """The fair three-sided coin under each model, and what the other model says of it.

    Bertrand's paradox in one screen: von Neumann's geometric answer xi = 1/(2 sqrt 2) and
    the dynamic answer xi = 1/sqrt 3 disagree: they assume different ways of tossing.  Under
    a --psi-dist only the sides are 1/3; heads and tails differ.

    Examples: coin fair ;  coin fair --diameter 30 ;  coin fair --psi-dist normal:90:18
    """
    emit_all(report.fair(**request), **request.output)
