"""What ``coin fit FILE`` prints: a file of experiments against the models.

:func:`fit` checks every experiment as :func:`coincli.reports.check.check` does, then compares
the models across experiments and fits the spread of psi; with caught flips, each tosser's
fair coin (``--design``), on a calibrated table too (``--calibration``).  ``--landing bounce``
calibrates a table instead (:func:`coincli.reports.calibrate.fit`).  The tables are
:mod:`coincli.reports.check_tables`'; the file is read by :mod:`coincli.io.experiments`.
numpy and scipy load when a report runs, never at import.
"""

from __future__ import annotations

import math

from coincli.errors import NotComputable, compute_error, shown, usage_error
from coincli.io import grammar as parse
from coincli.io.experiments import experiment_columns, file_name, read_experiments_text
from coincli.io.options import level_value
from coincli.io.table import Column, Result, check_format
from coincli.reports.check_tables import (
    CAUGHT_FIT_COLUMNS,
    CAUGHT_MACHINE_COLUMNS,
    FIT_COLUMNS,
    bound_note,
    chunked,
    deg_text,
    degrees,
    machine_chunks,
    observed_columns,
    observed_result,
    plural,
    psi_densities_by_spec,
    test_note,
    tests_result,
    warn_thick,
)

__all__ = ["fit", "FIT_COLUMNS"]


