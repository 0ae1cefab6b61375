"""``--tol``, ``--method`` and ``--seed`` of ``coin table`` and ``coin design``: their typer
declarations, and the progress bar of long Monte Carlo runs (rich, on stderr, only when stderr
is a terminal and a run has taken more than a second).  The options are parsed and the runs
made by :mod:`coincli.reports.accuracy`.  No numpy, scipy or rich at import time.
"""

from __future__ import annotations

import time
from typing import Annotated

import typer

from coincli.io.table import stderr_is_terminal

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


class Progress:
    """``progress(done, total)`` for the estimators: a rich bar on stderr once a run has taken
    a second, only when stderr is a terminal; nothing otherwise (never on stdout)."""

    def __init__(self, label: str, delay: float = 1.0):
        self.label = label
        self.delay = delay
        self.start = time.monotonic()
        self.enabled = stderr_is_terminal()
        self.bar = None
        self.task = None

    def __call__(self, done: int, total: int) -> None:
        if not self.enabled:
            return
        if self.bar is None:
            if time.monotonic() - self.start < self.delay or done >= total:
                return
            from rich.console import Console
            from rich.progress import BarColumn, Progress, TimeRemainingColumn

            self.bar = Progress(self.label, BarColumn(), "{task.completed:,}/{task.total:,}",
                                TimeRemainingColumn(), console=Console(stderr=True),
                                transient=True)
            self.bar.start()
            self.task = self.bar.add_task(self.label, total=total)
        self.bar.update(self.task, completed=done, total=total)

    def close(self) -> None:
        if self.bar is not None:
            self.bar.stop()
            self.bar = None
