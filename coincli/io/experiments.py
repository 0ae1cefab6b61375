"""The experiments file of ``coin fit`` and ``coin plot``: comma-, semicolon- or tab-separated
rows of a coin (``xi``, a catalog ``coin``, or ``diameter`` and ``thickness``) and its tosses.

:func:`parse_experiments` reads the text into :class:`coincli.core.stats.counts.Experiment`
rows (each with validated :class:`~coincli.core.stats.counts.Counts`), or raises
:class:`CSVError` naming the line and the column; :func:`delimiter_of` names the separators a
user may ask for.  The coin columns are read with the grammar of the command line
(:mod:`coincli.io.grammar`).
"""

from __future__ import annotations

import math
import re

from coincli.core.stats.counts import (
    MAX_COUNT,
    Caught,
    Counts,
    CountsError,
    Experiment,
    ExperimentColumns,
    make_caught,
    make_counts,
)

__all__ = [
    "CSV_COLUMNS",
    "DELIMITERS",
    "CSVError",
    "delimiter_of",
    "parse_experiment_columns",
    "parse_experiments",
]


CSV_COLUMNS = ("label", "xi", "coin", "count", "diameter", "thickness", "heads", "sides", "tails",
               "n", "same", "different", "start", "hsame", "hdiff", "tsame", "tdiff")
#: the columns of caught flips (faces only); any of them makes a row a caught one
CAUGHT_COLUMNS = ("same", "different", "start", "hsame", "hdiff", "tsame", "tdiff")
_CELLS = ("hsame", "hdiff", "tsame", "tdiff")
_CSV_ALIASES = {"name": "label", "tosses": "n", "diameter_mm": "diameter",
                "thickness_mm": "thickness"}
#: A number written with a decimal comma (``0,5``, ``2,4cm``): read so in semicolon files
_DECIMAL_COMMA = re.compile(r"^[+-]?\d+,\d+([eE][+-]?\d+)?[a-zA-Z\"]*$", re.ASCII)


#: why a table's calibration refuses a row of caught flips (as coin check --landing bounce does)
_NO_TABLE = ("a row of caught flips (same/different, start, or hsame/hdiff/tsame/tdiff): caught "
             "in the hand, they never met a table; --landing bounce fits tosses that landed on "
             "one (heads, sides, tails, or sides and n)")


class CSVError(ValueError):
    """A malformed experiments file; the message names the line and column."""

    def __init__(self, message: str, line: int, column: str | None = None):
        super().__init__(message)
        self.line = line
        self.column = column


def _err(line: int, column: str | None, msg: str) -> CSVError:
    where = f"line {line}" + (f", column {column!r}" if column else "")
    return CSVError(f"{where}: {msg}", line, column)


_WHOLE = re.compile(r"^\+?\d+(\.0*)?$", re.ASCII)


def _csv_count(text: str, name: str) -> int:
    s = text.strip()
    digits = s.split(".")[0].lstrip("+").lstrip("0")
    if not _WHOLE.match(s) or len(digits) > 16 or int(digits or "0") > MAX_COUNT:
        shown = text if len(text) <= 40 else text[:37] + "..."
        raise ValueError(f"{name} must be a whole number from 0 to {MAX_COUNT} (2**53), "
                         f"got {shown!r}")
    return int(digits or "0")


#: the separators a file may use, by what a user may call them
DELIMITERS = {",": ",", "comma": ",", ";": ";", "semicolon": ";", "\t": "\t", "tab": "\t",
              "\\t": "\t"}
_DELIMITER_NAMES = {",": "comma", ";": "semicolon", "\t": "tab"}


def delimiter_of(name: str) -> str:
    """The separator ``name`` means (``,``/``comma``, ``;``/``semicolon``, tab/``\t``/``tab``)."""
    try:
        return DELIMITERS[name if name == "\t" else name.strip().lower()]
    except (KeyError, AttributeError):
        raise ValueError(f"delimiter must be comma (,), semicolon (;) or tab, got {name!r}") \
            from None


def _sniff(header_line: str) -> str:
    """The separator of a header line: the most frequent of comma, semicolon and tab (comma
    when there is none, or on a tie)."""
    counts = {d: header_line.count(d) for d in (",", ";", "\t")}
    best = max(counts.values())
    return next(d for d in (",", ";", "\t") if counts[d] == best) if best else ","


