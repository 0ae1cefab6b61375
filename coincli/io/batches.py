"""Batches of values: an option that takes one value, a list, a range or ``-`` (one value a
line from standard input), read and checked whole before any output.

:func:`values_stream` returns :class:`Values`, handed out :data:`coincli.io.table.CHUNK_ROWS`
at a time (a range is never stored; a long stdin batch waits in a temporary file, so memory
stays flat); :func:`values_option` returns a list (or an array); :func:`read_stdin_lines` gives
the value lines of stdin as text.  The limits (:data:`MAX_STDIN_LINES`, :data:`MAX_LINE_CHARS`,
:data:`MAX_STDIN_BYTES`) hold for every command, and every bad value is one usage error naming
its stdin line.  numpy is imported only when a batch is read.
"""

from __future__ import annotations

import sys
from collections.abc import Callable

from coincli.errors import usage_error
from coincli.io.files import READ_CHUNK, UTF8_BOM, stream_reader
from coincli.io.table import CHUNK_ROWS

__all__ = [
    "MAX_STDIN_LINES",
    "MAX_LINE_CHARS",
    "MAX_STDIN_BYTES",
    "Values",
    "values_stream",
    "values_option",
    "read_stdin_lines",
]

MAX_STDIN_LINES = 10_000_000  #: the most values a stdin batch may hold
MAX_LINE_CHARS = 1000  #: the longest stdin line, in bytes (line end included)
#: the most bytes read from stdin: 10^7 full-precision doubles ('-2.2250738585072014e-308'),
#: one a line with CRLF ends, are 260 MB
MAX_STDIN_BYTES = 300_000_000


def _megabytes(n: int) -> str:
    return f"{n / 10**6:g} MB"


# Bytes that may begin a line that is not a value: blanks (bytes.strip and str.strip), '#',
# and every non-ASCII byte (a Unicode space).  Any other first byte begins a value (or an error).
_MAYBE_BLANK = bytes([*b" \t\r\x0b\x0c\x1c\x1d\x1e\x1f#", *range(0x80, 0x100)])
_LINE_STARTS = bytes(10 if b == 10 else 32 if b in _MAYBE_BLANK else 118 for b in range(256))


_RUN_MARKS = bytes(10 if b == 10 else 120 for b in range(256))  # newline stays, the rest 'x'
_LONG_RUN = b"x" * (MAX_LINE_CHARS + 1)
#: A cache, the one piece of state of this module: the compiled pattern of a value line (a
#: newline, then a line whose first non-blank character is not '#'), compiled on first use
#: by :func:`_piece_lines` (``re`` costs start-up time) and never changed after.
_VALUE_LINE = None


def _piece_text(what: str, piece: bytes, first: int) -> str:
    """``piece`` (lines ``first``, ``first + 1``, ...) decoded, or the error for its first line
    that is too long, holds a NUL byte or is not UTF-8 (checked in that order, as whole-piece
    scans: a flood of blank or comment lines costs no Python per line)."""
    bad = []
    run = piece.translate(_RUN_MARKS).find(_LONG_RUN)  # the first run lies in the first long line
    if run >= 0:
        bad.append((piece.count(b"\n", 0, run), 0, f"is longer than {MAX_LINE_CHARS} characters"))
    nul = piece.find(b"\0")
    if nul >= 0:
        bad.append((piece.count(b"\n", 0, nul), 1, "contains a NUL byte"))
    text = None
    try:
        text = piece.decode("utf-8")
    except UnicodeDecodeError as exc:
        bad.append((piece.count(b"\n", 0, exc.start), 2, "is not UTF-8 text"))
    if bad:
        k, _, problem = min(bad)
        raise usage_error(f"{what}: stdin line {first + k} {problem}")
    return text


def _no_stdin(what: str):
    return usage_error(f"{what}: '-' reads values from standard input, but there is none (it is "
                       "closed)")


def _too_big(what: str):
    return usage_error(
        f"{what}: stdin is larger than {_megabytes(MAX_STDIN_BYTES)}; a batch is at most "
        f"{MAX_STDIN_LINES} values, one a line, in at most {MAX_STDIN_BYTES} bytes")


def _too_many(what: str):
    return usage_error(f"{what}: stdin has more than {MAX_STDIN_LINES} values; split the batch "
                       f"(at most {MAX_STDIN_LINES} values, one a line)")


