"""``--tol``, ``--method`` and ``--seed`` of ``coin table`` and ``coin design``: their typer
declarations, and the progress bar of long Monte Carlo runs (rich, on stderr, only when stderr
is a terminal and a run has taken more than a second).  The options are parsed and the runs
made by :mod:`coincli.reports.accuracy`.  No numpy, scipy or rich at import time.
"""

from __future__ import annotations

from coincli.cli._options import option

TolOpt = option("--tol", "TOL", "Absolute error wanted on each psi-averaged chance, e.g. 1e-6 "
                "(the error is shown).")
MethodOpt = option("--method", "METHOD", "Averaging over psi: auto, quad (Gauss-Legendre), mc or "
                   "qmc (simulated tosses).")
DesignMethodOpt = option("--method", "auto|quad", "How to average over psi: auto (the fewest "
                         "nodes that meet --tol) or quad (Gauss-Legendre).")
SeedOpt = option("--seed", "SEED", "Seed of --method mc or qmc, a whole number >= 0 (default: "
                 "drawn, and reported).")

