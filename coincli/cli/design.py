"""``coin design``, ``coin table``, ``coin stack``, ``coin coins``, ``coin fair``.

Thin: parse the options, call :mod:`coincli.core.models` / :mod:`coincli.core.averages`, build a
:class:`Result`, emit it.  A single value under the geometric or dynamic model stays on Python
floats (no numpy); lists, ranges and stdin batches of those models go through numpy in one
vectorized call; psi models use quadrature and root finding (numpy, loaded then).
"""

from __future__ import annotations

import math
from typing import Annotated

import typer

from coincli.core import coins as coin_catalog
from coincli.core import models
from coincli.io import grammar as parse
from coincli.cli import _accuracy, _options, app
from coincli.cli import _bounce as BO
from coincli.io.table import (
    CHUNK_ROWS,
    Column,
    FormatOpt,
    QuietOpt,
    Result,
    Values,
    check_format,
    compute_error,
    emit,
    usage_error,
    values_stream,
)
from coincli.core.modelspec import DYNAMIC, GEOMETRIC, ModelSpec

MACHINE_FORMATS = ("csv", "tsv", "json", "jsonl")


def _model_names(models, fmt: str) -> list[str]:
    """Each model's name as a table cell: its spec in machine output (``normal``, reads back
    as --psi-dist), its human title on a terminal (``normal (paper)``)."""
    human = fmt.strip().lower() not in MACHINE_FORMATS
    return [m.title if human else m.name for m in models]

# --------------------------------------------------------------------------- models as options


class _Mirrored(ModelSpec):
    """Table I at psi > 90 deg, computed at its mirror image 180 deg - psi and named by psi."""

    __slots__ = ()

    @property
    def name(self) -> str:
        return f"psi={180.0 - math.degrees(self.psi):.10g}"


def _table_i_angle(deg: float) -> float:
    """The angle (radians) to evaluate Table I at for ``deg`` degrees.  Table I is symmetric,
    P(i | psi) = P(i | 180 deg - psi), and past 90 deg the mirror angle is taken in degrees,
    where ``180 - deg`` is exact: ``--psi 179.5`` is ``--psi 0.5`` to the last bit (in radians
    pi - psi would carry pi's rounding, 1e-16 rad, 1e-14 relative at 0.5 deg), and 180 deg is
    exactly 0 deg: the coin never precesses (``math.pi``, 1.2e-16 rad short of pi, would
    precess, and land on a side once xi > 4e15).
    """
    return _options.radians(180.0 - deg) if deg > 90.0 else _options.radians(deg)


def psi_model(psi_deg_text: str) -> ModelSpec:
    return angle_model(_options.psi_angle(psi_deg_text))


def angle_model(deg: float) -> ModelSpec:
    """Table I at ``deg`` degrees (checked to lie in [0, 180])."""
    label = f"psi = {deg:.10g} deg (Table I)"
    return (_Mirrored if deg > 90.0 else ModelSpec).fixed_psi(_table_i_angle(deg), label)


def density_model(spec: str) -> ModelSpec:
    return ModelSpec.psi_density(_options.psi_density(spec))


def choose_model(model: str | None, psi: str | None, psi_dist: str | None) -> ModelSpec:
    """The model from --model, --psi and --psi-dist; contradictions are usage errors."""
    m = (model or "").strip().lower()
    if m not in ("", "geometric", "dynamic", "psi"):
        raise usage_error(f"--model must be geometric, dynamic or psi; got {model!r}")
    _options.refuse_psi_and_dist(psi, psi_dist)
    if m in ("geometric", "dynamic") and (psi is not None or psi_dist is not None):
        raise usage_error(f"--model {m} takes no --psi or --psi-dist; use --model psi")
    if psi is not None:
        return psi_model(psi)
    if psi_dist is not None:
        return density_model(psi_dist)
    if m == "psi":
        raise usage_error("--model psi needs --psi DEG or --psi-dist SPEC "
                          "(e.g. --psi-dist normal:90:18)")
    return GEOMETRIC if m == "geometric" else DYNAMIC


