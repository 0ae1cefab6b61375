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
# (toss, simulate: coincli.reports.toss; phase: coincli.reports.phase)


def toss(*, xi=None, coin=None, count=None, quarters=None, diameter=None, thickness=None,
         psi=None, u=None, omega=None, seed=None, g=None, contact=None, z0=None, landing=None,
         surface=None, restitution=None, friction=None, torsional=None, rolling=None,
         release_height=None, vx=None, dt=None, t_max=None, trajectory=None) -> list[dict]:
    """One deterministic toss a row, as ``coin toss --format json`` prints it.

    Parameters
    ----------
    xi, coin, count, quarters, diameter, thickness : str, number or list, optional
        The coin, as ``coin toss`` takes it (``xi`` a value or a list; ``diameter`` and
        ``thickness`` lengths such as ``"24.26mm"``).
    psi : str, number or list, optional
        Angle of the angular momentum to the coin's normal, degrees [0, 180].
    u, omega : str, number or list, optional
        Launch speed (m/s, or with a unit: ``"240cm/s"``) and spin (rad/s, or ``"6rev/s"``).
        Lists of equal length are paired; whatever of ``psi``, ``u``, ``omega`` is missing is
        drawn from a hand toss.
    seed : int or str, optional
        Seeds what is drawn (drawn itself when None; the rows then carry it).
    g, contact, z0 : optional
        Gravity (m/s^2, default 9.81), ``"rim"`` (default) or ``"thick"``, launch height.
    landing : {"catch", "bounce"}, optional
        ``"bounce"``: one toss onto a surface (MuJoCo: ``pip install 'thickcoin[physics]'``),
        with ``surface``, ``restitution``, ``friction``, ``torsional``, ``rolling``,
        ``release_height``, ``vx``, ``dt``, ``t_max``, and ``trajectory`` (a CSV file to
        write).

    Returns
    -------
    list of dict
        One row per toss: ``xi``, ``psi_deg``, ``u``, ``omega``, ``t_f``, ``turns``,
        ``alpha_f_deg``, ``theta0_deg``, ``vigor``, ``outcome``, ``z0_mm``, ``contact``
        (and ``seed`` when something was drawn); a bouncing toss has its own columns.

    Raises
    ------
    coincli.errors.InputError
        A wrong input, with the command's message.
    coincli.errors.NotComputable
        ``landing="bounce"`` without MuJoCo installed.

    Examples
    --------
    >>> from coincli import api
    >>> row = api.toss(xi="0.577", psi=90, u=2, omega=40)[0]
    >>> row["outcome"], round(row["t_f"], 6), round(row["turns"], 3)
    ('tails', 0.409263, 2.605)
    >>> [r["outcome"] for r in api.toss(xi=0.577, psi=90, u=2, omega=[33, 34, 35, 36])]
    ['heads', 'sides', 'sides', 'tails']
    """
    options = {k: v for k, v in locals().items() if v is not None}
    from coincli.reports import toss as _r

    return _rows(_r.toss, "toss", options)


