"""What every command shares: exit codes, errors, stdin batches and the output writers.

Output is a :class:`Result`: a title, a note naming the model and assumptions, stable machine
column names with human headers, and rows.  One function, :func:`emit`, writes it in every
format, so a user learns the flags once:

- ``table`` (default): a rich table on a terminal; plain aligned text when piped (no colour codes);
- ``csv`` / ``tsv``: a header of machine names, then one line per row, floats as ``repr``
  (the shortest text that reads back to the same double);
- ``json``: an array of row objects; ``jsonl``: one object per line;
- ``--quiet``: the bare main number only.

Nothing is printed until everything is computed, so an error never leaves half a table behind.
rich is imported only to draw a table on a terminal.
"""

from __future__ import annotations

import itertools
import math
import os
import sys
from collections.abc import Callable, Sequence
from typing import Annotated, NamedTuple

import typer

from coincli.errors import CoinError, ExitCode, InputError, NotComputable
from coincli.io.files import READ_CHUNK, read_capped

__all__ = [
    "ExitCode",
    "CoinError",
    "usage_error",
    "compute_error",
    "Column",
    "Result",
    "emit",
    "FormatOpt",
    "QuietOpt",
    "FORMATS",
    "values_option",
    "read_stdin_lines",
    "read_capped",
    "stream_reader",
    "shown",
    "clip_message",
    "stdout_is_terminal",
    "stderr_is_terminal",
]


MAX_SHOWN_CHARS = 60  #: the most characters of a user's value that an error message repeats
MAX_MESSAGE_CHARS = 1000  #: an error line longer than this is cut in the middle
_ESCAPE = r"\\(?:x[0-9a-fA-F]{2}|u[0-9a-fA-F]{4}|U[0-9a-fA-F]{8}|N\{[^}]*\}|.)"
_QUOTED = None  # compiled on first use: `re` costs nothing at start-up this way


def _clip_repr(r: str, limit: int) -> str:
    """The repr ``r`` (quotes included) cut to about ``limit`` characters, ending in '...'."""
    import re

    q, body = r[0], r[1:-1]
    keep, n = [], 0
    for m in re.finditer(_ESCAPE + "|.", body, re.S):  # never split an escape like \x00
        tok = m.group()
        if n + len(tok) > limit - 3:
            break
        keep.append(tok)
        n += len(tok)
    return f"{q}{''.join(keep)}...{q}"


def shown(text: str, limit: int = MAX_SHOWN_CHARS) -> str:
    """``repr(text)`` for an error message, cut to about ``limit`` characters with '...'."""
    r = repr(str(text))
    return r if len(r) <= limit + 2 else _clip_repr(r, limit)


def clip_message(message: str) -> str:
    """``message`` with every quoted value ('...' or "...", as repr writes them) longer than
    :data:`MAX_SHOWN_CHARS` cut short with '...', and the whole line held to
    :data:`MAX_MESSAGE_CHARS` (its start and end kept: what was wrong, what is allowed)."""
    global _QUOTED
    if len(message) <= MAX_SHOWN_CHARS + 2:
        return message
    if _QUOTED is None:
        import re

        _QUOTED = re.compile(
            rf"""(?<!\w)(?:'(?:[^'\\\n]|{_ESCAPE})*'|"(?:[^"\\\n]|{_ESCAPE})*")""", re.S)
    message = _QUOTED.sub(
        lambda m: m.group() if len(m.group()) <= MAX_SHOWN_CHARS + 2
        else _clip_repr(m.group(), MAX_SHOWN_CHARS), message)
    if len(message) > MAX_MESSAGE_CHARS:
        head = MAX_MESSAGE_CHARS * 2 // 3
        message = message[:head] + " ... " + message[-(MAX_MESSAGE_CHARS - head - 5):]
    return message


def usage_error(message: str) -> InputError:
    """The error of a wrong input (exit 2)."""
    return InputError(message)


def compute_error(message: str) -> NotComputable:
    """The error of a valid input whose answer cannot be computed (exit 1)."""
    return NotComputable(message)


def stdout_is_terminal() -> bool:
    try:
        return sys.stdout.isatty()
    except (AttributeError, ValueError):
        return False


