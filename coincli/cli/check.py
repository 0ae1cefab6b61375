"""``coin check`` and ``coin fit``: real tosses against the models.

Thin: the typer declarations of the two commands; what they print is computed by
:mod:`coincli.reports.check` and written by :func:`coincli.io.table.emit_all`.
numpy and scipy load when a command runs, never at import.
"""

from __future__ import annotations

from typing import Annotated

import typer

from coincli.cli import _options, app
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

    Examples: coin check --xi 0.583 --heads 35 --sides 33 --tails 32 ;
    coin check --xi 0.075 --same 5080 --different 4920 ;
    coin check --quarters 8 --sides 33 -n 100 ;  coin check --coin nickel --count 3 --heads 60
    --sides 9 --tails 31 --psi-dist normal:90:20 --format json
    """
    from coincli.reports import check as report

    emit_all(report.check(**the_coin, heads=heads, sides=sides, tails=tails, tosses=tosses,
                          same=same, different=different, psi_dist=psi_dist, **levels,
                          **output), **output)


# --------------------------------------------------------------------------- fit


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

    Examples: coin fit tosses.csv ;  coin fit tosses.csv --format csv ;
    coin fit - --psi-dist uniform,cosine < tosses.csv
    """
    from coincli.reports import check as report

    emit_all(report.fit(file, psi_dist=psi_dist, no_spread=no_spread, delimiter=delimiter,
                        design=design, **levels, **output), **output)