def simulate(*, xi=None, coin=None, count=None, quarters=None, diameter=None, thickness=None,
             u=None, omega=None, psi=None, psi_dist=None, tosses=None, seed=None, g=None,
             contact=None, landing=None, surface=None, restitution=None, friction=None,
             torsional=None, rolling=None, release_height=None, vx=None, jobs=None, dt=None,
             t_max=None) -> list[dict]:
    """Seeded tosses from random launches, as ``coin simulate --format json`` prints them:
    the frequency of each outcome with its 95% Wilson interval, next to the vigorous limit.

    ``--stream`` (one letter a toss) is a way of printing, not a result: it has no keyword.

    Parameters
    ----------
    xi, coin, count, quarters, diameter, thickness : str or number, optional
        The coin, as ``coin simulate`` takes it (one coin).
    u, omega : str or number, optional
        The launch speed and spin: a value, ``"normal:MEAN:SD"`` or ``"uniform:LOW:HIGH"``, in
        m/s and rad/s or with a unit (``"normal:38:4rev/s"``).  Default: the hand toss.
    psi, psi_dist : str or number, optional
        A fixed angle psi (degrees), or its density (``"uniform"``, ``"cosine"``,
        ``"normal:90:18"``, ``"table:FILE"``).  Default: ``normal:90:10``.
    tosses : int or str, optional
        How many tosses (``-n``, ``--tosses``): 10000 by default, at most 10^8.
    seed : int or str, optional
        The seed; drawn (and in every row) when None.
    g, contact : optional
        Gravity (m/s^2, default 9.81) and ``"rim"`` (default) or ``"thick"``.
    landing : {"catch", "bounce"}, optional
        ``"bounce"``: the coins land on a surface (MuJoCo), with ``surface``,
        ``restitution``, ``friction``, ``torsional``, ``rolling``, ``release_height``, ``vx``,
        ``jobs``, ``dt``, ``t_max``.

    Returns
    -------
    list of dict
        One row per outcome (heads, sides, tails; and unsettled with ``landing="bounce"``):
        ``outcome``, ``count``, ``frequency``, ``ci_low``, ``ci_high``, ``vigorous``,
        ``difference``, ``seed``.

    Raises
    ------
    coincli.errors.InputError
        A wrong input, with the command's message.
    coincli.errors.NotComputable
        ``landing="bounce"`` without MuJoCo installed.

    Examples
    --------
    >>> from coincli import api
    >>> rows = api.simulate(xi=0.5, tosses=2000, seed=7)
    >>> [(r["outcome"], r["count"]) for r in rows]
    [('heads', 680), ('sides', 628), ('tails', 692)]
    >>> round(rows[1]["vigorous"], 4), rows[1]["seed"]
    (0.3068, 7)
    """
    options = {k: v for k, v in locals().items() if v is not None}
    from coincli.reports import toss as _r

    return _rows(_r.simulate, "simulate", options)


def phase(*, xi=None, coin=None, count=None, quarters=None, diameter=None, thickness=None,
          psi=None, u=None, omega=None, cols=None, rows=None, exact=None, no_curves=None,
          toss=None, g=None, contact=None) -> list[dict]:
    """The outcome of one deterministic toss from each cell of a grid over (u, omega) (Fig. 3),
    as ``coin phase --format json`` prints it.

    ``--out`` (a figure file) is a way of drawing, not a result: it has no keyword.

    Parameters
    ----------
    xi, coin, count, quarters, diameter, thickness : str or number, optional
        The coin; default the fair one, 1/sqrt 3, a quarter's size.
    psi : str or number, optional
        Angle psi, degrees [0, 180] (default 90).
    u, omega : str, optional
        The ranges ``"LOW:HIGH"``, m/s and rad/s or with a unit (default ``"0:3"`` and
        ``"0:60"``).
    cols, rows : int or str, optional
        Cells along u and omega (default 100 each).
    exact, no_curves : bool, optional
        Flags of the picture (they do not change the cells).
    toss : str, optional
        Tosses to mark, ``"U:OMEGA"`` (the picture's; not in the rows).
    g, contact : optional
        Gravity (m/s^2, default 9.81) and ``"rim"`` (default) or ``"thick"``.

    Returns
    -------
    list of dict
        One row per cell, omega slowest: ``u``, ``omega`` (the cell's centre), ``outcome``
        and its ``code`` (0 heads, 1 sides, 2 tails).

    Raises
    ------
    coincli.errors.InputError
        A wrong input, with the command's message.

    Examples
    --------
    >>> from coincli import api
    >>> cells = api.phase(cols=4, rows=2, u="0:3", omega="0:60")
    >>> [(c["u"], c["omega"], c["outcome"]) for c in cells[:4]]
    [(0.375, 15.0, 'sides'), (1.125, 15.0, 'tails'), (1.875, 15.0, 'heads'), (2.625, 15.0, 'sides')]
    """
    options = {k: v for k, v in locals().items() if v is not None}
    from coincli.reports import phase as _r

    return _rows(_r.phase, "phase", options, flags=frozenset({"exact", "no_curves"}))


# --------------------------------------------------------------------------- check family
# (check, fit: coincli.reports.check; book: coincli.reports.book)