def parse_experiments(text: str, *, max_rows: int = 100_000, delimiter: str | None = None,
                      caught: bool = True) -> list[Experiment]:
    """Parse an experiments file; raise :class:`CSVError` naming the line and column.

    The rows as a list of :class:`Experiment`; :func:`parse_experiment_columns` reads the same
    file into compact columns (a file of 10^5 rows in a few MB).

    Comma-, semicolon- or tab-separated: ``delimiter`` (``,``, ``;`` or a tab), or, when None,
    the most frequent of the three in the header line.  The first non-blank, non-``#`` line is
    the header (case-insensitive, any order).  Columns:

    - the coin, one of: ``xi``; ``coin`` (a catalog name, :func:`coincli.core.coins.get_coin`) with
      an optional ``count`` of stacked coins (default 1); ``diameter`` and ``thickness`` (mm, or
      with a unit: ``24.26mm``, ``2.4cm``, ``0.955in``) with an optional ``count``;
    - the tosses: ``heads``, ``sides``, ``tails`` (``n`` optional, must match), or ``sides``
      and ``n`` when the faces were not told apart;
    - or caught flips, faces only (:class:`~coincli.core.stats.counts.Caught`): ``same`` and
      ``different`` (or ``same`` and ``n``); ``heads`` and ``tails`` with ``start`` (``heads``
      or ``tails``, the side every flip of the row started on); or the four cells ``hsame``,
      ``hdiff``, ``tsame``, ``tdiff`` (started heads or tails, landed on the same side or not);
    - optionally ``label``.

    Rows may use different kinds (an empty cell is absent).  Aliases: ``name`` for ``label``,
    ``tosses`` for ``n``.  Blank lines and lines starting with ``#`` are skipped.  A header
    that does not parse says which separator it was read with.

    ``caught=False`` (a table's calibration, ``coin fit --landing bounce``): a row of caught
    flips is refused, naming its line: caught in the hand, its coins never met a table.
    """
    return list(_rows(text, max_rows, delimiter, caught))


def parse_experiment_columns(text: str, *, max_rows: int = 100_000,
                             delimiter: str | None = None, each=None,
                             caught: bool = True) -> ExperimentColumns:
    """:func:`parse_experiments` into :class:`~coincli.core.stats.counts.ExperimentColumns`:
    each row is read, passed to ``each(experiment)`` (a check that may raise) when given, and
    kept only as numbers in columns, so that memory does not hold 10^5 row objects.
    ``caught=False``: a row of caught flips is refused (:func:`parse_experiments`)."""
    rows = _rows(text, max_rows, delimiter, caught)
    return ExperimentColumns.from_rows(rows if each is None else _checked(rows, each))


def _checked(rows, each):
    for e in rows:
        each(e)
        yield e


