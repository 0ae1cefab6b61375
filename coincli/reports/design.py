"""What ``coin design``, ``coin table``, ``coin stack``, ``coin coins`` and ``coin fair`` print.

One function per command (:func:`design`, :func:`table`, :func:`stack`, :func:`coins`,
:func:`fair`), its parameters the command's options as typed (text, or a bool for a flag), each
returning the :class:`coincli.io.table.Result` the command writes; a wrong input raises the
command's one-line error (:func:`coincli.io.table.usage_error`, ``compute_error``).

The models come from :mod:`coincli.core.models` / :mod:`coincli.core.averages` through
:class:`coincli.core.modelspec.ModelSpec`.  A single value under the geometric or dynamic model
stays on Python floats (no numpy); lists, ranges and stdin batches of those models go through
numpy in one vectorized call, computed a chunk at a time as the result is written; psi models
use quadrature and root finding (numpy, loaded then).  ``--tol``, ``--method`` and ``--seed``
are :mod:`coincli.reports.accuracy`'s.
"""

from __future__ import annotations

import math

from coincli.core import coins as coin_catalog
from coincli.core import models
from coincli.core.modelspec import DYNAMIC, GEOMETRIC, ModelSpec, table_i_model, table_i_radians
from coincli.errors import compute_error, usage_error
from coincli.io import grammar as parse
from coincli.io import options
from coincli.io.batches import Values, values_option, values_stream
from coincli.io.table import CHUNK_ROWS, Column, Result, check_format
from coincli.reports import accuracy
from coincli.reports.accuracy import tolist

__all__ = ["design", "table", "stack", "coins", "fair"]

MACHINE_FORMATS = ("csv", "tsv", "json", "jsonl")


def _model_names(models, fmt: str) -> list[str]:
    """Each model's name as a table cell: its spec in machine output (``normal``, reads back
    as --psi-dist), its human title on a terminal (``normal (paper)``)."""
    human = fmt.strip().lower() not in MACHINE_FORMATS
    return [m.title if human else m.name for m in models]

# --------------------------------------------------------------------------- models as options


def density_model(spec: str) -> ModelSpec:
    """psi averaged over the one density ``spec`` (``--psi-dist``)."""
    return ModelSpec.psi_density(options.psi_density(spec))


def choose_model(model: str | None, psi: str | None, psi_dist: str | None) -> ModelSpec:
    """The model from --model, --psi and --psi-dist; contradictions are usage errors."""
    m = (model or "").strip().lower()
    if m not in ("", "geometric", "dynamic", "psi"):
        raise usage_error(f"--model must be geometric, dynamic or psi; got {model!r}")
    options.refuse_psi_and_dist(psi, psi_dist)
    if m in ("geometric", "dynamic") and (psi is not None or psi_dist is not None):
        raise usage_error(f"--model {m} takes no --psi or --psi-dist; use --model psi")
    if psi is not None:
        return table_i_model(options.psi_angle(psi))
    if psi_dist is not None:
        return density_model(psi_dist)
    if m == "psi":
        raise usage_error("--model psi needs --psi DEG or --psi-dist SPEC "
                          "(e.g. --psi-dist normal:90:18)")
    return GEOMETRIC if m == "geometric" else DYNAMIC


def _coin(name: str) -> coin_catalog.Coin:
    try:
        return coin_catalog.get_coin(name)
    except ValueError as exc:
        raise usage_error(f"--coin: {exc}") from None


def _length(text: str | None, what: str) -> float | None:
    if text is None:
        return None
    try:
        return parse.parse_length_mm(text, what)
    except ValueError as exc:
        raise usage_error(str(exc)) from None


def _vector(values):
    """numpy array for a batch (several values), a float for one."""
    if not isinstance(values, list):
        return values  # already an ndarray from a stdin batch
    if len(values) == 1:
        return float(values[0])
    import numpy as np

    return np.asarray(values, dtype=float)



def _column(v, n):
    """A result column: an array stays an array (the writers format it in C), a list is
    itself, a float (or None) is repeated ``n`` times."""
    if isinstance(v, list) or (hasattr(v, "dtype") and getattr(v, "ndim", 0) == 1):
        return v
    return [v] * n


def _ratio(a: float, b: float) -> float | None:
    """a / b for finite positive a, b; None where the quotient passes the largest double."""
    q = a / b
    return None if q == math.inf else q


def _product(a: float, b: float) -> float | None:
    q = a * b
    return None if q == math.inf else q


def _no_overflow(v, xi):
    """An array column with its cells that overflowed (inf although xi is finite and
    nonzero) as None: a list then; the array itself when none did."""
    import numpy as np

    bad = np.isinf(v) & (xi > 0) & (xi < np.inf)
    if not bad.any():
        return v
    out = v.tolist()
    for k in np.flatnonzero(bad).tolist():
        out[k] = None
    return out


def _coin_words(c: coin_catalog.Coin) -> str:
    """``US quarter: 24.26 x 1.75 mm``, or ``custom coin 25 x 2 mm`` (its label is its size)."""
    if c.name == "custom":
        return f"custom coin {c.diameter_mm:g} x {c.thickness_mm:g} mm"
    return f"{c.label}: {c.diameter_mm:g} x {c.thickness_mm:g} mm"