def fit(file: str, *, psi_dist: str | None = None, no_spread: bool = False,
        delimiter: str | None = None, design: str | None = None, alpha: str = "0.05",
        confidence: str = "0.95", landing: str = "catch", fit: str | None = None,
        seed: str | None = None, save: str | None = None, design_tosses: str | None = None,
        surface: str | None = None, restitution: str | None = None,
        friction: str | None = None, torsional: str | None = None, rolling: str | None = None,
        release_height: str | None = None, vx: str | None = None, u: str | None = None,
        omega: str | None = None, psi: str | None = None, jobs: str | None = None,
        dt: str | None = None, t_max: str | None = None, scheduler: str | None = None,
        checkpoint: str | None = None, timeout: str | None = None,
        calibration: str | None = None, fmt: str = "table", quiet: bool = False,
        progress=None):
    """What ``coin fit FILE`` prints: every experiment of ``file`` checked as :func:`check`
    does, then the models compared across experiments (log-likelihood, AIC, the paper's sum of
    squared errors of the side frequencies) and the maximum-likelihood spread of psi with its
    profile-likelihood interval.

    ``file`` is a path, or ``-`` for standard input.  Returns three human tables (a list) for
    ``fmt="table"``, else the one machine :class:`Result`, streamed by chunks (under ``quiet``:
    the fitted spread in degrees).  Raises InputError for a wrong input or file, NotComputable
    when the fit cannot be computed.

    ``landing="bounce"``: the table is calibrated instead (:func:`coincli.reports.calibrate.fit`,
    with ``fit``, ``seed``, ``save``, ``design_tosses``, the surface and launch options and
    where the design's tosses run, ``scheduler``, ``checkpoint``, ``timeout``; ``progress()``: a
    progress bar, or None).

    ``design`` with ``calibration`` (a calibration file): each tosser's coin is designed on the
    calibrated table too (:func:`_table_designs`: a bouncing design per tosser, at most
    ``design_tosses`` tosses each, ``seed``, ``jobs``).
    """
    from coincli.reports.landing import landing_of

    bounce = {"--fit": fit, "--seed": seed, "--save": save, "--design-tosses": design_tosses,
              "--surface": surface, "--restitution": restitution, "--friction": friction,
              "--torsional": torsional, "--rolling": rolling, "--release-height": release_height,
              "--vx": vx, "--u": u, "--omega": omega, "--psi": psi, "--jobs": jobs, "--dt": dt,
              "--t-max": t_max, "--scheduler": scheduler, "--checkpoint": checkpoint,
              "--timeout": timeout}
    if landing_of(landing) == "bounce":
        from coincli.reports import calibrate

        if calibration is not None:
            raise usage_error("--calibration goes with --design (each tosser's coin on your "
                              "calibrated table); --landing bounce fits a calibration (--save)")
        if no_spread or alpha != "0.05" or design is not None:
            raise usage_error("--no-spread, --design and --alpha go with the models (no "
                              "--landing); --landing bounce calibrates a table")
        return calibrate.fit(file, fit_params=fit, seed=seed, save=save,
                             design_tosses=design_tosses, delimiter=delimiter, surface=surface,
                             restitution=restitution, friction=friction, torsional=torsional,
                             rolling=rolling, release_height=release_height, vx=vx, u=u,
                             omega=omega, psi=psi, psi_dist=psi_dist, jobs=jobs, dt=dt,
                             t_max=t_max, confidence=confidence, fmt=fmt, quiet=quiet,
                             progress=progress, scheduler=scheduler, checkpoint=checkpoint,
                             timeout=timeout)
    with_table = ("--seed", "--design-tosses", "--jobs", "--dt", "--t-max", "--release-height",
                  "--vx", "--surface", "--restitution", "--friction", "--torsional", "--rolling")
    extra = [k for k, v in bounce.items() if v is not None
             and (calibration is None or k not in with_table)]
    if extra:
        raise usage_error(f"{', '.join(extra)} go{'es' if len(extra) == 1 else ''} with "
                          "--landing bounce" + (" (or --seed, --design-tosses and --jobs with "
                                                "--calibration)" if calibration else ""))
    physics = None
    if calibration is not None:
        if design is None:
            raise usage_error("--calibration goes with --design P: each tosser's coin, "
                              "designed on your calibrated table too")
        physics = _table_physics(calibration, surface=surface, restitution=restitution,
                                 friction=friction, torsional=torsional, rolling=rolling,
                                 release_height=release_height, vx=vx, jobs=jobs, dt=dt,
                                 t_max=t_max)
    from coincli.core.stats import fit as stats_fit
    from coincli.io.experiments import delimiter_of

    fmt = check_format(fmt)
    a = level_value(alpha, "--alpha")
    conf = level_value(confidence, "--confidence")
    dens = psi_densities_by_spec(psi_dist)
    if quiet and no_spread:
        raise usage_error("--quiet prints the fitted spread of psi; it cannot go with --no-spread")
    try:
        sep = None if delimiter is None else delimiter_of(delimiter)
    except ValueError as exc:
        raise usage_error(f"--{exc}") from None
    p_design = _design(design)
    text, name = read_experiments_text(file)
    exps = experiment_columns(text, name, sep)
    del text
    is_caught = exps.cc.caught
    if is_caught.any():
        from coincli.core.stats.caught import CAUGHT_XI_LIMIT

        over = (is_caught & (exps.xi > CAUGHT_XI_LIMIT)).nonzero()[0]
        if len(over):
            first = exps[int(over[0])]
            warn_thick(first.xi, f"{file_name(name)} line {first.line}"
                        + (f" and {len(over) - 1} more rows" if len(over) > 1 else "") + ": ")
    elif p_design is not None:
        raise usage_error("--design gives each tosser's fair coin from caught flips (same and "
                          f"different); {file_name(name)} has no caught rows")
    try:
        res = stats_fit.fit(exps, dens, confidence=conf, alpha=a, spread=not no_spread,
                        design=p_design)
    except ValueError as exc:
        raise compute_error(str(exc)) from None
    sp = res.spread
    if quiet:
        return Result("coin fit", FIT_COLUMNS, [], quiet=degrees(sp.sigma))
    table = None
    if physics is not None:
        table = _table_designs(physics, res.caught, exps, p_design, seed=seed,
                               design_tosses=design_tosses, progress=progress)
    lines = exps.line
    n_total = _total(exps.cc.n)
    cf = res.caught
    if fmt == "table":
        out = [
            observed_result(f"coin fit: {name}, "
                             f"{plural(len(exps), 'experiment', 'experiments')}, "
                             f"{plural(n_total, 'toss', 'tosses')}", res.rows, lines, conf),
            tests_result("models, each experiment", res.rows, lines, test_note(res.rows)),
            _comparison_result(res, conf),
        ]
        if cf is not None:
            out.append(_tossers_result(exps, cf, lines, conf, p_design, table))
        return out
    spread_cells = ([degrees(sp.sigma), degrees(sp.low), degrees(sp.high)] if sp is not None
                    else [None] * 3)
    models = res.rows.models

    def extra(k):
        return [None] * 4 + (spread_cells if models[k] == stats_fit.SPREAD_MODEL else [None] * 3)

    blank = [None] * len(observed_columns())
    tail = []
    for m in res.models:
        cells = ["model", None, "all", None, n_total, None, None, None, m.model,
                 None, None, None, None, None, None, None, None, None, None, None,
                 m.log_likelihood, None, *blank, m.n_params, m.aic,
                 None if math.isnan(m.delta_aic) else m.delta_aic, m.sse_sides]
        cells += spread_cells if m.model == stats_fit.SPREAD_MODEL else [None] * 3
        tail.append(tuple(cells))
    if cf is None:
        return Result("coin fit", FIT_COLUMNS, [],
                      chunks=machine_chunks(res.rows, lines, extra, tail))
    return _caught_fit_result(res, exps, lines, extra, tail, spread_cells, p_design, table)