def _stdin_pieces(what: str, stream):
    """Standard input as ``(first line number, bytes)`` pieces of whole lines, about
    :data:`READ_CHUNK` bytes each (the newline between two pieces belongs to neither), read as
    they are needed: memory holds one piece, whatever the length of the input.

    More than :data:`MAX_STDIN_BYTES` is an error as soon as the byte after them is read; a line
    that runs past :data:`MAX_LINE_CHARS` without a newline is handed on cut just past the limit,
    so the piece check names it (``yes``, or /dev/zero, costs one chunk).  A leading UTF-8
    byte-order mark is dropped.
    """
    if stream is None:
        raise _no_stdin(what)
    read = stream_reader(stream)
    carry, total, first, start = b"", 0, 1, True
    while True:
        chunk = read(READ_CHUNK)
        if not chunk:
            break
        total += len(chunk)
        if total > MAX_STDIN_BYTES:
            raise _too_big(what)
        buf = carry + chunk if carry else chunk
        if start and len(buf) >= len(UTF8_BOM):
            start = False
            if buf.startswith(UTF8_BOM):
                buf = buf[len(UTF8_BOM):]
        nul = buf.find(b"\0")
        if nul >= 0:  # reading stops at a NUL byte: _piece_text names its line
            yield first, buf[:nul + 1]
            return
        cut = buf.rfind(b"\n")
        if cut < 0:
            carry = buf
            if len(carry) > MAX_LINE_CHARS:  # _piece_text names the line
                yield first, carry[:MAX_LINE_CHARS + 1]
            continue
        piece, carry = buf[:cut], buf[cut + 1:]
        yield first, piece
        first += piece.count(b"\n") + 1
    if start and carry.startswith(UTF8_BOM):
        carry = carry[len(UTF8_BOM):]
    if carry:
        yield first, carry


def _piece_lines(piece: bytes, text: str, first: int) -> list[tuple[int, str]]:
    """The value lines of a piece (neither blank nor '#' comments) as (line number, text)."""
    global _VALUE_LINE
    nl = piece.count(b"\n")
    marks = piece.translate(_LINE_STARTS)
    if marks.count(b"\nv") == nl and marks.startswith(b"v"):  # every line a value
        return list(zip(range(first, first + nl + 1), map(str.strip, text.split("\n")),
                        strict=True))
    if not piece.translate(None, b" \t\r\x0b\x0c\n"):  # only blank lines
        return []
    if _VALUE_LINE is None:
        import re

        _VALUE_LINE = re.compile(r"\n[^\S\n]*+[^\s#]")  # str.strip's blanks: \s, Unicode
    # The value lines, found by the regex: blank and comment lines cost no Python.
    out = []
    text = "\n" + text  # line k (from 0) follows the k-th newline
    k = at = 0
    for m in _VALUE_LINE.finditer(text):
        pos = m.start()
        k += text.count("\n", at, pos)
        at = pos
        end = text.find("\n", pos + 1)
        out.append((first + k, text[pos + 1:end if end >= 0 else None].strip()))
    return out


def read_stdin_lines(what: str, stdin=None) -> list[tuple[int, str]]:
    """Non-blank, non-comment lines of stdin as (line number, text); CRLF and spaces stripped.

    Limits: at most 10^7 values, 1000 characters a line and :data:`MAX_STDIN_BYTES` bytes; a
    NUL byte or undecodable text is an error naming the line.  A leading byte-order mark is
    ignored.  (A list of every line: for a batch of numbers, :func:`values_stream` keeps memory
    flat.)
    """
    out: list[tuple[int, str]] = []
    for first, piece in _stdin_pieces(what, stdin if stdin is not None else sys.stdin):
        out += _piece_lines(piece, _piece_text(what, piece, first), first)
        if len(out) > MAX_STDIN_LINES:
            raise _too_many(what)
    if not out:
        raise usage_error(f"{what}: '-' read no values from standard input")
    return out


FAST_MIN_BYTES = 20_000  # below this (a few thousand values), per-line parsing costs nothing
_PLAIN_BYTES = b"0123456789.eE+-\r\n"
SPOOL_VALUES = 1 << 19  #: past this many values (4 MB), a checked batch waits in a temporary file
LIST_VALUES = 5_000  #: a batch shorter than this is handed to the old callers as a list


