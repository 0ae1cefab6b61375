"""What every ``coin`` command prints, from Python.

One function per command, with keyword arguments named after the command's long options
(dashes as underscores: ``--p-sides`` is ``p_sides``, ``--all`` is ``all``).  A value is a
Python number, a bool for a flag, a list or tuple for a list option, or the very string the
option takes on the command line (``"1/3"``, ``"25mm"``, ``"normal:90:18"``, ``"0.1:1:0.1"``).
Each returns the list of row dicts that ``--format json`` prints: for the same inputs,
``json.loads(coin COMMAND ... --format json)`` equals ``api.COMMAND(...)``.

A wrong input raises :class:`coincli.errors.InputError` (a :class:`ValueError`) with the
one-line message the command line prints; an answer that cannot be computed raises
:class:`coincli.errors.NotComputable` (an :class:`ArithmeticError`).

>>> from coincli import api
>>> row = api.design(p_sides="1/3")[0]
>>> round(row["xi"], 6), row["coin"], row["stack_n"]
(0.57735, 'quarter', 8)
"""

from __future__ import annotations

import inspect
import math

from coincli.errors import InputError

__all__ = ["design", "table", "stack", "coins", "fair", "toss", "simulate", "phase", "check",
           "fit", "book"]


def _text(name: str, value):
    """``value`` as the text its option takes: strings as they are, numbers as their shortest
    repr (which reads back to the same double), lists joined with commas."""
    if value is None or isinstance(value, (str, bool)):
        return value
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if not math.isfinite(value):
            return "inf" if value > 0 else ("-inf" if value < 0 else "nan")
        return repr(value)
    if isinstance(value, (list, tuple)):
        return ",".join(_text(name, v) for v in value)
    if hasattr(value, "item"):  # a numpy scalar
        return _text(name, value.item())
    raise InputError(f"{name.replace('_', '-')}: a number, a string or a list of them; got "
                     f"{type(value).__name__}")


def _rows(report, command: str, options: dict, flags: frozenset = frozenset()) -> list[dict]:
    """Call ``report`` (a :mod:`coincli.reports` function) with ``options`` as the command line
    would give them, and return its rows as ``--format json`` prints them."""
    from coincli.io.table import Result, json_rows

    params = inspect.signature(report).parameters
    hidden = {"fmt", "quiet"}
    kwargs = {}
    for name, value in options.items():
        if name not in params or name in hidden:
            allowed = ", ".join(p for p in params if p not in hidden)
            raise InputError(f"coin {command} has no option --{name.replace('_', '-')}; its "
                             f"options are {allowed}")
        kwargs[name] = bool(value) if name in flags else _text(name, value)
    if "fmt" in params:
        kwargs["fmt"] = "json"
    out = report(**kwargs)
    results = [out] if isinstance(out, Result) else list(out or ())
    rows: list[dict] = []
    for r in results:
        rows.extend(json_rows(r))
    return rows


# --------------------------------------------------------------------------- design family
# (design, table, stack, coins, fair: coincli.reports.design)


# --------------------------------------------------------------------------- toss family
# (toss, simulate, phase: coincli.reports.toss)


# --------------------------------------------------------------------------- check family
# (check, fit: coincli.reports.check; book: coincli.reports.book)
