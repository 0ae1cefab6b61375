"""``coin book``: the paper's Problem 1, a tossed book or die (three different moments).

Thin: the typer declaration of the command; what it prints is computed by
:mod:`coincli.reports.book` (which also draws and writes a figure for ``--out FILE.png``) and
written here to stdout, or to the ``--out`` file through
:func:`coincli.io.files.write_text_atomic`.
"""

from __future__ import annotations

import sys
from typing import Annotated

import typer

from coincli.cli import app
from coincli.cli._options import OUTPUT, SeedOpt, TossesOpt, with_groups
from coincli.errors import compute_error, usage_error
from coincli.io.table import Result, emit_all
from coincli.io.terminal import stderr_is_terminal
from coincli.render.progress import tossing_bar


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
        sys.stderr.write(f"coin: wrote {out} ({size:,} bytes)\n")


# --------------------------------------------------------------------------- the command


@app.command("book")
@with_groups
def book_cmd(
    size: Annotated[str | None, typer.Option(
        "--size", help="The box's three sides AxBxC along body axes 1, 2, 3: mm, or with a unit "
        "per side (23.5cmx15.5cmx3cm, 1inx1inx1in).", metavar="AxBxC")] = None,
    moments: Annotated[str | None, typer.Option(
        "--moments", help="Principal moments I1,I2,I3 instead of a size (any unit; each at most "
        "the sum of the other two).  Faces are those of the uniform box with these moments.",
        metavar="I1,I2,I3")] = None,
    spin: Annotated[str | None, typer.Option(
        "--spin", help="Angular velocity at launch about body axes 1, 2, 3: w1,w2,w3 in rad/s "
        "(or with a unit: rev/s, rpm, deg/s).  With --toss each component may be a "
        "distribution: normal:MEAN:SD or uniform:LOW:HIGH (a unit once at the end applies to "
        "both numbers: normal:6:1rev/s).", metavar="W1,W2,W3")] = None,
    times: Annotated[str | None, typer.Option(
        "--times", help="Times (s) for the time series of omega, the attitude and the face up: "
        "a list a,b,c, a range START:STOP:STEP, or - for stdin; units s or ms (500ms, "
        "0:600:100ms).", metavar="TIMES")] = None,
    toss: Annotated[bool, typer.Option(
        "--toss", help="Toss many boxes with random spins and flight times; give the chance of "
        "each face beside the geometric model.")] = False,
    n: TossesOpt = None,
    seed: SeedOpt = None,
    flight: Annotated[str | None, typer.Option(
        "--flight", help="Flight time from launch to catch, s: a value, or with --toss "
        "normal:MEAN:SD (truncated at 0) or uniform:LOW:HIGH.  Default 0.5 with --toss; "
        "without --toss it adds the face up at that catch to the motion table.",
        metavar="SPEC")] = None,
    start: Annotated[str | None, typer.Option(
        "--start", help="Face up at launch (+1 -1 +2 -2 +3 -3: outward normal along +-body "
        "axis; default +3), or random (a uniformly random attitude, with --toss).",
        metavar="FACE")] = None,
    rule: Annotated[str | None, typer.Option(
        "--rule", help="Which face is up at the catch: centre (the vertical through the centre "
        "passes through it: the coin's rule, matched by solid angles) or normal (its outward "
        "normal is nearest the vertical).  Default centre.", metavar="centre|normal")] = None,
    out: Annotated[str | None, typer.Option(
        "--out", "-o", help="Write to FILE: a figure when it ends in .png, .svg or .pdf (omega(t) "
        "and the face up; with --toss the face chances), else the output in --format.",
        metavar="FILE")] = None,
    output=OUTPUT,
):
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

    result = report.book(size=size, moments=moments, spin=spin, times=times, toss=toss,
                         tosses=n, seed=seed, flight=flight, start=start, rule=rule, out=out,
                         **output, progress=tossing_bar)
    _output(result, output.fmt, output.quiet, out)
    report.seed_note(result, seed, output.quiet)
