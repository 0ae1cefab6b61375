"""What every ``coin`` command prints, from Python.

One function per command, with keyword arguments named after the command's long options
(dashes as underscores: ``--p-sides`` is ``p_sides``, ``--all`` is ``all``).  A value is a
Python number, a bool for a flag, a list or tuple for a list option, or the very string the
option takes on the command line (``"1/3"``, ``"25mm"``, ``"normal:90:18"``, ``"0.1:1:0.1"``).
Each returns the list of row dicts that ``--format json`` prints: for the same inputs,
``json.loads(coin COMMAND ... --format json)`` equals ``api.COMMAND(...)``.  The list is a
`coincli.io.notes.Rows`, which also carries what the command line says besides the rows:
``rows.notes``, the lines it writes to stderr (`coincli.io.notes.Note` records: warnings, notes
such as the tosses that did not settle, a drawn seed), and ``rows.caption``, the paragraph a
terminal table shows under the rows (the model, the method, the caveats).  Each warning is also
issued as a `coincli.errors.CoinWarning` (``warnings.simplefilter("error", CoinWarning)`` turns
it into an error).  Nothing is written to stderr.

A wrong input raises `coincli.errors.InputError` (a `ValueError`) with the
one-line message the command line prints; an answer that cannot be computed raises
`coincli.errors.NotComputable` (an `ArithmeticError`).  A keyword the command does not take
raises `coincli.errors.UnknownInput` (an `InputError` and a `TypeError`) naming the nearest one,
as the command line does for a misspelled option.

>>> from coincli import api
>>> row = api.design(p_sides="1/3")[0]
>>> round(row["xi"], 6), row["coin"], row["stack_n"]
(0.57735, 'quarter', 8)
"""

from __future__ import annotations

import functools
import math
import os
import warnings

from coincli.errors import CoinWarning, InputError
from coincli.requests.fields import unknown_input

__all__ = ["design", "table", "stack", "coins", "fair", "toss", "simulate", "phase", "check",
           "fit", "book"]


def _text(name: str, value):
    """``value`` as the text its option takes: strings as they are, paths as their text,
    numbers (numpy's too) as their shortest repr (which reads back to the same double), lists,
    tuples and arrays joined with commas."""
    if value is None or isinstance(value, str):
        return value
    if isinstance(value, os.PathLike):
        return os.fspath(value)
    if hasattr(value, "tolist") and not isinstance(value, (int, float)):  # numpy: arrays, scalars
        value = value.tolist()
    if isinstance(value, bool):
        raise InputError(f"--{name.replace('_', '-')} takes a value, not {value!r}")
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if not math.isfinite(value):
            return "inf" if value > 0 else ("-inf" if value < 0 else "nan")
        return float.__repr__(float(value))  # numpy.float64's repr is 'np.float64(...)'
    if isinstance(value, (list, tuple)):
        return ",".join(_text(name, v) for v in value)
    raise InputError(f"--{name.replace('_', '-')}: a number, a string or a list of them; got "
                     f"{type(value).__name__}")


def _declared(command: str):
    """The api function of ``coin COMMAND``: a keyword it does not take is refused as the
    command line refuses an option, naming the nearest one
    (:class:`coincli.errors.UnknownInput`, a ``TypeError`` and an ``InputError``).  Its
    keywords are the command's declaration's (:mod:`coincli.requests`), as
    ``tests/cli/test_requests.py`` checks."""

    def wrap(fn):
        @functools.wraps(fn)
        def call(*args, **options):
            from coincli.requests import command as declaration

            allowed = declaration(command).api_names()
            for name in options:
                if name not in allowed:
                    raise unknown_input(declaration(command), name, allowed, api=True)
            return fn(*args, **options)

        return call

    return wrap