ModelOpt = Annotated[
    str | None,
    typer.Option("--model", "-m", help="geometric, dynamic (default) or psi.", metavar="MODEL"),
]
PsiOpt = _options.PsiOpt
PsiDistOpt = _options.PsiDistOpt
CoinOpt = Annotated[
    str, typer.Option("--coin", "-c", metavar="NAME", help="Catalog coin of the stack "
                      "(see coin coins).")
]


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


def _tolist(v, n):
    return v.tolist() if hasattr(v, "tolist") and not isinstance(v, float) else [v] * n


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


# --------------------------------------------------------------------------- design


def _stack_columns(coin, p, model: ModelSpec, xi=None):
    """Nearest stack of ``coin`` to each target ``p``: (n, xi_n, p_n, p_n-1, p_n+1) columns.

    Vectorized (given the targets' ``xi``) under the geometric and dynamic models; otherwise
    :func:`coincli.core.coins.nearest_stack` per target.  Cells are None where there is no stack:
    ``p = 1`` (infinitely tall), past :data:`coincli.core.coins.MAX_STACK` coins, and n - 1 = 0.
    """
    if model.key in ("geometric", "dynamic") and xi is not None and not isinstance(xi, float):
        return coin_catalog.nearest_stacks(coin, p, xi, lambda x: model.forward(x).sides)
    ps = _tolist(p, 1) if not isinstance(p, float) else [p]
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