def _piece_floats(what: str, piece: bytes, first: int, item, bounds):
    """The values of one piece of stdin as a float64 array, each checked (by ``item``, or
    against ``bounds`` on the fast path); an error names its line."""
    import numpy as np

    if bounds is not None:  # plain decimals only (ASCII, no NUL): no text check needed
        fast = _fast_floats(piece, what, bounds, item, first)
        if fast is not None:
            return fast
    text = _piece_text(what, piece, first)
    vals = []
    for n, t in _piece_lines(piece, text, first):
        try:
            vals.append(item(t, what))
        except ValueError as exc:
            raise usage_error(f"stdin line {n}: {exc}") from None
    return np.array(vals, dtype=float)


class Values:
    """The values of an option that takes one value, a list, a range or ``-`` (stdin), all
    checked before any output, then handed out :data:`CHUNK_ROWS` at a time by :meth:`chunks`.

    A range is never stored (each chunk is computed, :meth:`coincli.io.grammar.Range.chunk`); a stdin batch is read and
    checked a piece at a time, and past :data:`SPOOL_VALUES` values waits as doubles in an
    anonymous temporary file (in ``TMPDIR``; in memory if none can be made), so memory stays
    flat in the number of values.  ``single`` is the value when one plain value was typed.
    """

    def __init__(self, n: int, arrays=None, spool=None, rng=None, single=None):
        self.n, self._arrays, self._spool, self._range = n, arrays, spool, rng
        self.single = single

    def __len__(self) -> int:
        return self.n

    def __iter__(self):
        for chunk in self.chunks():
            yield from chunk.tolist()

    def __getitem__(self, k: int) -> float:
        if self.single is not None and k in (0, -1):
            return self.single
        k = k + self.n if k < 0 else k
        if not 0 <= k < self.n:
            raise IndexError(k)
        for j, chunk in enumerate(self.chunks()):
            if k < (j + 1) * CHUNK_ROWS:
                return float(chunk[k - j * CHUNK_ROWS])
        raise IndexError(k)  # pragma: no cover

    def chunks(self, size: int = CHUNK_ROWS):
        """float64 arrays of at most ``size`` values, in order."""
        import numpy as np

        if self.single is not None:
            yield np.array([self.single])
        elif self._range is not None:
            for k in range(0, self.n, size):
                yield self._range.chunk(k, min(k + size, self.n))
        elif self._spool is not None:
            self._spool.seek(0)
            for k in range(0, self.n, size):
                yield np.fromfile(self._spool, dtype=float, count=min(size, self.n - k))
        else:
            buf, held = [], 0
            for a in self._arrays:
                while a.size:
                    take = a[:size - held]
                    buf.append(take)
                    held += take.size
                    a = a[take.size:]
                    if held == size:
                        yield np.concatenate(buf)
                        buf, held = [], 0
            if held:
                yield np.concatenate(buf)

    def array(self):
        """Every value in one float64 array (memory: 8 bytes a value)."""
        import numpy as np

        parts = list(self.chunks(max(self.n, 1)))
        return parts[0] if len(parts) == 1 else np.concatenate(parts or [np.empty(0)])

    def values(self):
        """A float for one value, else the array (the form the computing functions take)."""
        if self.n == 1:
            return self.single if self.single is not None else float(self.array()[0])
        return self.array()


def _stdin_values(what: str, item, bounds, stdin=None) -> Values:
    """Read, check and hold a stdin batch (see :class:`Values`)."""

    arrays, n, spool = [], 0, None
    for first, piece in _stdin_pieces(what, stdin if stdin is not None else sys.stdin):
        a = _piece_floats(what, piece, first, item, bounds)
        n += a.size
        if n > MAX_STDIN_LINES:
            raise _too_many(what)
        if spool is None and n > SPOOL_VALUES:
            spool = _spool_file()
            if spool is not None:
                for b in arrays:
                    b.tofile(spool)
                arrays = None
        if spool is not None:
            a.tofile(spool)
        elif a.size:
            arrays.append(a)
    if n == 0:
        raise usage_error(f"{what}: '-' read no values from standard input")
    if spool is not None:
        spool.flush()
    return Values(n, arrays=arrays if spool is None else None, spool=spool)


def _spool_file():
    import tempfile

    try:
        return tempfile.TemporaryFile(prefix="coin-batch-")
    except OSError:
        return None  # no temporary directory: the batch stays in memory


