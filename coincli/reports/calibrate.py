"""The user's own table: ``coin fit --landing bounce FILE`` calibrates it from tosses
(:func:`fit`), and ``coin design --landing bounce --calibration CAL.json`` designs for it with
the calibration's uncertainty (:func:`design`).  ``--calibration CAL.json`` under every
bouncing command is :mod:`coincli.reports.calibrated`.

The method is :mod:`coincli.core.bounce.calibrate` (docs/calibration.md); the file is
:mod:`coincli.io.calibration`.  Nothing here imports numpy, scipy or mujoco at import time.
"""

from __future__ import annotations

import math

from coincli.errors import compute_error, usage_error
from coincli.io.table import Column

__all__ = ["fit", "design", "fit_warnings", "FIT_NAMES"]

#: what --fit may name, and the parameter each is
FIT_NAMES = {"restitution": "restitution", "friction": "friction", "psi-spread": "psi_sd_deg"}
#: the most prototypes one calibration simulates (each costs a whole design)
MAX_PROTOTYPES = 6
#: tosses at each design point for each prototype, by default (16 groups of 16)
DESIGN_TOSSES = 256
_UNITS = {"restitution": "", "friction": "", "psi_sd_deg": " deg"}


# --------------------------------------------------------------------------- coin fit, bounce


def _fit_names(text: str | None) -> tuple:
    if text is None:
        return ("restitution", "friction")
    names = []
    for part in text.split(","):
        key = part.strip().lower()
        if key not in FIT_NAMES:
            raise usage_error(f"--fit takes restitution, friction and psi-spread (comma-separated)"
                              f", got {part.strip()!r}")
        if FIT_NAMES[key] in names:
            raise usage_error(f"--fit names {key} twice")
        names.append(FIT_NAMES[key])
    return tuple(n for n in ("restitution", "friction", "psi_sd_deg") if n in names)