# --------------------------------------------------------------------------- design


def _stack_columns(coin, p, model: ModelSpec, xi=None):
    """Nearest stack of ``coin`` to each target ``p``: (n, xi_n, p_n, p_n-1, p_n+1) columns.

    Vectorized (given the targets' ``xi``) under the geometric and dynamic models; otherwise
    :func:`coincli.core.coins.nearest_stack` per target.  Cells are None where there is no stack:
    ``p = 1`` (infinitely tall), past :data:`coincli.core.coins.MAX_STACK` coins, and n - 1 = 0.
    """
    if model.key in ("geometric", "dynamic") and xi is not None and not isinstance(xi, float):
        return coin_catalog.nearest_stacks(coin, p, xi, lambda x: model.forward(x).sides)
    ps = tolist(p, 1) if not isinstance(p, float) else [p]
    cols = [[], [], [], [], []]
    for pk in ps:
        vals = (None,) * 5
        if pk < 1.0:
            try:
                ch = coin_catalog.nearest_stack(coin, pk, lambda x: float(model.forward(x).sides))
            except coin_catalog.NoStackError:
                pass
            else:
                nb = {k: s for k, _, s in ch.neighbours}
                vals = (ch.count, ch.xi, ch.p_sides, nb.get(ch.count - 1), nb.get(ch.count + 1))
        for col, v in zip(cols, vals, strict=True):
            col.append(v)
    return cols


def _physics(landing: str, **bounce_options):
    """The ``--landing`` and bounce options, parsed once
    (:func:`coincli.reports.landing.parse_physics`): its Physics, or None for ``--landing
    catch`` (then no bounce option may be given)."""
    from coincli.reports.landing import landing_of, parse_physics

    return parse_physics(landing_of(landing), **bounce_options)


