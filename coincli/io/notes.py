"""The notes and warnings of a run: written to stderr by the command line, returned by the api.

A report says what its result cannot: a tosser whose coin is too thick for the caught model, a
drawn seed, the tosses that did not settle, ``--jobs`` capped at the cores.  It calls
:func:`note`, :func:`warning` or :func:`seed` (here, the one writer of such lines).  Where they
go depends on who called the report:

- the command line (no collector): each line is written to stderr at once, ``coin: warning:
  ...``, ``coin: note: ...``, ``coin: seed N (...)``, exactly where the run is;
- :mod:`coincli.api` runs the report inside :func:`collected`: the lines are gathered as
  :class:`Note` records, returned with the rows (``rows.notes``), and each warning is also
  issued as a :class:`coincli.errors.CoinWarning` (:func:`warnings.warn`), which a notebook
  shows once and a test can turn into an error.  Nothing is written to stderr.

The collector is a :class:`contextvars.ContextVar`: the one piece of state of this module, held
for the length of one api call (threads and asyncio tasks each have their own).
"""

from __future__ import annotations

import contextlib
import contextvars
import sys
from typing import NamedTuple

__all__ = ["Note", "note", "warning", "seed", "wrote", "lines", "after", "collected", "Rows"]


class Note(NamedTuple):
    """One line a run says besides its rows: ``kind`` (``"warning"``, ``"note"``, ``"seed"`` or
    ``"wrote"``, a file written) and its ``text``; ``str(note)`` is the line the command line
    prints."""

    kind: str
    text: str

    def __str__(self) -> str:
        if self.kind == "seed":
            return f"coin: {self.text}"
        if self.kind == "wrote":
            return f"coin: wrote {self.text}"
        return f"coin: {self.kind}: {self.text}"


_COLLECTOR: contextvars.ContextVar[list | None] = contextvars.ContextVar("coin_notes",
                                                                        default=None)


def _say(item: Note) -> None:
    sink = _COLLECTOR.get()
    if sink is not None:
        sink.append(item)
        return
    try:
        sys.stderr.write(f"{item}\n")
        sys.stderr.flush()
    except (OSError, ValueError):  # stderr closed: the result still stands
        pass


def note(text: str) -> None:
    """``coin: note: TEXT``: something the result does not show (tosses that did not settle)."""
    _say(Note("note", text))


def warning(text: str) -> None:
    """``coin: warning: TEXT``: a result to read with care (a model stretched past its case)."""
    _say(Note("warning", text))


def seed(value: int) -> None:
    """``coin: seed N (--seed N repeats this run)``: a drawn seed the output has no room for."""
    _say(Note("seed", f"seed {value} (--seed {value} repeats this run)"))


def wrote(path: str, what: str) -> None:
    """``coin: wrote PATH (WHAT)``: a file written besides the output (a figure, ``--out``)."""
    _say(Note("wrote", f"{path} ({what})"))


def lines(items) -> None:
    """Several notes at once, in order (:class:`Note` records), after what was printed: the
    command line flushes stdout first."""
    items = list(items)
    if items and _COLLECTOR.get() is None:
        sys.stdout.flush()
    for item in items:
        _say(item)


def after(result) -> list[Note]:
    """The lines that follow a result's output: the ``warning`` and ``notes`` a bouncing run's
    result carries (a design that stopped before its intervals met ``--tol``, tosses that did
    not settle); none for any other result."""
    out = [Note("warning", result.warning)] if getattr(result, "warning", None) else []
    return out + [Note("note", n) for n in getattr(result, "notes", ()) or () if n]


class Rows(list):
    """The rows an api function returns: a plain list of dicts, equal to ``--format json``'s,
    with what the command line says besides them.

    ``notes``: the :class:`Note` records it writes to stderr (warnings, notes, a drawn seed), in
    order.  ``caption``: the paragraph a terminal table shows under the rows (the model, the
    method, the caveats: what the note of ``--format table`` says), or ``""``."""

    __slots__ = ("notes", "caption")

    def __init__(self, rows=(), notes=(), caption: str = ""):
        super().__init__(rows)
        self.notes = list(notes)
        self.caption = caption


@contextlib.contextmanager
def collected():
    """Gather the notes of what runs inside (instead of writing them): yields the list they
    are appended to."""
    sink: list[Note] = []
    token = _COLLECTOR.set(sink)
    try:
        yield sink
    finally:
        _COLLECTOR.reset(token)