@app.command()
def design(
    p_sides: Annotated[
        str,
        typer.Option("--p-sides", "-p", metavar="P", help="Target chance of a side: 0.33, 1/3 "
                     "or 33%; a list a,b; a range lo:hi:step; or - (stdin)."),
    ],
    model: ModelOpt = None,
    psi: PsiOpt = None,
    psi_dist: PsiDistOpt = None,
    diameter: Annotated[
        str | None,
        typer.Option("--diameter", "-d", metavar="D", help="Diameter (24.26, 2.4cm, 0.955in); "
                     "the thickness is computed.  Default: the --coin's."),
    ] = None,
    thickness: Annotated[
        str | None,
        typer.Option("--thickness", "-t", metavar="H", help="Thickness (mm or a unit); the "
                     "diameter is computed instead."),
    ] = None,
    coin: CoinOpt = "quarter",
    tol: _accuracy.TolOpt = None,
    method: _accuracy.DesignMethodOpt = None,
    landing: BO.LandingOpt = "catch",
    surface: BO.SurfaceOpt = None,
    restitution: BO.RestitutionOpt = None,
    friction: BO.FrictionOpt = None,
    torsional: BO.TorsionalOpt = None,
    rolling: BO.RollingOpt = None,
    u: Annotated[str | None, typer.Option("--u", help="With --landing bounce: launch speed, "
                                          "m/s, a value or normal:MEAN:SD / uniform:LOW:HIGH "
                                          "(default the hand toss of coin simulate, "
                                          "normal:2.4:0.3).", metavar="SPEC")] = None,
    omega: Annotated[str | None, typer.Option("--omega", help="With --landing bounce: "
                                              "precession rate, rad/s or with a unit (default "
                                              "the hand toss, normal:38:4rev/s).",
                                              metavar="SPEC")] = None,
    height: BO.ReleaseHeightOpt = None,
    vx: BO.VxOpt = None,
    seed: Annotated[str | None, typer.Option("--seed", metavar="SEED", help="With --landing "
                                             "bounce: the seed of the simulated tosses, a whole "
                                             "number >= 0 (default: drawn, and reported).")
                    ] = None,
    max_tosses: Annotated[str | None, typer.Option("--max-tosses", help="With --landing "
                                                   "bounce: stop before simulating more tosses "
                                                   "than this (default 200000, at least 180).",
                                                   metavar="N")] = None,
    time_limit: Annotated[str | None, typer.Option("--time-limit", help="With --landing bounce: "
                                                   "stop at the end of the first round after "
                                                   "this many seconds (default 300); the note "
                                                   "gives the --max-tosses that reproduces the "
                                                   "result.", metavar="S")] = None,
    jobs: BO.JobsOpt = None,
    dt: BO.DtOpt = None,
    t_max: BO.TMaxOpt = None,
    fmt: FormatOpt = "table",
    quiet: QuietOpt = False,
):
    """The aspect ratio (thickness/diameter) that lands on a side with the chance you want.

    Reports xi, D/h, the thickness for a diameter (or the diameter for a thickness), the
    nearest stack of a catalog coin with N-1, N and N+1 coins, and what the other model says.

    --landing bounce answers another question: the coin lands on a surface (--surface) and
    bounces; tosses are simulated (MuJoCo) at a sweep of xi, a probit curve in log xi is fitted,
    inverted for each target, and refined until its 95% interval is within --tol (in xi).

    Examples: coin design --p-sides 1/3 ;  coin design -p 25% --model geometric --diameter 30 ;
    seq 0.05 0.05 0.95 | coin design -p - --format csv ;
    coin design --p-sides 1/3 --landing bounce --surface wood --seed 1
    """
    check_format(fmt)
    bounce_only = {"--u": u, "--omega": omega, "--seed": seed, "--max-tosses": max_tosses,
                   "--time-limit": time_limit}
    from coincli.reports import bounce as bounce_report

    physics = bounce_report.parse_physics(
        bounce_report.landing_of(landing), surface=surface, restitution=restitution,
        friction=friction, torsional=torsional, rolling=rolling, height=height, vx=vx,
        jobs=jobs, dt=dt, t_max=t_max) \
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
        from coincli.io.table import emit_all

        result = bounce_report.bounce_design(
            physics, p_sides=p_sides, psi=psi, psi_dist=psi_dist, u=u, omega=omega,
            diameter=diameter, coin=coin, tol=tol, seed=seed, max_tosses=max_tosses,
            time_limit=time_limit, fmt=fmt, quiet=quiet, progress=BO.design_progress)
        emit_all(result, fmt, quiet)
        bounce_report.warn_unmet(result)  # after the table
        return
    m = choose_model(model, psi, psi_dist)
    if method is not None and method.strip().lower() not in _accuracy.METHODS:
        raise usage_error(f"--method must be auto or quad; got {method!r}")
    acc = _accuracy.parse(tol, method, None)
    m = _accuracy.design_model(acc, m)
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
           f"({c.diameter_mm:g} x {c.thickness_mm:g} mm)" + _accuracy.design_note(acc, m)
    if len(vals) > 1 and m.key in ("geometric", "dynamic"):
        # a batch under a closed form: computed and written a chunk at a time (flat memory);
        # the input was read and checked whole first, and these models cannot fail on it
        emit(Result("coin design", columns, [], note=note, quiet=1, vertical=True,
                     chunks=map(compute, vals.chunks())), fmt, quiet)
        return
    data = [_tolist(col, len(vals)) if hasattr(col, "dtype") else col
            for col in compute(vals.values())]
    emit(Result("coin design", columns, [], note=note, quiet=data[1], vertical=True,
                data=data), fmt, quiet)


# --------------------------------------------------------------------------- table

_ALL_DENSITIES = ("uniform", "cosine", "normal")


def _table_coins(xi, coin, count, quarters, diameter, thickness, stream=False) -> _options.Coins:
    return _options.resolve_coin(xi, coin, count, quarters, diameter, thickness, many=True,
                                 xi_rule="any", command="coin table", stream=stream)


def _materialized(coins: _options.Coins) -> _options.Coins:
    """``coins`` with its values as lists (a streamed batch read whole: the paths that need
    every value at once)."""
    if not isinstance(coins.counts, Values) and not isinstance(coins.xis, Values):
        return coins
    if isinstance(coins.xis, Values):
        xis = coins.xis.values() if len(coins.xis) > 1 else [coins.xis.values()]
        return _options.Coins(xis, coins.kind, coins.unit, coins.counts, coins.diameter_mm,
                              coins.typed)
    counts = [int(k) for k in coins.counts.array().tolist()]
    return _options.Coins(coin_catalog.stack_xis(coins.unit, counts).tolist(), coins.kind,
                          coins.unit, counts, coins.diameter_mm, coins.typed)


