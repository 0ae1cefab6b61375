"""``coin book``: the paper's Problem 1, a tossed book or die (three different moments).

Thin: the help of the command, and the call of its report; what it prints is computed by
:mod:`coincli.reports.book` (which also draws and writes a figure for ``--out FILE.png``) and
written here to stdout, or to the ``--out`` file through
:func:`coincli.io.files.write_text_atomic`.  Its options are declared in
:mod:`coincli.requests.book`.
"""

from __future__ import annotations

from coincli.cli import app
from coincli.cli._options import declared
from coincli.errors import compute_error, usage_error
from coincli.io import notes
from coincli.io.table import Result, emit_all
from coincli.io.terminal import stderr_is_terminal
from coincli.render.progress import tossing_bar
from coincli.requests.book import BOOK


def _output(result, fmt: str, quiet: bool, out: str | None) -> None:
    """What the report returned, on stdout, or in the ``--out`` file: written whole or not at
    all (:func:`coincli.io.files.write_text_atomic`), streamed into it (a long --times never
    sits in memory).  A figure was already written by the report (it returns nothing)."""
    if out is None or out == "-" or not isinstance(result, Result):
        emit_all(result, fmt, quiet)
        return
    from coincli.io.files import FileKindError, write_text_atomic

    try:
        size = write_text_atomic(out, lambda fh: emit_all(result, fmt, quiet, out=fh))
    except FileKindError as exc:
        raise usage_error(f"--out: {exc}") from None
    except OSError as exc:
        raise compute_error(f"cannot write {out!r}: {exc.strerror or exc}") from None
    if stderr_is_terminal():
        notes.wrote(out, f"{size:,} bytes")


# --------------------------------------------------------------------------- the command


@app.command("book")
@declared(BOOK)
def book_cmd(request):
    """The paper's Problem 1: a tossed book (a box with three different moments).

    Solves Euler's equations of the free body exactly (Jacobi elliptic functions) from the spin
    at launch.  The motion table gives each omega component's range, its period, the paper's
    Gamma (the linearized frequency about the largest or smallest axis) next to the exact
    frequency, and for a spin near the middle axis the growth rate lambda and the time between
    flips (the tennis-racket flip) next to the separatrix asymptote.  --times gives omega, the
    attitude (a quaternion, body to lab) and the face up at each time; --toss the chance of each
    face of a box caught after its flight, beside the geometric model (each face's solid angle).

    Examples: coin book --size 235x155x30 --spin 0,0,40 ;
    coin book --size 235x155x30 --spin 0.4,40,0.3 --times 0:2:0.01 --format csv ;
    coin book --size 235x155x30 --spin 0.4,40,0.3 --out book.png ;
    coin book --size 16x16x16 --toss -n 100000 --seed 1 --spin normal:0:30,normal:0:30,normal:0:30
    """
    from coincli.reports import book as report

    result = report.book(**request, progress=tossing_bar)
    _output(result, request.fmt, request.quiet, request.out)
    report.seed_note(result, request.seed, request.quiet)