def write_figure(fig, path: str, dpi: float = 150.0, too_small: str = "") -> None:
    """Save a figure through :func:`coincli.render.figures.save_figure` (whole or not at all, the old
    file intact on failure) and say so on stderr (``coin: wrote sides.png (1050 x 675
    pixels)``), as every command that writes a figure does; each failure is one line (a path
    that is not a regular file is a usage error; ``too_small`` is the hint for a figure too
    small for its labels)."""
    from coincli.io.files import FileKindError
    from coincli.render.figures import FigureTooSmall, figure_format, save_figure

    try:
        save_figure(fig, path, dpi)
    except FigureTooSmall as exc:
        raise usage_error(f"{exc}{too_small}") from None
    except FileKindError as exc:
        raise usage_error(f"--out: {exc}") from None
    except OSError as exc:
        raise compute_error(f"cannot write {path!r}: {exc.strerror or exc}") from None
    except MemoryError:
        raise compute_error(f"not enough memory to draw {path!r}") from None
    w, h = (float(v) for v in fig.get_size_inches())
    dims = (f"{round(w * dpi)} x {round(h * dpi)} pixels" if figure_format(path) == "png" else
            f"{w:g} x {h:g} inches")
    try:
        sys.stderr.write(f"coin: wrote {path} ({dims})\n")
    except (OSError, ValueError):
        pass


def stderr_is_terminal() -> bool:
    try:
        return sys.stderr.isatty()
    except (AttributeError, ValueError):
        return False


# --------------------------------------------------------------------------- options

FORMATS = ("table", "csv", "tsv", "json", "jsonl", "markdown")

FormatOpt = Annotated[
    str,
    typer.Option(
        "--format",
        "-f",
        help="Output format: table (default: aligned text, folded to fit a terminal), csv, "
        "tsv, json, jsonl or markdown (a pipe table).",
        metavar="FORMAT",
    ),
]
QuietOpt = Annotated[
    bool, typer.Option("--quiet", "-q", help="Print only the main number (for shell scripts).")
]


def check_format(fmt: str) -> str:
    f = fmt.strip().lower()
    if f not in FORMATS:
        raise usage_error(f"--format must be one of {', '.join(FORMATS)}; got {fmt!r}")
    return f


# --------------------------------------------------------------------------- results


class Column(NamedTuple):
    """A column: machine ``name`` (stable, for csv/json), human ``header`` and number style."""

    name: str
    header: str
    style: str = "g6"  # g6: 6 significant digits; int; text; pct


class Result:
    """A table of results and what produced it.

    ``rows`` (tuples) or ``data`` (the columns' values, one list per column; ``rows`` then reads
    them on demand).  ``quiet`` is the main number for ``--quiet`` (a value or a list, one per
    row); ``vertical`` shows a single row as "quantity  value" lines on the human table; ``key``
    is how many leading columns name a row, repeated in each block when a terminal is too narrow
    for the whole table (default: :func:`key_columns`).  ``chunks``, an iterable of ``data``
    (a list of columns, lists or arrays, at most :data:`CHUNK_ROWS` rows each), is a streamed
    batch: each chunk is computed when it is written, and ``quiet`` is then the index of the
    column ``--quiet`` prints.
    A plain class, not a dataclass: creating a dataclass costs most of a millisecond at import.
    """

    __slots__ = ("title", "columns", "rows", "note", "quiet", "vertical", "data", "key",
                 "chunks")

    def __init__(self, title: str, columns: Sequence[Column], rows: list, note: str = "",
                 quiet: object = None, vertical: bool = False, data: list | None = None,
                 key: int | None = None, chunks=None):
        self.title, self.columns, self.rows, self.note = title, columns, rows, note
        self.quiet, self.vertical, self.data, self.key = quiet, vertical, data, key
        self.chunks = chunks
        if data is not None and not rows:
            if len({len(col) for col in data}) > 1:
                raise ValueError("Result.data: columns of different lengths")
            self.rows = _RowView(data)  # rows on demand: csv of a long batch needs none

    def __repr__(self):
        return f"Result({self.title!r}, {len(self.columns)} columns, {len(self.rows)} rows)"


class _RowView(Sequence):
    """The rows of column data, read on demand (a list of 10^6 tuples costs half a second)."""

    def __init__(self, data):
        self._data = data

    def __len__(self):
        return len(self._data[0]) if self._data else 0

    def __getitem__(self, k):
        if isinstance(k, slice):
            return list(zip(*(col[k] for col in self._data), strict=True))
        return tuple(col[k] for col in self._data)

    def __iter__(self):
        return zip(*self._data, strict=True)


def _machine(v):
    """Text for csv/tsv: floats as repr (round-trips), inf as inf, None as empty."""
    if v is None:
        return ""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, float):
        return repr(float(v))  # numpy.float64 is a float, but its repr is 'np.float64(...)'
    return str(v)


_JSON_TYPES = (float, int, str, bool, type(None))


def _json_value(v):
    if type(v) not in _JSON_TYPES:
        if hasattr(v, "item"):  # a numpy scalar: json cannot write numpy.int64
            v = v.item()
        elif isinstance(v, float):
            v = float(v)
    if isinstance(v, float) and not math.isfinite(v):
        # JSON has no NaN or Infinity (RFC 8259; jq and JSON.parse reject them): NaN is null,
        # +-inf the strings "inf" / "-inf" that float() reads back, as in csv.
        return None if math.isnan(v) else ("inf" if v > 0 else "-inf")
    return v


