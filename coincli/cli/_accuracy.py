"""``--tol``, ``--method`` and ``--seed`` of ``coin table`` and ``coin design``: their typer
declarations, and the progress bar of long Monte Carlo runs (rich, on stderr, only when stderr
is a terminal and a run has taken more than a second).  The options are parsed and the runs
made by :mod:`coincli.reports.accuracy`.  No numpy, scipy or rich at import time.
"""

from __future__ import annotations

from typing import Annotated

import typer

TolOpt = Annotated[
    str | None,
    typer.Option("--tol", help="Absolute error wanted on each psi-averaged chance, e.g. "
                 "1e-6 (the error is shown).", metavar="TOL"),
]
MethodOpt = Annotated[
    str | None,
    typer.Option("--method", help="Averaging over psi: auto, quad (Gauss-Legendre), mc or qmc "
                 "(simulated tosses).", metavar="METHOD"),
]
DesignMethodOpt = Annotated[
    str | None,
    typer.Option("--method", help="How to average over psi: auto (the fewest nodes that meet "
                 "--tol) or quad (Gauss-Legendre).", metavar="auto|quad"),
]
SeedOpt = Annotated[
    str | None,
    typer.Option("--seed", help="Seed of --method mc or qmc, a whole number >= 0 (default: "
                 "drawn, and reported).", metavar="SEED"),
]  # the shared --seed (coincli.cli._options.SeedOpt), with what it seeds here