def _design_tosses(text: str | None) -> int:
    from coincli.core.bounce.calibrate import GROUPS

    if text is None:
        return DESIGN_TOSSES // GROUPS
    t = text.strip()
    if not (t.isascii() and t.isdigit()) or not 32 <= int(t) <= 100_000:
        raise usage_error(f"--design-tosses must be a whole number from 32 to 100000 (tosses "
                          f"of each prototype at each design point), got {text!r}")
    return -(-int(t) // GROUPS)


def _diameter_of(exps, name: str) -> float:
    """The prototypes' one diameter (m): the rows that name a coin or a diameter must agree;
    rows given as xi alone take it (the quarter's, 24.26 mm, when no row names one)."""
    from coincli.core.toss.flight import DEFAULT_DIAMETER

    given = [(e.line, e.diameter) for e in exps if e.diameter is not None]
    for line, d in given[1:]:
        if not math.isclose(d, given[0][1], rel_tol=1e-9):
            raise usage_error(f"{name}: line {given[0][0]} is a coin of diameter "
                              f"{given[0][1]:g} mm, line {line} {d:g} mm; a calibration is one "
                              "table and one coin size: one file per coin size")
    return given[0][1] / 1000 if given else DEFAULT_DIAMETER


def fit(file: str, *, fit_params: str | None = None, seed: str | None = None,
        save: str | None = None, design_tosses: str | None = None, delimiter=None,
        surface=None, restitution=None, friction=None, torsional=None, rolling=None,
        release_height=None, vx=None, u=None, omega=None, psi=None, psi_dist=None, jobs=None,
        dt=None, t_max=None, confidence="0.95", fmt: str = "table", quiet: bool = False,
        progress=None, scheduler=None, checkpoint=None, timeout=None):
    """``coin fit --landing bounce FILE``: the table's restitution and friction (and psi's
    spread) from the tosses of the prototypes in ``file``, with 95% intervals, a goodness of
    fit and the warnings of :func:`fit_warnings`; ``save``: write the calibration there.  The
    launch (``u``, ``omega``, ``psi`` or ``psi_dist``, as ``coin simulate --landing bounce``
    takes them; the hand toss for what is not given) is the prototypes' toss, recorded in the
    calibration."""
    from coincli import __version__
    from coincli.core.bounce import calibrate as bounce_calibrate
    from coincli.io.experiments import delimiter_of, experiment_columns, read_experiments_text
    from coincli.io.options import level_value, seed_value
    from coincli.limits import STANDARD_G
    from coincli.reports.calibrated import dist_dict
    from coincli.reports.executor import executor
    from coincli.reports.launch import HAND, U_MAX, bounce_launch, no_progress, reach
    from coincli.reports.physics import bounce_physics, check_coin, check_landing

    names = _fit_names(fit_params)
    if "psi_sd_deg" in names and (psi is not None or psi_dist is not None):
        raise usage_error("--psi and --psi-dist cannot go with --fit psi-spread: the spread of "
                          "psi about 90 deg is what it estimates")
    clash = [f"--{n}" for n in ("restitution", "friction")
             if n in names and {"restitution": restitution, "friction": friction}[n] is not None]
    if clash:
        raise usage_error(f"{', '.join(clash)} cannot go with --fit {','.join(names)}: a fitted "
                          "parameter is estimated, not given")
    conf = level_value(confidence, "--confidence")
    per_group = _design_tosses(design_tosses)
    # the fixed values: the surface's (default wood) for the parameters not fitted
    name0 = surface if surface is not None or (restitution is not None
                                               and friction is not None) else "wood"
    p = bounce_physics(surface=name0, restitution=restitution, friction=friction,
                       torsional=torsional, rolling=rolling, height=release_height, vx=vx,
                       jobs=jobs, dt=dt, t_max=t_max, scheduler=scheduler,
                       checkpoint=checkpoint, timeout=timeout)
    if save is not None:
        from coincli.io.files import refuse_unwritable

        refuse_unwritable(save, "--save")
        if checkpoint is not None and _same_file(save, checkpoint):
            raise usage_error(f"--save and --checkpoint name one file ({save}): the "
                              "calibration would overwrite the record of its own tosses; give "
                              "each its own path")
    sep = None
    if delimiter is not None:
        try:
            sep = delimiter_of(delimiter)
        except ValueError as exc:
            raise usage_error(f"--{exc}") from None
    text, name = read_experiments_text(file)
    exps = experiment_columns(text, name, sep, caught=False)  # a caught coin met no table
    if len(exps) > MAX_PROTOTYPES:
        raise usage_error(f"{name}: {len(exps)} prototypes; a calibration takes at most "
                          f"{MAX_PROTOTYPES} (each is simulated at every design point)")
    dia = _diameter_of(exps, name)
    for e in exps:
        try:
            check_coin(p, e.xi, dia)
        except Exception as exc:  # an InputError naming --xi: say the line instead
            raise usage_error(f"{name} line {e.line}: the prototype {e.label} is outside the "
                              f"engine's limits ({str(exc).split(' (')[0]})") from None
    u_spec, w_spec, psi_spec, labels = bounce_launch(psi, psi_dist, u, omega)
    if getattr(psi_spec, "kind", None) == "density" and str(psi_spec).startswith("table:"):
        raise usage_error(f"--psi-dist {psi_dist.strip()}: a calibration records its launch, "
                          "and a table of psi is a file it cannot hold; give uniform, "
                          "uniform:LOW:HIGH, cosine or normal:MEAN:SD")
    for e in exps:
        check_landing(p, u_top=reach(u_spec, U_MAX), g=STANDARD_G, xi=e.xi, dia=dia,
                      u_text=u or HAND["u"])
    data = [(e.counts.heads, e.counts.sides, e.counts.tails, e.counts.n) for e in exps]
    seed_v = seed_value(seed)
    fixed = {"u": u_spec, "omega": w_spec, "psi": psi_spec,
             "torsional": p.surface.torsional, "rolling": p.surface.rolling,
             "height": p.height, "vx": p.vx, "diameter": dia, "dt": p.dt, "t_max": p.t_max}
    if "restitution" not in names:
        fixed["restitution"] = p.surface.restitution
    if "friction" not in names:
        fixed["friction"] = p.surface.friction
    points = bounce_calibrate.design_points(len(names), 4 if len(names) == 2 else None)
    groups = bounce_calibrate.GROUPS
    planned = len(exps) * len(points) * per_group * groups
    # the design's tosses on the local pool, a cluster (--scheduler), from a --checkpoint
    with executor(p, "coin fit --landing bounce", **{
            "--seed": seed_v, "--fit": ",".join(names), "--design-tosses": per_group * groups,
            "FILE's prototypes (xi)": [e.xi for e in exps], "--diameter": dia,
            "launch": labels}) as run, \
            (progress or no_progress)() as tick:
        try:
            counts = bounce_calibrate.run_design(
                [e.xi for e in exps], names, points, seed=seed_v, per_group=per_group,
                fixed=fixed, jobs=p.jobs, simulate=_simulate, executor=run,
                progress=lambda d, t: tick(d * per_group * groups, planned))
        except ValueError as exc:
            raise usage_error(str(exc)) from None
    try:
        f = bounce_calibrate.fit_table(names, points, counts, data, level=conf)
    except (ValueError, ArithmeticError) as exc:
        raise compute_error(f"the calibration cannot be computed: {exc}") from None
    unsettled = int(counts[..., 3].sum())
    cal = {
        "format": "coin-calibration", "version": 1, "coin_version": __version__,
        "seed": seed_v, "fitted": list(names), "method": bounce_calibrate.METHOD, "level": conf,
        "parameters": {n: {"estimate": f.estimate[n], "low": f.low[n], "high": f.high[n],
                           "low_data_only": f.data_low[n], "high_data_only": f.data_high[n],
                           "surface_share": f.surface_share[n], "at_edge": f.at_edge[n],
                           "range": list(bounce_calibrate.RANGES[n])} for n in names},
        "coordinates": [("ln " if n == "friction" else "") + n + " scaled to [-1, 1] over its "
                        "range" for n in names],
        "covariance": f.covariance,
        "profile": {n: {"values": v, "q_rise": d} for n, (v, d) in f.profile.items()},
        "goodness_of_fit": {"statistic": f.statistic, "df": f.df, "p_value": f.p_value,
                            "deviance": f.deviance},
        "surface": {"design_points": [list(pt) for pt in points],
                    "degree": bounce_calibrate.default_degree(len(names)),
                    "groups": bounce_calibrate.GROUPS, "tosses_per_group": per_group,
                    "coefficients": [s.coef.tolist() for s in f.surfaces],
                    "deviance": [s.deviance for s in f.surfaces],
                    "df": [s.df for s in f.surfaces],
                    "lack_of_fit_tau2": list(f.tau2),
                    "counts": counts.tolist(), "unsettled": unsettled},
        "launch": {"u": dist_dict(fixed["u"]), "omega": dist_dict(fixed["omega"]),
                   "psi": dist_dict(psi_spec), "text": labels,
                   "release_height_m": dist_dict(p.height),
                   "vx_ms": dist_dict(p.vx), "dt": p.dt, "t_max": p.t_max},
        "fixed": {k: fixed[k] for k in ("torsional", "rolling", "restitution", "friction")
                  if k in fixed},
        "diameter_mm": dia * 1000,
        "data": [{"line": e.line, "label": e.label, "xi": e.xi, "heads": e.counts.heads,
                  "sides": e.counts.sides, "tails": e.counts.tails, "n": e.counts.n}
                 for e in exps],
        "predicted": [list(q) for q in f.predicted],
    }
    if save is not None:
        from coincli.io.calibration import save as save_cal
        from coincli.io.files import FileKindError

        try:
            save_cal(save, cal)
        except FileKindError as exc:
            raise usage_error(f"--save: {exc}") from None
        except OSError as exc:
            raise compute_error(f"cannot write {save!r}: {exc.strerror or exc}") from None
    return _fit_result(f, cal, exps, name, p, points, per_group, unsettled, save)


def _simulate(xi, params, n, seed, stream, kw):
    """:func:`coincli.core.bounce.calibrate.engine_simulate` with the fixed surface values."""
    from coincli.core.bounce.calibrate import engine_simulate

    kw = dict(kw)
    params = dict(params)
    for k in ("restitution", "friction"):
        if k in kw:
            params[k] = kw.pop(k)
    return engine_simulate(xi, params, n, seed, stream, kw)


def _same_file(a: str, b: str) -> bool:
    """Whether two paths name one file (links followed; the file need not exist yet)."""
    import os

    return os.path.realpath(a) == os.path.realpath(b)


def _fit_result(f, cal, exps, name, p, points, per_group, unsettled, save):
    from coincli.core.bounce.calibrate import GROUPS, METHOD
    from coincli.reports.bounce import DesignResult, dist_text
    from coincli.reports.calibrated import launch_text

    cols, row = [], []
    for n in ("restitution", "friction", "psi_sd_deg"):
        if n in f.names:
            cols += [Column(n, n.replace("_deg", " (deg)")), Column(f"{n}_low", "95% low"),
                     Column(f"{n}_high", "95% high")]
            row += [f.estimate[n], f.low[n], f.high[n]]
        elif n != "psi_sd_deg":
            cols += [Column(n, f"{n} (fixed)")]
            row += [cal["fixed"][n]]
    sims = len(exps) * len(points) * per_group * GROUPS
    cols += [Column("p_value", "fit p-value"), Column("statistic", "Q (chi-square)"),
             Column("df", "df", "int"), Column("deviance", "deviance"),
             Column("pinned", "pinned by the data", "text"),
             Column("prototypes", "prototypes", "int"), Column("tosses", "your tosses", "int"),
             Column("simulated", "simulated tosses", "int"),
             Column("design_points", "design points", "int"), Column("method", "method", "text"),
             Column("seed", "seed", "int")]
    row += [f.p_value if math.isfinite(f.p_value) else None, f.statistic,
            f.df if f.df >= 0 else None, f.deviance,
            ",".join(f.pinned) or "none", len(exps), sum(e.counts.n for e in exps), sims,
            len(points), METHOD, cal["seed"]]
    per = "; ".join(
        f"{e.label} (xi = {e.xi:.4g}): observed "
        + (f"{e.counts.heads}/{e.counts.sides}/{e.counts.tails}" if e.counts.heads is not None
           else f"{e.counts.sides} sides of {e.counts.n}")
        + f", fitted {q[0]:.3f}/{q[1]:.3f}/{q[2]:.3f}"
        for e, q in zip(exps, f.predicted, strict=True))
    shares = ", ".join(f"{n} {f.surface_share[n]:.0%}" for n in f.names)
    note = (f"Your table, calibrated from {name} (heads/sides/tails, observed against fitted: "
            f"{per}).  Simulated table (MuJoCo): {sims} tosses ({unsettled} unsettled, left "
            f"out), seed {cal['seed']}: each prototype at {len(points)} designed tables, the "
            f"same {per_group * GROUPS} launches at each (common random numbers, {GROUPS} "
            f"groups); the launch: {launch_text(cal)}; D = {cal['diameter_mm']:g} mm, "
            f"surface {dist_text(p.height, 'mm', 1000)} below the launch plane, torsional "
            f"{p.surface.torsional * 1000:g} mm, rolling {p.surface.rolling * 1000:g} mm, "
            f"dt = {p.dt:g} s.  Method: a "
            + ("cubic" if len(f.names) <= 2 else "quadratic")
            + " multinomial logit fitted to the simulated counts of each prototype; the estimate "
            "minimizes Q, the chi-square of your counts against it with the surface's own "
            "variance (a jackknife over the launch groups) and its lack of fit ("
            + ", ".join(f"deviance {s.deviance:.1f} on {s.df} df" for s in f.surfaces)
            + ", carried as extra variance) added; 95% intervals where Q's "
            "profile rises by 3.84; "
            + (f"the fit p-value is Q's on {f.df} df" if f.df > 0 else
               "no df is left for a test of fit (as many parameters as counts, or more)")
            + f".  Share of each interval's width due to the simulation: {shares} "
            "(more --design-tosses narrows it).  docs/calibration.md has the method, its "
            "assumptions and its round trip on the engine, where these 95% intervals held "
            "the truth in 20 of 20 tables (restitution) and 19 of 20 (friction), 1000 tosses "
            "a prototype."
            + (f"  Saved: {save}." if save else "  --save CAL.json keeps it for "
               "--calibration."))
    return DesignResult("coin fit --landing bounce", cols, [tuple(row)], note,
                        quiet=[f.estimate[n] for n in f.names], vertical=True,
                        warning=fit_warnings(f, exps))


def fit_warnings(f, exps) -> str | None:
    """What the user must hear: a rejected model, parameters the data do not pin (with the
    curve of equally good tables), an estimate at the end of the designed range."""
    out = []
    if math.isfinite(f.p_value) and f.p_value < 0.05:
        out.append(f"the simulated table does not fit your counts (p = {f.p_value:.2g}): the "
                   "model is rejected; its numbers are the nearest table, not yours")
    elif not math.isfinite(f.p_value) and f.reach_p < 0.05:
        out.append(f"no table in the designed range gives your counts (Q = {f.statistic:.4g} at "
                   f"the nearest; a table that gives them leaves a chi-square on "
                   f"{f.df + len(f.names)} df, p <= {f.reach_p:.2g}): the model is rejected; its "
                   "numbers are the nearest table, not yours")
    elif not math.isfinite(f.p_value):
        out.append("no test of fit: as many parameters as independent counts (toss more "
                   "prototypes)")
    loose = [n for n in f.names if n not in f.pinned]
    if loose:
        what = " and ".join(loose)
        line = (f"your counts do not pin {what} ({len(exps)} prototype"
                f"{'' if len(exps) == 1 else 's'}, {len(f.names)} parameters)")
        if f.ridge and len(f.names) >= 2:
            pts = ", ".join("(" + ", ".join(f"{n} {v:.3g}" for n, v in zip(f.names, r,
                                                                            strict=True)) + ")"
                            for r in f.ridge)
            line += (f"; these tables fit them equally well (within the 95% region): {pts}; "
                     f"what the counts pin is the chances of the prototype"
                     f"{'' if len(exps) == 1 else 's'} tossed; toss another prototype (another "
                     "xi) to tell the parameters apart")
        out.append(line)
    edge = [f"{n} at the {'low' if f.at_edge[n] == 'low' else 'high'} end of its range"
            for n in f.names if f.at_edge[n] in ("low", "high") and n in f.pinned]
    if edge:
        out.append("the interval reaches the designed range's end (" + ", ".join(edge)
                   + "): the table may lie beyond it")
    return "; ".join(out) if out else None


# --------------------------------------------------------------------------- coin design


def design(p, *, targets, seed, tol, max_tosses, time_limit, given, diameter, g, progress=None,
           psi=None):
    """``coin design --landing bounce --calibration CAL.json``: the design on the calibrated
    table (its estimate), then the calibration's uncertainty carried to each answer: the
    chance of a side is simulated at the answer's xi on tables one standard deviation either
    side of the estimate along each fitted parameter (the same launches for all: common
    random numbers), its probit slope per parameter read off, and the variance of ln xi from
    the calibration's covariance (delta method) added to the simulation's.  ``given``: the
    launch options typed (u, omega, psi), which must agree with the calibration's.  ``psi``: a
    launch's psi (a Dist) that replaces the calibration's (``coin fit --design --calibration``:
    each tosser's own spread); a fitted psi-spread of the calibration is then not varied."""
    import numpy as np
    from scipy.special import ndtri
    from scipy.stats import norm

    from coincli.core.bounce import calibrate as bounce_calibrate
    from coincli.core.bounce import design as bounce_design
    from coincli.core.bounce import runs
    from coincli.reports.bounce import DesignResult
    from coincli.reports.calibrated import check_launch, launch_of
    from coincli.reports.launch import core_call, no_progress
    from coincli.reports.physics import engine

    path, cal = p.calibration
    check_launch(path, cal, given)
    u_spec, w_spec, psi_spec = launch_of(cal)
    if psi is not None:
        psi_spec = psi
    warn = []
    if not math.isclose(diameter * 1000, cal["diameter_mm"], rel_tol=1e-6):
        warn.append(f"the calibration's prototypes were {cal['diameter_mm']:g} mm across, this "
                    f"design is for {diameter * 1000:g} mm: the table's parameters carry over, "
                    "the fit's check on your counts does not")
    kw = {"u": u_spec, "omega": w_spec, "psi": psi_spec, "landing": "bounce", "height": p.height,
          "vx": p.vx, "diameter": diameter, "g": g, "dt": p.dt, "t_max": p.t_max, "jobs": p.jobs}
    names = cal["fitted"]
    est = {n: cal["parameters"][n]["estimate"] for n in names}
    cov = np.array(cal["covariance"], dtype=float)
    u_hat = np.array([bounce_calibrate.to_coords(n, est[n]) for n in names])
    sd = np.sqrt(np.clip(np.diag(cov), 0.0, None))
    n_b = max(32, min(400, int(max_tosses) // 4))  # each of 2 x parameters tables
    varied = sum(psi is None or n != "psi_sd_deg" for n in names)  # parameters varied
    with (progress or no_progress)() as tick:
        r = core_call(bounce_design.design, targets, seed=seed, tol=tol, max_tosses=max_tosses,
                      time_limit=time_limit, surf=p.surface, progress=tick, **kw)
        rows = []
        for ti, (t, x, lo, hi, f) in enumerate(zip(r.targets, r.xi, r.low, r.high, r.fits,
                                                   strict=True)):
            slope = np.zeros(len(names))
            slope_var = np.zeros(len(names))
            for i, _n in enumerate(names):
                if psi is not None and _n == "psi_sd_deg":
                    continue  # the launch's psi is given, not the calibration's
                ends = []
                for sgn in (-1.0, 1.0):
                    u = u_hat.copy()
                    u[i] = float(np.clip(u_hat[i] + sgn * max(sd[i], 0.05), -1.0, 1.0))
                    params = {m: bounce_calibrate.from_coords(m, float(v))
                              for m, v in zip(names, u, strict=True)}
                    surf = engine().Surface(params.get("restitution", p.surface.restitution),
                                            params.get("friction", p.surface.friction),
                                            p.surface.torsional, p.surface.rolling, "calibrated")
                    kw_i = dict(kw)
                    if "psi_sd_deg" in params:
                        from coincli.core.toss.launch import Dist

                        kw_i["psi"] = Dist("normal", math.pi / 2,
                                           math.radians(params["psi_sd_deg"]), 0.0, math.pi)
                    sim = core_call(runs.simulate, n_b, seed, xi=x, surf=surf,
                                    stream=(90, ti), **kw_i)
                    k, m = sim.counts[1], sim.settled
                    q = min(max((k + 0.5) / (m + 1.0), 1e-4), 1 - 1e-4)
                    ends.append((float(u[i]), float(ndtri(q)),
                                 q * (1 - q) / (max(m, 1) * float(norm.pdf(ndtri(q))) ** 2)))
                (u0, z0, v0), (u1, z1, v1) = ends
                if u1 > u0:
                    slope[i] = (z1 - z0) / (u1 - u0)
                    slope_var[i] = (v0 + v1) / (u1 - u0) ** 2
            b = f.beta  # d probit / d ln xi of the local fit
            grad = -slope / b
            var_cal = float(grad @ cov @ grad + np.sum(slope_var * np.diag(cov)) / b ** 2)
            z = float(norm.ppf(0.975))
            var_sim = ((math.log(hi) - math.log(lo)) / (2 * z)) ** 2
            tot = math.sqrt(var_sim + var_cal)
            xlo, xhi = x * math.exp(-z * tot), x * math.exp(z * tot)
            dominant = "calibration" if var_cal > var_sim else "simulation"
            dia_mm = diameter * 1000
            rows.append((t, x, xlo, xhi, dia_mm * x, dia_mm * xlo, dia_mm * xhi,
                         math.sqrt(var_sim), math.sqrt(var_cal), dominant,
                         float(f.p_sides(x)), f.p_value,
                         r.tosses + 2 * varied * n_b,
                         r.seed))
    from coincli.reports.bounce import design_columns

    columns = [
        *design_columns(diameter * 1000),
        Column("sd_ln_xi_simulation", "sd of ln xi: simulation"),
        Column("sd_ln_xi_calibration", "sd of ln xi: calibration"),
        Column("dominant", "dominant", "text"),
        Column("fitted_p_sides", "fitted P(sides)"), Column("fit_p_value", "fit p-value"),
        Column("tosses", "tosses", "int"), Column("seed", "seed", "int"),
    ]
    tab = ", ".join(f"{n} {cal['parameters'][n]['estimate']:.3g} "
                    f"[{cal['parameters'][n]['low']:.3g}, {cal['parameters'][n]['high']:.3g}]"
                    for n in names)
    note = (f"Your table, calibrated ({path}: {tab}; seed {cal['seed']}).  Simulated (MuJoCo): "
            f"the design on the calibrated table, {r.tosses} tosses at {len(r.fit.points)} "
            f"aspect ratios, seed {r.seed}; then at each answer {n_b} tosses on tables one "
            "standard deviation either side of the calibration along each parameter (the "
            "same launches: common random numbers), whose probit slopes carry the "
            "calibration's covariance to ln xi (delta method).  The intervals hold both: "
            "the simulation's (the design's) and the calibration's, added in variance; "
            "'dominant' says which is larger.  Toss the design and check it with coin check.")
    if warn:
        note += "  " + "; ".join(warn) + "."
    return DesignResult("coin design --landing bounce --calibration", columns, rows, note,
                        quiet=[row[1] for row in rows], vertical=len(rows) == 1,
                        warning="; ".join(warn) if warn else (
                            None if r.met else "the design on the calibrated table stopped "
                            "before --tol"))
