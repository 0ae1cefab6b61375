"""The ``coin`` console script and ``python -m coincli``.

Importing the command line (typer, click) is most of a closed-form run's 60 ms; a Ctrl-C in that
window would otherwise end in a traceback.  This module is tiny and imports nothing of its own, so
the handler is in place from the first line of coin's code that runs.

The cyclic garbage collector is paused while coin starts: importing typer, click and coin's own
modules and building the command allocate some hundred thousand objects and no garbage, yet
trigger collections that scan them all (about 5 ms, 7% of a closed-form run).  Once the command
is built, what exists is frozen (never scanned again: it lives until exit anyway) and collection
resumes for the command's own work (:func:`coincli.cli.run`).
"""

import gc
import sys


def main() -> None:
    """Run ``coin``; exit 130 with one line on stderr if interrupted while still starting up."""
    gc.disable()
    try:
        from coincli.cli import run
    except KeyboardInterrupt:
        sys.stderr.write("coin: error: interrupted\n")
        raise SystemExit(130) from None
    sys.exit(run(gc_paused=True))