def _human(v, style: str) -> str:
    if v is None:
        return "-"
    if isinstance(v, str):
        return v
    if style == "int":
        return str(int(v))
    if isinstance(v, float):
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        if style == "pct":
            return f"{100 * v:.4g}%"
        if style.startswith("g"):
            digits = int(style[1:] or 6)
            if v == 0:
                return "0"
            return f"{v:.{digits}g}"
    return str(v)


CHUNK_ROWS = 8_192  #: rows computed, formatted and written at a time by a streamed batch


def option_given(name: str) -> bool:
    """The value of a flag that the shared output options add to every command (``no_headers``),
    read from the running command's click context; False outside a command."""
    try:  # typer's vendored click (0.26 to 0.28), already imported by typer
        from typer._click.globals import get_current_context
    except ImportError:  # pragma: no cover - a typer that uses click itself
        from click import get_current_context

    ctx = get_current_context(silent=True)
    return bool(ctx is not None and ctx.params.get(name))


def emit(result: Result, fmt: str = "table", quiet: bool = False, out=None,
         no_headers: bool | None = None) -> None:
    """Write ``result`` to ``out`` (stdout) in the chosen format.

    A result with ``chunks`` (a streamed batch) is written a chunk at a time, so memory stays flat
    in the number of rows; its input was checked before the first chunk (see :class:`Values`).
    ``no_headers`` (the ``--no-headers`` flag, read from the command line when None) drops the
    csv/tsv header line.
    """
    out = out if out is not None else sys.stdout
    fmt = check_format(fmt)
    if no_headers is None:
        no_headers = option_given("no_headers")
    if result.chunks is not None:  # the first chunk is computed before anything is written
        chunks = iter(result.chunks)
        first = next(chunks, None)
        result.chunks = itertools.chain([] if first is None else [first], chunks)
    if quiet:
        if result.chunks is None:
            q = result.quiet
            _write_rows(out, [q if isinstance(q, list) else [q]], "\n", quote=False)
        else:
            for data in result.chunks:
                _write_rows(out, [_plain_list(data[result.quiet])], "\n", quote=False)
        return
    names = [c.name for c in result.columns]
    if fmt in ("csv", "tsv"):
        sep = "," if fmt == "csv" else "\t"
        if not no_headers:
            out.write(sep.join(names) + "\n")
        for cols in _column_chunks(result, arrays=True):
            _write_rows(out, cols, sep)
    elif fmt in ("json", "jsonl"):
        _write_json(out, names, _column_chunks(result), fmt == "json")
    elif fmt == "markdown":
        if result.chunks is None:
            out.write(markdown_table(result))
        else:
            first = True
            for cols in result.chunks:
                part = markdown_table(_chunk_result(result, cols))
                if not first:  # the header once; the note after the last chunk
                    part = part.split("\n", 2)[2]
                body, _, note = part.partition("\n\n")
                out.write(body + "\n")
                first = False
            if result.note:
                out.write("\n" + "\n".join(_md_text(p) for p in result.note.split("\n")) + "\n")
    elif stdout_is_terminal() and out is sys.stdout:
        _human_table(result, out, terminal=True)
    else:
        _human_table(result, out, terminal=False)


def emit_all(results, fmt: str = "table", quiet: bool = False, out=None) -> None:
    """Write a report's output: one :class:`Result` or several, in order, through :func:`emit`
    (what a command of :mod:`coincli.cli` does with what :mod:`coincli.reports` returns).
    Human tables (``table``, not ``quiet``) are separated by a blank line."""
    results = [results] if isinstance(results, Result) else results
    for k, result in enumerate(results):
        if k and not quiet and check_format(fmt) == "table":
            (out if out is not None else sys.stdout).write("\n")
        emit(result, fmt, quiet, out)


def _chunk_result(result: Result, cols) -> Result:
    return Result(result.title, result.columns, [], note=result.note, vertical=result.vertical,
                  data=[_plain_list(c) for c in cols], key=result.key)


