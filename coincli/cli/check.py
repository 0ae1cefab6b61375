"""``coin check`` and ``coin fit``: real tosses against the models.

Thin: the typer declarations of the two commands; what they print is computed by
:mod:`coincli.reports.check` and written by :func:`coincli.io.table.emit_all`.
numpy and scipy load when a command runs, never at import.
"""

from __future__ import annotations

from typing import Annotated

import typer

from coincli.cli import _options, app
from coincli.cli._bounce import BOUNCE, LAUNCH, RUNS
from coincli.cli._options import COIN, OUTPUT, Group, option, with_groups
from coincli.io.table import emit_all

# --------------------------------------------------------------------------- shared options

PsiDistsOpt = _options.PsiDistsOpt
AlphaOpt = option("--alpha", "A", "Significance level of the verdicts.", kind=str)
ConfidenceOpt = option("--confidence", "C", "Confidence level of the intervals.", kind=str)
#: the coin group, in this command's order
CHECK_COIN = COIN.only("xi", "quarters", "coin", "count", "diameter", "thickness")
#: the levels of the verdicts and of the intervals
LEVELS = Group(("alpha", AlphaOpt, "0.05"), ("confidence", ConfidenceOpt, "0.95"))


def _opt(*names: str, mv: str, help: str):
    return typer.Option(*names, metavar=mv, help=help)


ExpectOpt = option("--expect", "H,S,T", "Also test against chances you state: heads, sides, "
                   "tails (0.3,0.4,0.3; 1/3,1/3,1/3; 30%,40%,30%; they add up to 1).  The coin is "
                   "then optional.")
FairOpt = option("--fair", None, "Also test against a fair three-sided coin: --expect "
                 "1/3,1/3,1/3.", kind=bool)


#: ``--landing bounce`` of ``coin check``: the table your tosses are compared with, and the
#: launch of the tosses simulated on it (as ``coin simulate`` takes them)
CHECK_TABLE = Group(
    BOUNCE.only("landing", "calibration", "surface", "restitution", "friction", "torsional",
                "rolling"),
    LAUNCH.only("u", "omega", "psi", "seed"),
    BOUNCE.only("release_height", "vx", *RUNS, "dt", "t_max"),
)


# --------------------------------------------------------------------------- check


@app.command()
@with_groups
def check(
    the_coin=CHECK_COIN,
    heads: Annotated[str | None, _opt("--heads", mv="H", help="Tosses that landed heads.")
                     ] = None,
    sides: Annotated[str | None, _opt("--sides", "-s", mv="S",
                                      help="Tosses that landed on a side.")] = None,
    tails: Annotated[str | None, _opt("--tails", mv="T", help="Tosses that landed tails.")
                     ] = None,
    tosses: _options.TossesOpt = None,
    same: Annotated[str | None, _opt("--same", mv="S", help="Caught flips (faces only) that "
                                     "landed on the side they started on.")] = None,
    different: Annotated[str | None, _opt("--different", mv="D", help="Caught flips that "
                                          "landed on the other side.")] = None,
    psi_dist: PsiDistsOpt = None,
    expect: ExpectOpt = None,
    fair: FairOpt = False,
    table=CHECK_TABLE,
    levels=LEVELS,
    output=OUTPUT,
):
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

    emit_all(report.check(**the_coin, heads=heads, sides=sides, tails=tails, tosses=tosses,
                          same=same, different=different, psi_dist=psi_dist,
                          expect=expect, fair=fair, **table, **levels, **output), **output)


# --------------------------------------------------------------------------- fit

#: ``coin fit --landing bounce``: calibrate the table the prototypes were tossed on
FIT_TABLE = Group(
    BOUNCE.only("landing"),
    ("fit", option("--fit", "PARAMS", "With --landing bounce: what to estimate, comma-separated: "
                   "restitution, friction (default both), psi-spread."), None),
    ("seed", option("--seed", "SEED", "With --landing bounce or --calibration: the seed of the "
                    "simulated tosses (default: drawn, and reported)."), None),
    ("save", option("--save", "CAL.json", "With --landing bounce: write the calibration there, "
                    "for --calibration."), None),
    ("design_tosses", option("--design-tosses", "N", "With --landing bounce: simulated tosses of "
                             "each prototype at each designed table (default 256).  With "
                             "--calibration: the most tosses of each tosser's design (default "
                             "2000)."), None),
    BOUNCE.only("surface", "restitution", "friction", "torsional", "rolling"),
    LAUNCH.only("u", "omega", "psi"),
    BOUNCE.only("release_height", "vx", *RUNS, "dt", "t_max"),
    ("calibration", option("--calibration", "CAL.json", "With --design: each tosser's coin "
                           "designed on your table too, calibrated from tosses (coin fit "
                           "--landing bounce FILE --save CAL.json): a bouncing design per "
                           "tosser (MuJoCo), at most --design-tosses tosses each."), None),
)


@app.command()
@with_groups
def fit(
    file: Annotated[str, typer.Argument(help="Experiments CSV, or - for stdin.",
                                        metavar="FILE")],
    psi_dist: PsiDistsOpt = None,
    no_spread: Annotated[bool, typer.Option("--no-spread", help="Skip the fit of the spread "
                                            "of psi.")] = False,
    delimiter: Annotated[str | None, typer.Option(
        "--delimiter", help="Separator of FILE: comma, semicolon or tab (default: the one the "
        "header uses).", metavar="SEP")] = None,
    design: Annotated[str | None, typer.Option(
        "--design", help="For caught rows: each tosser's coin with this chance of a side "
        "(1/3: fair three-sided) under their fitted spread.", metavar="P")] = None,
    levels=LEVELS,
    table=FIT_TABLE,
    output=OUTPUT,
):
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

    result = report.fit(file, psi_dist=psi_dist, no_spread=no_spread, delimiter=delimiter,
                        design=design, **levels, **table, **output, progress=simulating_bar)
    emit_all(result, **output)
    if table.landing.strip().lower() == "bounce":
        from coincli.reports.bounce import warn_unmet

        warn_unmet(result)  # after the table
