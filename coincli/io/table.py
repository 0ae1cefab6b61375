"""The output writers: a command's :class:`Result` written in every format.

Output is a :class:`Result`: a title, a note naming the model and assumptions, stable machine
column names with human headers, and rows.  One function, :func:`emit`, writes it in every
format, so a user learns the flags once:

- ``table`` (default): a rich table on a terminal; plain aligned text when piped (no colour codes);
- ``csv`` / ``tsv``: a header of machine names, then one line per row, floats as ``repr``
  (the shortest text that reads back to the same double);
- ``json``: an array of row objects; ``jsonl``: one object per line;
- ``markdown``: a pipe table;
- ``--quiet``: the bare main number only.

Nothing is printed until everything is computed, so an error never leaves half a table behind.
:func:`json_rows` gives Python the rows ``--format json`` writes.  Objects to text only: no
typer (the options that choose the format are declared in :mod:`coincli.cli._options`), and
rich is imported only to draw a table on a terminal.
"""

from __future__ import annotations

import contextlib
import itertools
import math
import sys
from collections.abc import Sequence
from typing import NamedTuple

from coincli.errors import usage_error
from coincli.io.terminal import stdout_is_terminal

__all__ = [
    "Column",
    "Result",
    "emit",
    "emit_all",
    "json_rows",
    "FORMATS",
    "check_format",
    "key_columns",
    "plain_table",
    "markdown_table",
    "CHUNK_ROWS",
    "headers_left_out",
]


# --------------------------------------------------------------------------- formats

FORMATS = ("table", "csv", "tsv", "json", "jsonl", "markdown")


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


def machine_text(v):
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

#: ``--no-headers`` of the running command: :mod:`coincli.cli` sets it around each command
#: (:func:`headers_left_out`); :func:`emit` reads it when not told
_NO_HEADERS = [False]  #: the running command's --no-headers (a command runs one at a time)


@contextlib.contextmanager
def headers_left_out(on: bool = True):
    """Within the block, :func:`emit` leaves out the csv/tsv header line unless told otherwise
    (how the command line's ``--no-headers`` reaches it)."""
    saved, _NO_HEADERS[0] = _NO_HEADERS[0], bool(on)
    try:
        yield
    finally:
        _NO_HEADERS[0] = saved


def emit(result: Result, fmt: str = "table", quiet: bool = False, out=None,
         no_headers: bool | None = None) -> None:
    """Write ``result`` to ``out`` (stdout) in the chosen format.

    A result with ``chunks`` (a streamed batch) is written a chunk at a time, so memory stays flat
    in the number of rows; its input was checked before the first chunk (see
    :class:`coincli.io.batches.Values`).  ``no_headers`` (the ``--no-headers`` flag: when None,
    as the running command was given it, see :func:`headers_left_out`) drops the csv/tsv header
    line.
    """
    out = out if out is not None else sys.stdout
    fmt = check_format(fmt)
    if no_headers is None:
        no_headers = _NO_HEADERS[0]
    if result.chunks is not None:  # the first chunk is computed before anything is written
        chunks = iter(result.chunks)
        first = next(chunks, None)
        result.chunks = itertools.chain([] if first is None else [first], chunks)
    if quiet:
        if result.chunks is None:
            q = result.quiet
            write_rows(out, [q if isinstance(q, list) else [q]], "\n", quote=False)
        else:
            for data in result.chunks:
                write_rows(out, [_plain_list(data[result.quiet])], "\n", quote=False)
        return
    names = [c.name for c in result.columns]
    if fmt in ("csv", "tsv"):
        sep = "," if fmt == "csv" else "\t"
        if not no_headers:
            out.write(sep.join(names) + "\n")
        for cols in _column_chunks(result, arrays=True):
            write_rows(out, cols, sep)
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
        from coincli.io.terminal import colour_allowed, terminal_width

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
    ``arrays`` the columns as the command gave them (:func:`write_rows` takes a float64 array
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


def write_rows(out, cols, sep: str, quote: bool = True) -> None:
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
                fields.append(((csv_cell(text, sep) if quote else text).replace("%", "%%"),
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
            text = machine_text(col[0])
            fields.append(((csv_cell(text, sep) if quote else text).replace("%", "%%"), None))
        elif kinds <= {float}:
            fields.append(("%r", col))
        elif kinds == {int}:
            fields.append(("%d", col))
        elif kinds == {float, type(None)}:  # e.g. a neighbour that does not exist: empty cell
            cells = _few_cells(col)
            fields.append(("%r", [_EMPTY if v is None else v for v in col]) if cells is None
                          else ("%s", cells))
        elif kinds <= {str, type(None)}:  # few distinct texts (a coin, a model): each once
            cells = {v: csv_cell(machine_text(v), sep) if quote else machine_text(v)
                     for v in set(col)}
            fields.append(("%s", list(map(cells.__getitem__, col))))
        else:  # mixed: cell by cell (a set would merge 0.0 with -0.0 and 1 with True)
            fields.append(("%s", [csv_cell(machine_text(v), sep) if quote else machine_text(v)
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


def csv_cell(text: str, sep: str) -> str:
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