def _human_table(result: Result, out, terminal: bool) -> None:
    """The human table (laid out in the terminal's width, bold title and headers unless
    NO_COLOR or TERM=dumb, on a terminal; as wide as it needs in a pipe).  A streamed batch is
    laid out by its first chunk and written a chunk at a time: a later cell wider than its
    column shifts its row, it is never cut."""
    width, bold = None, False
    if terminal:
        from coincli.render.terminal import colour_allowed, terminal_width

        width, bold = terminal_width(out), colour_allowed()
    if result.chunks is None:
        out.write(plain_table(result, width, bold))
        return
    chunks = iter(result.chunks)
    first = next(chunks, None)
    if first is None:
        out.write(plain_table(Result(result.title, result.columns, [], result.note), width,
                              bold))
        return
    second = next(chunks, None)
    whole = _chunk_result(result, first)
    if second is None:
        out.write(plain_table(whole, width, bold))
        return
    out.write(plain_table(Result(whole.title, whole.columns, whole.rows, "", key=whole.key),
                          width, bold))
    headers, rows, right = _human_cells(whole)
    blocks = _Layout(headers, rows, width).blocks(key_columns(result))
    for cols in itertools.chain([second], chunks):
        _, rows, _ = _human_cells(_chunk_result(result, cols))
        if blocks is not None and len(blocks) == 1:  # one table: the rows go on under it
            lines = _block_lines(headers, rows, right, *blocks[0], header=False)
        elif blocks is not None:  # folded: each chunk's blocks, with their headers
            lines = []
            for bcols, widths in blocks:
                lines += ["", *_block_lines(headers, rows, right, bcols, widths, bold)]
        else:
            lines = _vertical_lines(headers, rows, width)
        out.write("\n".join(lines) + "\n")
    if result.note:
        out.write("\n".join(_paragraphs(result.note, width)) + "\n")


def _column_chunks(result: Result, arrays: bool = False):
    """The result's columns a chunk at a time (one chunk unless it is streamed): lists, or with
    ``arrays`` the columns as the command gave them (:func:`_write_rows` takes a float64 array
    as it is; a list of floats it would turn back into one)."""
    plain = (lambda c: c) if arrays else _plain_list
    if result.chunks is not None:
        for cols in result.chunks:
            yield [plain(c) for c in cols]
        return
    if result.data is not None and isinstance(result.rows, _RowView):
        yield [plain(c) for c in result.data]
    elif result.rows:
        yield [list(c) for c in zip(*result.rows, strict=True)]
    else:
        yield [[] for _ in result.columns]


def _plain_list(col):
    """A column as a list of Python values (an ndarray's ``tolist``: numpy's float64 writes
    itself as ``np.float64(0.5)`` through ``%r``)."""
    if hasattr(col, "tolist"):
        return col.tolist()
    return col if isinstance(col, list) else list(col)


def _json_cells(col) -> list:
    """A column's cells as JSON text: floats as repr (non-finite as null / "inf" / "-inf"),
    ints, true/false, null, strings quoted once per distinct value."""
    import json

    kinds = set(map(type, col))
    if kinds <= {float}:
        if all(map(math.isfinite, col)):
            return list(map(float.__repr__, col))
    elif kinds == {int}:
        return list(map(int.__repr__, col))
    elif kinds <= {str, type(None)}:
        cells = {v: json.dumps(v) for v in set(col)}
        return list(map(cells.__getitem__, col))
    return [json.dumps(_json_value(v), allow_nan=False) for v in col]


_JSON_BLOCK = 2048  #: rows of JSON formatted at a time


def _write_json(out, names, chunks, array: bool) -> None:
    """JSON (an array of objects, indented as ``json.dumps(indent=2)`` writes it) or JSON lines,
    written a chunk at a time: the array's brackets and commas are written around the chunks."""
    import json

    keys = [json.dumps(n) for n in names]
    if array:
        template = "  {\n" + ",\n".join(f"    {k.replace('%', '%%')}: %s" for k in keys) + \
            "\n  }"
        joiner = ",\n"
    else:
        template = "{" + ", ".join(f"{k.replace('%', '%%')}: %s" for k in keys) + "}"
        joiner = "\n"
    if not names:
        template = "  {}" if array else "{}"
    started = False
    for cols in chunks:
        n = len(cols[0]) if cols else 0
        for k in range(0, n, _JSON_BLOCK):  # a block of rows at a time: a JSON row is long
            ready = [_json_cells(c[k:k + _JSON_BLOCK]) for c in cols]
            part = list(zip(*ready, strict=True))
            text = joiner.join(map(template.__mod__, part))
            if array:
                text = (",\n" if started else "[\n") + text
            else:
                text += "\n"
            out.write(text)
            started = True
    if array:
        out.write("\n]\n" if started else "[]\n")


class _Empty:
    """A cell that ``%r`` writes as nothing (None in a float column)."""

    def __repr__(self):
        return ""


_EMPTY = _Empty()
_CHUNK = 8_192  # rows formatted and written at a time (bounded memory for long batches)


def _constant(col, kinds) -> bool:
    """Whether every cell of a long column is the same plain value (not a zero: 0.0 == -0.0)."""
    if len(col) < 2 or len(kinds) != 1 or not kinds <= {float, int, str}:
        return False
    v = col[0]
    return (v != 0 if isinstance(v, (float, int)) else True) and col.count(v) == len(col)


