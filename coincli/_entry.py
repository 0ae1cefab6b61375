"""The ``coin`` console script and ``python -m coincli``.

Importing the command line (typer, click) is most of a closed-form run's 60 ms; a Ctrl-C in that
window would otherwise end in a traceback.  This module is tiny and imports nothing of its own, so
the handler is in place from the first line of coin's code that runs.
"""

import sys


def main() -> None:
    """Run ``coin``; exit 130 with one line on stderr if interrupted while still starting up."""
    try:
        from coincli.cli import run
    except KeyboardInterrupt:
        sys.stderr.write("coin: error: interrupted\n")
        raise SystemExit(130) from None
    sys.exit(run())