def _rows(command: str, report, options: dict) -> list[dict]:
    """Call ``report`` (a `coincli.reports` function) with ``options`` as the command line
    would give them (the rest at the declared defaults of ``coin COMMAND``), and return its
    rows as ``--format json`` prints them.  A flag takes True or False; any other option a
    value (`_text`)."""
    from coincli.io import notes
    from coincli.io.table import Result, json_rows
    from coincli.requests import command as declaration

    declared = declaration(command)
    given = {}
    for name, value in options.items():
        if declared.param(name).decl.flag:
            if not isinstance(value, bool):
                raise InputError(f"--{name.replace('_', '-')} is a flag: True or False, not "
                                 f"{value!r}")
            given[name] = value
        else:
            given[name] = _text(name, value)
    request = declared.request(given, api=True)
    kwargs = dict(request, fmt="json") if "fmt" in request else dict(request)
    rows: list[dict] = []
    with notes.collected() as said:
        out = report(**kwargs)
        results = [out] if isinstance(out, Result) else list(out or ())
        for r in results:
            rows.extend(json_rows(r))  # a streamed result is computed here
            notes.lines(notes.after(r))
    for n in said:
        if n.kind == "warning":
            warnings.warn(n.text, CoinWarning, stacklevel=4)
    caption = "\n\n".join(r.note for r in results if getattr(r, "note", None))
    return notes.Rows(rows, said, caption)


def _given(options: dict) -> dict:
    """The options a caller gave: those not None (None is "the command's default")."""
    return {k: v for k, v in options.items() if v is not None}


# --------------------------------------------------------------------------- design family
# (design, table, stack, coins, fair: coincli.reports.design)


@_declared("design")
def design(*, p_sides, model=None, psi=None, psi_dist=None, diameter=None, thickness=None,
           coin=None, tol=None, method=None, landing=None, surface=None, restitution=None,
           friction=None, torsional=None, rolling=None, u=None, omega=None,
           release_height=None, vx=None, seed=None, max_tosses=None, time_limit=None,
           jobs=None, scheduler=None, checkpoint=None, timeout=None, dt=None,
           t_max=None, calibration=None, no_table=None) -> list[dict]:
    """The coin that lands on a side with the chance you want: ``coin design``.

    Parameters
    ----------
    p_sides : float, str or list
        Target chance of a side: ``1/3``, ``"1/3"``, ``"33%"``; a list ``[0.2, 0.3]`` or
        ``"0.2,0.3"``; a range ``"0.1:0.9:0.1"``.  One row per target.
    model : str, optional
        ``"geometric"``, ``"dynamic"`` (default) or ``"psi"`` (with ``psi`` or ``psi_dist``).
    psi : float or str, optional
        Table I at this angle psi, degrees in [0, 180].
    psi_dist : str, optional
        psi averaged over a density: ``"uniform"``, ``"cosine"``, ``"normal:90:18"``,
        ``"table:FILE"``.
    diameter, thickness : float or str, optional
        The coin's diameter (default the ``coin``'s), for the thickness column; or its
        thickness, for the diameter column instead.  In mm, or with a unit (``"2.4cm"``).
    coin : str, optional
        Catalog coin of the stack columns (default ``"quarter"``; see `coins()`).
    tol : float or str, optional
        Absolute error wanted on a psi-averaged chance (with ``psi_dist``).
    method : str, optional
        ``"auto"`` or ``"quad"``: how to average over psi.
    landing : str, optional
        ``"catch"`` (default: the paper's exact model) or ``"bounce"``: the coin lands on a
        surface and bounces, simulated with MuJoCo (``pip install 'thickcoin[physics]'``).
    surface, restitution, friction, torsional, rolling, release_height, vx : optional
        With ``landing="bounce"``: the surface and the launch, as the options of the same
        names (``coin design --help``).
    u, omega, seed, max_tosses, time_limit, jobs, dt, t_max : optional
        With ``landing="bounce"``: the launch, the seed and the simulation's limits.
    calibration : str, optional
        With ``landing="bounce"``: a calibration file (``fit(..., landing="bounce",
        save=...)``): the design is for that table, its intervals (``xi_low``, ``xi_high``,
        ``thickness_low_mm``, ``thickness_high_mm``) hold the calibration's uncertainty too.
    scheduler, checkpoint, timeout : str, optional
        With ``landing="bounce"``: a Dask scheduler (``"tcp://host:port"`` or ``"local"``)
        to run the tosses on, a checkpoint file, and the cluster's timeout (s); see
        ``docs/cluster.md``.
    no_table : bool, optional
        With ``landing="bounce"``: simulate every toss, not starting from the table shipped
        for a surface preset with the default launch and coin (``--no-table``).

    Returns
    -------
    list of dict
        One row per target: ``p_sides``, ``xi``, ``d_over_h``, ``diameter_mm``,
        ``thickness_mm``, ``p_heads``, ``p_tails``, the nearest stack of the coin (``coin``,
        ``stack_n``, ``stack_xi``, ``stack_p_sides`` and its neighbours') and the other
        model's P(sides), as ``coin design --format json`` prints them.

    Raises
    ------
    coincli.errors.InputError
        A wrong or contradictory input (the command's message).
    coincli.errors.NotComputable
        A target no coin reaches under the model.

    Examples
    --------
    >>> from coincli import api
    >>> row = api.design(p_sides="1/3")[0]
    >>> round(row["xi"], 6), row["stack_n"]
    (0.57735, 8)
    >>> [round(r["xi"], 4) for r in api.design(p_sides=[0.25, 1/3], model="geometric")]
    [0.2582, 0.3536]
    """
    options = _given(locals())
    from coincli.reports import design as _r

    return _rows("design", _r.design, options)


