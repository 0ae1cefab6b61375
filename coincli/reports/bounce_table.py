"""``coin table --landing bounce``: the chances of heads, sides and tails on a table, simulated
(MuJoCo) for every coin and every table of a parameter study, a row a cell.

The cells are the coins given (``--xi``, ``--coin``/``--count``, ... as ``coin table`` takes
them) times the values of ``--restitution`` times those of ``--friction`` (each a value, a list
or a range; one of each by default: the ``--surface`` preset's), in that order: the coins
outermost, friction innermost.  Every cell tosses the same seeded launches (common random
numbers: block ``k`` of the run draws from ``(seed, k)`` whatever the cell), so the differences
between neighbouring cells are far less noisy than the chances themselves, and the same seed
gives the same bytes for any ``--jobs``.  Rows are computed as they are written (a streamed
:class:`coincli.io.table.Result`), so a long study prints each cell when it completes.
"""

from __future__ import annotations

import math
from dataclasses import replace

from coincli import limits as L
from coincli.errors import usage_error
from coincli.io import grammar as parse
from coincli.io import options
from coincli.io.table import Column, Result
from coincli.limits import MAX_BOUNCE_TOSSES, STANDARD_G
from coincli.reports import bounce as bounce_report
from coincli.reports.calibrated import bounce_launch_for
from coincli.reports.launch import U_MAX, bounded_number, core_call, reach
from coincli.reports.physics import bounce_physics, check_coin, check_landing

#: tosses a cell when -n is not given
DEFAULT_TOSSES = 1000
#: the most cells (coins x restitutions x frictions) one command simulates
MAX_CELLS = 1000
#: the most tosses of a whole study (cells x -n): a ``coin simulate --landing bounce`` run's
MAX_STUDY_TOSSES = MAX_BOUNCE_TOSSES

OUTCOMES = ("heads", "sides", "tails")

COLUMNS = [
    Column("xi", "xi = h/D"), Column("diameter_mm", "D (mm)"),
    Column("surface", "surface", "text"), Column("restitution", "restitution"),
    Column("friction", "friction"),
    *(Column(f"p_{o}{end}", f"P({o}){head}") for o in OUTCOMES
      for end, head in (("", ""), ("_low", " 95% low"), ("_high", " 95% high"))),
    Column("settled", "settled", "int"), Column("unsettled", "unsettled", "int"),
    Column("seed", "seed", "int"),
]
_STACKED = [Column("coin", "coin", "text"), Column("count", "count", "int")]


def _coefficients(text: str | None, what: str, lo: float, hi: float) -> list[float] | None:
    """A value, a list or a range of a surface coefficient, each in [lo, hi]."""
    if text is None:
        return None
    try:
        return parse.parse_values(text, what, lambda t, w: bounded_number(t, w, lo, hi),
                                  max_rows=MAX_CELLS)
    except ValueError as exc:
        raise usage_error(str(exc)) from None