def design(p_sides: str, *, model: str | None = None, psi: str | None = None,
           psi_dist: str | None = None, diameter: str | None = None,
           thickness: str | None = None, coin: str = "quarter", tol: str | None = None,
           method: str | None = None, landing: str = "catch", surface: str | None = None,
           restitution: str | None = None, friction: str | None = None,
           torsional: str | None = None, rolling: str | None = None, u: str | None = None,
           omega: str | None = None, release_height: str | None = None, vx: str | None = None,
           seed: str | None = None, max_tosses: str | None = None,
           time_limit: str | None = None, jobs: str | None = None, dt: str | None = None,
           t_max: str | None = None, calibration: str | None = None,
           scheduler: str | None = None, checkpoint: str | None = None,
           timeout: str | None = None, no_table: bool = False, fmt: str = "table",
           quiet: bool = False, progress=None):
    """``coin design``: the aspect ratio (and size, and nearest stack of a catalog coin) that
    lands on a side with the chance ``p_sides``, under a model; one row per target.

    With ``landing="bounce"`` the design is simulated (MuJoCo) instead
    (:func:`bounce_design`; ``progress()``, a progress bar, or None);
    its result may carry a warning that :func:`coincli.reports.bounce.warn_unmet` writes after
    the table."""
    check_format(fmt)
    bounce_only = {"--u": u, "--omega": omega, "--seed": seed, "--max-tosses": max_tosses,
                   "--time-limit": time_limit, "--no-table": no_table or None}
    physics = _physics(landing, surface=surface, restitution=restitution, friction=friction,
                       torsional=torsional, rolling=rolling, height=release_height, vx=vx,
                       jobs=jobs, dt=dt, t_max=t_max, calibration=calibration,
                       scheduler=scheduler, checkpoint=checkpoint, timeout=timeout) \
        if landing.strip().lower() == "bounce" or not any(
            v is not None for v in bounce_only.values()) else None
    if physics is None:
        extra = [k for k, v in bounce_only.items() if v is not None]
        if extra:
            raise usage_error(f"{', '.join(extra)} go{'es' if len(extra) == 1 else ''} with "
                              "--landing bounce")
    else:
        if model is not None or method is not None or thickness is not None:
            raise usage_error("--model, --method and --thickness go with --landing catch")
        return bounce_design(physics, p_sides=p_sides, psi=psi, psi_dist=psi_dist, u=u,
                             omega=omega, diameter=diameter, coin=coin, tol=tol, seed=seed,
                             max_tosses=max_tosses, time_limit=time_limit, fmt=fmt,
                             quiet=quiet, progress=progress, no_table=no_table)
    m = choose_model(model, psi, psi_dist)
    if method is not None and method.strip().lower() not in accuracy.METHODS:
        raise usage_error(f"--method must be auto or quad; got {method!r}")
    acc = accuracy.parse(tol, method, None)
    m = accuracy.design_model(acc, m)
    if diameter is not None and thickness is not None:
        raise usage_error("give --diameter or --thickness, not both (the other one is computed)")
    c = _coin(coin)
    dia, thick = _length(diameter, "--diameter"), _length(thickness, "--thickness")
    if dia is None and thick is None:
        dia = c.diameter_mm
    vals = values_stream(p_sides, "--p-sides", parse.parse_probability, bounds=(0.0, 1.0))
    other = DYNAMIC if m.key == "geometric" else GEOMETRIC

    def compute(p):
        """The table's columns for the targets ``p`` (a float, or an array of them)."""
        try:
            xi = m.inverse(p)
            out = m.forward(xi)
        except ValueError as exc:
            raise compute_error(str(exc)) from None
        other_sides = other.forward(xi).sides
        n = 1 if isinstance(p, float) else len(p)
        if isinstance(xi, float):
            d_over_h = math.inf if xi == 0 else _ratio(1.0, xi)
            thick_col = (_product(dia, xi) if xi != math.inf else math.inf) if dia is not None \
                else thick
            dia_col = dia if dia is not None else (math.inf if xi == 0 else _ratio(thick, xi))
        else:
            import numpy as np

            with np.errstate(all="ignore"):
                d_over_h = np.where(xi == 0, np.inf, 1 / np.where(xi == 0, 1, xi))
                if dia is not None:
                    thick_col, dia_col = dia * xi, np.full(xi.shape, dia)
                else:
                    thick_col = np.full(xi.shape, thick)
                    dia_col = np.where(xi == 0, np.inf, thick / np.where(xi == 0, 1, xi))
            # a finite length or ratio past the largest double (xi below 5.6e-309 or a 1e300
            # diameter) is an empty cell, not inf: inf is kept for xi = 0 and xi = inf
            d_over_h, thick_col, dia_col = (_no_overflow(v, xi) for v in (d_over_h, thick_col,
                                                                         dia_col))
        # -q prints xi alone: no stack search (it is most of the time of a long -q batch)
        stack = [[None] * n] * 5 if quiet else _stack_columns(c, p, m, xi)
        return [
            _column(p, n), _column(xi, n), _column(d_over_h, n), _column(dia_col, n),
            _column(thick_col, n), _column(out.heads, n), _column(out.tails, n),
            [c.name] * n, *stack, _column(other_sides, n),
        ]

    columns = [
        Column("p_sides", "P(sides) target"),
        Column("xi", "xi = h/D"),
        Column("d_over_h", "D/h"),
        Column("diameter_mm", "diameter (mm)"),
        Column("thickness_mm", "thickness (mm)"),
        Column("p_heads", "P(heads)"),
        Column("p_tails", "P(tails)"),
        Column("coin", "stack coin", "text"),
        Column("stack_n", "coins in nearest stack", "int"),
        Column("stack_xi", "xi of that stack"),
        Column("stack_p_sides", "P(sides), N coins"),
        Column("stack_p_sides_minus1", "P(sides), N-1 coins"),
        Column("stack_p_sides_plus1", "P(sides), N+1 coins"),
        Column(f"{other.key}_p_sides", f"P(sides), {other.key} model"),
    ]
    note = f"model: {m.label}; vigorous toss caught without bouncing; stack of {c.label} " \
           f"({c.diameter_mm:g} x {c.thickness_mm:g} mm)" + accuracy.design_note(acc, m)
    if len(vals) > 1 and m.key in ("geometric", "dynamic"):
        # a batch under a closed form: computed and written a chunk at a time (flat memory);
        # the input was read and checked whole first, and these models cannot fail on it
        return Result("coin design", columns, [], note=note, quiet=1, vertical=True,
                      chunks=map(compute, vals.chunks()))
    data = [tolist(col, len(vals)) if hasattr(col, "dtype") else col
            for col in compute(vals.values())]
    return Result("coin design", columns, [], note=note, quiet=data[1], vertical=True,
                  data=data)


# --------------------------------------------------------------------------- table

_ALL_DENSITIES = ("uniform", "cosine", "normal")


def _table_coins(xi, coin, count, quarters, diameter, thickness, stream=False) -> options.Coins:
    return options.resolve_coin(xi, coin, count, quarters, diameter, thickness, many=True,
                                xi_rule="any", command="coin table", stream=stream)


def _materialized(coins: options.Coins) -> options.Coins:
    """``coins`` with its values as lists (a streamed batch read whole: the paths that need
    every value at once)."""
    if not isinstance(coins.counts, Values) and not isinstance(coins.xis, Values):
        return coins
    if isinstance(coins.xis, Values):
        xis = coins.xis.values() if len(coins.xis) > 1 else [coins.xis.values()]
        return options.Coins(xis, coins.kind, coins.unit, coins.counts, coins.diameter_mm,
                             coins.typed)
    counts = [int(k) for k in coins.counts.array().tolist()]
    return options.Coins(coin_catalog.stack_xis(coins.unit, counts).tolist(), coins.kind,
                         coins.unit, counts, coins.diameter_mm, coins.typed)


