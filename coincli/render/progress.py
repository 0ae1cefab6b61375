"""The progress bar of a long run: one class, :class:`ProgressBar`, for every command.

A bar is drawn by rich on stderr, only when stderr is a terminal, and is gone when the run ends
(transient); off a terminal nothing is written (never to stdout), so a pipe or a log sees only
the result.  rich is imported only when a bar is drawn.  The commands use it as:

- ``coin simulate``, ``coin book``: ``ProgressBar("tossing", n, least=200_000)``, a bar with
  the time left once a run has that many tosses, ticked with the tosses done;
- ``coin design --landing bounce``: ``ProgressBar("simulating", unit="tosses", elapsed=True)``,
  the time taken, ticked with the tosses done and planned (the plan grows);
- the sampling estimators (``--method mc/qmc``): ``ProgressBar(label, delay=1.0)``, drawn
  once a run has taken a second and is not done, ticked with ``(done, total)``.
"""

from __future__ import annotations

import time

from coincli.io.terminal import stderr_is_terminal

__all__ = ["ProgressBar"]


class ProgressBar:
    """A progress bar on stderr for a run of ``total`` steps, on a terminal only.

    ``bar(done)`` or ``bar(done, total)`` reports progress (a new ``total`` replaces the old,
    never below ``done``).  The bar is drawn when the ``with`` block is entered, or with a
    ``delay`` (seconds) at the first report after that delay that is not the last; never when
    ``total`` is below ``least`` or stderr is not a terminal.  Columns: ``label``, the bar,
    ``done/total`` (thousands separated), ``unit`` when given, then the time left (or the time
    taken, with ``elapsed``).  :meth:`close` (or leaving the ``with`` block) takes it away.
    """

    def __init__(self, label: str, total: int = 1, *, least: int = 0,
                 delay: float | None = None, unit: str = "", elapsed: bool = False):
        self.label, self.total, self.delay = label, total, delay
        self.unit, self.elapsed = unit, elapsed
        self.started = time.monotonic()
        self.enabled = total >= least and stderr_is_terminal()
        self.bar = None
        self.task = None

    def __enter__(self):
        if self.delay is None and self.enabled:
            self._draw(self.total)
        return self

    def __exit__(self, *exc):
        self.close()
        return False

    def __call__(self, done: int, total: int | None = None) -> None:
        if self.bar is None:
            whole = self.total if total is None else total
            if not self.enabled or self.delay is None or \
                    time.monotonic() - self.started < self.delay or done >= whole:
                return
            self._draw(whole)
        if total is None:
            self.bar.update(self.task, completed=done)
        else:
            self.bar.update(self.task, completed=done, total=max(total, done))

    def _draw(self, total: int) -> None:
        from rich.console import Console
        from rich.progress import BarColumn, Progress, TimeElapsedColumn, TimeRemainingColumn

        columns = [self.label, BarColumn(), "{task.completed:,}/{task.total:,}"]
        if self.unit:
            columns.append(self.unit)
        columns.append(TimeElapsedColumn() if self.elapsed else TimeRemainingColumn())
        self.bar = Progress(*columns, console=Console(stderr=True), transient=True)
        self.bar.start()
        self.task = self.bar.add_task(self.label, total=total)

    def close(self) -> None:
        if self.bar is not None:
            self.bar.stop()
            self.bar = None


def tossing_bar(total: int, least: int = 200_000) -> ProgressBar:
    """The bar of a run of ``total`` tosses (``coin simulate``, ``coin book --toss``, the
    bouncing runs): the time left, from ``least`` tosses."""
    return ProgressBar("tossing", total, least=least)


def simulating_bar() -> ProgressBar:
    """The bar of ``coin design --landing bounce``: the tosses done of those planned (the plan
    grows) and the time taken."""
    return ProgressBar("simulating", unit="tosses", elapsed=True)


def estimator_bar(label: str) -> ProgressBar:
    """The bar of a long ``--method mc`` or ``qmc`` run: drawn once it has taken a second."""
    return ProgressBar(label, delay=1.0)