def _design(text: str | None) -> float | None:
    """--design P: the chance of a side of each tosser's coin (1/3: fair three-sided)."""
    if text is None:
        return None
    try:
        v = parse.parse_probability(text, "--design")
    except ValueError:
        v = math.nan
    if not 0.0 < v < 1.0:
        raise usage_error(f"--design must be a chance of a side strictly between 0 and 1 (1/3 "
                          f"for a fair three-sided coin), got {shown(text)}")
    return v


_N_CAUGHT_FIT = len(CAUGHT_FIT_COLUMNS)


def _caught_fit_result(res, exps, lines, extra, tail, spread_cells, p_design,
                       table=None) -> Result:
    """The machine table of a fit with caught rows: every column, the caught ones last; each
    caught row's psi-spread line carries its own spread; a row of scope ``all`` the tossers'
    heterogeneity.  Each row's cells are made from arrays when its chunk is written."""
    import numpy as np

    from coincli.core.stats import fit as stats_fit

    cf = res.caught
    T = len(res.rows)
    models = res.rows.models
    M = len(models)
    k_spread = models.index(stats_fit.SPREAD_MODEL) if stats_fit.SPREAD_MODEL in models else None
    own = (cf.fits.sigma, cf.fits.low, cf.fits.high)  # radians, of the caught rows alone
    is_caught = res.rows.cc.caught
    bound = np.zeros(T, np.int8)
    bound[cf.rows] = cf.fits.at_bound
    notes = {b: bound_note(b) or None for b in (-1, 0, 1)}
    design_xi = None
    if cf.fair_xi is not None:
        design_xi = np.full(T, np.nan)
        design_xi[cf.rows] = cf.fair_xi
    base = len(FIT_COLUMNS)  # the sigma columns are the last three of FIT_COLUMNS

    def sigma_maker(c):
        pooled = spread_cells[c]

        def make(a, b):
            j0, j1 = np.searchsorted(cf.rows, [a, b]).tolist()  # the chunk's caught rows
            mine = np.full(b - a, np.nan)
            mine[cf.rows[j0:j1] - a] = np.degrees(own[c][j0:j1])
            out = []
            for caught_i, v in zip(is_caught[a:b].tolist(), mine.tolist(), strict=True):
                for k in range(M):
                    if k != k_spread:
                        out.append(None)
                    elif caught_i:
                        out.append(None if v != v else v)
                    else:
                        out.append(pooled)
            return out
        return make

    def row_cells(j):
        def make(a, b):
            if j == 0:
                return [notes[v] if k == k_spread else None for v in bound[a:b].tolist()
                        for k in range(M)]
            if design_xi is None or not 8 <= j <= 10:
                return [None] * ((b - a) * M)
            xs, cs = design_xi[a:b].tolist(), is_caught[a:b].tolist()
            if j == 8:
                cells = [p_design if c else None for c in cs]
            elif j == 9:
                cells = [x if c else None for x, c in zip(xs, cs, strict=True)]
            else:
                cells = [(None if d != d else x * d) if c else None
                         for x, c, d in zip(xs, cs, exps.diameter[a:b].tolist(), strict=True)]
            return [v for v in cells for _ in range(M)]
        return make

    caught_extra = [row_cells(j) for j in range(_N_CAUGHT_FIT)]
    table_columns = []
    if table is not None:  # each tosser's coin on the calibrated table
        table_columns = TABLE_DESIGN_COLUMNS
        for c in range(len(table_columns)):
            col = np.full(T, None, dtype=object)
            col[cf.rows] = [row[c] for row in table.rows]
            caught_extra.append(lambda a, b, col=col: [v for v in col[a:b].tolist()
                                                       for _ in range(M)])
    row_extra = {base - 3 + c: sigma_maker(c) for c in range(3)}
    n_caught = len(CAUGHT_MACHINE_COLUMNS) + _N_CAUGHT_FIT + len(table_columns)
    tail = [t + (None,) * n_caught for t in tail]
    het = cf.heterogeneity
    if het is not None:
        from coincli.core.stats.caught import HETEROGENEITY_METHOD

        n_c = _total(res.rows.cc.n[cf.rows])
        cells = ["all", None, "caught rows", None, n_c] + [None] * 3 + [stats_fit.SPREAD_MODEL]
        cells += [None] * (base - len(cells) - 3)
        cells += [degrees(het.sigma_common), None, None]
        cells += [None] * len(CAUGHT_MACHINE_COLUMNS)
        cells += [None, HETEROGENEITY_METHOD, het.statistic, het.df, het.p_value,
                  degrees(het.sigma_common), degrees(math.exp(het.mu)), het.tau, None, None, None]
        cells += [None] * len(table_columns)
        tail.append(tuple(cells))
    return Result("coin fit", FIT_COLUMNS + CAUGHT_MACHINE_COLUMNS + CAUGHT_FIT_COLUMNS
                  + table_columns, [], note="" if table is None else table.note,
                  chunks=machine_chunks(res.rows, lines, extra, tail, caught_extra,
                                         row_extra))


