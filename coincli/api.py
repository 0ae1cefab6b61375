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
import os

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


def check(*, xi=None, quarters=None, coin=None, count=None, diameter=None, thickness=None,
          heads=None, sides=None, tails=None, tosses=None, psi_dist=None, alpha=None,
          confidence=None) -> list[dict]:
    """``coin check``: are the tosses of one coin consistent with the models?

    Parameters
    ----------
    xi, quarters, coin, count, diameter, thickness : str or number, optional
        The coin tossed, as the coin group of every command takes it: ``xi`` (h/D, ``0.577``
        or ``"17/30"``), or ``coin`` (a catalog name) with ``count``, or ``quarters``, or
        ``diameter`` and ``thickness`` (lengths, ``"24.26mm"``).  One of them.
    heads, sides, tails : int or str, optional
        Tosses that landed heads, on a side, tails (whole numbers >= 0).
    tosses : int or str, optional
        The number of tosses (``-n``), with ``sides`` alone: a binomial test of the side.
    psi_dist : str or list of str, optional
        psi densities to check as models too (``"normal:90:20"``, ``["uniform", "cosine"]``).
    alpha : str or float, optional
        Significance level of the verdicts (``0.05``, ``"1/20"``, ``"5%"``; default 0.05).
    confidence : str or float, optional
        Confidence level of the intervals (default 0.95).

    Returns
    -------
    list of dict
        The rows ``coin check --format json`` prints: one per model (``model``, ``p_value``,
        ``log_likelihood``, ``verdict``, expected counts, the observed frequencies with
        their Wilson and Clopper-Pearson intervals, ...).

    Raises
    ------
    coincli.errors.InputError
        A wrong input (the message ``coin check`` prints).
    coincli.errors.NotComputable
        The models cannot be evaluated for this coin.

    Examples
    --------
    >>> from coincli import api
    >>> rows = api.check(xi="0.577", heads=45, sides=38, tails=37)
    >>> [(r["model"], r["verdict"]) for r in rows]
    [('geometric', 'rejected, p = 1.6e-4'), ('dynamic', 'consistent at the 5% level (p = 0.65)')]
    """
    options = {k: v for k, v in locals().items() if v is not None}
    from coincli.reports import check as _r

    return _rows(_r.check, "check", options)


def fit(file, *, psi_dist=None, no_spread=None, delimiter=None, alpha=None,
        confidence=None) -> list[dict]:
    """``coin fit FILE``: which model do the tosses of a file of experiments follow?

    Parameters
    ----------
    file : str or path-like
        The experiments file (CSV: a header, then one experiment a row: the coin as ``xi``,
        ``coin`` (and ``count``) or ``diameter`` and ``thickness``; the tosses as ``heads``,
        ``sides``, ``tails``, or ``sides`` and ``n``; optionally a ``label``), or ``"-"`` to
        read standard input.
    psi_dist : str or list of str, optional
        psi densities to compare as models too.
    no_spread : bool, optional
        Skip the fit of the spread of psi.
    delimiter : str, optional
        Separator of the file: ``comma``, ``semicolon`` or ``tab`` (default: the header's).
    alpha, confidence : str or float, optional
        Significance level of the verdicts (default 0.05), confidence level of the intervals
        (default 0.95).

    Returns
    -------
    list of dict
        The rows ``coin fit FILE --format json`` prints: one per experiment and model
        (``scope`` ``"experiment"``), then one per model across experiments (``scope``
        ``"model"``: ``aic``, ``delta_aic``, ``sse_sides``, and for the psi-spread model the
        fitted spread ``sigma_deg`` with its interval).

    Raises
    ------
    coincli.errors.InputError
        A wrong input or file (the message ``coin fit`` prints).
    coincli.errors.NotComputable
        The fit cannot be computed.

    Examples
    --------
    >>> import os, tempfile
    >>> from coincli import api
    >>> path = os.path.join(tempfile.mkdtemp(), "tosses.csv")
    >>> with open(path, "w") as f:
    ...     _ = f.write("label,xi,heads,sides,tails\\nthin,0.3,45,12,43\\nthick,0.5,30,40,30\\n")
    >>> rows = api.fit(path, no_spread=True)
    >>> [(r["model"], round(r["aic"], 2)) for r in rows if r["scope"] == "model"]
    [('geometric', 35.84), ('dynamic', 26.92)]
    """
    options = {k: v for k, v in locals().items() if v is not None}
    options["file"] = os.fspath(file)
    from coincli.reports import check as _r

    return _rows(_r.fit, "fit", options, flags=frozenset({"no_spread"}))


