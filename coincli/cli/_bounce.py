"""``--landing bounce``: the options and outputs shared by ``coin simulate``, ``coin toss``,
``coin design`` and ``coin plot sides`` for tosses that land on a surface (issue 16).

The physics is :mod:`coincli.core.bounce.engine` (MuJoCo, an optional extra).  This module parses the
surface and launch options, turns a missing MuJoCo into the one-line hint
``pip install 'thickcoin[physics]'`` (exit 1), and builds the results.  Nothing here imports
numpy, scipy, rich or mujoco at import time; ``--landing catch`` (the default) never loads them.
"""

from __future__ import annotations

import math
import sys
from typing import Annotated

import typer

from coincli.errors import compute_error, usage_error
from coincli.io import grammar as parse
from coincli.io.table import Column, Result

LANDINGS = ("catch", "bounce")
SURFACE_NAMES = ("wood", "hard-floor", "felt", "rice")  # coincli.core.bounce.engine.SURFACES, without mujoco
MAX_BOUNCE_TOSSES = 10**6  #: -n with --landing bounce: ~4 hours at ~75 tosses/s on two cores

LandingOpt = Annotated[
    str, typer.Option("--landing", help="catch (the paper's: caught at first contact, the "
                      "exact model) or bounce (lands on a surface, bounces and settles; "
                      "simulated with MuJoCo, pip install 'thickcoin[physics]').",
                      metavar="catch|bounce")
]
SurfaceOpt = Annotated[
    str | None, typer.Option("--surface", help="With --landing bounce: wood (default), "
                             "hard-floor, felt or rice (the paper's catch surface); "
                             "--restitution and the friction options change one number.",
                             metavar="NAME")
]
RestitutionOpt = Annotated[
    str | None, typer.Option("--restitution", help="Coefficient of restitution of the surface "
                             "(the rebound speed ratio of a flat drop), 0.06 to 0.95.",
                             metavar="E")
]
FrictionOpt = Annotated[
    str | None, typer.Option("--friction", help="Sliding friction coefficient of the surface, "
                             "0 to 10.", metavar="MU")
]
TorsionalOpt = Annotated[
    str | None, typer.Option("--torsional", help="Torsional friction, a length (mm or with a "
                             "unit): resisting torque per unit normal force.", metavar="MM")
]
RollingOpt = Annotated[
    str | None, typer.Option("--rolling", help="Rolling resistance, a length (mm or with a "
                             "unit): c_rr times the radius.", metavar="MM")
]
ReleaseHeightOpt = Annotated[
    str | None, typer.Option("--release-height", help="With --landing bounce: the height of "
                             "the launch plane above the surface (mm or with a unit; or "
                             "normal:MEAN:SD, uniform:LOW:HIGH in mm).  Default 0: the surface "
                             "is the paper's catch plane.", metavar="SPEC")
]
VxOpt = Annotated[
    str | None, typer.Option("--vx", help="With --landing bounce: horizontal speed, m/s (or "
                             "normal:MEAN:SD, uniform:LOW:HIGH), in a random direction.",
                             metavar="SPEC")
]
JobsOpt = Annotated[
    str | None, typer.Option("--jobs", "-j", help="Worker processes for --landing bounce "
                             "(default: every core).  The results do not depend on it.",
                             metavar="N")
]
DtOpt = Annotated[
    str | None, typer.Option("--dt", help="MuJoCo's timestep, s (default 1e-4; see "
                             "docs/bounce.md for the convergence study), 1e-6 to 1e-3.",
                             metavar="S")
]
TMaxOpt = Annotated[
    str | None, typer.Option("--t-max", help="Simulated seconds after which a coin still "
                             "moving counts as unsettled (default 10).", metavar="S")
]


class Physics:
    """The parsed ``--landing bounce`` options (SI)."""

    __slots__ = ("surface", "height", "vx", "jobs", "dt", "t_max", "B")

    def describe(self) -> str:
        s = self.surface
        return (f"surface {s.name} (restitution {s.restitution:g}, friction {s.friction:g}, "
                f"torsional {s.torsional * 1000:g} mm, rolling {s.rolling * 1000:g} mm)")


def bounce_module():
    """:mod:`coincli.core.bounce.engine` with MuJoCo loaded, or the one-line install hint (exit 1)."""
    from coincli.core.bounce import engine as B

    try:
        B.require_mujoco()
    except B.PhysicsMissing as exc:
        raise compute_error(str(exc)) from None
    return B


def landing_of(text: str) -> str:
    t = text.strip().lower()
    if t not in LANDINGS:
        raise usage_error(f"--landing must be catch or bounce, got {text!r}")
    return t