@app.command()
def table(
    xi: _options.XisOpt = None,
    coin: _options.CoinOpt = None,
    count: _options.CountsOpt = None,
    quarters: _options.QuartersManyOpt = None,
    diameter: _options.DiameterOpt = None,
    thickness: _options.ThicknessOpt = None,
    psi: _options.PsisOpt = None,
    psi_dist: _options.PsiDistsOpt = None,
    all_models: Annotated[
        bool, typer.Option("--all", help="Also Table II's densities: uniform, cosine, normal.")
    ] = False,
    vs: Annotated[
        str | None, typer.Option("--vs", metavar="psi", help="psi: one row per --psi angle "
                                 "(default 0:180:15), regimes named.")
    ] = None,
    tol: _accuracy.TolOpt = None,
    method: _accuracy.MethodOpt = None,
    seed: _accuracy.SeedOpt = None,
    fmt: FormatOpt = "table",
    quiet: Annotated[
        bool, typer.Option("--quiet", "-q", help="Print only P(sides), a line a row: each "
                           "coin's geometric, then dynamic, then the other models.")
    ] = False,
    old_n: _options.OldCountOpt = None,
):
    """Chances of heads, sides and tails under every model, for one or more coins.

    One row per coin and model: geometric (eq. 11) and dynamic (eq. 12) always; Table I at
    each --psi angle; psi-averaged densities with --psi-dist or --all (Table II).

    Examples: coin table --xi 0.577 ;  coin table --xi 0.1:1:0.1 --format csv ;
    coin table --quarters 8 --all ;  coin table --diameter 30 --thickness 17 --psi 60,90 ;
    coin table --xi 17/30 --vs psi --psi 0:180:10
    """
    _options.refuse_old_count(old_n, "coin table --coin quarter --count {n}")
    check_format(fmt)
    if vs is not None:
        if vs.strip().lower() != "psi":
            raise usage_error(f"--vs takes psi, got {vs!r}")
        if psi_dist is not None or all_models:
            raise usage_error("--vs psi tabulates Table I over psi; it takes no --psi-dist or "
                              "--all")
        return _table_vs_psi(_table_coins(xi, coin, count, quarters, diameter, thickness), psi,
                             fmt, quiet)
    coins = _table_coins(xi, coin, count, quarters, diameter, thickness, stream=True)
    extra: list[ModelSpec] = []
    if psi is not None:
        extra += [angle_model(d) for d in _options.psi_angles(psi)]
    dens = []
    if all_models:
        dens += [_options.psi_density(s) for s in _ALL_DENSITIES]
    if psi_dist is not None:
        dens += _options.psi_densities(psi_dist)
    seen = set()
    for d in dens:
        if d.spec not in seen:
            seen.add(d.spec)
            extra.append(ModelSpec.psi_density(d))
    acc = _accuracy.parse(tol, method, seed)
    _accuracy.require_density(acc, bool(dens))
    _table_rows(coins, extra, acc, fmt, quiet)
    if quiet and acc is not None and acc.sampling:  # the note that names the seed is not shown
        _options.report_seed(acc.seed, seed is not None)