def _total(n) -> int:
    """The sum of an int64 array of counts, exact (a Python int: 10^5 counts of up to 2**53
    overflow int64), a block at a time."""
    return sum(sum(n[a:a + 4096].tolist()) for a in range(0, len(n), 4096))


#: the columns of each tosser's coin on a calibrated table (``coin fit --design P
#: --calibration CAL.json``), after every other column
TABLE_DESIGN_COLUMNS = [
    Column("table_design_xi", "xi on your table"),
    Column("table_design_xi_low", "95% low"),
    Column("table_design_xi_high", "95% high"),
    Column("table_design_diameter_mm", "diameter (mm)"),
    Column("table_design_thickness_mm", "thickness (mm) on your table"),
    Column("table_design_thickness_low_mm", "thickness 95% low"),
    Column("table_design_thickness_high_mm", "thickness 95% high"),
    Column("table_design_dominant", "larger uncertainty", "text"),
    Column("table_design_tosses", "tosses simulated", "int"),
    Column("table_design_seed", "seed", "int"),
]


#: the most tosses of each tosser's design on a calibrated table (``--design-tosses``)
TABLE_DESIGN_TOSSES = 2000


class _TableDesigns:
    """Each caught row's coin on the calibrated table: ``rows`` (one tuple of
    :data:`TABLE_DESIGN_COLUMNS` per caught row, in order) and the ``note`` that says how."""

    def __init__(self, rows, note):
        self.rows, self.note = rows, note


def _table_physics(calibration: str, *, release_height, **opts):
    """The calibrated table of ``--calibration`` (the surface options refused with it)."""
    from coincli.reports.physics import bounce_physics

    return bounce_physics(calibration=calibration, height=release_height, **opts)