def _number(text: str, what: str, lo: float, hi: float) -> float:
    try:
        v = parse.parse_number(text, what)
    except ValueError:
        v = math.nan
    if not lo <= v <= hi:
        raise usage_error(f"{what} must be a number from {lo:g} to {hi:g}, got {text!r}")
    return v


def _zero_length(text: str) -> bool:
    """``0``, ``0mm``, ``0.0 cm``...: a zero length (which the shared length parser, made for
    sizes, refuses), its unit checked by that parser."""
    import re

    m = re.fullmatch(r"\s*([-+]?[0-9.]+(?:e[-+]?[0-9]+)?)\s*([a-z]*)\s*", str(text).lower())
    if m is None:
        return False
    try:
        if parse.parse_number(m.group(1), "length") != 0:
            return False
        return not m.group(2) or parse.parse_length_mm("1" + m.group(2)) > 0
    except ValueError:
        return False


def _length_m(text: str, what: str, hi_mm: float) -> float:
    """A length from 0 to ``hi_mm`` mm (a number in mm, or with a unit), in metres."""
    try:
        v = parse.parse_length_mm(text, what)
    except ValueError as exc:
        if not _zero_length(text):
            raise usage_error(str(exc).replace("a finite length > 0", "a finite length >= 0")
                              ) from None
        v = 0.0
    if not 0.0 <= v <= hi_mm:
        raise usage_error(f"{what} must be a length from 0 to {hi_mm:g} mm, got {text!r}")
    return v / 1000.0


def _dist(text: str, what: str, unit: str, scale: float, hi: float):
    """A fixed value (a length with a unit for mm) or normal:MEAN:SD / uniform:LOW:HIGH."""
    from coincli.core.toss import launch as T

    t = text.strip()
    if ":" not in t:
        if unit == "mm":
            return _length_m(t, what, hi)
        return _number(t, what, 0.0, hi)
    try:
        return T.parse_dist(t, what, 0.0, hi, unit).scaled(scale)
    except ValueError as exc:
        raise usage_error(str(exc)) from None


def given(*values) -> list[str]:
    return [v for v in values if v is not None]


def parse_physics(landing: str, *, surface=None, restitution=None, friction=None,
                  torsional=None, rolling=None, height=None, vx=None, jobs=None, dt=None,
                  t_max=None) -> Physics | None:
    """The bounce options, or None for ``--landing catch`` (then none may be given)."""
    if landing == "catch":
        extra = [name for name, v in (("--surface", surface), ("--restitution", restitution),
                                      ("--friction", friction), ("--torsional", torsional),
                                      ("--rolling", rolling), ("--release-height", height),
                                      ("--vx", vx),
                                      ("--jobs", jobs), ("--dt", dt), ("--t-max", t_max))
                 if v is not None]
        if extra:
            raise usage_error(f"{', '.join(extra)} go{'es' if len(extra) == 1 else ''} with "
                              "--landing bounce (the catch ends at first contact: no surface)")
        return None
    name = None if surface is None else surface.strip().lower()
    if name is not None and name not in SURFACE_NAMES:
        raise usage_error(f"--surface must be one of {', '.join(SURFACE_NAMES)}, got {surface!r}")
    e = None if restitution is None else _number(restitution, "--restitution", 0.06, 0.95)
    mu = None if friction is None else _number(friction, "--friction", 0.0, 10.0)
    tor = None if torsional is None else _length_m(torsional, "--torsional", 100.0)
    rol = None if rolling is None else _length_m(rolling, "--rolling", 100.0)
    B = bounce_module()
    p = Physics()
    p.B = B
    if name is None and e is not None and mu is None:
        raise usage_error("--restitution without --surface needs --friction too (or start "
                          "from a preset: --surface wood --restitution 0.4)")
    if name is None and mu is not None and e is None:
        raise usage_error("--friction without --surface needs --restitution too (or start from "
                          "a preset: --surface wood --friction 0.5)")
    try:
        p.surface = B.surface(name, restitution=e, friction=mu, torsional=tor, rolling=rol)
    except ValueError as exc:
        raise usage_error(str(exc)) from None
    p.height = 0.0 if height is None else _dist(height, "--release-height", "mm", 1e-3, 1e5)
    p.vx = 0.0 if vx is None else _dist(vx, "--vx", "m/s", 1.0, 100.0)
    if jobs is None:
        from coincli.core.bounce.runs import default_jobs

        p.jobs = default_jobs()
    else:
        j = jobs.strip()
        if not (j.isascii() and j.isdigit()) or not 1 <= int(j) <= 1024:
            raise usage_error(f"--jobs must be a whole number from 1 to 1024, got {jobs!r}")
        p.jobs = int(j)
    p.dt = B.DEFAULT_DT if dt is None else _number(dt, "--dt", 1e-6, 1e-3)
    p.t_max = B.DEFAULT_T_MAX if t_max is None else _number(t_max, "--t-max", 0.01, 1000.0)
    return p


