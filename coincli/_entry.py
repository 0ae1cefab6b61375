"""The ``coin`` console script and ``python -m coincli``: the signal handlers first
(:mod:`coincli.signals`), then the command line (:func:`coincli.cli.run`).

The cyclic garbage collector is paused while coin starts: importing typer, click and coin's own
modules and building the command allocate some hundred thousand objects and no garbage, yet
trigger collections that scan them all (about 5 ms, 7% of a closed-form run).  Once the command
is built, what exists is frozen (never scanned again: it lives until exit anyway) and collection
resumes for the command's own work (:func:`coincli.cli.run`).
"""

import gc
import sys

from coincli.signals import catch_signals, release_signals, stop_line


def main() -> None:
    """Run ``coin``; exit 128 + signal with one line on stderr if stopped while starting up."""
    gc.disable()
    previous = catch_signals()
    try:
        from coincli.cli import run

        code = run(gc_paused=True)  # never raises; a stop can only come between its steps
    except KeyboardInterrupt:
        words, code = stop_line()
        try:
            sys.stderr.write(f"coin: error: {words}\n")
        except (AttributeError, OSError, ValueError):
            pass
    release_signals(previous)  # the run is over: a signal now ends the process as by default
    sys.exit(code)