def _float_cells(col):
    """The repr of every cell of a float64 array, as a list, when that can be had with fewer
    than one repr a cell: a column of few distinct values (the nearest stack's chances)
    formats each value once, and one that repeats each value ``r`` times in a row (a table's xi,
    one row per model) formats every ``r``-th.  None otherwise.  Zeros and NaN are left to the
    plain path: equality merges 0.0 with -0.0 and never holds for NaN."""
    import numpy as np

    n = len(col)
    if n < 64:
        return None
    if col[0] == col[1]:
        for r in range(2, 9):
            if n % r == 0 and col[r - 1] == col[0] and col[r] != col[0]:
                grid = col.reshape(-1, r)
                every = grid[:, 0]
                if (grid == every[:, None]).all() and every.all():
                    strs = repr(every.tolist())[1:-1].split(", ")
                    return list(itertools.chain.from_iterable(zip(*[strs] * r)))
                break
    if len(set(col[:512].tolist())) > 384:  # mostly distinct: not worth sorting
        return None
    uniq = np.unique(col)
    if len(uniq) * 4 > n or not uniq.all() or np.isnan(uniq).any():
        return None
    strs = repr(uniq.tolist())[1:-1].split(", ")
    return list(map(strs.__getitem__, np.searchsorted(uniq, col).tolist()))


def _few_cells(col: list):
    """The text of every cell of a long list of floats and Nones (None: empty), each distinct
    value formatted once, when there are few (but more than one: one is a constant column);
    None otherwise, and when a zero is among them (a dict merges 0.0 with -0.0).  A NaN is its
    own key (a dict finds an object by identity)."""
    n = len(col)
    if n < 64 or len(set(col[:512])) > 384:
        return None
    distinct = set(col)
    if len(distinct) * 4 > n or len(distinct) < 2 or 0.0 in distinct:
        return None
    text = {v: "" if v is None else repr(v) for v in distinct}
    return list(map(text.__getitem__, col))


def _write_rows(out, cols, sep: str, quote: bool = True) -> None:
    """Write columns as lines of ``sep``-separated cells: floats as repr, None as empty.

    Columns are lists or arrays.  Formatting a double as its shortest text is most of the cost,
    so it is done in C (the repr of a whole list, split) and as seldom as the column allows: a
    column that holds one value throughout (a coin's name, a diameter) becomes part of the
    separator, a float column equal to an earlier one (P(tails) = P(heads)) reuses its text,
    and :func:`_float_cells` formats a column of few values, or of repeated values, once per
    value.  The cells of a block of rows are then joined once: no Python call per row.
    """
    fields = []  # (spec, cells or None); cells None: the spec is the constant text itself
    floats = []  # (field index, array) of the float64 array columns so far
    for col in cols:
        kind = getattr(getattr(col, "dtype", None), "kind", None)
        if kind is None and len(col) >= 64 and isinstance(col[0], float) and \
                set(map(type, col)) == {float}:
            cells = _few_cells(col)  # a nearest stack's chances: each once, no array needed
            if cells is not None:
                fields.append(("%s", cells))
                continue
            import numpy as np

            col, kind = np.array(col, dtype=float), "f"
        if kind == "f" and col.ndim == 1:
            if len(cols) > 1 and len(col) > 1 and col[0] != 0 and (col == col[0]).all():
                text = repr(float(col[0]))
                fields.append(((_csv_cell(text, sep) if quote else text).replace("%", "%%"),
                               None))
                continue
            twin = next((k for k, prev in floats if prev[0] == col[0] and
                         (prev == col).all()), None) if len(col) else None
            if twin is not None and col.all():  # no zeros: 0.0 == -0.0
                spec, cells = fields[twin]
                if spec == "%r":
                    cells = repr(cells)[1:-1].split(", ")
                    fields[twin] = ("%s", cells)
                fields.append(("%s", cells))
                continue
            cells = _float_cells(col)
            fields.append(("%r", col.tolist()) if cells is None else ("%s", cells))
            floats.append((len(fields) - 1, col))
            continue
        if kind in ("i", "u") and col.ndim == 1:
            fields.append(("%d", col.tolist()))
            continue
        col = _plain_list(col)
        kinds = set(map(type, col))
        if len(cols) > 1 and _constant(col, kinds):
            text = _machine(col[0])
            fields.append(((_csv_cell(text, sep) if quote else text).replace("%", "%%"), None))
        elif kinds <= {float}:
            fields.append(("%r", col))
        elif kinds == {int}:
            fields.append(("%d", col))
        elif kinds == {float, type(None)}:  # e.g. a neighbour that does not exist: empty cell
            cells = _few_cells(col)
            fields.append(("%r", [_EMPTY if v is None else v for v in col]) if cells is None
                          else ("%s", cells))
        elif kinds <= {str, type(None)}:  # few distinct texts (a coin, a model): each once
            cells = {v: _csv_cell(_machine(v), sep) if quote else _machine(v) for v in set(col)}
            fields.append(("%s", list(map(cells.__getitem__, col))))
        else:  # mixed: cell by cell (a set would merge 0.0 with -0.0 and 1 with True)
            fields.append(("%s", [_csv_cell(_machine(v), sep) if quote else _machine(v)
                                  for v in col]))
    n = len(cols[0]) if cols else 0
    if len(fields) == 1 and fields[0][0] == "%r":  # one column of floats (-q of a batch)
        col = fields[0][1]
        for k in range(0, len(col), _CHUNK):
            out.write("\n".join(map(repr, col[k:k + _CHUNK])) + "\n")
        return
    # One %-format for a row (a constant column is part of it, its text escaped), repeated for
    # a block of rows and applied once to the block's cells, laid out row by row in one flat
    # list: a single C call formats and joins a block, with no per-row Python and no list of
    # cell texts in between (a quarter less time than splitting a repr of each column).
    row, cells_of = [], []
    for spec, cells in fields:
        if row:
            row.append(sep)
        row.append(spec)  # a constant column's text, already %-escaped
        if cells is not None:
            cells_of.append(cells)
    row = "".join(row) + "\n"
    if not cells_of:  # every column constant
        out.write((row % ()) * n)
        return
    width = len(cells_of)
    for k in range(0, n, _CHUNK):
        m = min(_CHUNK, n - k)
        flat = [None] * (width * m)
        for j, cells in enumerate(cells_of):
            flat[j::width] = cells[k:k + m]
        out.write((row * m) % tuple(flat))