def _run(fn, *args, **kwargs):
    """Call the engine: a ValueError there is bad input (exit 2)."""
    try:
        return fn(*args, **kwargs)
    except ValueError as exc:
        raise usage_error(str(exc)) from None


def check_speed(p: Physics, u_top: float, g: float, text: str) -> None:
    """Refuse a launch speed whose flight cannot end within ``--t-max``: the coin rises and
    falls back for ``2 u / g`` seconds before it reaches a surface at the launch plane, so
    ``u`` may be at most ``g t_max / 2`` (49 m/s at the default 10 s).  ``u_top``: the largest
    speed the run draws (m/s); ``text``: the value as typed."""
    u_max = g * p.t_max / 2
    if not u_top <= u_max:
        raise usage_error(f"--u must be at most {u_max:.3g} m/s with --landing bounce and "
                          f"--t-max {p.t_max:g} s (the coin must land within --t-max: the "
                          f"flight lasts 2u/g), got {text!r}")


def check_coin(p: Physics, xi: float | None, dia: float, *, xi_text=None, diameter_text=None,
               thickness_text=None) -> None:
    """Refuse, naming the option as typed, a coin MuJoCo cannot simulate: a diameter outside
    [the smallest with a mass and inertia MuJoCo takes at xi = 100, 10 m], or an aspect ratio
    (``xi`` None: not checked) too thin for that diameter
    (:func:`coincli.core.bounce.engine.smallest_xi`)."""
    B = p.B
    why = "(MuJoCo's limits on a body's mass and inertia)"
    if not B.smallest_diameter() <= dia <= 10.0:
        lo = B.round_up(B.smallest_diameter() * 1000)
        what = "--diameter" if diameter_text is not None else "the coin's diameter"
        got = repr(diameter_text) if diameter_text is not None else f"{dia * 1000:g} mm"
        raise usage_error(f"{what} must be from {lo:g} to 10000 mm with --landing bounce "
                          f"{why}, got {got}")
    if xi is None:
        return
    lo = B.smallest_xi(dia)
    if not xi >= lo:
        if thickness_text is not None:
            raise usage_error(f"--thickness must be at least {B.round_up(lo * dia * 1000):g} mm "
                              f"with --landing bounce and a {dia * 1000:g} mm diameter {why}, "
                              f"got {thickness_text!r}")
        got = repr(xi_text) if xi_text is not None else f"{xi:g}"
        raise usage_error(f"--xi must be at least {B.round_up(lo):g} with --landing bounce and "
                          f"D = {dia * 1000:g} mm {why}, got {got}")


def dist_text(v, unit: str, scale: float = 1.0) -> str:
    if isinstance(v, float):
        return f"{v * scale:g} {unit}"
    return f"{v.scaled(scale)} {unit}"


# --------------------------------------------------------------------------- coin simulate


def simulate(p: Physics, *, count, seed, xi, u, omega, psi, diameter, g, labels, fmt, quiet,
             progress):
    """``coin simulate --landing bounce``: frequencies among settled tosses with Wilson
    intervals, what the catch would have said of the same tosses, the vigorous limit."""
    from coincli.core.bounce import runs
    from coincli.core.toss.simulate import wilson_interval
    from coincli.io.table import emit

    if count > MAX_BOUNCE_TOSSES:
        raise usage_error(f"-n must be at most {MAX_BOUNCE_TOSSES} with --landing bounce (a "
                          f"simulated toss takes milliseconds), got {count}")
    with progress(count) as tick:
        sim = _run(runs.simulate, count, seed, xi=xi, u=u, omega=omega, psi=psi, surf=p.surface,
                   landing="bounce", height=p.height, vx=p.vx, diameter=diameter, g=g,
                   dt=p.dt, t_max=p.t_max, jobs=p.jobs, progress=tick)
    rows = []
    n = sim.n
    for i, f in enumerate(sim.frequencies):
        rows.append((f.outcome, f.count, f.p, f.lo, f.hi, sim.catch_counts[i] / n,
                     float(sim.vigorous[i])))
    lo, hi = wilson_interval(sim.counts[3], n)
    rows.append(("unsettled", sim.counts[3], sim.counts[3] / n, lo, hi, None, None))
    common = ["bounce", p.surface.name, p.surface.restitution, p.surface.friction, sim.seed,
              sim.mean_bounces, sim.mean_t_settle, sim.agree / n]
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
            f"{sim.mean_bounces:.3g}, mean time to settle {sim.mean_t_settle:.3g} s; "
            f"{sim.agree / n:.1%} land as the catch at first contact would have said ('if "
            "caught': the same tosses caught, eq. 7).  The vigorous limit is the paper's catch "
            "model averaged over psi.")
    emit(Result("coin simulate --landing bounce", columns, rows, note,
                quiet=[r[2] for r in rows[:3]]), fmt, quiet)


