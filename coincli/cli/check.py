"""``coin check`` and ``coin fit``: real tosses against the models.

Thin: their help, and the call of their report; what they print is computed by
:mod:`coincli.reports.check` and written by :func:`coincli.io.table.emit_all`.  Their options
are declared in :mod:`coincli.requests.check`.  numpy and scipy load when a command runs, never
at import.
"""

from __future__ import annotations

from coincli.cli import app
from coincli.cli._options import declared
from coincli.io.table import emit_all
from coincli.requests.check import CHECK, FIT


@app.command()
@declared(CHECK)
def check(request):
    """Are your tosses consistent with the models?  Intervals, exact tests, verdicts.

    Gives the observed frequencies with Wilson and Clopper-Pearson intervals and, for the
    geometric and dynamic models (and each --psi-dist), the expected counts, an exact
    multinomial goodness-of-fit p-value (binomial with --sides and -n alone), the
    log-likelihood and a verdict.  --quiet prints the p-values, one per model.  Caught flips
    (--same and --different, faces only) are tested on the chance of the starting side given a
    face, P(H)/(P(H)+P(T)), with the tosser's fitted spread of psi in the note.

    --expect (or --fair) adds a test against the chances you state.  --landing bounce adds
    the table: tosses of your coin are simulated on the surface (MuJoCo, ten times yours, at
    least 4000) and your counts and the simulated ones are tested for one set of chances
    (exact conditional test), so the simulation's own error is counted; --psi-dist is then
    the launch's.

    Examples: coin check --xi 0.583 --heads 35 --sides 33 --tails 32 ;
    coin check --fair --heads 45 --sides 38 --tails 37 ;
    coin check --landing bounce --surface felt --xi 0.5 --heads 45 --sides 38 --tails 37
    --seed 1 ;
    coin check --xi 0.075 --same 5080 --different 4920 ;
    coin check --quarters 8 --sides 33 -n 100 ;  coin check --coin nickel --count 3 --heads 60
    --sides 9 --tails 31 --psi-dist normal:90:20 --format json
    """
    from coincli.reports import check as report

    emit_all(report.check(**request), **request.output)


@app.command()
@declared(FIT)
def fit(request):
    """Which model do your tosses follow?  Checks a file of experiments and compares models.

    FILE has a header and one experiment a row: the coin as xi, or coin (and count), or
    diameter and thickness; the tosses as heads, sides, tails, or sides and n; optionally a
    label.  Reports every row as `coin check` does, then across rows: the paper's sum of
    squared errors of the side frequencies, each model's log-likelihood and AIC, and the
    maximum-likelihood spread of psi (sd of a normal about 90 deg, truncated to [0, 180]) with
    its profile-likelihood interval.  --quiet prints that spread in degrees.  Rows of caught
    flips (same and different, heads/tails with start, or hsame,hdiff,tsame,tdiff) are
    tossers: each gets its own spread, and the tossers are compared.

    --landing bounce calibrates the table the prototypes were tossed on instead: its
    restitution and friction (--fit) with 95% intervals and a test of fit, from tosses
    simulated on designed tables; --save CAL.json keeps it for --calibration.  The launch
    (--u, --omega, --psi or --psi-dist, --release-height, --vx; the hand toss by default) is
    how the prototypes were tossed, and is recorded in the calibration.

    Examples: coin fit tosses.csv ;  coin fit tosses.csv --format csv ;
    coin fit - --psi-dist uniform,cosine < tosses.csv ;
    coin fit tosses.csv --landing bounce --seed 1 --save table.json ;
    coin fit sim.csv --landing bounce --fit friction --restitution 0.7 --psi-dist uniform
    """
    from coincli.render.progress import simulating_bar
    from coincli.reports import fit as report

    result = report.fit(**request, progress=simulating_bar)
    emit_all(result, **request.output)
    if request.landing.strip().lower() == "bounce":
        from coincli.reports.bounce import warn_unmet

        warn_unmet(result)  # after the table