def _csv_cell(text: str, sep: str) -> str:
    if sep in text or '"' in text or "\n" in text:
        return '"' + text.replace('"', '""') + '"'
    return text


def _human_cells(result: Result):
    """``(headers, rows, right)``: the human table's text, one row of cells per result row (one
    ``quantity / value`` line per column for a one-row ``vertical`` result), and which columns
    are right-aligned (numbers)."""
    if result.vertical and len(result.rows) == 1:
        row = result.rows[0]
        cells = [[c.header, _human(v, c.style)]
                 for c, v in zip(result.columns, row, strict=True)]
        return ["quantity", "value"], cells, [False, False]
    if result.data is not None and isinstance(result.rows, _RowView):
        cols = [_human_column(_plain_list(col), c.style)
                for col, c in zip(result.data, result.columns, strict=True)]
        cells = [list(r) for r in zip(*cols, strict=True)]
    else:
        cells = [[_human(v, c.style) for v, c in zip(row, result.columns, strict=True)]
                 for row in result.rows]
    return [c.header for c in result.columns], cells, [c.style != "text" for c in result.columns]


def _human_column(col: list, style: str) -> list[str]:
    """:func:`_human` of every cell of a column; a column of plain floats in a ``gN`` style
    in one C-level pass (a streamed batch has a million of them)."""
    if style.startswith("g") and set(map(type, col)) <= {float}:
        spec = f".{int(style[1:] or 6)}g"
        cells = list(map(format, col, itertools.repeat(spec, len(col))))
        if 0.0 in col:  # -0.0 is shown as 0, as _human does
            cells = ["0" if c == "-0" else c for c in cells]
        return cells
    return [_human(v, style) for v in col]


GAP = 2  #: blanks between two columns of a human table


def _wrap(text: str, width: int) -> list[str]:
    """``text`` in lines of at most ``width`` characters, broken at blanks: a word (and so a
    number) is never cut, except that a word with letters longer than ``width`` (a web address)
    is broken after its ``/``; a piece still longer stands alone on its line."""
    if len(text) <= width:
        return [text]
    lines, cur = [], ""
    for word in text.split():
        if cur and len(cur) + 1 + len(word) > width:
            lines.append(cur)
            cur = ""
        if len(word) > width and _breakable(word):
            for piece in _pieces(word):
                if cur and len(cur) + len(piece) > width:
                    lines.append(cur)
                    cur = ""
                cur += piece
            continue
        cur = f"{cur} {word}" if cur else word
    lines.append(cur)
    return lines


def _breakable(word: str) -> bool:
    return "/" in word and any(c.isalpha() for c in word)


def _pieces(word: str) -> list[str]:
    """``a/b/c`` -> ``a/``, ``b/``, ``c``."""
    out, start = [], 0
    for k, c in enumerate(word):
        if c == "/":
            out.append(word[start:k + 1])
            start = k + 1
    if start < len(word):
        out.append(word[start:])
    return out


def _longest_word(text: str) -> int:
    return max((max(map(len, _pieces(w))) if _breakable(w) else len(w)
                for w in text.split()), default=len(text))