@_declared("table")
def table(*, xi=None, coin=None, count=None, quarters=None, diameter=None, thickness=None,
          psi=None, psi_dist=None, all=None, vs=None, tol=None, method=None, seed=None,
          layout=None, landing=None, calibration=None, surface=None, restitution=None,
          friction=None, torsional=None, rolling=None, u=None, omega=None, tosses=None,
          release_height=None, vx=None, jobs=None, scheduler=None, checkpoint=None, timeout=None,
          dt=None, t_max=None) -> list[dict]:
    """The chances of heads, sides and tails under every model: ``coin table``; with
    ``landing="bounce"``, simulated on tables (a parameter study).

    Parameters
    ----------
    xi : float, str or list, optional
        Aspect ratios h/D: ``0.577``, ``"17/30"``, a list, or a range ``"0.1:1:0.1"``.
    coin, count, quarters, diameter, thickness : optional
        The coin otherwise: a catalog ``coin`` (``count`` of them stacked; a list or range of
        counts gives one coin each), ``quarters`` N US quarters, or ``diameter`` and
        ``thickness`` (mm, or with a unit).
    psi : float, str or list, optional
        Table I at each angle psi (degrees in [0, 180]): a value, a list or a range.
    psi_dist : str or list, optional
        psi densities to average over: ``"normal:90:18"``, ``"uniform,cosine"``, a list.
    all : bool, optional
        Also Table II's densities: uniform, cosine, normal.
    vs : str, optional
        ``"psi"``: one coin over the ``psi`` angles (default ``"0:180:15"``), regimes named.
    tol : float or str, optional
        Absolute error wanted on each psi-averaged chance; error columns are added.
    method : str, optional
        ``"auto"``, ``"quad"``, ``"mc"`` or ``"qmc"``: how to average over psi.
    seed : int or str, optional
        Seed of ``method="mc"`` or ``"qmc"``, or of the tosses of ``landing="bounce"``
        (default: drawn; the rows' ``seed`` says it).
    layout : str, optional
        ``"long"`` (default): a row per coin and model; ``"wide"``: a row per coin, each
        model's (each table's) columns side by side, named ``MODEL_COLUMN``
        (``geometric_p_sides``; ``e0.5_mu0.3_p_sides`` with ``landing="bounce"``).
    landing : str, optional
        ``"catch"`` (default, the paper's models) or ``"bounce"``: ``tosses`` (default 1000)
        simulated for each coin and each table, the same seeded launches in every cell.
    surface, restitution, friction, torsional, rolling, release_height, vx : optional
        With ``landing="bounce"``: the table (``restitution`` and ``friction`` may be lists or
        ranges: a row each) and the launch, as the options of the same names.
    u, omega, tosses, jobs, dt, t_max : optional
        With ``landing="bounce"``: the launch, the tosses a cell and the simulation's limits.
    calibration : str, optional
        With ``landing="bounce"``: a calibration file (``coin fit --landing bounce --save``):
        its table and its launch.
    scheduler, checkpoint, timeout : str, optional
        With ``landing="bounce"``: a Dask scheduler (``"tcp://host:port"`` or ``"local"``)
        to run the cells' tosses on, a checkpoint file, and the cluster's timeout (s); see
        ``docs/cluster.md``.

    Returns
    -------
    list of dict
        One row per coin and model (geometric, dynamic, then the others): ``xi``,
        ``model``, ``p_heads``, ``p_sides``, ``p_tails`` (led by ``coin`` and ``count`` for a
        stacked coin; with ``method`` or ``tol`` also ``method``, ``err_heads``,
        ``err_sides``, ``err_tails``), as ``coin table --format json`` prints them.  With
        ``landing="bounce"``, one per coin and table: ``xi``, ``diameter_mm``, ``surface``,
        ``restitution``, ``friction``, ``p_heads``, ``p_heads_low``, ``p_heads_high`` (and
        the same for sides and tails: 95% Wilson intervals; None where no toss settled),
        ``settled``, ``unsettled``, ``seed``.

    Raises
    ------
    coincli.errors.InputError
        A wrong or contradictory input (the command's message).
    coincli.errors.NotComputable
        A chance that cannot be computed (e.g. a density too costly for the run).

    Examples
    --------
    >>> from coincli import api
    >>> [(r["model"], round(r["p_sides"], 4)) for r in api.table(xi=0.5, psi=60)]
    [('geometric', 0.4472), ('dynamic', 0.2952), ('psi=60', 0.4646)]
    >>> [r["model"] for r in api.table(xi=[0.2, 0.577], all=True)][:5]
    ['geometric', 'dynamic', 'uniform', 'cosine', 'normal']
    """
    options = _given(locals())
    from coincli.reports import design as _r

    return _rows("table", _r.table, options)