# --------------------------------------------------------------------------- coin toss


def toss(p: Physics, *, xi, psi, u, omega, diameter, g, z0, trajectory, fmt, quiet,
         note_extra: str = "", seed: int | None = None):
    """``coin toss --landing bounce``: one toss onto the surface, its bounces, time to settle
    and final side; ``trajectory`` (a path) gets the time series as CSV, written atomically."""
    from coincli.core.toss.flight import default_z0
    from coincli.io.table import emit

    B = p.B
    if trajectory is not None:
        _output_path(trajectory)
    if not (isinstance(p.height, float) and isinstance(p.vx, float)):
        raise usage_error("coin toss takes one --release-height and one --vx (a number, not a "
                          "distribution)")
    coin = _run(B.Coin, xi, diameter)
    z0v = default_z0(xi, diameter, "thick") if z0 is None else z0
    eng = _run(B.Engine, coin, p.surface, dt=p.dt, g=g, landing="bounce", t_max=p.t_max)
    launch = B.Launch(u, omega, psi, z0v, p.height, p.vx, 0.0)
    t_land = eng.first_contacts([launch])[0]
    if not t_land < p.t_max:  # a lower surface lengthens the flight past 2u/g
        raise usage_error(f"the coin lands {t_land:.4g} s after launch, past --t-max "
                          f"{p.t_max:g} s: lower --u or --release-height, or raise --t-max")
    r = _run(eng.run, launch, record=trajectory is not None, t_contact=t_land)
    if trajectory is not None:
        write_csv_atomic(trajectory, B.TRAJECTORY_COLUMNS, r.trajectory)
    names = B.NAMES
    data = [[xi], [math.degrees(psi)], [u], [omega], ["bounce"], [p.surface.name],
            [r.t_first], [names[r.catch_code]], [r.bounces], [r.t_settle],
            [math.degrees(r.alpha)], [r.outcome], [r.steps]]
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
            "side without slipping) fell below what it needs to cross a corner, so the side "
            "could no longer change.  'if caught': the paper's catch at the first contact.")
    if trajectory is not None:
        note += f"  Trajectory: {trajectory} ({len(r.trajectory)} rows)."
    note += note_extra
    if seed is not None and fmt != "table":  # drawn launch values: the seed that repeats them
        columns.append(Column("seed", "seed", "int"))
        data.append([seed])
    emit(Result("coin toss --landing bounce", columns, [], note, quiet=r.outcome,
                vertical=True, data=data), fmt, quiet)


def _output_path(path: str) -> None:
    """Refuse a --trajectory path that cannot be written, before any simulating."""
    from coincli.io.files import FileKindError, check_output_path

    try:
        check_output_path(path)
    except FileKindError as exc:
        raise usage_error(f"--trajectory: {exc}") from None
    except OSError as exc:
        raise compute_error(f"cannot write {path!r}: {exc.strerror or exc}") from None


def write_csv_atomic(path: str, header, rows) -> None:
    """A CSV written whole or not at all (:func:`coincli.io.files.write_atomic`)."""
    from coincli.io.files import FileKindError, write_atomic

    lines = [",".join(header)]
    lines += [",".join(repr(v) if isinstance(v, float) else str(v) for v in row) for row in rows]
    try:
        write_atomic(path, ("\n".join(lines) + "\n").encode())
    except FileKindError as exc:
        raise usage_error(f"--trajectory: {exc}") from None
    except OSError as exc:
        raise compute_error(f"cannot write {path!r}: {exc.strerror or exc}") from None


# --------------------------------------------------------------------------- coin design


