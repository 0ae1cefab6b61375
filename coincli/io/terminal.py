"""The terminal: whether stdout or stderr is one, how wide it is, and whether it takes colour.

One width for everything ``coin`` lays out (tables in :mod:`coincli.io.table`, text plots in
:mod:`coincli.render.text`, ``coin phase``): :func:`terminal_width`.  ``COLUMNS`` set to a whole
number from 1 up wins (as in every POSIX tool); anything else there (``0``, empty, a word) is
ignored and the terminal is asked; when there is no terminal, 80.  :func:`stdout_is_terminal`
and :func:`stderr_is_terminal` say where a table may be laid out and a progress bar drawn.
Nothing is imported.
"""

from __future__ import annotations

import os
import sys

__all__ = ["terminal_width", "terminal_height", "colour_allowed", "env_no_color",
           "stdout_is_terminal", "stderr_is_terminal", "MAX_WIDTH"]

DEFAULT_SIZE = (80, 24)
MAX_WIDTH = 10_000  #: a width beyond this (COLUMNS=999999999) is taken as this


def _env_size(name: str) -> int | None:
    text = os.environ.get(name, "").strip()
    if text.isascii() and text.isdigit() and len(text) < 10 and int(text) > 0:
        return int(text)
    return None


def _os_size(stream):
    for s in (stream, sys.__stdout__, sys.__stderr__):
        try:
            size = os.get_terminal_size(s.fileno())
        except (AttributeError, ValueError, OSError):
            continue
        if size.columns > 0 and size.lines > 0:
            return size.columns, size.lines
    return None


def terminal_width(stream=None) -> int:
    """Columns to lay text out in: ``COLUMNS`` when it is a whole number >= 1, else the size of
    the terminal behind ``stream`` (stdout by default) or of the process's stdout or stderr,
    else 80.  At most :data:`MAX_WIDTH`."""
    cols = _env_size("COLUMNS")
    if cols is None:
        size = _os_size(stream if stream is not None else sys.stdout)
        cols = size[0] if size else DEFAULT_SIZE[0]
    return min(cols, MAX_WIDTH)


def terminal_height(stream=None) -> int:
    """Lines of the terminal, by the same rules as :func:`terminal_width` (``LINES``, else the
    terminal, else 24)."""
    lines = _env_size("LINES")
    if lines is None:
        size = _os_size(stream if stream is not None else sys.stdout)
        lines = size[1] if size else DEFAULT_SIZE[1]
    return min(lines, MAX_WIDTH)


def colour_allowed() -> bool:
    """Escape codes are welcome: NO_COLOR (no-color.org) unset or empty and TERM not 'dumb'."""
    return not os.environ.get("NO_COLOR") and os.environ.get("TERM", "") != "dumb"


def env_no_color() -> bool:
    """NO_COLOR set to a non-empty value (no-color.org)."""
    return bool(os.environ.get("NO_COLOR"))


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