def _rows(text: str, max_rows: int, delimiter: str | None, caught: bool = True):
    """The experiments of ``text``, one at a time (see :func:`parse_experiments`)."""
    import csv

    from coincli.core import coins
    from coincli.io.grammar import parse_length_mm, parse_number

    if text.startswith("\ufeff"):
        text = text[1:]
    sep = delimiter_of(delimiter) if delimiter is not None else None
    if sep is None:
        for raw_line in (piece for chunk in _lines(text) for piece in chunk.splitlines()):
            if raw_line.strip() and not raw_line.lstrip().startswith("#"):
                sep = _sniff(raw_line)
                break
        else:
            sep = ","
    read_as = (f"read as {_DELIMITER_NAMES[sep]}-separated"
               + ("" if delimiter is not None else ", the separator sniffed from the header"))
    # the text's lines one at a time, as io.StringIO(text) gives them (no copy of the text)
    reader = csv.reader(_lines(text), delimiter=sep, skipinitialspace=True, strict=True)
    header: list[str] | None = None
    header_line = 0
    rows = 0
    try:
        for cells in reader:
            line = reader.line_num
            if not cells or all(not c.strip() for c in cells) or cells[0].lstrip().startswith("#"):
                continue
            if header is None:
                header, header_line = [], line
                while cells and not cells[-1].strip():  # a spreadsheet's trailing separators
                    cells = cells[:-1]
                for k, raw in enumerate(cells, start=1):
                    name = raw.strip().lower()
                    name = _CSV_ALIASES.get(name, name)
                    if not name:
                        raise _err(line, f"#{k}", f"the header's column {k} has no name; expected "
                                   f"some of {', '.join(CSV_COLUMNS)} ({read_as})")
                    if name not in CSV_COLUMNS:
                        raise _err(line, raw.strip() or f"#{k}",
                                   f"unknown column; expected some of {', '.join(CSV_COLUMNS)} "
                                   f"({read_as})")
                    if name in header:
                        raise _err(line, raw.strip(), "appears twice in the header")
                    header.append(name)
                caught_cols = set(CAUGHT_COLUMNS) & set(header)
                if "sides" not in header and not caught_cols:
                    raise _err(line, None, f"the header has no 'sides' column ({read_as})")
                if "start" in header and not {"heads", "tails"} <= set(header):
                    raise _err(line, "start", "start goes with heads and tails (the flips that "
                               f"landed heads and tails, started on start) ({read_as})")
                if not ({"xi", "coin", "diameter"} & set(header)):
                    raise _err(line, None,
                               "the header needs xi, coin (and count), or diameter and thickness "
                               f"({read_as})")
                width = len(header)
                continue
            if len(cells) > width:
                extra = cells[width:]
                if any(c.strip() for c in extra):
                    raise _err(line, f"#{width + 1}",
                               f"{len(cells)} fields but the header (line {header_line}) has "
                               f"{width} columns ({read_as})")
                cells = cells[:width]
            elif len(cells) < width:
                cells = cells + [""] * (width - len(cells))
            row = dict(zip(header, (c.strip() for c in cells), strict=True))
            if sep == ";":  # a decimal comma, as such spreadsheets write it: 0,5 is 0.5
                for key in ("xi", "diameter", "thickness"):
                    v = row.get(key)
                    if v and _DECIMAL_COMMA.match(v):
                        row[key] = v.replace(",", ".")
            e = _experiment(line, row, parse_number, parse_length_mm, coins)
            if not caught and isinstance(e.counts, Caught):
                raise _err(line, next(k for k in CAUGHT_COLUMNS if row.get(k)), _NO_TABLE)
            rows += 1
            if rows > max_rows:
                raise _err(line, None, f"more than {max_rows} experiments")
            yield e
    except csv.Error as exc:
        raise _err(reader.line_num, None, f"not valid CSV: {exc}") from None
    if header is None:
        raise _err(1, None, "the file is empty (expected a header such as xi,heads,sides,tails)")
    if not rows:
        raise _err(header_line, None, "no experiments after the header")


def _lines(text: str):
    """The lines of ``text``, each with its ``\n``, one at a time (what iterating
    ``io.StringIO(text)`` gives, without its copy of the text: four bytes a character)."""
    find, start, end = text.find, 0, len(text)
    while start < end:
        stop = find("\n", start)
        stop = end if stop < 0 else stop + 1
        yield text[start:stop]
        start = stop


def _fast_count(text: str, name: str) -> int:
    """A count cell: plain ASCII digits take the fast path; anything else :func:`_csv_count`."""
    if text.isdigit() and text.isascii() and len(text) <= 15:
        return int(text)
    return _csv_count(text, name)


def _counts_of(h, s, t, m) -> Counts:
    """:func:`make_counts` for whole numbers already read: the two usual shapes directly."""
    if s is not None and h is not None and t is not None and m is None:
        total = h + s + t
        if 0 < total <= MAX_COUNT:
            return Counts(total, s, h, t)
    elif s is not None and h is None and t is None and m is not None and 0 < m and s <= m:
        return Counts(m, s)
    return make_counts(h, s, t, m)