def _table_rows(coins, extra, acc, fmt: str, quiet: bool) -> None:
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
        return _table_stream(coins, models_, extra, fmt, quiet)
    coins = _materialized(coins)
    x = _vector(coins.xis)
    n = 1 if isinstance(x, float) else len(x)
    models_ = (GEOMETRIC, DYNAMIC, *extra)
    names = _model_names(models_, fmt)
    blocks = []
    budget = _accuracy.plan(acc, [m.density for m in extra if m.key == "dist"], x)  # per run
    for m, name in zip(models_, names, strict=True):
        more = [("closed form", None, None, None) + ((None,) if acc is not None and
                                                      acc.sampling else ())] * n
        try:
            if acc is not None and m.key == "dist":
                o, more = _accuracy.run(acc, m.density, x, n, budget)
            else:
                o = m.forward(x)
        except ValueError as exc:
            raise compute_error(str(exc)) from None
        blocks.append((name, _tolist(o.heads, n), _tolist(o.sides, n), _tolist(o.tails, n), more))
    xs = _tolist(x, n)
    acc_cols = _accuracy.columns(acc, fmt != "table") if acc is not None else []
    stacked = coins.counts is not None
    rows = []
    for k in range(n):
        for name, h, s, t, more in blocks:
            lead = (coins.coin_name, coins.counts[k]) if stacked else ()
            rows.append((*lead, xs[k], name, h[k], s[k], t[k], *more[k][:len(acc_cols)]))
    columns = ([Column("coin", "coin", "text"), Column("count", "count", "int")] if stacked
               else []) + [
        Column("xi", "xi = h/D"),
        Column("model", "model", "text"),
        Column("p_heads", "P(heads)"),
        Column("p_sides", "P(sides)"),
        Column("p_tails", "P(tails)"),
    ] + acc_cols
    note = "vigorous toss starting heads up, caught without bouncing; geometric = eq. 11, " \
           "dynamic = eq. 12 (psi = 90 deg)" + "".join(f"; {m.label}" for m in extra) + \
           (f"; {_coin_words(coins.unit)}" if stacked else "") + \
           (_accuracy.note(acc) if acc is not None else "")
    k = -2 - len(acc_cols)  # p_sides, from the end
    emit(Result("coin table", columns, rows, note=note,
                quiet=[r[k] for r in rows if r[k - 3] is not None]), fmt, quiet)


_TABLE_COLUMNS = [Column("xi", "xi = h/D"), Column("model", "model", "text"),
                  Column("p_heads", "P(heads)"), Column("p_sides", "P(sides)"),
                  Column("p_tails", "P(tails)")]


def _table_note(extra) -> str:
    return "vigorous toss starting heads up, caught without bouncing; geometric = eq. 11, " \
           "dynamic = eq. 12 (psi = 90 deg)" + "".join(f"; {m.label}" for m in extra)