def design(p: Physics, *, targets, seed, tol, max_tosses, time_limit, u, omega, psi, diameter,
           g, labels, fmt, quiet, progress):
    from coincli.core.bounce import design as bounce_design
    from coincli.io.table import emit

    with progress() as tick:
        r = _run(bounce_design.design, targets, seed=seed, tol=tol, max_tosses=max_tosses,
                 time_limit=time_limit, u=u, omega=omega, psi=psi, surf=p.surface,
                 landing="bounce", height=p.height, vx=p.vx, diameter=diameter, g=g, dt=p.dt,
                 t_max=p.t_max, jobs=p.jobs, progress=tick)
    dia_mm = diameter * 1000
    rows = [(t, x, lo, hi, dia_mm * x, float(f.p_sides(x)), f.p_value, len(f.points), r.tosses,
             r.seed)
            for t, x, lo, hi, f in zip(r.targets, r.xi, r.low, r.high, r.fits, strict=True)]
    columns = [
        Column("p_sides", "P(sides) target"), Column("xi", "xi = h/D"),
        Column("xi_low", "95% low"), Column("xi_high", "95% high"),
        Column("thickness_mm", f"thickness (mm) for D = {dia_mm:g}"),
        Column("fitted_p_sides", "fitted P(sides)"), Column("fit_p_value", "fit p-value"),
        Column("fit_points", "aspect ratios fitted", "int"),
        Column("tosses", "tosses", "int"), Column("seed", "seed", "int"),
    ]
    why = {"tol": f"every interval within --tol {tol:g}",
           "max_tosses": f"--max-tosses {max_tosses} reached before --tol {tol:g}",
           "time_limit": f"the --time-limit of {time_limit:g} s passed before --tol {tol:g}"}
    note = (f"Simulated table (MuJoCo), not the paper's catch: tosses onto {p.describe()}, "
            f"{labels}; seed {r.seed}.  {r.tosses} tosses ({r.unsettled} unsettled, left out) "
            f"at {len(r.fit.points)} aspect ratios in {r.rounds + 1} "
            f"round{'' if r.rounds == 0 else 's'}.  Each answer is "
            "from P(sides) = Phi(alpha + beta ln xi) fitted by maximum likelihood to the "
            "aspect ratios near it ('aspect ratios fitted'; "
            + "; ".join(f"{t:.4g}: Phi({f.alpha:.4g} + {f.beta:.4g} ln xi), deviance "
                        f"{f.deviance:.3g} on {f.df} df, p = {f.p_value:.3g}"
                        for t, f in zip(r.targets, r.fits, strict=True))
            + ")" + ("; a curve misses its points by more than their noise: its interval is "
                     "widened by the dispersion" if any(f.p_value < 0.01 for f in r.fits)
                     else "")
            + f"; 95% intervals by the delta method.  Stopped: {why[r.stopped_by]}"
            + ("" if r.first >= bounce_design.DESIGN_FIRST else
               f" (--max-tosses {max_tosses} cut the first sweep to {r.first} tosses per aspect "
               f"ratio, from {bounce_design.DESIGN_FIRST})")
            + ("" if r.stopped_by == "tol" else
               f"; --max-tosses {r.tosses} reproduces this result") + ".  "
            "The catch model (no --landing) gives the paper's xi.  Toss a prototype and check "
            "it with coin check.")
    emit(Result("coin design --landing bounce", columns, rows, note,
                quiet=[row[1] for row in rows], vertical=len(rows) == 1), fmt, quiet)
    if not r.met:
        sys.stdout.flush()
        sys.stderr.write(f"coin: warning: {why[r.stopped_by]}; the intervals are wider than "
                         "asked\n")


# --------------------------------------------------------------------------- coin plot sides


class FittedSpec:
    """The fitted bounce curve, shaped as :class:`coincli.core.modelspec.ModelSpec` for the plots
    (``forward``, ``inverse``, ``label``, ``gid``)."""

    key = "fitted"
    closed_form = False

    def __init__(self, fit, surface_name: str):
        self.fit = fit
        self.label = f"bounce on {surface_name}: fitted probit (simulated)"
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
    """Simulated points (one per xi, 95% Wilson intervals) and the fitted curve, or None and
    why not when the points do not determine one."""
    from coincli.core.bounce import design as bounce_design
    from coincli.core.bounce import runs
    from coincli.render.figures import ExperimentPoint

    pts = []
    for j, x in enumerate(xis):
        r = _run(runs.simulate, n, seed, xi=x, u=u, omega=omega, psi=psi, surf=p.surface,
                 landing="bounce", height=p.height, vx=p.vx, diameter=diameter, g=g, dt=p.dt,
                 t_max=p.t_max, jobs=p.jobs, stream=(0, j))
        f = r.frequencies[1]
        pts.append(ExperimentPoint(f"simulated bounce on {p.surface.name}", x, r.settled,
                                   f.count, f.p, f.lo, f.hi))
    try:
        fit = bounce_design.fit_sides([(e.xi, e.n, e.sides) for e in pts])
    except ValueError as exc:
        return pts, None, str(exc)
    return pts, FittedSpec(fit, p.surface.name), None