@_declared("stack")
def stack(*, coin=None, count=None, p_sides=None, quarters=None, diameter=None,
          thickness=None, model=None, psi=None, psi_dist=None) -> list[dict]:
    """Stacks of real coins glued together, their xi = N h / D and chances: ``coin stack``.

    Parameters
    ----------
    coin : str, optional
        Catalog coin stacked (default ``"quarter"``; see `coins()`).
    count : int, str or list, optional
        How many coins: N, a list or a range ``"1:12:1"``; one row each.
    p_sides : float, str or list, optional
        Instead of ``count``: find the stack nearest this chance of a side (with its
        neighbours, N - 1 and N + 1); a list or a range gives one row per target.
    quarters : int, str or list, optional
        N US quarters (``coin="quarter", count=N``).
    diameter, thickness : float or str, optional
        A custom coin instead of a catalog one (mm, or with a unit).
    model, psi, psi_dist : optional
        The model, as in `design()` (default dynamic).

    Returns
    -------
    list of dict
        One row per stack: ``coin``, ``count``, ``height_mm``, ``xi``, ``p_heads``,
        ``p_sides``, ``p_tails`` and ``mark`` (``"nearest"``); for several targets,
        ``target_p_sides`` first and no ``mark``; as ``coin stack --format json`` prints them.

    Raises
    ------
    coincli.errors.InputError
        A wrong or contradictory input (the command's message).
    coincli.errors.NotComputable
        A target no stack reaches (``p_sides=1`` needs an infinitely tall one).

    Examples
    --------
    >>> from coincli import api
    >>> [(r["count"], r["mark"]) for r in api.stack(p_sides="1/3")]
    [(7, ''), (8, 'nearest'), (9, '')]
    >>> round(api.stack(quarters=8)[0]["p_sides"], 4)
    0.3332
    """
    options = _given(locals())
    from coincli.reports import design as _r

    return _rows("stack", _r.stack, options)


@_declared("coins")
def coins() -> list[dict]:
    """The catalog of real coins, their dimensions and sources: ``coin coins``.

    It takes no parameters and raises nothing.

    Returns
    -------
    list of dict
        One row per coin: ``name``, ``label``, ``diameter_mm``, ``thickness_mm``, ``xi`` and
        ``p_sides_dynamic`` (the chance of a side of one coin, dynamic model), ``source``;
        as ``coin coins --format json`` prints them.

    Examples
    --------
    >>> from coincli import api
    >>> [r["name"] for r in api.coins()][:3]
    ['cent', 'nickel', 'dime']
    """
    from coincli.reports import design as _r

    return _rows("coins", _r.coins, {})


@_declared("fair")
def fair(*, diameter=None, coin=None, psi_dist=None) -> list[dict]:
    """The fair three-sided coin (P(sides) = 1/3) under each model: ``coin fair``.

    Parameters
    ----------
    diameter : float or str, optional
        Diameter for the thickness column (default the ``coin``'s), mm or with a unit.
    coin : str, optional
        Catalog coin of the stack columns (default ``"quarter"``).
    psi_dist : str, optional
        Also psi averaged over this density (only its sides are 1/3 then).

    Returns
    -------
    list of dict
        One row per model: ``model``, ``xi``, ``d_over_h``, ``thickness_mm``, the chances,
        the nearest stack (``stack_n``, ``stack_xi``, ``stack_p_sides``) and what the
        geometric and dynamic models say of it; as ``coin fair --format json`` prints them.

    Raises
    ------
    coincli.errors.InputError
        A wrong input (the command's message).
    coincli.errors.NotComputable
        A density under which no coin is fair.

    Examples
    --------
    >>> from coincli import api
    >>> [(r["model"], round(r["xi"], 6), r["stack_n"]) for r in api.fair()]
    [('geometric', 0.353553, 5), ('dynamic', 0.57735, 8)]
    """
    options = _given(locals())
    from coincli.reports import design as _r

    return _rows("fair", _r.fair, options)