def table(*, xi=None, coin=None, count=None, quarters=None, diameter=None, thickness=None,
          psi=None, psi_dist=None, u=None, omega=None, tosses=None, seed=None, surface=None,
          restitution=None, friction=None, torsional=None, rolling=None, release_height=None,
          vx=None, jobs=None, dt=None, t_max=None, calibration=None, scheduler=None,
          checkpoint=None, timeout=None, wide=False, progress=None) -> Result:
    """``coin table --landing bounce``: one row per coin and table (restitution, friction),
    each the frequencies of heads, sides and tails among ``tosses`` simulated tosses that
    settled, with 95% Wilson intervals, the unsettled count and the seed.  ``wide``: one row
    per coin, the tables side by side (:func:`widen`).  ``progress()``: a progress bar
    (:class:`coincli.render.progress.ProgressBar`) ticked with the tosses done, or None."""
    es = _coefficients(restitution, "--restitution", L.BOUNCE_RESTITUTION_MIN,
                       L.BOUNCE_RESTITUTION_MAX)
    mus = _coefficients(friction, "--friction", 0.0, L.BOUNCE_FRICTION_MAX)
    physics = bounce_physics(
        surface=surface, restitution=None if es is None else repr(es[0]),
        friction=None if mus is None else repr(mus[0]), torsional=torsional, rolling=rolling,
        height=release_height, vx=vx, jobs=jobs, dt=dt, t_max=t_max, calibration=calibration,
        scheduler=scheduler, checkpoint=checkpoint, timeout=timeout)
    base = physics.surface
    es = es or [base.restitution]
    mus = mus or [base.friction]
    if psi is not None and "," in psi:
        raise usage_error(f"--psi with --landing bounce is the launch's one angle (or use "
                          f"--psi-dist for a distribution), got {psi!r}")
    coins = options.resolve_coin(xi, coin, count, quarters, diameter, thickness, many=True,
                                 xi_rule="finite", command="coin table")
    xis = [float(x) for x in coins.xis]
    from coincli.reports.phase import diameter_m

    dia = diameter_m(coins, diameter)
    cells = len(xis) * len(es) * len(mus)
    if cells > MAX_CELLS:
        raise usage_error(f"--landing bounce simulates at most {MAX_CELLS} cells (coins x "
                          f"restitutions x frictions) a command; these options make {cells}")
    n = DEFAULT_TOSSES if tosses is None else options.tosses_value(tosses, high=MAX_BOUNCE_TOSSES)
    if cells * n > MAX_STUDY_TOSSES:
        raise usage_error(f"-n {n} tosses in each of {cells} cells is {cells * n} tosses; "
                          f"--landing bounce simulates at most {MAX_STUDY_TOSSES} a command "
                          f"(lower -n, or split the study)")
    for x in xis:
        check_coin(physics, x, dia, xi_text=xi if len(xis) == 1 else repr(x),
                   diameter_text=diameter, thickness_text=thickness)
    u_spec, w_spec, psi_spec, labels = bounce_launch_for(physics, psi, psi_dist, u, omega)
    for x in xis:  # every coin must land within half of --t-max (reports.physics)
        check_landing(physics, u_top=reach(u_spec, U_MAX), g=STANDARD_G, xi=x, dia=dia,
                      u_text=u or "the hand toss's")
    seed_v = options.seed_value(seed)
    stacked = coins.counts is not None
    columns = (_STACKED if stacked else []) + COLUMNS
    plan = [(k, e, mu) for k in range(len(xis)) for e in es for mu in mus]
    note = (f"Simulated tables (MuJoCo), not the paper's catch: {n} tosses a cell onto "
            f"{base.name} (torsional {base.torsional * 1000:g} mm, rolling "
            f"{base.rolling * 1000:g} mm) at each restitution and friction, D = "
            f"{dia * 1000:g} mm, {labels}; seed {seed_v}, the same launches in every cell "
            f"(common random numbers); dt = {physics.dt:g} s.  Chances among the settled tosses, "
            f"95% Wilson intervals; 'unsettled': still moving at {physics.t_max:g} s.  "
            + bounce_report.CONTACT_NOTE)

    def rows():
        from contextlib import ExitStack

        from coincli.reports.executor import executor

        with ExitStack() as stack:  # the cluster, the checkpoint and the bar, for the study
            run = stack.enter_context(executor(physics, "coin table --landing bounce", **{
                "-n": n, "--seed": seed_v, "--xi": xis, "cells": [
                    f"{e!r}/{mu!r}" for e in es for mu in mus], "--u": u_spec,
                "--omega": w_spec, "--psi": psi_spec, "--diameter": dia, "--g": STANDARD_G}))
            bar = stack.enter_context(progress()) if progress is not None else None
            done = unsettled = never = 0
            for k, e, mu in plan:
                surf = replace(base, restitution=e, friction=mu)
                tick = None if bar is None else (lambda d, done=done: bar(done + d, cells * n))
                sim = core_call(_runs().simulate, n, seed_v, xi=xis[k], u=u_spec, omega=w_spec,
                                psi=psi_spec, surf=surf, landing="bounce",
                                height=physics.height, vx=physics.vx, diameter=dia,
                                g=STANDARD_G, dt=physics.dt, t_max=physics.t_max,
                                jobs=physics.jobs, progress=tick, executor=run)
                done += n
                unsettled += sim.counts[3]
                never += sim.n - sum(sim.catch_counts)  # no first contact: no catch outcome
                yield [[v] for v in study_row(coins, k, xis[k], dia, surf, sim, stacked)]
        # after the last cell, the tosses that did not settle (written after the table)
        said = bounce_report.unsettled_note(
            physics, unsettled, done, never,
            left="each cell's chances are among its settled tosses; a cell where none settled "
                 "has empty chances")
        if said:
            result.notes.append(said)

    if wide:
        result = widen(columns, rows(), [(e, mu) for e in es for mu in mus], note)
    else:
        result = bounce_report.BounceResult(
            "coin table --landing bounce", columns, [], note=note,
            quiet=columns.index(next(c for c in columns if c.name == "p_sides")),
            chunks=rows())
    return result