class _Layout:
    """Column widths for a human table within ``width`` characters (None: no limit).

    A column's natural width is its longest cell or header; its narrowest is its longest word,
    since cells and headers wrap at blanks only.  A table that does not fit its natural widths is
    fitted by wrapping the widest wrappable columns; one whose narrowest widths still do not fit
    is folded into blocks of columns, each repeating the key columns; when even the key columns
    and one more do not fit, each row is shown as ``quantity  value`` lines.  A number is never
    cut: it is one word.
    """

    def __init__(self, headers, rows, width):
        n = len(headers)
        self.width = width
        self.headers, self.rows = headers, rows
        self.nat = [len(h) for h in headers]
        self.min = [_longest_word(h) for h in headers]
        for r in rows:
            for i in range(n):
                s = r[i]
                if len(s) > self.nat[i]:
                    self.nat[i] = len(s)
                w = _longest_word(s)
                if w > self.min[i]:
                    self.min[i] = w

    def fit(self, cols):
        """Widths for the columns ``cols`` within the width, or None when they cannot fit."""
        w = [self.nat[i] for i in cols]
        if self.width is None:
            return w
        avail = self.width - GAP * (len(cols) - 1)
        excess = sum(w) - avail
        if excess <= 0:
            return w
        slack = [w[k] - self.min[c] for k, c in enumerate(cols)]
        if sum(slack) < excess:
            return None
        while excess > 0:  # narrow the widest column that can still wrap, a character at a time
            k = max((k for k in range(len(cols)) if slack[k] > 0), key=w.__getitem__)
            w[k] -= 1
            slack[k] -= 1
            excess -= 1
        for k, c in enumerate(cols):  # a wrapped column is as wide as its longest line
            if w[k] < self.nat[c]:
                texts = {self.headers[c], *(r[c] for r in self.rows)}
                w[k] = max(len(line) for t in texts for line in _wrap(t, w[k]))
        return w

    def blocks(self, key: int):
        """[(columns, widths)]: all columns at once, or blocks repeating the first ``key``
        columns; None when some block cannot fit even one column beside the key."""
        n = len(self.nat)
        every = list(range(n))
        w = self.fit(every)
        if w is not None:
            return [(every, w)]
        key = min(key, n - 1)
        keys, out, cur = every[:key], [], []
        for c in every[key:]:
            if self.fit(keys + cur + [c]) is not None:
                cur.append(c)
                continue
            if not cur:
                return None
            out.append(keys + cur)
            cur = [c]
            if self.fit(keys + cur) is None:
                return None
        if cur:
            out.append(keys + cur)
        return [(cols, self.fit(cols)) for cols in out]


def _bold(text: str, on: bool) -> str:
    return f"\x1b[1m{text}\x1b[0m" if on and text else text


def _block_lines(headers, rows, right, cols, widths, bold=False, header=True) -> list[str]:
    """The lines of one block: wrapped headers (bottom-aligned), a rule, the rows."""
    lines = []
    if header:
        heads = [_wrap(headers[c], w) for c, w in zip(cols, widths, strict=True)]
        depth = max(map(len, heads))
        for k in range(depth):
            parts = []
            for h, w in zip(heads, widths, strict=True):
                j = k - (depth - len(h))
                parts.append((h[j] if j >= 0 else "").ljust(w))
            lines.append(_bold("  ".join(parts).rstrip(), bold))
        lines.append("  ".join("-" * w for w in widths).rstrip())
    for r in rows:
        cells = [_wrap(r[c], w) if len(r[c]) > w else [r[c]]
                 for c, w in zip(cols, widths, strict=True)]
        for k in range(max(map(len, cells))):
            parts = []
            for c, cell, w in zip(cols, cells, widths, strict=True):
                s = cell[k] if k < len(cell) else ""
                parts.append(s.rjust(w) if right[c] else s.ljust(w))
            lines.append("  ".join(parts).rstrip())
    return lines


def _paragraphs(text: str, width: int | None) -> list[str]:
    if width is None:
        return text.split("\n")
    return [line for para in text.split("\n") for line in _wrap(para, width)]


def _vertical_lines(headers, rows, width) -> list[str]:
    """Each row as ``header  value`` lines, rows apart by a blank line (a terminal too narrow
    for even two columns of the table)."""
    lines = []
    for k, r in enumerate(rows):
        pairs = [[h, v] for h, v in zip(headers, r, strict=True)]
        two = _Layout(["", ""], pairs, width)
        widths = two.fit([0, 1]) or two.min
        if k:
            lines.append("")
        lines += _block_lines(["", ""], pairs, [False, False], [0, 1], widths, header=False)
    return lines


def key_columns(result: Result) -> int:
    """How many leading columns name a row (repeated in every block of a folded table):
    ``result.key`` when set; else the first column, and the second too when it is text and the
    first is not (``xi``, ``model``)."""
    if result.key is not None:
        return result.key
    cols = result.columns
    if len(cols) > 2 and cols[0].style != "text" and cols[1].style == "text":
        return 2
    return 1