def _table_designs(physics, cf, exps, p_design: float, *, seed, design_tosses,
                   progress=None) -> _TableDesigns:
    """Each tosser's coin with the chance of a side ``p_design`` on the calibrated table
    (:func:`coincli.reports.calibrate.design`, as ``coin design --landing bounce --calibration``
    makes it): the calibration's launch (speed and spin) with psi ~ normal(90 deg, the
    tosser's fitted sd) truncated to [0, 180] (sd 0: psi = 90 deg; inf: uniform), the row's
    diameter (else the calibration's prototypes'), at most ``design_tosses`` tosses
    (:data:`TABLE_DESIGN_TOSSES`) and no time limit, so that the seed repeats it.  Tossers of
    one spread and diameter share one design.  Its interval holds the simulation's and the
    calibration's uncertainty (added in variance), not that of the tosser's own sd."""
    from coincli.core.bounce import design as bounce_design
    from coincli.core.toss.launch import Dist
    from coincli.io.options import seed_value
    from coincli.limits import MAX_BOUNCE_TOSSES, STANDARD_G
    from coincli.reports import calibrate
    from coincli.reports.calibrated import launch_of
    from coincli.reports.launch import U_MAX, reach
    from coincli.reports.physics import bounce_tosses, check_coin, check_landing

    least = bounce_design.DESIGN_LEAST
    most = (TABLE_DESIGN_TOSSES if design_tosses is None else
            bounce_tosses(design_tosses, "--design-tosses", least, MAX_BOUNCE_TOSSES))
    seed_v = seed_value(seed)
    path, cal = physics.calibration
    u_spec = launch_of(cal)[0]
    done: dict = {}
    rows = []
    failed: list = []  # (line, why) of the tossers whose design found no answer
    for j, i in enumerate(cf.rows.tolist()):
        sigma = float(cf.fits.sigma[j])
        d = float(exps.diameter[i])
        dia_mm = float(cal["diameter_mm"]) if math.isnan(d) else d
        key = (sigma, dia_mm)
        if key not in done:
            psi = (math.pi / 2 if sigma == 0 else
                   Dist("uniform", 0.0, math.pi, 0.0, math.pi) if math.isinf(sigma) else
                   Dist("normal", math.pi / 2, sigma, 0.0, math.pi))
            dia = dia_mm / 1000
            check_coin(physics, None, dia, xi_low=min(bounce_design.DESIGN_GRID),
                       command="coin fit --design --calibration")
            check_landing(physics, u_top=reach(u_spec, U_MAX), g=STANDARD_G,
                          xi=max(bounce_design.DESIGN_GRID), dia=dia, u_text="the calibration's")
            try:
                r = calibrate.design(physics, targets=[p_design], seed=seed_v, tol=0.01,
                                     max_tosses=most, time_limit=None, diameter=dia,
                                     g=STANDARD_G, given={"u": None, "omega": None, "psi": None},
                                     progress=progress, psi=psi)
            except NotComputable as exc:  # this tosser's design only: the others stand
                failed.append((int(exps.line[i]), str(exc)))
                done[key] = (None,) * 3 + (dia_mm,) + (None,) * 4 + (0, seed_v)
            else:
                v = dict(zip((c.name for c in r.columns), r.rows[0], strict=True))
                done[key] = (v["xi"], v["xi_low"], v["xi_high"], dia_mm, v["thickness_mm"],
                             v["thickness_low_mm"], v["thickness_high_mm"], v["dominant"],
                             v["tosses"], v["seed"])
        elif done[key][0] is None:
            failed.append((int(exps.line[i]), "as the row of the same spread and diameter above"))
        rows.append(done[key])
    tab = ", ".join(f"{n} {cal['parameters'][n]['estimate']:.3g}" for n in cal["fitted"])
    note = (f"on your table: each tosser's coin with P(sides) = {p_design:.6g} designed on the "
            f"calibrated table ({path}: {tab}), simulated (MuJoCo): the calibration's launch "
            "(speed, spin) with psi ~ normal about 90 deg with the tosser's fitted sd, "
            f"truncated to [0, 180]; {len(done)} bouncing design"
            f"{'' if len(done) == 1 else 's'} (one per distinct sd and diameter), at most "
            f"{most} tosses each (--design-tosses) and more on tables either side of the "
            f"calibration, {sum(v[8] for v in done.values())} tosses in all, seed {seed_v}.  "
            "Each interval holds the "
            "simulation's and the calibration's uncertainty (delta method, added in variance; "
            "table_design_dominant says which is larger), not that of the tosser's own sd.  "
            "A row with no diameter is designed for the calibration's prototypes "
            f"({float(cal['diameter_mm']):g} mm).")
    if failed:
        note += "  No design on your table (empty table_design_ cells) for " + "; ".join(
            f"line {line}: {why}" for line, why in failed) + "."
    return _TableDesigns(rows, note)