#: the columns of a cell that the wide layout repeats for each table
_PER_TABLE = ("p_heads", "p_heads_low", "p_heads_high", "p_sides", "p_sides_low",
              "p_sides_high", "p_tails", "p_tails_low", "p_tails_high", "settled", "unsettled")


def _distinct_texts(values) -> dict:
    """Each value's text in a column name: 6 significant digits (``0.3``), or, where two values
    would then read alike (``0.3`` and ``0.3000001``), the shortest text that reads back to each
    double, so that no two tables share a column."""
    values = sorted(set(values))
    short = {v: f"{v:g}" for v in values}
    if len(set(short.values())) == len(values):
        return short
    return {v: repr(float(v)) for v in values}


def widen(columns, cells, tables, note) -> Result:
    """The study as one row per coin: the coin's columns, then for each table (restitution
    ``e``, friction ``mu``) its chances and counts, named ``e0.5_mu0.3_p_sides`` (``--layout
    wide``, for a spreadsheet), then the seed.  ``cells``: the long rows, one a chunk, in
    order (each coin's tables together)."""
    names = [c.name for c in columns]
    per = [names.index(c) for c in _PER_TABLE]
    lead = [i for i, c in enumerate(names) if c in ("coin", "count", "xi", "diameter_mm",
                                                   "surface")]
    out = [columns[i] for i in lead]
    e_text, mu_text = (_distinct_texts([t[k] for t in tables]) for k in (0, 1))
    for e, mu in tables:
        es, ms = e_text[e], mu_text[mu]
        out += [Column(f"e{es}_mu{ms}_{columns[i].name}", f"e {es} mu {ms} {columns[i].header}",
                       columns[i].style) for i in per]
    out.append(columns[names.index("seed")])

    def rows():
        group = []
        for chunk in cells:
            group.append([col[0] for col in chunk])
            if len(group) == len(tables):
                row = [group[0][i] for i in lead]
                for r in group:
                    row += [r[i] for i in per]
                row.append(group[0][names.index("seed")])
                group = []
                yield [[v] for v in row]

    return bounce_report.BounceResult("coin table --landing bounce", out, [], note=note,
                                      chunks=rows())


def _runs():
    from coincli.core.bounce import runs

    return runs


def study_row(coins, k, x, dia, surf, sim, stacked) -> list:
    """One cell's row: the chances (None where no toss settled: an empty cell, never nan)."""
    cells = []
    for f in sim.frequencies:
        settled = sim.settled > 0 and math.isfinite(f.p)
        cells += [f.p, f.lo, f.hi] if settled else [None, None, None]
    lead = [coins.unit.name if coins.unit is not None else "custom", coins.counts[k]] \
        if stacked else []
    return [*lead, x, dia * 1000, surf.name, surf.restitution, surf.friction, *cells,
            sim.settled, sim.counts[3], sim.seed]