def table(*, xi: str | None = None, coin: str | None = None, count: str | None = None,
          quarters: str | None = None, diameter: str | None = None,
          thickness: str | None = None, psi: str | None = None, psi_dist: str | None = None,
          all: bool = False, vs: str | None = None, tol: str | None = None,
          method: str | None = None, seed: str | None = None, layout: str | None = None,
          landing: str = "catch", surface=None, restitution=None, friction=None,
          torsional=None, rolling=None, release_height=None, vx=None, u=None, omega=None,
          tosses: str | None = None, jobs=None, dt=None, t_max=None, calibration=None,
          scheduler=None, checkpoint=None, timeout=None, fmt: str = "table",
          quiet: bool = False, progress=None) -> Result:
    """``coin table``: the chances of heads, sides and tails of each coin under each model (the
    closed forms, Table I at each ``psi``, psi densities with ``psi_dist`` or ``all``); with
    ``vs="psi"``, one coin over the ``psi`` angles.  ``layout="wide"``: one row per coin, the
    models side by side (:func:`widen`).  ``landing="bounce"``: the chances on a table,
    simulated for each coin and each ``restitution`` and ``friction`` (lists or ranges), a
    parameter study (:func:`coincli.reports.bounce_table.table`).

    ``progress`` makes the progress bar of a long ``--method mc`` or ``qmc`` run (see
    :func:`coincli.reports.accuracy.run`); none by default.  Under ``-q`` the note that names a
    drawn seed is not printed: the command then reports it
    (:func:`coincli.io.options.report_drawn_seed`)."""
    check_format(fmt)
    wide = layout_value(layout, quiet)
    bouncing = (surface, restitution, friction, torsional, rolling, release_height, vx, jobs,
                dt, t_max, calibration, scheduler, checkpoint, timeout)
    if landing.strip().lower() != "catch" or any(v is not None for v in bouncing):
        from coincli.reports.landing import landing_of, parse_physics

        landing = landing_of(landing)
        if landing == "catch":
            parse_physics("catch", surface=surface, restitution=restitution, friction=friction,
                          torsional=torsional, rolling=rolling, height=release_height, vx=vx,
                          jobs=jobs, dt=dt, t_max=t_max, calibration=calibration,
                          scheduler=scheduler, checkpoint=checkpoint, timeout=timeout)
    if landing == "bounce":
        for name, v in (("--vs", vs), ("--all", all or None), ("--tol", tol),
                        ("--method", method)):
            if v is not None:
                raise usage_error(f"{name} goes with --landing catch (the closed forms and "
                                  "their averages over psi); --landing bounce simulates")
        from coincli.reports import bounce_table

        return bounce_table.table(
            xi=xi, coin=coin, count=count, quarters=quarters, diameter=diameter,
            thickness=thickness, psi=psi, psi_dist=psi_dist, u=u, omega=omega, tosses=tosses,
            seed=seed, surface=surface, restitution=restitution, friction=friction,
            torsional=torsional, rolling=rolling, release_height=release_height, vx=vx,
            jobs=jobs, dt=dt, t_max=t_max, calibration=calibration, scheduler=scheduler,
            checkpoint=checkpoint, timeout=timeout, wide=wide, progress=progress)
    options.refuse_old_count(tosses, "coin table --coin quarter --count {n}")
    for name, v in (("--u", u), ("--omega", omega)):
        if v is not None:
            raise usage_error(f"{name} goes with --landing bounce (a launch to simulate); the "
                              "catch's tables are over psi (--psi, --psi-dist)")
    if vs is not None:
        if vs.strip().lower() != "psi":
            raise usage_error(f"--vs takes psi, got {vs!r}")
        if psi_dist is not None or all:
            raise usage_error("--vs psi tabulates Table I over psi; it takes no --psi-dist or "
                              "--all")
        return _table_vs_psi(_table_coins(xi, coin, count, quarters, diameter, thickness), psi)
    coins = _table_coins(xi, coin, count, quarters, diameter, thickness, stream=True)
    extra: list[ModelSpec] = []
    if psi is not None:
        extra += [table_i_model(d) for d in options.psi_angles(psi)]
    dens = []
    if all:
        dens += [options.psi_density(s) for s in _ALL_DENSITIES]
    if psi_dist is not None:
        dens += options.psi_densities(psi_dist)
    seen = set()
    for d in dens:
        if d.spec not in seen:
            seen.add(d.spec)
            extra.append(ModelSpec.psi_density(d))
    acc = accuracy.parse(tol, method, seed)
    accuracy.require_density(acc, bool(dens))
    result = _table_rows(coins, extra, acc, fmt, progress)
    return widen(result, (GEOMETRIC, DYNAMIC, *extra), fmt) if wide else result


LAYOUTS = ("long", "wide")


def layout_value(text: str | None, quiet: bool) -> bool:
    """Whether ``--layout`` asks for the wide table (``long``, the default, or ``wide``)."""
    if text is None:
        return False
    t = text.strip().lower()
    if t not in LAYOUTS:
        raise usage_error(f"--layout must be long (a row per coin and model) or wide (a row per "
                          f"coin, the models side by side), got {text!r}")
    if t == "wide" and quiet:
        raise usage_error("--layout wide lays out a table; -q prints one P(sides) a line and "
                          "takes no layout")
    return t == "wide"