def _table_stream(coins: _options.Coins, models_, extra, fmt: str, quiet: bool) -> None:
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

    columns = ([Column("coin", "coin", "text"), Column("count", "count", "int")]
               if unit is not None else []) + _TABLE_COLUMNS
    values = coins.counts if unit is not None else coins.xis
    emit(Result("coin table", columns, [], note=_table_note(extra), quiet=len(columns) - 2,
                chunks=map(compute, values.chunks(max(CHUNK_ROWS // k, 1)))), fmt, quiet)


def _table_vs_psi(coins: _options.Coins, psi_text, fmt, quiet):
    if len(coins.xis) != 1:
        raise usage_error("--vs psi tabulates one coin: give a single --xi (or one count)")
    x = float(coins.xis[0])
    degs = _options.psi_angles(psi_text or "0:180:15")
    rows = []
    t = math.degrees(models.theta0(x)) / 2
    for d in degs:
        o = ModelSpec.fixed_psi(_table_i_angle(d)).forward(x)
        fold = min(d, 180.0 - d)
        regime = "heads only" if fold < t else ("heads/sides" if fold < 90 - t else "all three")
        rows.append((x, d, regime, o.heads, o.sides, o.tails))
    columns = [Column("xi", "xi = h/D"), Column("psi_deg", "psi (deg)"),
               Column("regime", "regime", "text"), Column("p_heads", "P(heads)"),
               Column("p_sides", "P(sides)"), Column("p_tails", "P(tails)")]
    note = (f"Table I at xi = {x:g}: theta0/2 = {t:.6g} deg; heads only below it, all three "
            f"outcomes within {t:.6g} deg of 90")
    emit(Result("coin table --vs psi", columns, rows, note=note, quiet=[r[4] for r in rows],
                key=2), fmt, quiet)  # a folded table repeats xi and psi: psi names the row


# --------------------------------------------------------------------------- stack and coins


@app.command()
def stack(
    coin: _options.CoinOpt = None,
    count: _options.CountsOpt = None,
    p_sides: Annotated[
        str | None, typer.Option("--p-sides", "-p", metavar="P", help="Find the stack nearest "
                                 "this chance of a side (0.33, 1/3, 33%), and its neighbours; "
                                 "a list, a range or - for one row each.")
    ] = None,
    quarters: _options.QuartersManyOpt = None,
    diameter: _options.DiameterOpt = None,
    thickness: _options.ThicknessOpt = None,
    xi: Annotated[str | None, typer.Option("--xi", "-x", hidden=True)] = None,
    model: ModelOpt = None,
    psi: PsiOpt = None,
    psi_dist: PsiDistOpt = None,
    fmt: FormatOpt = "table",
    quiet: QuietOpt = False,
    old_n: _options.OldCountOpt = None,
):
    """Stacks of real coins glued together: their xi = N h / D and chances.

    The coin is a US quarter unless --coin or --diameter/--thickness says otherwise.

    Examples: coin stack --coin quarter --count 8 ;  coin stack --coin quarter --p-sides 1/3 ;
    coin stack --diameter 25 --thickness 2 --count 1:12:1 ;
    seq 0.1 0.1 0.9 | coin stack --coin nickel --p-sides - --format csv
    """
    _options.refuse_old_count(old_n, "coin stack --coin quarter --count {n}")
    check_format(fmt)
    m = choose_model(model, psi, psi_dist)
    if quarters is not None and p_sides is not None:
        raise usage_error("--quarters N is a stack already; give --coin quarter --p-sides P to "
                          "find the count")
    if xi is not None:
        raise usage_error("coin stack stacks a coin of known size: give --coin NAME, --quarters "
                          "N or --diameter D --thickness H (for a coin given by --xi, use coin "
                          "table --xi X)")
    coins = _options.resolve_coin(None, coin, count, quarters, diameter, thickness, many=True,
                                  default="quarter", need_count=False, command="coin stack",
                                  stream=True, takes_xi=False)
    c = coins.unit
    if quarters is not None:
        count = quarters
    if (count is None) == (p_sides is None):
        raise usage_error("give --count N (how many coins) or --p-sides P (find the count), "
                          "one of them")
    if p_sides is not None and _is_batch(p_sides):
        return _stack_batch(c, p_sides, m, fmt, quiet)
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
            return _stack_counts_stream(c, counts, m, fmt, quiet)
        counts = _materialized(coins).counts
        best = None
    rows = []
    for k in counts:
        x = coin_catalog.stack_xi(c, k)
        o = m.forward(x)
        mark = ("nearest" if k == best else "") if best is not None else ""
        rows.append((c.name, k, k * c.thickness_mm, x, o.heads, o.sides, o.tails, mark))
    columns = [Column("coin", "coin", "text"), Column("count", "count", "int"),
               Column("height_mm", "height (mm)"), Column("xi", "xi = h/D"),
               Column("p_heads", "P(heads)"), Column("p_sides", "P(sides)"),
               Column("p_tails", "P(tails)"), Column("mark", "mark", "text")]
    note = f"{_coin_words(c)}; model: {m.label}"
    quiet_val = best if best is not None else [r[5] for r in rows]
    emit(Result("coin stack", columns, rows, note=note, quiet=quiet_val), fmt, quiet)


def _coin_words(c: coin_catalog.Coin) -> str:
    """``US quarter: 24.26 x 1.75 mm``, or ``custom coin 25 x 2 mm`` (its label is its size)."""
    if c.name == "custom":
        return f"custom coin {c.diameter_mm:g} x {c.thickness_mm:g} mm"
    return f"{c.label}: {c.diameter_mm:g} x {c.thickness_mm:g} mm"


def _is_batch(text: str) -> bool:
    """Whether --p-sides asks for several targets: '-' (stdin), a list or a range."""
    s = text.strip()
    return s == "-" or "," in s or ":" in s


_STACK_COLUMNS = [Column("coin", "coin", "text"), Column("count", "count", "int"),
                  Column("height_mm", "height (mm)"), Column("xi", "xi = h/D"),
                  Column("p_heads", "P(heads)"), Column("p_sides", "P(sides)"),
                  Column("p_tails", "P(tails)"), Column("mark", "mark", "text")]


def _stack_counts_stream(c, counts, m: ModelSpec, fmt: str, quiet: bool) -> None:
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
    emit(Result("coin stack", _STACK_COLUMNS, [], note=note, quiet=5,
                chunks=map(compute, counts.chunks())), fmt, quiet)


def _stack_batch(c, p_text: str, m: ModelSpec, fmt: str, quiet: bool) -> None:
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
                for k, v in zip(known, _tolist(vals_, len(known)), strict=True):
                    col[k] = v
        heights = [None if k is None else k * c.thickness_mm for k in counts]
        return [_tolist(p, n), [c.name] * n, counts, heights, xis, *chances]

    columns = [Column("target_p_sides", "target"), Column("coin", "coin", "text"),
               Column("count", "count", "int"), Column("height_mm", "height (mm)"),
               Column("xi", "xi = h/D"), Column("p_heads", "P(heads)"),
               Column("p_sides", "P(sides)"), Column("p_tails", "P(tails)")]
    note = (f"{_coin_words(c)}; model: {m.label}; the stack nearest each target (empty where "
            f"no stack of up to {coin_catalog.MAX_STACK_WORDS} coins reaches it)")
    if len(vals) > 1 and m.key in ("geometric", "dynamic"):
        emit(Result("coin stack", columns, [], note=note, quiet=2,
                    chunks=map(compute, vals.chunks())), fmt, quiet)
        return
    data = compute(vals.values())
    emit(Result("coin stack", columns, [], note=note, quiet=data[2], data=data), fmt, quiet)


@app.command()
def coins(fmt: FormatOpt = "table", quiet: QuietOpt = False):
    """The catalog of real coins, with their dimensions and sources.

    Examples: coin coins ;  coin coins --format csv ;  coin coins -q
    """
    check_format(fmt)
    rows = []
    for c in coin_catalog.CATALOG.values():
        rows.append((c.name, c.label, c.diameter_mm, c.thickness_mm, c.xi,
                     models.dynamic(c.xi).sides, c.source))
    columns = [Column("name", "name", "text"), Column("label", "coin", "text"),
               Column("diameter_mm", "diameter (mm)"), Column("thickness_mm", "thickness (mm)"),
               Column("xi", "xi = h/D"), Column("p_sides_dynamic", "P(sides), one coin"),
               Column("source", "source", "text")]
    emit(Result("coin coins", columns, rows, note="P(sides) of a single coin, dynamic model",
                quiet=[r[0] for r in rows]), fmt, quiet)


# --------------------------------------------------------------------------- fair


@app.command()
def fair(
    diameter: Annotated[
        str | None, typer.Option("--diameter", "-d", metavar="D", help="Diameter for the "
                                 "thickness column (default: the --coin's).")
    ] = None,
    coin: CoinOpt = "quarter",
    psi_dist: PsiDistOpt = None,
    fmt: FormatOpt = "table",
    quiet: QuietOpt = False,
):
    """The fair three-sided coin under each model, and what the other model says of it.

    Bertrand's paradox in one screen: von Neumann's geometric answer xi = 1/(2 sqrt 2) and
    the dynamic answer xi = 1/sqrt 3 disagree: they assume different ways of tossing.  Under
    a --psi-dist only the sides are 1/3; heads and tails differ.

    Examples: coin fair ;  coin fair --diameter 30 ;  coin fair --psi-dist normal:90:18
    """
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
    emit(Result(title, columns, rows, note=note, quiet=[r[1] for r in rows]), fmt, quiet)