def plain_table(result: Result, width: int | None = None, bold: bool = False) -> str:
    """The human table as text: title, aligned columns (headers over a rule), note.

    With a ``width`` (a terminal's), nothing passes it but a word longer than the width: the
    table is wrapped or folded as :class:`_Layout` says, and a number is never cut.  ``bold``
    sets the title and headers in bold (a terminal that takes colour).
    """
    headers, rows, right = _human_cells(result)
    transposed = result.vertical and len(result.rows) == 1
    lines = [_bold(t, bold) for t in _paragraphs(result.title, width)]
    layout = _Layout(headers, rows, width)
    blocks = layout.blocks(1 if transposed else key_columns(result))
    if blocks is not None:
        for k, (cols, widths) in enumerate(blocks):
            if k:
                lines.append("")
            lines += _block_lines(headers, rows, right, cols, widths, bold)
    else:  # not even two columns fit: each row as quantity / value lines
        lines += _vertical_lines(headers, rows, width)
    if result.note:
        lines += _paragraphs(result.note, width)
    return "\n".join(lines) + "\n"


def markdown_table(result: Result) -> str:
    """The human table as a Markdown pipe table (numbers right-aligned), then the note."""
    headers, rows, right = _human_cells(result)

    def cell(s: str) -> str:
        return s.replace("\\", "\\\\").replace("|", "\\|").replace("\n", " ")

    lines = ["| " + " | ".join(map(cell, headers)) + " |",
             "|" + "|".join("---:" if r else ":---" for r in right) + "|"]
    lines += ["| " + " | ".join(map(cell, r)) + " |" for r in rows]
    if result.note:
        lines += ["", *(_md_text(p) for p in result.note.split("\n"))]
    return "\n".join(lines) + "\n"


def _md_text(text: str) -> str:
    """Prose for Markdown: the characters that would start emphasis, code or HTML escaped."""
    for ch in "\\`*_<[|":
        text = text.replace(ch, "\\" + ch)
    return text


def _terminal_table(result: Result) -> None:
    """The human table on a terminal: laid out in its width, bold title and headers unless
    NO_COLOR (no-color.org) or TERM=dumb."""
    from coincli.render.terminal import colour_allowed, terminal_width

    sys.stdout.write(plain_table(result, terminal_width(sys.stdout), colour_allowed()))


# --------------------------------------------------------------------------- values and batches

MAX_STDIN_LINES = 10_000_000  #: the most values a stdin batch may hold
MAX_LINE_CHARS = 1000  #: the longest stdin line, in bytes (line end included)
#: the most bytes read from stdin: 10^7 full-precision doubles ('-2.2250738585072014e-308'),
#: one a line with CRLF ends, are 260 MB
MAX_STDIN_BYTES = 300_000_000
_BOM = b"\xef\xbb\xbf"


def stream_reader(stream) -> Callable[[int], bytes]:
    """``read(n) -> bytes`` for a binary or text stream (stdin, or a file opened ``"rb"``)."""
    buf = getattr(stream, "buffer", None)
    read = (buf if buf is not None else stream).read

    def read_bytes(n: int) -> bytes:
        chunk = read(n)
        return chunk.encode("utf-8", "surrogateescape") if isinstance(chunk, str) else chunk

    return read_bytes


def _megabytes(n: int) -> str:
    return f"{n / 10**6:g} MB"


# Bytes that may begin a line that is not a value: blanks (bytes.strip and str.strip), '#',
# and every non-ASCII byte (a Unicode space).  Any other first byte begins a value (or an error).
_MAYBE_BLANK = bytes([*b" \t\r\x0b\x0c\x1c\x1d\x1e\x1f#", *range(0x80, 0x100)])
_LINE_STARTS = bytes(10 if b == 10 else 32 if b in _MAYBE_BLANK else 118 for b in range(256))


_RUN_MARKS = bytes(10 if b == 10 else 120 for b in range(256))  # newline stays, the rest 'x'
_LONG_RUN = b"x" * (MAX_LINE_CHARS + 1)
_VALUE_LINE = None  # a newline, then a line whose first non-blank character is not '#'


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
        if start and len(buf) >= len(_BOM):
            start = False
            if buf.startswith(_BOM):
                buf = buf[len(_BOM):]
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
    if start and carry.startswith(_BOM):
        carry = carry[len(_BOM):]
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


def env_no_color() -> bool:
    """NO_COLOR set to a non-empty value (no-color.org)."""
    return bool(os.environ.get("NO_COLOR"))


# --------------------------------------------------------------------------- rows for Python


def json_rows(result: Result) -> list[dict]:
    """The rows of ``result`` as ``--format json`` writes them, as Python dicts: the same writer
    (:func:`_write_json`, as JSON lines) read back, so ``json.loads`` of a command's JSON equals
    what :mod:`coincli.api` returns, cell for cell (floats as the shortest repr, non-finite as
    None / "inf" / "-inf")."""
    import io
    import json

    buf = io.StringIO()
    _write_json(buf, [c.name for c in result.columns], _column_chunks(result), False)
    return [json.loads(line) for line in buf.getvalue().splitlines()]