def widen(result: Result, models_, fmt: str) -> Result:
    """The long table (a row per coin and model, the ``models_`` in order for every coin) as a
    wide one: a row per coin, and each model's value columns side by side, named
    ``MODEL_COLUMN`` (``geometric_p_sides``, ``normal:90:18_p_heads``: MODEL is the model's
    name as the machine formats write it, in every format) and headed by its title on a
    terminal (``--layout wide`` of ``coin table``, for a spreadsheet).  A streamed result stays
    streamed, a chunk at a time."""
    k = len(models_)
    cols = list(result.columns)
    m = next(i for i, c in enumerate(cols) if c.name == "model")
    lead, values = cols[:m], cols[m + 1:]
    titles = _model_names(models_, fmt)
    columns = lead + [Column(f"{model.name}_{c.name}", f"{title} {c.header}", c.style)
                      for model, title in zip(models_, titles, strict=True) for c in values]

    def wide(data):
        out = [list(col[::k]) for col in data[:m]]
        for j in range(k):
            out += [list(col[j::k]) for col in data[m + 1:]]
        return out

    if result.chunks is not None:
        return Result(result.title, columns, [], note=result.note,
                      chunks=map(wide, result.chunks))
    data = [list(col) for col in zip(*result.rows, strict=True)]
    return Result(result.title, columns, [], note=result.note,
                  data=wide(data) if data else [[] for _ in columns])




_TABLE_COLUMNS = [Column("xi", "xi = h/D"), Column("model", "model", "text"),
                  Column("p_heads", "P(heads)"), Column("p_sides", "P(sides)"),
                  Column("p_tails", "P(tails)")]
_STACKED_COLUMNS = [Column("coin", "coin", "text"), Column("count", "count", "int")]


def _table_note(extra) -> str:
    return "vigorous toss starting heads up, caught without bouncing; geometric = eq. 11, " \
           "dynamic = eq. 12 (psi = 90 deg)" + "".join(f"; {m.label}" for m in extra)


def _table_rows(coins, extra, acc, fmt: str, progress=None) -> Result:
    models_ = (GEOMETRIC, DYNAMIC, *extra)
    many = coins.counts if isinstance(coins.counts, Values) else coins.xis
    if isinstance(many, Values) and len(many) > 1 and acc is None:
        # closed forms and quadrature alike are computed a chunk of coins at a time (the
        # quadrature of one xi does not depend on the others); a table density's work is
        # bounded for the whole run before the first chunk
        for m in extra:
            if m.key == "dist":
                from coincli.core.averages import check_table_work

                try:
                    check_table_work(m.density, len(many))
                except ValueError as exc:
                    raise compute_error(str(exc)) from None
        return _table_stream(coins, models_, extra, fmt)
    coins = _materialized(coins)
    x = _vector(coins.xis)
    n = 1 if isinstance(x, float) else len(x)
    names = _model_names(models_, fmt)
    blocks = []
    budget = accuracy.plan(acc, [m.density for m in extra if m.key == "dist"], x)  # per run
    for m, name in zip(models_, names, strict=True):
        more = [("closed form", None, None, None) + ((None,) if acc is not None and
                                                      acc.sampling else ())] * n
        try:
            if acc is not None and m.key == "dist":
                o, more = accuracy.run(acc, m.density, x, n, budget, progress)
            else:
                o = m.forward(x)
        except ValueError as exc:
            raise compute_error(str(exc)) from None
        blocks.append((name, tolist(o.heads, n), tolist(o.sides, n), tolist(o.tails, n), more))
    xs = tolist(x, n)
    acc_cols = accuracy.columns(acc, fmt != "table") if acc is not None else []
    stacked = coins.counts is not None
    rows = []
    for k in range(n):
        for name, h, s, t, more in blocks:
            lead = (coins.coin_name, coins.counts[k]) if stacked else ()
            rows.append((*lead, xs[k], name, h[k], s[k], t[k], *more[k][:len(acc_cols)]))
    columns = (_STACKED_COLUMNS if stacked else []) + _TABLE_COLUMNS + acc_cols
    note = _table_note(extra) + (f"; {_coin_words(coins.unit)}" if stacked else "") + \
        (accuracy.note(acc) if acc is not None else "")
    k = -2 - len(acc_cols)  # p_sides, from the end
    return Result("coin table", columns, rows, note=note,
                  quiet=[r[k] for r in rows if r[k - 3] is not None])