def values_stream(text: str, what: str, item: Callable, *, bounds=None, stdin=None) -> Values:
    """The values of an option that takes one value, a list ``a,b``, a range
    ``start:stop:step`` or ``-`` (one a line from stdin), checked whole, as :class:`Values`.

    Each value is parsed by ``item(text, what)`` (raising ValueError); with ``bounds = (lo, hi)``
    ``item`` must accept exactly the plain decimals in [lo, hi] (inclusive), which lets a long
    stdin batch be converted in one pass and a range be checked at its two ends.  A bad value
    is a usage error naming it (and its stdin line).
    """
    from coincli.io import grammar as parse

    s = text.strip()
    if s == "-":
        return _stdin_values(what, item, bounds, stdin)
    try:
        if ":" in s and bounds is not None:
            rng = parse.parse_range(s, what)
            if not rng.whole or rng.stop <= 2.0**53:  # whole numbers below 2^53 are exact
                for v in (rng.value(0), rng.value(rng.count - 1)):
                    item(str(int(v)) if rng.whole else repr(v), what)
                return Values(rng.count, rng=rng)
        vals = parse.parse_values(text, what, item)
    except ValueError as exc:
        raise usage_error(str(exc)) from None
    if len(vals) == 1 and ":" not in s and "," not in s:
        return Values(1, single=float(vals[0]))  # one value: no numpy on the closed-form path
    import numpy as np

    return Values(len(vals), arrays=[np.array(vals, dtype=float)])


def values_option(text: str, what: str, item: Callable, *, bounds=None, stdin=None):
    """Values of an option that takes one value, a list, a range, or '-' for stdin.

    Each value is parsed by ``item(text, what)`` (raising ValueError); a bad value from stdin
    names its line.  A stdin batch of more than a few thousand values is returned as an
    ndarray (checked against ``bounds = (lo, hi)``, inclusive, when given), a shorter one as a
    list; a list or range typed as a list.  Raises :class:`CoinError` (usage) on any bad value.
    A long batch is better read with :func:`values_stream`, whose memory stays flat.
    """
    from coincli.io.grammar import parse_values

    if text.strip() == "-":
        vals = _stdin_values(what, item, bounds, stdin).array()
        return vals.tolist() if vals.size < LIST_VALUES else vals
    try:
        return parse_values(text, what, item)
    except ValueError as exc:
        raise usage_error(str(exc)) from None


def _fast_floats(data: bytes, what: str, bounds, item, first: int = 1):
    """Plain decimals, exactly one per line, as an ndarray; None (use the per-line path) otherwise.

    The text must use only digits, ``.``, ``eE+-`` and line ends (``\\r`` only before ``\\n``):
    no blanks, comments, spaces, ``inf``, ``nan``, ``%`` or ``/``, and no line may pass the
    1000-character limit.  Then every line holds one token, Python's ``float`` parses each (the
    grammar of ``float`` on this alphabet is the plain decimal one; a malformed token sends the
    whole piece to the per-line path, which names its line), and a value out of ``bounds`` is
    reported with its line number (``first`` is the number of the piece's first line) by
    ``item`` itself.
    """
    if len(data) < FAST_MIN_BYTES and first == 1:
        return None
    if data.translate(None, _PLAIN_BYTES) or data.count(b"\r") != data.count(b"\r\n"):
        return None
    lines = data.count(b"\n") + (0 if data.endswith(b"\n") else 1)
    tokens = data.split()
    if len(tokens) != lines or max(map(len, tokens), default=0) > MAX_LINE_CHARS:
        return None  # blank or over-long lines: the per-line path says which
    import numpy as np

    try:
        arr = np.array(tokens, dtype=float) + 0.0  # -0.0 -> 0.0, as Fraction-based parsers give
    except ValueError:
        return None
    lo, hi = bounds
    bad = ~((arr >= lo) & (arr <= hi))
    for k in np.flatnonzero(arr == 0.0).tolist():  # a nonzero text that underflowed to 0
        if tokens[k].partition(b"e")[0].partition(b"E")[0].strip(b"+-.0"):
            bad[k] = True
            break
    if bad.any():
        k = int(np.argmax(bad))
        t = tokens[k].decode()
        try:
            item(t, what)
        except ValueError as exc:
            raise usage_error(f"stdin line {first + k}: {exc}") from None
        raise usage_error(f"stdin line {first + k}: {what} must be in [{lo:g}, {hi:g}], "
                          f"got {t!r}")
    return arr