def book(*, size=None, moments=None, spin=None, times=None, toss=None, tosses=None, seed=None,
         flight=None, start=None, rule=None, out=None) -> list[dict]:
    """``coin book``: the paper's Problem 1, a tossed book or die (a box with three different
    moments).

    Parameters
    ----------
    size : str, optional
        The box's sides along body axes 1, 2, 3: ``"235x155x30"`` (mm) or with units
        (``"23.5cmx15.5cmx3cm"``).  This or ``moments``.
    moments : str or sequence of 3 numbers, optional
        Principal moments I1, I2, I3 instead of a size (``(1, 2, 3)``, any unit).
    spin : str or sequence of 3, optional
        Angular velocity at launch about body axes 1, 2, 3, rad/s or with a unit
        (``(0.4, 40, 0.3)``, ``"0,6rev/s,0"``); with ``toss`` each component may be a
        distribution (``"normal:0:30"``).
    times : str or sequence of numbers, optional
        Times (s, or with a unit: ``"500ms"``) for the series of omega, the attitude and the
        face up: a list, or a range ``"0:2:0.01"``.
    toss : bool, optional
        Toss many boxes with random spins and flight times: the chance of each face.
    tosses : int or str, optional
        Tosses of a ``toss`` run (``-n``; default 10000).
    seed : int or str, optional
        Seed of a ``toss`` run (default: drawn; it is in the rows).
    flight : str or float, optional
        Flight time from launch to catch, s (with ``toss`` also a distribution; default 0.5).
    start : str, optional
        Face up at launch: ``+1 -1 +2 -2 +3 -3`` (default ``+3``), or ``random`` with ``toss``.
    rule : str, optional
        Which face is up at the catch: ``centre`` (default) or ``normal``.
    out : str, optional
        A figure file (``.png``, ``.svg``, ``.pdf``): drawn and written, and nothing is
        returned.  Any other path is checked, but not written: the rows are returned (the
        command line writes them to it in its --format).

    Returns
    -------
    list of dict
        The rows ``coin book --format json`` prints: the motion (one row: its kind, each omega
        component's range, the period, the paper's Gamma, the growth rate and the flip times),
        the series (one row a time) or the chance of each face (six rows).

    Raises
    ------
    coincli.errors.InputError
        A wrong input (the message ``coin book`` prints).
    coincli.errors.NotComputable
        A figure cannot be drawn or written.

    Examples
    --------
    >>> from coincli import api
    >>> row = api.book(moments=(1, 2, 3), spin=(0, 0, 40))[0]
    >>> row["motion"], row["spin_axis"], round(row["period"], 6)
    ('steady spin (omega constant)', '3 (largest moment)', 0.15708)
    >>> rows = api.book(size="16x16x16", toss=True, tosses=200, seed=1,
    ...                 spin="normal:0:30,normal:0:30,normal:0:30")
    >>> sum(r["count"] for r in rows), [r["face"] for r in rows]
    (200, ['+1', '-1', '+2', '-2', '+3', '-3'])
    """
    options = {k: v for k, v in locals().items() if v is not None}
    from coincli.reports import book as _r

    return _rows(_r.book, "book", options, flags=frozenset({"toss"}))