def _table_stream(coins: options.Coins, models_, extra, fmt: str) -> Result:
    """``coin table`` over many coins under closed forms and quadrature over psi: one row per
    coin and model, computed from arrays and written a chunk of coins at a time (memory flat
    in the number of rows).
    The coins are a Values of xi, or of counts of a stacked coin."""
    import numpy as np

    names = _model_names(models_, fmt)
    k = len(models_)
    unit = coins.unit if isinstance(coins.counts, Values) else None

    def compute(v):
        x = v if unit is None else coin_catalog.stack_xis(unit, v)
        outs = [m.forward(x) for m in models_]
        cols = [np.stack([getattr(o, f) for o in outs], axis=1).ravel()
                for f in ("heads", "sides", "tails")]
        lead = [] if unit is None else [[coins.coin_name] * (k * len(v)),
                                        np.repeat(v, k).astype(np.int64)]
        return [*lead, np.repeat(x, k), names * len(x), *cols]

    columns = (_STACKED_COLUMNS if unit is not None else []) + _TABLE_COLUMNS
    values = coins.counts if unit is not None else coins.xis
    return Result("coin table", columns, [], note=_table_note(extra), quiet=len(columns) - 2,
                  chunks=map(compute, values.chunks(max(CHUNK_ROWS // k, 1))))


def _table_vs_psi(coins: options.Coins, psi_text) -> Result:
    if len(coins.xis) != 1:
        raise usage_error("--vs psi tabulates one coin: give a single --xi (or one count)")
    x = float(coins.xis[0])
    degs = options.psi_angles(psi_text or "0:180:15")
    rows = []
    t = math.degrees(models.theta0(x)) / 2
    for d in degs:
        o = ModelSpec.fixed_psi(table_i_radians(d)).forward(x)
        fold = min(d, 180.0 - d)
        regime = "heads only" if fold < t else ("heads/sides" if fold < 90 - t else "all three")
        rows.append((x, d, regime, o.heads, o.sides, o.tails))
    columns = [Column("xi", "xi = h/D"), Column("psi_deg", "psi (deg)"),
               Column("regime", "regime", "text"), Column("p_heads", "P(heads)"),
               Column("p_sides", "P(sides)"), Column("p_tails", "P(tails)")]
    note = (f"Table I at xi = {x:g}: theta0/2 = {t:.6g} deg; heads only below it, all three "
            f"outcomes within {t:.6g} deg of 90")
    return Result("coin table --vs psi", columns, rows, note=note, quiet=[r[4] for r in rows],
                  key=2)  # a folded table repeats xi and psi: psi names the row


# --------------------------------------------------------------------------- stack and coins

_STACK_COLUMNS = [Column("coin", "coin", "text"), Column("count", "count", "int"),
                  Column("height_mm", "height (mm)"), Column("xi", "xi = h/D"),
                  Column("p_heads", "P(heads)"), Column("p_sides", "P(sides)"),
                  Column("p_tails", "P(tails)"), Column("mark", "mark", "text")]


def stack(*, coin: str | None = None, count: str | None = None, p_sides: str | None = None,
          quarters: str | None = None, diameter: str | None = None,
          thickness: str | None = None, xi: str | None = None, model: str | None = None,
          psi: str | None = None, psi_dist: str | None = None, fmt: str = "table",
          quiet: bool = False, old_n: str | None = None) -> Result:
    """``coin stack``: stacks of ``count`` real coins (a quarter unless ``coin``, ``quarters``
    or ``diameter`` and ``thickness`` say otherwise), or the stack nearest each ``p_sides``,
    with their xi = N h / D and chances under a model."""
    options.refuse_old_count(old_n, "coin stack --coin quarter --count {n}")
    check_format(fmt)
    m = choose_model(model, psi, psi_dist)
    if quarters is not None and p_sides is not None:
        raise usage_error("--quarters N is a stack already; give --coin quarter --p-sides P to "
                          "find the count")
    if xi is not None:
        raise usage_error("coin stack stacks a coin of known size: give --coin NAME, --quarters "
                          "N or --diameter D --thickness H (for a coin given by --xi, use coin "
                          "table --xi X)")
    coins = options.resolve_coin(None, coin, count, quarters, diameter, thickness, many=True,
                                 default="quarter", need_count=False, command="coin stack",
                                 stream=True, takes_xi=False)
    c = coins.unit
    if quarters is not None:
        count = quarters
    if (count is None) == (p_sides is None):
        raise usage_error("give --count N (how many coins) or --p-sides P (find the count), "
                          "one of them")
    if p_sides is not None and _is_batch(p_sides):
        return _stack_batch(c, p_sides, m)
    if p_sides is not None:
        try:
            p = parse.parse_probability(p_sides, "--p-sides")
        except ValueError as exc:
            raise usage_error(str(exc)) from None
        if p >= 1.0:
            raise compute_error("P(sides) = 1 needs an infinitely tall stack; choose p < 1")
        try:
            ch = coin_catalog.nearest_stack(c, p, lambda x: float(m.forward(x).sides))
        except ValueError as exc:
            raise compute_error(str(exc)) from None
        counts = [k for k, _, _ in ch.neighbours]
        best = ch.count
    else:
        counts = coins.counts
        if isinstance(counts, Values) and len(counts) > 1 and (m.closed_form or
                                                                m.key == "dist"):
            if m.key == "dist":  # a table density's work, for the whole run, before a row
                from coincli.core.averages import check_table_work

                try:
                    check_table_work(m.density, len(counts), what="counts")
                except ValueError as exc:
                    raise compute_error(str(exc)) from None
            return _stack_counts_stream(c, counts, m)
        counts = _materialized(coins).counts
        best = None
    rows = []
    for k in counts:
        x = coin_catalog.stack_xi(c, k)
        o = m.forward(x)
        mark = ("nearest" if k == best else "") if best is not None else ""
        rows.append((c.name, k, k * c.thickness_mm, x, o.heads, o.sides, o.tails, mark))
    note = f"{_coin_words(c)}; model: {m.label}"
    quiet_val = best if best is not None else [r[5] for r in rows]
    return Result("coin stack", _STACK_COLUMNS, rows, note=note, quiet=quiet_val)


def _is_batch(text: str) -> bool:
    """Whether --p-sides asks for several targets: '-' (stdin), a list or a range."""
    s = text.strip()
    return s == "-" or "," in s or ":" in s


def _stack_counts_stream(c, counts, m: ModelSpec) -> Result:
    """``coin stack --count`` for many counts under a closed form or a psi density (quadrature,
    one xi independent of the others): arrays, a chunk at a time."""
    import numpy as np

    def compute(k):
        x = coin_catalog.stack_xis(c, k)
        o = m.forward(x)
        n = len(k)
        return [[c.name] * n, k.astype(np.int64), k * c.thickness_mm, x, o.heads, o.sides,
                o.tails, [""] * n]

    note = f"{_coin_words(c)}; model: {m.label}"
    return Result("coin stack", _STACK_COLUMNS, [], note=note, quiet=5,
                  chunks=map(compute, counts.chunks()))


def _stack_batch(c, p_text: str, m: ModelSpec) -> Result:
    """``coin stack --p-sides`` for several targets: one row each, the nearest stack (closed
    forms a chunk of targets at a time)."""
    vals = values_stream(p_text, "--p-sides", parse.parse_probability, bounds=(0.0, 1.0))

    def compute(p):
        n = 1 if isinstance(p, float) else len(p)
        xi = m.inverse(p) if m.key in ("geometric", "dynamic") and n > 1 else None
        counts, xis = _stack_columns(c, p, m, xi)[:2]
        known = [k for k, x in enumerate(xis) if x is not None]
        chances = [[None] * n for _ in range(3)]
        if known:
            try:
                o = m.forward(_vector([xis[k] for k in known]))
            except ValueError as exc:
                raise compute_error(str(exc)) from None
            for col, vals_ in zip(chances, o, strict=True):
                for k, v in zip(known, tolist(vals_, len(known)), strict=True):
                    col[k] = v
        heights = [None if k is None else k * c.thickness_mm for k in counts]
        return [tolist(p, n), [c.name] * n, counts, heights, xis, *chances]

    columns = [Column("target_p_sides", "target"), Column("coin", "coin", "text"),
               Column("count", "count", "int"), Column("height_mm", "height (mm)"),
               Column("xi", "xi = h/D"), Column("p_heads", "P(heads)"),
               Column("p_sides", "P(sides)"), Column("p_tails", "P(tails)")]
    note = (f"{_coin_words(c)}; model: {m.label}; the stack nearest each target (empty where "
            f"no stack of up to {coin_catalog.MAX_STACK_WORDS} coins reaches it)")
    if len(vals) > 1 and m.key in ("geometric", "dynamic"):
        return Result("coin stack", columns, [], note=note, quiet=2,
                      chunks=map(compute, vals.chunks()))
    data = compute(vals.values())
    return Result("coin stack", columns, [], note=note, quiet=data[2], data=data)


def coins(*, fmt: str = "table", quiet: bool = False) -> Result:
    """``coin coins``: the catalog of real coins, their dimensions, sources and P(sides)."""
    check_format(fmt)
    rows = []
    for c in coin_catalog.CATALOG.values():
        rows.append((c.name, c.label, c.diameter_mm, c.thickness_mm, c.xi,
                     models.dynamic(c.xi).sides, c.source))
    columns = [Column("name", "name", "text"), Column("label", "coin", "text"),
               Column("diameter_mm", "diameter (mm)"), Column("thickness_mm", "thickness (mm)"),
               Column("xi", "xi = h/D"), Column("p_sides_dynamic", "P(sides), one coin"),
               Column("source", "source", "text")]
    return Result("coin coins", columns, rows, note="P(sides) of a single coin, dynamic model",
                  quiet=[r[0] for r in rows])


# --------------------------------------------------------------------------- fair


def fair(*, diameter: str | None = None, coin: str = "quarter", psi_dist: str | None = None,
         fmt: str = "table", quiet: bool = False) -> Result:
    """``coin fair``: the fair three-sided coin (P(sides) = 1/3) under each model, and what the
    other model says of it."""
    check_format(fmt)
    c = _coin(coin)
    dia = _length(diameter, "--diameter") or c.diameter_mm
    ms = [GEOMETRIC, DYNAMIC]
    if psi_dist is not None:
        ms.append(density_model(psi_dist))
    rows = []
    for m, name in zip(ms, _model_names(ms, fmt), strict=True):
        try:
            x = m.inverse(1 / 3)
        except ValueError as exc:
            raise compute_error(str(exc)) from None
        ch = coin_catalog.nearest_stack(c, 1 / 3, lambda v, m=m: float(m.forward(v).sides))
        own, g, d = m.forward(x), GEOMETRIC.forward(x), DYNAMIC.forward(x)
        rows.append((name, x, 1 / x, dia * x, own.heads, own.sides, own.tails,
                     ch.count, ch.xi, float(m.forward(ch.xi).sides), g.sides, d.sides))
    columns = [Column("model", "model", "text"), Column("xi", "xi = h/D"),
               Column("d_over_h", "D/h"), Column("thickness_mm", f"thickness for D = {dia:g} mm"),
               Column("p_heads", "P(heads)"), Column("p_sides", "P(sides)"),
               Column("p_tails", "P(tails)"), Column("stack_n", f"{c.name}s stacked", "int"),
               Column("stack_xi", "xi of stack"), Column("stack_p_sides", "P(sides) of stack"),
               Column("geometric_p_sides", "geometric says P(sides)"),
               Column("dynamic_p_sides", "dynamic says P(sides)")]
    note = ("fair = P(sides) 1/3; geometric: every orientation equally likely (von Neumann); "
            "dynamic: angular momentum conserved, Keller flip psi = 90 deg")
    title = ("coin fair" if psi_dist is None else
             "coin fair: P(sides) = 1/3 (under a psi density only the sides are 1/3)")
    return Result(title, columns, rows, note=note, quiet=[r[1] for r in rows])


# --------------------------------------------------------------------------- --landing bounce


def bounce_design(physics, *, p_sides, psi, psi_dist, u, omega, diameter, coin, tol, seed,
                  max_tosses, time_limit, fmt="table", quiet=False, progress=None,
                  no_table=False):
    """``coin design --landing bounce``: the report, from the options as typed (``physics``:
    :func:`coincli.reports.landing.parse_physics` of the surface options).  ``fmt`` and
    ``quiet`` are the command's (unused: the same result is written in every format);
    ``progress``: a progress bar, or None.  After writing it, call
    :func:`coincli.reports.bounce.warn_unmet`.

    The choice of the table is here: a preset (or the user's surface options), designed by
    :func:`coincli.reports.bounce.design`, or a calibration (``physics.calibration``), designed
    with its uncertainty by :func:`coincli.reports.calibrate.design`."""
    from coincli.core.bounce import design as core_bounce_design
    from coincli.limits import BOUNCE_DESIGN_TOSSES, MAX_BOUNCE_TOSSES, STANDARD_G
    from coincli.reports import bounce
    from coincli.reports.launch import HAND, U_MAX, bounce_launch, bounded_number, reach
    from coincli.reports.physics import bounce_tosses, check_coin, check_landing

    targets = values_option(p_sides, "--p-sides", parse.parse_probability, bounds=(0.0, 1.0))
    targets = [float(t) for t in targets]
    if len(targets) > 20:
        raise usage_error(f"--landing bounce designs at most 20 targets a run, got "
                          f"{len(targets)}")
    for t in targets:
        if not 0.0 < t < 1.0:
            raise usage_error(f"--p-sides must be strictly between 0 and 1 with --landing "
                              f"bounce, got {t:g}")
    tol_v = 0.01 if tol is None else bounded_number(tol, "--tol", 1e-4, 1.0)
    least = core_bounce_design.DESIGN_LEAST
    mt = (BOUNCE_DESIGN_TOSSES if max_tosses is None else
          bounce_tosses(max_tosses, "--max-tosses", least, MAX_BOUNCE_TOSSES))
    tl = 300.0 if time_limit is None else bounded_number(time_limit, "--time-limit", 1.0, 1e6)
    if diameter is not None:
        try:
            dia = parse.parse_length_mm(diameter, "--diameter") / 1000
        except ValueError as exc:
            raise usage_error(str(exc)) from None
    else:
        try:
            dia = coin_catalog.get_coin(coin).diameter_mm / 1000
        except ValueError as exc:
            raise usage_error(str(exc)) from None
    u_spec, w_spec, psi_spec, labels = bounce_launch(psi, psi_dist, u, omega)
    grid = core_bounce_design.DESIGN_GRID  # the sweep's coins must be simulable
    check_coin(physics, None, dia, diameter_text=diameter, xi_low=min(grid),
               command="coin design --landing bounce")
    check_landing(physics, u_top=reach(u_spec, U_MAX), g=STANDARD_G, xi=max(grid), dia=dia,
                  u_text=u or HAND["u"])
    if physics.calibration is not None:  # the user's table: its uncertainty carried too
        from coincli.reports import calibrate

        return calibrate.design(physics, targets=targets, seed=options.seed_value(seed), tol=tol_v,
                                max_tosses=mt, time_limit=tl, diameter=dia, g=STANDARD_G,
                                given={"u": u_spec if u is not None else None,
                                       "omega": w_spec if omega is not None else None,
                                       "psi": psi_spec if psi is not None or psi_dist
                                       is not None else None}, progress=progress)
    return bounce.design(physics, targets=targets, seed=options.seed_value(seed), tol=tol_v,
                         max_tosses=mt, time_limit=tl, u=u_spec, omega=w_spec, psi=psi_spec,
                         diameter=dia, g=STANDARD_G, labels=labels, progress=progress,
                         no_table=no_table)
