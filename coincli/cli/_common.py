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

import enum
import math
import os
import sys
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Annotated

import typer

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
    "stdout_is_terminal",
    "stderr_is_terminal",
]


class ExitCode(enum.IntEnum):
    """Exit codes of ``coin``; part of its public interface (see README)."""

    OK = 0
    ERROR = 1  #: the input is valid but the answer cannot be computed
    USAGE = 2  #: the input is wrong: a bad option, value, file line or combination
    INTERRUPTED = 130  #: Ctrl-C


class CoinError(Exception):
    """An error to print as one line on stderr, with its exit code."""

    def __init__(self, message: str, code: ExitCode = ExitCode.USAGE):
        super().__init__(message)
        self.message = message
        self.code = code


def usage_error(message: str) -> CoinError:
    return CoinError(message, ExitCode.USAGE)


def compute_error(message: str) -> CoinError:
    return CoinError(message, ExitCode.ERROR)


def stdout_is_terminal() -> bool:
    try:
        return sys.stdout.isatty()
    except (AttributeError, ValueError):
        return False


def stderr_is_terminal() -> bool:
    try:
        return sys.stderr.isatty()
    except (AttributeError, ValueError):
        return False


# --------------------------------------------------------------------------- options

FORMATS = ("table", "csv", "tsv", "json", "jsonl")