# --------------------------------------------------------------------------- toss family
# (toss, simulate: coincli.reports.toss; phase: coincli.reports.phase)


@_declared("toss")
def toss(*, xi=None, coin=None, count=None, quarters=None, diameter=None, thickness=None, psi=None,
         u=None, omega=None, seed=None, g=None, contact=None, z0=None, landing=None, surface=None,
         restitution=None, friction=None, torsional=None, rolling=None, release_height=None,
         vx=None, dt=None, t_max=None, calibration=None, trajectory=None) -> list[dict]:
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
    options = _given(locals())
    from coincli.reports import toss as _r

    return _rows("toss", _r.toss, options)


@_declared("simulate")
def simulate(*, xi=None, coin=None, count=None, quarters=None, diameter=None, thickness=None,
             u=None, omega=None, psi=None, psi_dist=None, tosses=None, seed=None, g=None,
             contact=None, landing=None, surface=None, restitution=None, friction=None,
             torsional=None, rolling=None, release_height=None, vx=None, jobs=None, scheduler=None,
             checkpoint=None, timeout=None, dt=None, t_max=None, calibration=None) -> list[dict]:
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
        ``jobs``, ``dt``, ``t_max``; or ``calibration``, a file of ``fit(..., landing="bounce",
        save=...)``: the calibrated table instead of the surface; ``scheduler`` (a Dask
        scheduler, ``"tcp://host:port"`` or ``"local"``), ``checkpoint`` (a file) and
        ``timeout`` (s) run them on a cluster and record them (``docs/cluster.md``).

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
    options = _given(locals())
    from coincli.reports import toss as _r

    return _rows("simulate", _r.simulate, options)


@_declared("phase")
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
    options = _given(locals())
    from coincli.reports import phase as _r

    return _rows("phase", _r.phase, options)


# --------------------------------------------------------------------------- check family
# (check, fit: coincli.reports.check; book: coincli.reports.book)