def _experiment(line: int, row: dict, parse_number, parse_length_mm, coins) -> Experiment:
    has = {k for k, v in row.items() if v}
    diameter = None
    geo = has & {"xi", "coin", "diameter", "thickness"}
    count = None
    if "count" in has:
        if geo == {"xi"}:
            raise _err(line, "count", "count goes with coin or diameter/thickness, not with xi")
        try:
            from coincli.io.grammar import parse_count

            count = parse_count(row["count"], "count")
        except ValueError as exc:
            raise _err(line, "count", str(exc)) from None
    if "xi" in geo:
        if len(geo) > 1:
            other = sorted(geo - {"xi"})[0]
            raise _err(line, other, "give xi, or coin, or diameter and thickness; not several")
        try:
            from coincli.io.grammar import parse_ratio

            xi = parse_ratio(row["xi"], "xi")  # as --xi takes it: 0.5, 1/2, 17/30
        except ValueError as exc:
            raise _err(line, "xi", str(exc)) from None
        if not (math.isfinite(xi) and xi > 0):
            raise _err(line, "xi", f"xi must be a finite number > 0 in a file of tosses (at "
                       f"xi = 0 no model lands on a side: coin check --xi 0 tests such a coin), "
                       f"got {row['xi']!r}")
        desc = f"xi={row['xi']}"
    elif "coin" in geo:
        if len(geo) > 1:
            other = sorted(geo - {"coin"})[0]
            raise _err(line, other, "give coin, or diameter and thickness; not both")
        try:
            coin = coins.get_coin(row["coin"])
        except ValueError as exc:
            raise _err(line, "coin", str(exc)) from None
        k = count or 1
        xi = coins.stack_xi(coin, k)
        diameter = coin.diameter_mm
        desc = coin.name if k == 1 else f"{coin.name} x{k}"
    elif geo:
        for name in ("diameter", "thickness"):
            if name not in has:
                raise _err(line, name, "diameter and thickness must be given together")
        try:
            d = parse_length_mm(row["diameter"], "diameter")
        except ValueError as exc:
            raise _err(line, "diameter", str(exc)) from None
        try:
            h = parse_length_mm(row["thickness"], "thickness")
        except ValueError as exc:
            raise _err(line, "thickness", str(exc)) from None
        k = count or 1
        diameter = d
        try:
            xi = coins.stack_xi(coins.custom_coin(d, h), k)
        except ValueError as exc:
            raise _err(line, "thickness", str(exc)) from None
        if not (math.isfinite(xi) and xi > 0):
            raise _err(line, "thickness", f"thickness / diameter = {xi!r} is not a usable ratio")
        desc = f"{row['diameter']}x{row['thickness']}" + (f" x{k}" if k > 1 else "")
    else:
        raise _err(line, "xi", "no coin on this row: give xi, coin, or diameter and thickness")
    vals = {}
    for name in ("heads", "sides", "tails", "n", "same", "different", *_CELLS):
        if name in has:
            try:
                vals[name] = _fast_count(row[name], name)
            except ValueError as exc:
                raise _err(line, name, str(exc)) from None
    if "start" in row and not has & set(CAUGHT_COLUMNS) and "sides" not in has and \
            has & {"heads", "tails"}:  # a heads,tails,start row whose start cell is empty
        raise _err(line, "start", "start is required (heads or tails: the side every flip of "
                   "the row started on)" + (", or give sides for tosses that can land on a "
                                           "side" if "sides" in row else ""))
    try:
        if has & set(CAUGHT_COLUMNS):
            counts = _caught_of(line, row, has, vals)
        else:
            counts = _counts_of(vals.get("heads"), vals.get("sides"), vals.get("tails"),
                                vals.get("n"))
    except CountsError as exc:
        raise _err(line, exc.argument, str(exc)) from None
    return Experiment(line, float(xi), counts, row.get("label") or desc, diameter)


def _caught_of(line: int, row: dict, has: set, vals: dict):
    """A caught row's :class:`~coincli.core.stats.counts.Caught` from whichever form it has."""
    if "sides" in has:
        raise _err(line, "sides", "a row of caught flips (same/different, start, or "
                   "hsame/hdiff/tsame/tdiff) has no sides: a caught coin lands on a face")
    cells = has & set(_CELLS)
    kinds = [bool(cells), bool(has & {"same", "different"}), "start" in has]
    if sum(kinds) > 1:
        raise _err(line, sorted(cells | (has & {"same", "different", "start"}))[0],
                   "give same and different, or heads, tails and start, or hsame, hdiff, "
                   "tsame and tdiff; not several")
    if cells:
        missing = [c for c in _CELLS if c not in cells]
        if missing:
            raise _err(line, missing[0], "hsame, hdiff, tsame and tdiff must be given together")
        if has & {"heads", "tails"}:
            raise _err(line, "heads", "give hsame, hdiff, tsame and tdiff, or heads and tails "
                       "with start; not both")
        return make_caught(vals["hsame"] + vals["tsame"], vals["hdiff"] + vals["tdiff"],
                           vals.get("n"))
    if "start" in has:
        start = row["start"].strip().lower()
        if start not in ("heads", "tails", "h", "t"):
            raise _err(line, "start", f"start must be heads or tails, got {row['start']!r}")
        for name in ("heads", "tails"):
            if name not in has:
                raise _err(line, name, "heads and tails go with start")
        h, t = vals["heads"], vals["tails"]
        same, diff = (h, t) if start in ("heads", "h") else (t, h)
        return make_caught(same, diff, vals.get("n"))
    if has & {"heads", "tails"}:
        raise _err(line, sorted(has & {"heads", "tails"})[0],
                   "heads and tails with same/different: give start instead, or one form")
    return make_caught(vals.get("same"), vals.get("different"), vals.get("n"))