def _tossers_result(exps, cf, lines, conf: float, p_design, table=None) -> Result:
    """The human table of the caught rows: each tosser's spread (and fair coin)."""
    from coincli.core.stats.tests import percent

    pct = percent(conf)
    cols = [Column("line", "line", "int"), Column("label", "label", "text"),
            Column("same", "same / n", "text"), Column("sigma_deg", "psi sd (deg)"),
            Column("interval", f"{pct} profile interval (deg)", "text")]
    if cf.fair_xi is not None:
        cols += [Column("design_xi", f"xi for P(sides) = {p_design:.6g}"),
                 Column("design_thickness_mm", "thickness (mm)")]
    if table is not None:
        cols += [Column("table_design_xi", "xi on your table"),
                 Column("table_interval", "95% interval", "text"),
                 Column("table_design_thickness_mm", "thickness (mm) on your table")]
    rows_of = cf.rows

    def body(a: int, b: int) -> list[tuple]:
        """Caught rows ``a`` to ``b`` (of the caught rows alone)."""
        out = []
        for j, i in enumerate(rows_of[a:b].tolist(), start=a):
            e = exps[i]
            row = [int(lines[i]), e.label, f"{e.counts.same} / {e.counts.n}",
                   degrees(float(cf.fits.sigma[j])),
                   f"{deg_text(float(cf.fits.low[j]))} to {deg_text(float(cf.fits.high[j]))}"]
            if cf.fair_xi is not None:
                x = float(cf.fair_xi[j])
                row += [x, None if e.diameter is None else x * e.diameter]
            if table is not None:
                t = table.rows[j]
                row += [t[0], f"{t[1]:.4g} to {t[2]:.4g}", t[4]]
            out.append(tuple(row))
        return out

    notes = ["caught flips (faces only): each row is one tosser, fitted alone: psi ~ normal "
             "about 90 deg truncated to [0, 180], the chance of the same side "
             "P(H) / (P(H) + P(T)) (the start side as heads); a row at a bound is noted in "
             "the machine output (sigma_note)."]
    bounds = int((cf.fits.at_bound != 0).sum())
    if bounds:
        notes.append(f"{plural(bounds, 'row has', 'rows have')} the estimate at a bound "
                     "(sd 0: no more same-side flips than a Keller flip's 1/2; inf: as many as "
                     "psi uniform gives, or more).")
    het = cf.heterogeneity
    if het is not None:
        notes.append(
            f"one spread for all tossers: sd {deg_text(het.sigma_common)} deg; do they differ? "
            f"likelihood-ratio test of one spread per tosser against one for all: "
            f"{het.statistic:.4g} on {het.df} df, p = {het.p_value:.3g}; random effects "
            f"(log sd ~ normal, maximum marginal likelihood): median tosser "
            f"{deg_text(math.exp(het.mu))} deg, sd of log sd between tossers {het.tau:.3g} "
            f"(a factor of {math.exp(het.tau):.3g}).")
    if cf.fair_xi is not None:
        notes.append(f"design: the xi whose chance of a side is {p_design:.6g} under each "
                     "tosser's fitted spread (the paper's model, no bounce); the thickness for "
                     "the row's diameter when the row gives one (coin or diameter).")
    if table is not None:
        notes.append(table.note)
    return chunked("each tosser (caught rows)", cols, body, len(rows_of), 1, "\n".join(notes))


def _comparison_result(res, conf: float) -> Result:
    cols = [Column("model", "model", "text"), Column("n_params", "fitted parameters", "int"),
            Column("log_likelihood", "log-likelihood"), Column("aic", "AIC"),
            Column("delta_aic", "delta AIC"), Column("sse_sides", "SSE of side frequencies")]
    body = [(m.model, m.n_params, m.log_likelihood, m.aic, m.delta_aic, m.sse_sides)
            for m in res.models]
    sp = res.spread
    notes = ["AIC = 2k - 2 log L (lower is better; a difference below 2 is no real preference); "
             "SSE = sum over experiments of (observed - predicted side frequency)^2, as in "
             "Sec. IV of the paper."]
    if sp is not None:
        pieces = ", ".join(f"{deg_text(lo)} to {deg_text(hi)}" for lo, hi in sp.pieces)
        notes.append(
            f"psi-spread: psi ~ normal about 90 deg truncated to [0, 180]; maximum-likelihood sd "
            f"{deg_text(sp.sigma)} deg, {100 * conf:g}% profile-likelihood interval {pieces} deg"
            + (f" ({sp.note})" if sp.note else "") + "."
        )
    return Result("model comparison, all experiments", cols, body, note="\n".join(notes))