@_declared("check")
def check(*, xi=None, quarters=None, coin=None, count=None, diameter=None, thickness=None,
          heads=None, sides=None, tails=None, tosses=None, same=None, different=None,
          psi_dist=None, expect=None, fair=None, landing=None, calibration=None, surface=None,
          restitution=None, friction=None, torsional=None, rolling=None, u=None, omega=None,
          psi=None, seed=None, release_height=None, vx=None, jobs=None, scheduler=None,
          checkpoint=None, timeout=None, dt=None, t_max=None, alpha=None,
          confidence=None) -> list[dict]:
    """``coin check``: are the tosses of one coin consistent with the models (with stated
    chances, with a simulated table)?

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
    same, different : int or str, optional
        Caught flips (faces only) that landed on the side they started on, and on the other
        (``tosses`` may replace one): tested on the chance of the starting side given a face,
        ``P(H) / (P(H) + P(T))``.
    psi_dist : str or list of str, optional
        psi densities to check as models too (``"normal:90:20"``, ``["uniform", "cosine"]``);
        with ``landing="bounce"``, the launch's distribution of psi instead.
    expect : str or list, optional
        Also test against stated chances of heads, sides and tails (``"1/3,1/3,1/3"``,
        ``[0.3, 0.4, 0.3]``, ``"30%,40%,30%"``): the row ``model = "expected"``.  The coin is
        then optional.
    fair : bool, optional
        ``expect="1/3,1/3,1/3"``.
    landing : str, optional
        ``"bounce"``: also test against the coin tossed on a table, simulated (MuJoCo, ten
        times the tosses, at least 4000, at most 10^5); the row's p-value is the exact
        conditional test that the two sets of counts share one set of chances.
    surface, restitution, friction, torsional, rolling, release_height, vx, u, omega, psi, seed, jobs, dt, t_max, calibration, scheduler, checkpoint, timeout : optional
        With ``landing="bounce"``: the table (or a calibration file: its table and launch),
        the launch and the seed of the simulated tosses, as the options of the same names.
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
    options = _given(locals())
    from coincli.reports import check as _r

    return _rows("check", _r.check, options)


@_declared("fit")
def fit(file, *, psi_dist=None, no_spread=None, delimiter=None, design=None, alpha=None,
        confidence=None, landing=None, fit=None, seed=None, save=None, design_tosses=None,
        surface=None, restitution=None, friction=None, torsional=None, rolling=None, u=None,
        omega=None, psi=None, release_height=None, vx=None, jobs=None, scheduler=None,
        checkpoint=None, timeout=None, dt=None, t_max=None, calibration=None) -> list[dict]:
    """``coin fit FILE``: which model do the tosses of a file of experiments follow?

    Parameters
    ----------
    file : str or path-like
        The experiments file (CSV: a header, then one experiment a row: the coin as ``xi``,
        ``coin`` (and ``count``) or ``diameter`` and ``thickness``; the tosses as ``heads``,
        ``sides``, ``tails``, or ``sides`` and ``n``; optionally a ``label``), or ``"-"`` to
        read standard input.
    psi_dist : str or list of str, optional
        psi densities to compare as models too; with ``landing="bounce"`` one density, the
        launch's (``"uniform"``: a tumbling toss).
    no_spread : bool, optional
        Skip the fit of the spread of psi.
    delimiter : str, optional
        Separator of the file: ``comma``, ``semicolon`` or ``tab`` (default: the header's).
    design : str or float, optional
        For caught rows: each tosser's coin with this chance of a side (``"1/3"``: the fair
        three-sided coin) under their fitted spread (``design_xi``, ``design_thickness_mm``).
    calibration : str or path-like, optional
        With ``design``: a calibration file (``fit(..., landing="bounce", save=...)``); each
        tosser's coin is designed on that table too, a bouncing design per tosser (MuJoCo; at
        most ``design_tosses`` tosses each, default 2000; ``seed``, ``jobs``):
        ``table_design_xi`` with ``table_design_xi_low``/``_high`` (the simulation's and the
        calibration's uncertainty), ``table_design_thickness_mm`` (and its interval),
        ``table_design_diameter_mm``, ``table_design_dominant``, ``table_design_tosses``,
        ``table_design_seed``.
    alpha, confidence : str or float, optional
        Significance level of the verdicts (default 0.05), confidence level of the intervals
        (default 0.95).
    landing : {"catch", "bounce"}, optional
        ``"bounce"``: calibrate the table the prototypes were tossed on (MuJoCo): one row with
        ``restitution``, ``restitution_low``, ``restitution_high``, ``friction``,
        ``friction_low``, ``friction_high`` (``psi_sd_deg...`` when fitted), ``p_value``,
        ``method``, ``seed``; with ``fit`` (``"restitution,friction"``, ``"psi-spread"``),
        ``seed``, ``save`` (a calibration file to write), ``design_tosses`` and the surface and
        launch options of ``simulate``: ``u``, ``omega`` and ``psi`` (or ``psi_dist``), how
        the prototypes were tossed (the hand toss by default), recorded in the calibration;
        ``scheduler`` (a Dask scheduler, ``"tcp://host:port"`` or ``"local"``), ``checkpoint``
        (a file) and ``timeout`` (s): where the design's tosses run, as for ``simulate``.

    Returns
    -------
    list of dict
        The rows ``coin fit FILE --format json`` prints: one per experiment and model
        (``scope`` ``"experiment"``), then one per model across experiments (``scope``
        ``"model"``: ``aic``, ``delta_aic``, ``sse_sides``, and for the psi-spread model the
        fitted spread ``sigma_deg`` with its interval).  With caught rows: each one's own
        spread on its psi-spread row, and a row of scope ``"all"`` comparing the tossers.

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
    options = _given(locals())
    if not isinstance(file, (str, os.PathLike)):
        raise InputError(f"FILE: a path (str or path-like) or '-' for stdin; got "
                         f"{type(file).__name__}")
    options["file"] = os.fspath(file)
    from coincli.reports import fit as _r

    return _rows("fit", _r.fit, options)


@_declared("book")
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
    options = _given(locals())
    from coincli.reports import book as _r

    return _rows("book", _r.book, options)