FormatOpt = Annotated[
    str,
    typer.Option(
        "--format",
        "-f",
        help="Output format: table (default; rich on a terminal, plain text in a pipe), "
        "csv, tsv, json or jsonl.",
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


@dataclass
class Column:
    """A column: machine ``name`` (stable, for csv/json), human ``header`` and number style."""

    name: str
    header: str
    style: str = "g6"  # g6: 6 significant digits; int; text; pct


@dataclass
class Result:
    """A table of results and what produced it."""

    title: str
    columns: Sequence[Column]
    rows: list
    note: str = ""
    quiet: object = None  # the main number for --quiet (a value or a list, one per row)
    vertical: bool = False  # a single row shown as "quantity  value" lines on the human table
    data: list | None = None  # alternatively the columns' values, one list per column

    def __post_init__(self):
        if self.data is not None and not self.rows:
            self.rows = list(zip(*self.data, strict=True))


def _machine(v):
    """Text for csv/tsv: floats as repr (round-trips), inf as inf, None as empty."""
    if v is None:
        return ""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, float):
        return repr(v)
    return str(v)


def _json_value(v):
    if isinstance(v, float) and math.isnan(v):
        return None
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


def emit(result: Result, fmt: str = "table", quiet: bool = False, out=None) -> None:
    """Write ``result`` to ``out`` (stdout) in the chosen format, in one piece."""
    out = out if out is not None else sys.stdout
    fmt = check_format(fmt)
    if quiet:
        q = result.quiet
        vals = q if isinstance(q, list) else [q]
        text = "\n".join(_machine(float(v)) if isinstance(v, (int, float)) and not isinstance(
            v, bool) else _machine(v) for v in vals)
        out.write(text + "\n")
        return
    names = [c.name for c in result.columns]
    if fmt in ("csv", "tsv"):
        sep = "," if fmt == "csv" else "\t"
        cols = result.data if result.data is not None else list(zip(*result.rows, strict=True))
        text_cols = [_text_column(col, sep) for col in cols]
        body = "\n".join(map(sep.join, zip(*text_cols, strict=True))) if result.rows else ""
        out.write(sep.join(names) + "\n" + (body + "\n" if body else ""))
    elif fmt in ("json", "jsonl"):
        import json

        objs = [{n: _json_value(v) for n, v in zip(names, row, strict=True)} for row in
                result.rows]
        if fmt == "json":
            out.write(json.dumps(objs, indent=2) + "\n")
        else:
            out.write("".join(json.dumps(o) + "\n" for o in objs))
    elif stdout_is_terminal() and out is sys.stdout:
        _rich_table(result)
    else:
        out.write(plain_table(result))


def _text_column(col, sep: str) -> list[str]:
    if all(type(v) is float for v in col):
        return list(map(repr, col))  # the fast path of a long batch
    return [_csv_cell(_machine(v), sep) for v in col]


def _csv_cell(text: str, sep: str) -> str:
    if sep in text or '"' in text or "\n" in text:
        return '"' + text.replace('"', '""') + '"'
    return text


def _transposed(result: Result) -> Result:
    row = result.rows[0]
    return Result(result.title, [Column("quantity", "quantity", "text"), Column("value", "value",
                  "text")], [(c.header, _human(v, c.style)) for c, v in zip(result.columns, row,
                                                                      strict=True)], result.note)


def plain_table(result: Result) -> str:
    """The human table as plain text: title, aligned columns, note."""
    if result.vertical and len(result.rows) == 1:
        result = _transposed(result)
    cells = [[c.header for c in result.columns]]
    cells += [[_human(v, c.style) for v, c in zip(row, result.columns, strict=True)]
              for row in result.rows]
    widths = [max(len(r[i]) for r in cells) for i in range(len(result.columns))]
    lines = [result.title]
    for k, r in enumerate(cells):
        lines.append("  ".join(
            (s.ljust(w) if (k == 0 or c.style == "text") else s.rjust(w))
            for s, w, c in zip(r, widths, result.columns, strict=True)).rstrip())
        if k == 0:
            lines.append("  ".join("-" * w for w in widths).rstrip())
    if result.note:
        lines.append(result.note)
    return "\n".join(lines) + "\n"


def _rich_table(result: Result) -> None:
    from rich.console import Console
    from rich.table import Table

    if result.vertical and len(result.rows) == 1:
        result = _transposed(result)
    table = Table(title=result.title, caption=result.note or None, caption_justify="left")
    for c in result.columns:
        table.add_column(c.header, justify="left" if c.style == "text" else "right")
    for row in result.rows:
        table.add_row(*(_human(v, c.style) for v, c in zip(row, result.columns, strict=True)))
    Console().print(table)


# --------------------------------------------------------------------------- values and batches

MAX_STDIN_LINES = 10_000_000
MAX_LINE_CHARS = 1000


def read_stdin_lines(what: str, stdin=None) -> list[tuple[int, str]]:
    """Non-blank, non-comment lines of stdin as (line number, text); CRLF and spaces stripped.

    Limits: at most 10^7 values and 1000 characters a line; a NUL byte or undecodable text is an
    error naming the line.
    """
    stream = stdin if stdin is not None else sys.stdin
    if stream is None:
        raise usage_error(f"{what}: '-' reads values from standard input, but there is none")
    buf = getattr(stream, "buffer", None)
    data = buf.read() if buf is not None else stream.read().encode("utf-8", "surrogateescape")
    out = []
    for n, raw in enumerate(data.split(b"\n"), start=1):
        if len(raw) > MAX_LINE_CHARS:
            raise usage_error(f"{what}: stdin line {n} is longer than {MAX_LINE_CHARS} characters")
        if b"\0" in raw:
            raise usage_error(f"{what}: stdin line {n} contains a NUL byte")
        try:
            text = raw.decode("utf-8").strip()
        except UnicodeDecodeError:
            raise usage_error(f"{what}: stdin line {n} is not UTF-8 text") from None
        if not text or text.startswith("#"):
            continue
        out.append((n, text))
        if len(out) > MAX_STDIN_LINES:
            raise usage_error(f"{what}: stdin has more than {MAX_STDIN_LINES} values")
    if not out:
        raise usage_error(f"{what}: '-' read no values from standard input")
    return out


def values_option(text: str, what: str, item: Callable, *, bounds=None, stdin=None):
    """Values of an option that takes one value, a list, a range, or '-' for stdin.

    Each value is parsed by ``item(text, what)`` (raising ValueError); a bad value from stdin
    names its line.  A long stdin batch of plain decimals is converted by numpy in one call and
    returned as an ndarray, checked against ``bounds = (lo, hi)`` (inclusive) when given;
    otherwise a list.  Raises :class:`CoinError` (usage) on any bad value.
    """
    from coincli.parse import parse_values

    if text.strip() == "-":
        lines = read_stdin_lines(what, stdin)
        if bounds is not None and len(lines) >= 5000:
            fast = _fast_floats(lines, what, bounds)
            if fast is not None:
                return fast
        vals = []
        for n, t in lines:
            try:
                vals.append(item(t, what))
            except ValueError as exc:
                raise usage_error(f"stdin line {n}: {exc}") from None
        return vals
    try:
        return parse_values(text, what, item)
    except ValueError as exc:
        raise usage_error(str(exc)) from None


_PLAIN = None


def _fast_floats(lines, what, bounds):
    """Plain decimals converted in one numpy call; None (fall back to per-line) otherwise."""
    global _PLAIN
    import re

    import numpy as np

    if _PLAIN is None:
        _PLAIN = re.compile(r"[+-]?(\d+(\.\d*)?|\.\d+)([eE][+-]?\d+)?")
    texts = [t for _, t in lines]
    if not all(_PLAIN.fullmatch(t) for t in texts):
        return None
    arr = np.array(texts, dtype=float)
    lo, hi = bounds
    bad = ~((arr >= lo) & (arr <= hi))
    if bad.any():
        k = int(np.argmax(bad))
        raise usage_error(
            f"stdin line {lines[k][0]}: {what} must be in [{lo:g}, {hi:g}], got {texts[k]!r}"
        )
    return arr


def env_no_color() -> bool:
    return "NO_COLOR" in os.environ
