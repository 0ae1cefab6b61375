"""The bouncing runs (``--landing bounce``, issue 16): what ``coin toss``, ``coin simulate`` and
``coin design`` print when the coin lands on a surface, bounces and settles; the simulated
points of ``coin plot sides --landing bounce``.

The physics is :mod:`coincli.core.bounce.engine` (MuJoCo, an optional extra); the options are
parsed into a :class:`coincli.reports.physics.Physics` (:func:`coincli.reports.landing.
parse_physics`).  This module builds the results (:func:`simulate`, :func:`toss`,
:func:`design`, called by :mod:`coincli.reports.toss` and
:func:`coincli.reports.design.bounce_design`, the report of ``coin design --landing bounce``)
and writes their warnings and notes after the output (:func:`warn_unmet`).  A run's progress is
shown by a bar the caller passes (``progress``); none when None.  Nothing here imports numpy,
scipy, rich or mujoco at import time; ``--landing catch`` (the default) never loads them.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

from coincli.errors import compute_error, usage_error
from coincli.io import notes
from coincli.io.table import Column, Result
from coincli.limits import MAX_BOUNCE_TOSSES
from coincli.reports.launch import core_call, no_progress

if TYPE_CHECKING:
    from coincli.reports.physics import Physics


#: How much the table's answer depends on the contact model itself (docs/contact-models.md,
#: measured by benchmarks/crosscheck_bullet.py: the hand toss on wood, 2000 tosses per engine
#: per xi): every answer of --landing bounce says so, beside its sampling interval.
CONTACT_NOTE = ("The contact model is itself uncertain: a second engine (Bullet) puts the fair "
                "xi of the hand toss on wood 0.04 lower (0.463 against 0.503) and P(sides) 0.01 "
                "to 0.05 apart, and heads against tails differs between them (docs: 'How much "
                "does the answer depend on the contact model?'); the intervals hold the "
                "simulation's error, not the contact model's.")


def design_columns(dia_mm: float) -> list[Column]:
    """The leading columns of every ``coin design --landing bounce`` answer (on a preset or a
    calibrated table): the target, xi with its interval, the thickness with its interval."""
    return [
        Column("p_sides", "P(sides) target"), Column("xi", "xi = h/D"),
        Column("xi_low", "95% low"), Column("xi_high", "95% high"),
        Column("thickness_mm", f"thickness (mm) for D = {dia_mm:g}"),
        Column("thickness_low_mm", "thickness 95% low"),
        Column("thickness_high_mm", "thickness 95% high"),
    ]


# --------------------------------------------------------------------------- empty results
#
# One rule for every bouncing command: what only settled tosses can give (a frequency, a time
# to settle, a final side) is an empty cell (None: '-' in a table, nothing in csv/tsv and -q,
# null in json) when no toss settled, never NaN; and a note on stderr, after the output, says
# how many tosses did not settle and why (:func:`unsettled_note`, written by warn_unmet).


def empty(v):
    """``v``, or None (an empty cell) for NaN."""
    return None if isinstance(v, float) and math.isnan(v) else v


def unsettled_note(p: Physics, unsettled: int, total: int, never_landed: int = 0,
                   left: str | None = None) -> str | None:
    """The note of tosses that did not settle (None when all did): how many, why, what is left
    out (``left``: by default the frequencies), and what to change."""
    if not unsettled:
        return None
    moving, by = unsettled - never_landed, f"--t-max {p.t_max:g} s"
    if total == 1:
        how = "never reached the surface by" if never_landed else "still moving at"
        return (f"the toss did not settle ({how} {by}): its time to settle and final tilt "
                "are empty; raise --t-max, or land more gently (a lower --u, --vx, "
                "--release-height or --restitution)")
    why = ([f"{moving} still moving at {by}"] if moving else []) + (
        [f"{never_landed} never reached the surface by then"] if never_landed else [])
    left = left or ("no frequency can be given (empty cells)" if unsettled == total else
                    "they are left out of the frequencies")
    return (f"{unsettled} of {total} tosses did not settle ({'; '.join(why)}): {left}; raise "
            "--t-max, or land more gently (a lower --u, --vx, --release-height or "
            "--restitution)")


def dist_text(v, unit: str, scale: float = 1.0) -> str:
    if isinstance(v, float):
        return f"{v * scale:g} {unit}"
    return f"{v.scaled(scale)} {unit}"


# --------------------------------------------------------------------------- coin simulate


def simulate(p: Physics, *, count, seed, xi, u, omega, psi, diameter, g, labels, fmt,
             progress=None) -> Result:
    """``coin simulate --landing bounce``: frequencies among settled tosses with Wilson
    intervals, what the catch would have said of the same tosses, the vigorous limit.
    ``progress(total)``: a progress bar (a context manager giving ``tick(done)``), or None."""
    from coincli.core.bounce import runs
    from coincli.core.toss.simulate import wilson_interval
    from coincli.reports.executor import executor

    if count > MAX_BOUNCE_TOSSES:  # (the command line's -n is checked by bounce_tosses)
        raise usage_error(f"-n must be a whole number from 1 to {MAX_BOUNCE_TOSSES} with "
                          f"--landing bounce (a simulated toss takes milliseconds), got {count}")
    with executor(p, "coin simulate --landing bounce", **{
            "-n": count, "--seed": seed, "--xi": xi, "--u": u, "--omega": omega, "--psi": psi,
            "--diameter": diameter, "--g": g}) as run, (progress or no_progress)(count) as tick:
        sim = core_call(runs.simulate, count, seed, xi=xi, u=u, omega=omega, psi=psi,
                        surf=p.surface, landing="bounce", height=p.height, vx=p.vx,
                        diameter=diameter, g=g, dt=p.dt, t_max=p.t_max, jobs=p.jobs,
                        progress=tick, executor=run)
    rows = []
    n = sim.n
    none = sim.settled == 0  # no frequency among settled tosses: empty cells, not NaN
    for i, f in enumerate(sim.frequencies):
        rows.append((f.outcome, f.count, *((None,) * 3 if none else (f.p, f.lo, f.hi)),
                     sim.catch_counts[i] / n, float(sim.vigorous[i])))
    lo, hi = wilson_interval(sim.counts[3], n)
    rows.append(("unsettled", sim.counts[3], sim.counts[3] / n, lo, hi, None, None))
    common = ["bounce", p.surface.name, p.surface.restitution, p.surface.friction, sim.seed,
              sim.mean_bounces, None if none else empty(sim.mean_t_settle), sim.agree / n]
    rows = [r + tuple(common) for r in rows]
    columns = [
        Column("outcome", "outcome", "text"), Column("count", "count", "int"),
        Column("frequency", "frequency"), Column("ci_low", "95% low"),
        Column("ci_high", "95% high"), Column("caught", "if caught"),
        Column("vigorous", "vigorous limit"), Column("landing", "landing", "text"),
        Column("surface", "surface", "text"), Column("restitution", "restitution"),
        Column("friction", "friction"), Column("seed", "seed", "int"),
        Column("mean_bounces", "mean bounces"), Column("mean_t_settle", "mean time to settle"),
        Column("agree_caught", "same as caught"),
    ]
    if fmt == "table":  # the human table: the run-wide numbers go to the note
        columns = columns[:7]
        rows = [r[:7] for r in rows]
    note = (f"Simulated table (MuJoCo), not the paper's catch: {n} tosses, seed {sim.seed}, "
            f"onto {p.describe()}; xi = {xi:g}, {labels}; surface "
            f"{dist_text(p.height, 'mm', 1000)} below the launch plane, horizontal speed "
            f"{dist_text(p.vx, 'm/s')}; dt = {p.dt:g} s.  Frequencies among the "
            f"{sim.settled} settled tosses, 95% Wilson intervals; {sim.counts[3]} still moving "
            f"at {p.t_max:g} s are 'unsettled' (their share of all tosses).  Mean bounces "
            f"{sim.mean_bounces:.3g}, "
            + ("no toss settled" if none else f"mean time to settle {sim.mean_t_settle:.3g} s")
            + f"; {sim.agree / n:.1%} land as the catch at first contact would have said ('if "
            "caught': the same tosses caught, eq. 7).  The vigorous limit is the paper's catch "
            "model averaged over psi.")
    never = n - sum(sim.catch_counts)  # no first contact by t_max: no catch outcome either
    return BounceResult("coin simulate --landing bounce", columns, rows, note,
                        quiet=[r[2] for r in rows[:3]],
                        notes=[unsettled_note(p, sim.counts[3], n, never)])


# --------------------------------------------------------------------------- coin toss


def toss(p: Physics, *, xi, psi, u, omega, diameter, g, z0, trajectory, fmt,
         note_extra: str = "", seed: int | None = None) -> Result:
    """``coin toss --landing bounce``: one toss onto the surface, its bounces, time to settle
    and final side; ``trajectory`` (a path) gets the time series as CSV, written atomically."""
    from coincli.core.toss.flight import NAMES, default_z0
    from coincli.reports.physics import engine

    bounce_engine = engine()
    if trajectory is not None:
        _output_path(trajectory)
    if not (isinstance(p.height, float) and isinstance(p.vx, float)):
        raise usage_error("coin toss takes one --release-height and one --vx (a number, not a "
                          "distribution)")
    coin = core_call(bounce_engine.Coin, xi, diameter)
    z0v = default_z0(xi, diameter, "thick") if z0 is None else z0
    eng = core_call(bounce_engine.Engine, coin, p.surface, dt=p.dt, g=g, landing="bounce",
                    t_max=p.t_max)
    launch = bounce_engine.Launch(u, omega, psi, z0v, p.height, p.vx, 0.0)
    t_land = eng.first_contacts([launch])[0]
    if not t_land <= p.t_max / 2:  # check_landing's rule, on the exact flight
        raise usage_error(f"the coin lands {t_land:.4g} s after launch, past half of --t-max "
                          f"{p.t_max:g} s (the other half is left to bounce and settle): lower "
                          "--u or --release-height, or raise --t-max")
    r = core_call(eng.run, launch, record=trajectory is not None, t_contact=t_land)
    if trajectory is not None:
        write_csv_atomic(trajectory, bounce_engine.TRAJECTORY_COLUMNS, r.trajectory)
    unsettled_code = bounce_engine.UNSETTLED
    settled = r.code < unsettled_code  # else: an empty time to settle, tilt and outcome cell
    data = [[xi], [math.degrees(psi)], [u], [omega], ["bounce"], [p.surface.name],
            [empty(r.t_first)], [NAMES[r.catch_code] if r.catch_code < unsettled_code else None],
            [r.bounces], [empty(r.t_settle)],
            [math.degrees(r.alpha) if settled else None], [r.outcome], [r.steps]]
    columns = [
        Column("xi", "xi"), Column("psi_deg", "psi (deg)"), Column("u", "u (m/s)"),
        Column("omega", "omega (rad/s)"), Column("landing", "landing", "text"),
        Column("surface", "surface", "text"), Column("t_first", "first contact (s)", "g10"),
        Column("caught", "if caught (eq. 7)", "text"), Column("bounces", "bounces", "int"),
        Column("t_settle", "settled at (s)", "g6"), Column("tilt_deg", "final tilt (deg)"),
        Column("outcome", "outcome", "text"), Column("steps", "MuJoCo steps", "int"),
    ]
    note = (f"One toss onto {p.describe()} (MuJoCo, dt = {p.dt:g} s), the surface "
            f"{p.height * 1000:g} mm below the launch plane; D = {diameter * 1000:g} mm.  "
            "'settled at': when the coin's energy (less that of rolling, when it rolls on its "
            "side without slipping, or the kinetic energy its spin keeps at a corner, for a thick "
            "coin) fell below what it needs to cross a corner, so the side "
            "could no longer change.  'if caught': the paper's catch at the first contact.")
    if trajectory is not None:
        note += f"  Trajectory: {trajectory} ({len(r.trajectory)} rows)."
    note += note_extra
    if seed is not None and fmt != "table":  # drawn launch values: the seed that repeats them
        columns.append(Column("seed", "seed", "int"))
        data.append([seed])
    never = int(r.catch_code >= unsettled_code)
    return BounceResult("coin toss --landing bounce", columns, [], note, quiet=r.outcome,
                        vertical=True, data=data,
                        notes=[unsettled_note(p, int(not settled), 1, never)])


def _output_path(path: str) -> None:
    """Refuse a --trajectory path that cannot be written, before any simulating."""
    from coincli.io.files import refuse_unwritable

    refuse_unwritable(path, "--trajectory")


def write_csv_atomic(path: str, header, rows) -> None:
    """A CSV written whole or not at all, by the one csv writer (:func:`coincli.io.table.emit`
    into :func:`coincli.io.files.write_text_atomic`)."""
    from coincli.io.files import FileKindError, write_text_atomic
    from coincli.io.table import emit

    table = Result("trajectory", [Column(name, name) for name in header], list(rows))
    try:
        write_text_atomic(path, lambda fh: emit(table, "csv", out=fh, no_headers=False))
    except FileKindError as exc:
        raise usage_error(f"--trajectory: {exc}") from None
    except OSError as exc:
        raise compute_error(f"cannot write {path!r}: {exc.strerror or exc}") from None


# --------------------------------------------------------------------------- coin design


def design(p: Physics, *, targets, seed, tol, max_tosses, time_limit, u, omega, psi, diameter,
           g, labels, progress=None, no_table=False) -> DesignResult:
    """The aspect ratios of the ``targets`` chances of a side, fitted to simulated tosses, as
    :func:`bounce_design` prints them.  ``progress()``: a progress bar (a context manager
    giving ``tick(done, planned)``), or None.  Starts from the table shipped for a preset
    (:mod:`coincli.core.bounce.tables`) when the tosses are that table's, unless
    ``no_table``."""
    from coincli.core.bounce import design as bounce_design
    from coincli.core.bounce import tables
    from coincli.reports.executor import executor

    sim = {"u": u, "omega": omega, "psi": psi, "surf": p.surface, "landing": "bounce",
           "height": p.height, "vx": p.vx, "diameter": diameter, "g": g, "dt": p.dt,
           "t_max": p.t_max}
    table = None if no_table else tables.for_design(sim)
    with executor(p, "coin design --landing bounce", **{
            "--p-sides": targets, "--seed": seed, "--tol": tol, "--max-tosses": max_tosses,
            "--time-limit": time_limit, "--u": u, "--omega": omega, "--psi": psi,
            "--diameter": diameter, "--g": g, "--no-table": table is None}) as run, (
            progress or no_progress)() as tick:
        try:
            r = bounce_design.design(targets, seed=seed, tol=tol, max_tosses=max_tosses,
                                     time_limit=time_limit, table=table, **sim,
                                     jobs=p.jobs, progress=tick, executor=run)
        except (bounce_design.BeyondTheEngine, bounce_design.TooFewSettled) as exc:
            raise _design_error(p, exc) from None
        except bounce_design.Undetermined as exc:  # valid input: no answer from these tosses
            raise compute_error(str(exc)) from None
        except ValueError as exc:
            raise usage_error(str(exc)) from None
    dia_mm = diameter * 1000
    outside = [(t, x) for t, x in zip(r.targets, r.xi, strict=True)
               if not r.span[0] <= x <= r.span[1]]
    tab = r.table  # the precomputed table it started from, or None
    # the --max-tosses that reproduces a run cut short: its own tosses (none, when a table
    # gave every point), and never below the smallest --max-tosses accepted
    least = bounce_design.DESIGN_LEAST
    from_table = tab.tosses if tab is not None else 0
    total = r.tosses + from_table
    unsettled = r.unsettled + (tab.unsettled if tab is not None else 0)
    never = r.never_landed + (tab.never_landed if tab is not None else 0)
    rows = [(t, x, lo, hi, dia_mm * x, dia_mm * lo, dia_mm * hi, float(f.p_sides(x)),
             empty(f.p_value), len(f.points), total, from_table, r.seed)
            for t, x, lo, hi, f in zip(r.targets, r.xi, r.low, r.high, r.fits, strict=True)]
    columns = [
        *design_columns(dia_mm),
        Column("fitted_p_sides", "fitted P(sides)"), Column("fit_p_value", "fit p-value"),
        Column("fit_points", "aspect ratios fitted", "int"),
        Column("tosses", "tosses", "int"), Column("table_tosses", "from the table", "int"),
        Column("seed", "seed", "int"),
    ]
    rounds = r.rounds + (tab is None)  # (a first sweep is a round; a table replaces it)
    if tab is None:
        source = (f"{r.tosses} tosses ({r.unsettled} unsettled, left out) at "
                  f"{len(r.fit.points)} aspect ratios in {rounds} "
                  f"round{'' if rounds == 1 else 's'}")
    else:
        gen = tab.generated
        source = (f"Started from the table precomputed for {tab.surface} with this launch and "
                  f"coin ({from_table} tosses, {tab.unsettled} unsettled, at "
                  f"{len(tab.points)} aspect ratios; seed {tab.seed}; coincli "
                  f"{gen.get('coincli', '?')}, MuJoCo {gen.get('mujoco', '?')}; "
                  "benchmarks/precompute_bounce_tables.py; --no-table simulates every toss)"
                  + ("; no toss simulated here: the table alone gave the intervals"
                     if not r.tosses else
                     f", then {r.tosses} tosses simulated here ({r.unsettled} unsettled, left "
                     f"out) in {rounds} round{'' if rounds == 1 else 's'}; "
                     f"{len(r.fit.points)} aspect ratios in all"))
    why = {"tol": f"every interval within --tol {tol:g}",
           "max_tosses": f"--max-tosses {max_tosses} reached before --tol {tol:g}",
           "time_limit": f"the --time-limit of {time_limit:g} s passed before --tol {tol:g}"}
    note = (f"Simulated table (MuJoCo), not the paper's catch: tosses onto {p.describe()}, "
            f"{labels}; seed {r.seed}.  {source}.  Each answer is "
            "from P(sides) = Phi(alpha + beta ln xi) fitted by maximum likelihood to the "
            "aspect ratios near it ('aspect ratios fitted'; "
            + "; ".join(f"{t:.4g}: Phi({f.alpha:.4g} + {f.beta:.4g} ln xi), deviance "
                        f"{f.deviance:.3g} on {f.df} df, p = {f.p_value:.3g}"
                        for t, f in zip(r.targets, r.fits, strict=True))
            + ")" + ("; a curve misses its points by more than their noise: its interval is "
                     "widened by the dispersion" if any(f.p_value < 0.01 for f in r.fits)
                     else "")
            + "; 95% intervals: Fieller's (the slope's error carried), widened by the shift a "
            "local quadratic probit makes (lack of fit; docs/bounce.md, 'How a design's "
            f"interval is made').  Stopped: {why[r.stopped_by]}"
            + ("" if not outside else
               "; " + ", ".join(f"xi = {x:.4g} for P(sides) = {t:.4g}" for t, x in outside)
               + f" extrapolated from the aspect ratios simulated ({r.span[0]:.4g} to "
               f"{r.span[1]:.4g})")
            + ("" if r.first >= bounce_design.DESIGN_FIRST else
               f" (--max-tosses {max_tosses} cut the first sweep to {r.first} tosses per aspect "
               f"ratio, from {bounce_design.DESIGN_FIRST})")
            + ("" if r.stopped_by == "tol" else
               f"; --max-tosses {max(r.tosses, least)} reproduces this result") + ".  "
            + CONTACT_NOTE + "  The catch model (no --landing) gives the paper's xi.  Toss a "
            "prototype and check it with coin check.  " + PRESET_SPREAD)
    warning = [] if r.met else [f"{why[r.stopped_by]}; the intervals are wider than asked"]
    if outside:
        warning.append(f"{len(outside)} answer{'' if len(outside) == 1 else 's'} extrapolated "
                       f"beyond the aspect ratios simulated ({r.span[0]:.4g} to "
                       f"{r.span[1]:.4g}): raise --max-tosses or --time-limit to simulate "
                       "near them")
    return DesignResult("coin design --landing bounce", columns, rows, note,
                        quiet=[row[1] for row in rows], vertical=len(rows) == 1,
                        warning="; ".join(warning) or None,
                        notes=[unsettled_note(p, unsettled, total, never)])


def _design_error(p: Physics, exc):
    """The error of a design the core could not finish, named for the user: an answer beyond
    the engine's aspect ratios (--p-sides, exit 2), or too few settled tosses (exit 1, with the
    unsettled note)."""
    from coincli.core.bounce import design as bounce_design

    if isinstance(exc, bounce_design.BeyondTheEngine):
        t = f"{exc.target:g}" if float(f"{exc.target:g}") == exc.target else repr(exc.target)
        return usage_error(f"--p-sides {t} needs xi = {exc.xi:.3g}, outside the "
                           f"aspect ratios MuJoCo can simulate for this coin ({exc.lo:.3g} to "
                           f"{exc.hi:g}): no simulated toss could check it; give a P(sides) "
                           "whose coin can be simulated")
    return compute_error("no design: " + unsettled_note(
        p, exc.unsettled, exc.tosses, exc.never_landed,
        left="fitting P(sides) needs settled tosses at two aspect ratios or more"))


#: what a design on a preset cannot say: how far another table moves it (docs/bounce.md)
PRESET_SPREAD = ("Your table is not a preset either.  Over "
                 "docs/bounce.md's sensitivity table (other tables and tosses) the fair xi "
                 "runs from 0.25 (friction 0.6) to 0.81 (psi exactly 90), 0.445 on rice; "
                 "calibrate your table from tosses of two prototypes (coin fit --landing bounce "
                 "FILE --save CAL.json) and design with --calibration CAL.json.")


class BounceResult(Result):
    """What a bouncing command prints, and the lines that follow it on stderr
    (:func:`warn_unmet` writes them, after the output): ``warning``, a design that stopped
    before every interval was within ``--tol`` (``coin: warning: ...``), and ``notes``, the
    tosses that did not settle (:func:`unsettled_note`; ``coin: note: ...``; Nones dropped)."""

    __slots__ = ("warning", "notes")

    def __init__(self, *args, warning: str | None = None, notes=(), **kwargs):
        super().__init__(*args, **kwargs)
        self.warning = warning
        self.notes = [n for n in notes if n]


DesignResult = BounceResult  #: what ``coin design --landing bounce`` returns


def warn_unmet(results) -> None:
    """After a report's output is written: the warning and notes of a bouncing run
    (:class:`BounceResult`, :func:`coincli.io.notes.after`), on stderr; nothing for any other
    result."""
    for r in [results] if isinstance(results, Result) else results:
        notes.lines(notes.after(r))



# --------------------------------------------------------------------------- coin plot sides


class FittedSpec:
    """The fitted bounce curve, shaped as :class:`coincli.core.modelspec.ModelSpec` for the plots
    (``forward``, ``inverse``, ``label``, ``gid``)."""

    key = "fitted"
    closed_form = False

    def __init__(self, fit, surface_name: str, level: float = 0.05):
        self.fit = fit
        #: the points reject the probit (goodness of fit p < level): drawn dashed, labelled so
        self.rejected = fit.p_value < level  # nan (no degrees of freedom left) is not
        verdict = (f"REJECTED by its points, fit p = {fit.p_value:.2g}: shown for reference"
                   if self.rejected else (f"fit p = {fit.p_value:.3g}"
                                          if math.isfinite(fit.p_value) else "exact fit"))
        self.label = f"bounce on {surface_name}: fitted probit (simulated; {verdict})"
        self.name = self.gid = "bounce"

    def forward(self, xi):
        from coincli.core.models import Outcome

        s = self.fit.p_sides(xi)
        return Outcome((1 - s) / 2, s, (1 - s) / 2)  # faces not told apart by the fit

    def inverse(self, p):
        return self.fit.inverse(p)


#: The aspect ratios `coin plot sides --landing bounce` simulates, at most: below 0.05 a coin
#: hardly ever lands on its side (no points worth their time), above 100 MuJoCo's body limits.
PLOT_XI = (0.05, 100.0)


def sides_points(p: Physics, *, seed, n, xis, u, omega, psi, diameter, g):
    """Simulated points (one per xi with a settled toss, 95% Wilson intervals), the fitted
    curve (None when the points do not determine one) and a note: why there is no curve,
    and/or the tosses that did not settle (:func:`unsettled_note`), or None."""
    from coincli.core.bounce import design as bounce_design
    from coincli.core.bounce import runs
    from coincli.render.figures import ExperimentPoint
    from coincli.reports.executor import executor

    pts = []
    unsettled = never = 0
    with executor(p, "coin plot sides --landing bounce", **{
            "--seed": seed, "-n": n, "--xi-range": xis, "--u": u, "--omega": omega,
            "--psi": psi, "--diameter": diameter, "--g": g}) as run:
        for j, x in enumerate(xis):
            r = core_call(runs.simulate, n, seed, xi=x, u=u, omega=omega, psi=psi,
                          surf=p.surface, landing="bounce", height=p.height, vx=p.vx,
                          diameter=diameter, g=g, dt=p.dt, t_max=p.t_max, jobs=p.jobs,
                          stream=(0, j), executor=run)
            unsettled += r.counts[3]
            never += r.n - sum(r.catch_counts)
            f = r.frequencies[1]
            if r.settled:  # an aspect ratio where no toss settled has no point (not a NaN one)
                pts.append(ExperimentPoint(f"simulated bounce on {p.surface.name}", x,
                                           r.settled, f.count, f.p, f.lo, f.hi, simulated=True))
    note = unsettled_note(p, unsettled, n * len(xis), never)
    try:
        fit = bounce_design.fit_sides([(e.xi, e.n, e.sides) for e in pts])
    except ValueError as exc:
        return pts, None, str(exc) + ("" if note is None else f"; {note}")
    return pts, FittedSpec(fit, p.surface.name), note