# --------------------------------------------------------------------------- reading a file
#
# The experiments file of ``coin fit FILE`` (and of ``coin fit --landing bounce FILE``): its
# text, read capped (:func:`read_experiments_text`), and its experiments as columns with the
# commands' messages (:func:`experiment_columns`).

MAX_FILE_BYTES = 50_000_000  #: the largest experiments file (coin fit FILE or -)


def read_experiments_text(path: str) -> tuple[str, str]:
    """The text of an experiments file, or of stdin for '-', and the name to call it by.

    At most :data:`MAX_FILE_BYTES` are read, in chunks, whatever the file claims to be
    (/dev/zero and pipes have no size); reading stops at a NUL byte.  A named file must be a
    regular file (:func:`coincli.io.files.read_regular`).
    """
    import sys

    from coincli.errors import usage_error
    from coincli.io.files import FileKindError, read_capped, read_regular, stream_reader

    if path.strip() == "-":
        if sys.stdin is None:
            raise usage_error("FILE '-' reads the experiments from standard input, but there "
                              "is none")
        name = "stdin"
        data, why = read_capped(stream_reader(sys.stdin), MAX_FILE_BYTES)
    else:
        name = path
        try:
            data, why = read_regular(path, MAX_FILE_BYTES)  # a FIFO or device: refused
        except FileKindError as exc:
            raise usage_error(f"cannot read {clipped(path)}: it is {exc.kind}, not a regular "
                              "file; give an experiments file, or '-' to read a pipe") from None
        except OSError as exc:
            raise usage_error(f"cannot read {clipped(path)}: {exc.strerror or exc}") from None
    if why == "size":
        raise usage_error(f"{file_name(name)}: larger than {MAX_FILE_BYTES // 10**6} MB; is this "
                          f"an experiments file? (at most {MAX_FILE_BYTES} bytes)")
    if why == "nul":
        raise usage_error(f"{file_name(name)}: contains a NUL byte; expected a CSV text file")
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError:
        raise usage_error(f"{file_name(name)}: not UTF-8 text") from None
    return text, name


def clipped(text: str, limit: int = 60) -> str:
    """User text (a path, a number) for an error message: unquoted unless it holds control
    characters (then as repr writes it: one line), cut to about ``limit`` characters."""
    from coincli.errors import shown

    if not text.isprintable():
        return shown(text, limit)
    return text if len(text) <= limit + 2 else text[:limit - 3] + "..."


def file_name(path: str) -> str:
    """A file that opened: its whole name (at most PATH_MAX), on one line."""
    return clipped(path, 4096)


def check_total(counts, where: str = "") -> None:
    """Every count below 2**53 can still add up to more: the total is held to it too."""
    from coincli.errors import usage_error

    if counts.n > MAX_COUNT:
        raise usage_error(f"{where}heads + sides + tails = {counts.n}; at most {MAX_COUNT} "
                          "(2**53) tosses are allowed")


def experiment_columns(text: str, name: str, delimiter: str | None = None, caught: bool = True):
    """The experiments of ``text`` as columns (:class:`ExperimentColumns`: a file of 10^5 rows
    holds numbers, not row objects); each count, and each row's total, at most 2**53.
    ``caught=False`` (a table's calibration): a row of caught flips is refused, naming its
    line."""
    from coincli.errors import InputError, usage_error

    name = file_name(name)

    def each(e):
        c = e.counts
        for column in ("heads", "sides", "tails", "n"):
            v = getattr(c, column)
            if v is not None and v > MAX_COUNT and (column != "n" or c.heads is None):
                raise usage_error(f"{name} line {e.line}, column {column!r}: {column} must be a "
                                  f"whole number from 0 to {MAX_COUNT} (2**53), got "
                                  f"{clipped(str(v))}")
        check_total(c, f"{name} line {e.line}: ")

    try:
        return parse_experiment_columns(text, delimiter=delimiter, each=each, caught=caught)
    except InputError:
        raise
    except ValueError as exc:
        raise usage_error(f"{name} {exc}") from None


__all__ += ["MAX_FILE_BYTES", "read_experiments_text", "experiment_columns", "check_total",
            "clipped", "file_name"]
