"""The bounce setup (``--landing bounce``, issue 16): the surface, release and run options parsed
once into a :class:`Physics` (:func:`bounce_physics`), the engine they run on (:func:`engine`:
MuJoCo, an optional extra, or the one-line hint ``pip install 'thickcoin[physics]'``, exit 1),
and the limits of a bouncing run, checked before any simulation (:func:`check_g`,
:func:`bounce_tosses`, :func:`check_landing`, :func:`check_coin`; the spin's,
:func:`coincli.reports.launch.check_omega`).

Loaded only when a command runs with ``--landing bounce`` (:func:`coincli.reports.landing.
parse_physics` comes here): the catch, the default, never imports it.  Nothing here imports
numpy, scipy, rich or mujoco at import time.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from coincli import limits as L
from coincli.errors import InputError, compute_error, shown, usage_error
from coincli.io import notes
from coincli.io import grammar as parse
from coincli.io import options
from coincli.limits import BOUNCE_G_MAX, BOUNCE_XI_MAX, HAND, MAX_BOUNCE_TOSSES, SURFACE_NAMES
from coincli.reports.launch import bounded_number, reach


@dataclass(frozen=True)
class Physics:
    """The parsed ``--landing bounce`` options (SI), built once by :func:`bounce_physics`
    (a variant: :func:`dataclasses.replace`).

    ``surface``: the engine's :class:`coincli.core.bounce.engine.Surface`; ``height`` and
    ``vx``: a value or a :class:`coincli.core.toss.launch.Dist`; ``jobs``: local workers;
    ``dt``, ``t_max``: the step and time limit (s); ``calibration``: ``(path, its contents)``
    on a calibrated table (:func:`coincli.reports.calibrated.apply`), else None;
    ``scheduler``, ``checkpoint``, ``timeout``: where the tosses run
    (:func:`coincli.reports.executor.parse_run`); ``height_text``: --release-height as typed.
    """

    surface: object
    height: object
    vx: object
    jobs: int
    dt: float
    t_max: float
    scheduler: object = None
    checkpoint: str | None = None
    timeout: float | None = None
    calibration: tuple | None = None
    height_text: str | None = None

    def describe(self) -> str:
        s = self.surface
        return (f"surface {s.name} (restitution {s.restitution:g}, friction {s.friction:g}, "
                f"torsional {s.torsional * 1000:g} mm, rolling {s.rolling * 1000:g} mm)")


def engine():
    """:mod:`coincli.core.bounce.engine` with MuJoCo loaded, or the one-line install hint
    (exit 1)."""
    from coincli.core.bounce import engine as bounce_engine

    try:
        bounce_engine.require_mujoco()
    except bounce_engine.PhysicsMissing as exc:
        raise compute_error(str(exc)) from None
    return bounce_engine


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
    from coincli.core.toss import launch as toss_launch

    t = text.strip()
    if ":" not in t:
        if unit == "mm":
            return _length_m(t, what, hi)
        return bounded_number(t, what, 0.0, hi)
    try:
        return toss_launch.parse_dist(t, what, 0.0, hi, unit).scaled(scale)
    except ValueError as exc:
        raise usage_error(str(exc)) from None


def bounce_physics(*, surface=None, restitution=None, friction=None, torsional=None,
                   rolling=None, height=None, vx=None, jobs=None, dt=None, t_max=None,
                   calibration=None, scheduler=None, checkpoint=None,
                   timeout=None) -> Physics:
    """The ``--landing bounce`` options as typed, parsed once into a :class:`Physics`.
    ``calibration``: a calibration file (:func:`coincli.reports.calibrated.apply`), the table
    instead of the surface options."""
    from coincli.reports import calibrated

    if calibration is not None:
        calibrated.refuse_surface_options(calibration, surface=surface,
                                          restitution=restitution, friction=friction,
                                          torsional=torsional, rolling=rolling)
    name = None if surface is None else surface.strip().lower()
    if name is not None and name not in SURFACE_NAMES:
        raise usage_error(f"--surface must be one of {', '.join(SURFACE_NAMES)}, "
                          f"got {surface!r}")
    e = None if restitution is None else bounded_number(
        restitution, "--restitution", L.BOUNCE_RESTITUTION_MIN, L.BOUNCE_RESTITUTION_MAX)
    mu = None if friction is None else bounded_number(friction, "--friction", 0.0,
                                                      L.BOUNCE_FRICTION_MAX)
    tor = None if torsional is None else _length_m(torsional, "--torsional",
                                                   L.BOUNCE_FRICTION_LENGTH_MAX_MM)
    rol = None if rolling is None else _length_m(rolling, "--rolling",
                                                 L.BOUNCE_FRICTION_LENGTH_MAX_MM)
    bounce_engine = engine()
    if name is None and e is not None and mu is None:
        raise usage_error("--restitution without --surface needs --friction too (or start "
                          "from a preset: --surface wood --restitution 0.4)")
    if name is None and mu is not None and e is None:
        raise usage_error("--friction without --surface needs --restitution too (or start from "
                          "a preset: --surface wood --friction 0.5)")
    try:
        surf = bounce_engine.surface(name, restitution=e, friction=mu, torsional=tor,
                                     rolling=rol)
    except ValueError as exc:
        raise usage_error(str(exc)) from None
    height_v = 0.0 if height is None else _dist(height, "--release-height", "mm", 1e-3,
                                                L.BOUNCE_HEIGHT_MAX_MM)
    vx_v = 0.0 if vx is None else _dist(vx, "--vx", "m/s", 1.0, L.BOUNCE_VX_MAX)
    if jobs is None:
        from coincli.core.bounce.runs import default_jobs

        jobs_v = default_jobs()
    else:
        j = jobs.strip()
        if not (j.isascii() and j.isdigit()) or not 1 <= int(j) <= 1024:
            raise usage_error(f"--jobs must be a whole number from 1 to 1024, got {jobs!r}")
        from coincli.core.bounce.runs import capped_jobs

        jobs_v = capped_jobs(int(j))
        if jobs_v < int(j):  # more workers than cores only share them, and cost a process each
            notes.note(f"--jobs {int(j)} capped at {jobs_v}, the cores this process may use")
    from coincli.reports.executor import parse_run

    sched, ckpt, tmo = parse_run(jobs=jobs, scheduler=scheduler, checkpoint=checkpoint,
                                 timeout=timeout)
    dt_v = bounce_engine.DEFAULT_DT if dt is None else bounded_number(
        dt, "--dt", L.BOUNCE_DT_MIN, L.BOUNCE_DT_MAX)
    t_max_v = (bounce_engine.DEFAULT_T_MAX if t_max is None else
               bounded_number(t_max, "--t-max", L.BOUNCE_T_MAX_MIN, L.BOUNCE_T_MAX_MAX))
    p = Physics(surface=surf, height=height_v, vx=vx_v, jobs=jobs_v, dt=dt_v, t_max=t_max_v,
                scheduler=sched, checkpoint=ckpt, timeout=tmo, height_text=height)
    if calibration is not None:
        p = calibrated.apply(p, calibration, height_given=height is not None,
                             vx_given=vx is not None, dt_given=dt is not None,
                             t_max_given=t_max is not None)
    return p


# --------------------------------------------------------------------------- limits
#
# Every limit of a bouncing run is checked here, before any simulation, by every bouncing
# command that takes the option (toss, simulate, design, plot sides), and named as the user
# typed it with its range for --landing bounce (issue 28).  The numbers are coincli.limits'.

#: why the engine limits the coin's size (the numbers: coincli.core.bounce.engine.smallest_xi)
_BODY = "MuJoCo's limits on a body's mass and inertia"


def check_g(g: float, text: str) -> None:
    """``--g`` at most :data:`coincli.limits.BOUNCE_G_MAX`: a stronger gravity presses the coin
    into MuJoCo's soft contact further than its stiffness, set by the time step, holds."""
    if not g <= BOUNCE_G_MAX:
        raise usage_error(f"--g must be at most {BOUNCE_G_MAX:g} m/s^2 with --landing bounce "
                          "(under a stronger gravity the coin sinks into the surface's soft "
                          f"contact), got {shown(text)}")


def bounce_tosses(text: str, what: str = "-n", low: int = 1,
                  high: int = MAX_BOUNCE_TOSSES) -> int:
    """A number of tosses of a bouncing run (``-n``, ``--max-tosses``): a whole number from
    ``low`` to ``high`` (at most :data:`coincli.limits.MAX_BOUNCE_TOSSES`, about 4 hours at 75
    tosses a second on two cores), named as typed."""
    try:
        return options.tosses_value(text, low=low, high=high, what=what)
    except InputError:
        raise usage_error(f"{what} must be a whole number from {low} to {high} with --landing "
                          f"bounce (a simulated toss takes milliseconds), got {shown(text)}"
                          ) from None


def _fall(u: float, g: float, drop: float) -> float:
    """When a centre launched up at ``u`` has fallen ``drop`` below its start."""
    from coincli.core._numerics.backend import M
    from coincli.core.toss.flight import fall_time

    return fall_time(M, u, g, max(drop, 0.0))


def check_landing(p: Physics, *, u_top: float, g: float, xi: float, dia: float, u_text: str,
                  z0: float | None = None) -> None:
    """Refuse a launch that cannot settle by construction: the coin must land within half of
    ``--t-max``, leaving the other half to bounce and settle (a ball landing at ``v`` on a
    surface of restitution ``e`` bounces for ``2 v e / (g (1 - e))``: at 0.5, wood's, as long
    again as its fall).  The landing is bounded below by the time the centre of the fastest
    launch (``u_top``, m/s; ``u_text`` as typed), from the highest surface (``--release-height``
    at the top of its distribution), falls on its way down to the half-diagonal ``R`` above the
    surface: no part of the coin touches on the way down before.  The option blamed is the one
    whose value alone is too much: ``--release-height``, else ``--u``, else ``--t-max`` (the
    fall from the launch height alone is too long)."""
    from coincli.core.toss.flight import default_z0

    if p.calibration is not None and u_text in (HAND["u"], "the hand toss's"):
        u_text = f"the calibration's launch.u ({p.calibration[0]})"  # not typed: the file's
    half = p.t_max / 2
    z = default_z0(xi, dia, "thick") if z0 is None else z0
    drop = z - math.hypot(dia / 2, xi * dia / 2)  # the centre's fall before R
    h_top = p.height if isinstance(p.height, float) else reach(p.height, 100.0)
    if _fall(u_top, g, drop + h_top) <= half:
        return
    rule = ("the coin must land within half of --t-max, leaving the other half to bounce and "
            "settle")
    if _fall(0.0, g, drop) > half:
        fall = _fall(0.0, g, drop)
        raise usage_error(f"--t-max must be at least {2 * fall:.3g} s with --landing bounce "
                          f"({rule}; it falls for {fall:.3g} s from its launch height), got "
                          f"{p.t_max:g} s")
    ctx = f"with --landing bounce and --t-max {p.t_max:g} s ({rule})"
    if h_top > 0 and _fall(u_top, g, drop) <= half:
        h_max = g * half * half / 2 - u_top * half - drop  # (u + sqrt(u^2 + 2gd))/g = half
        raise usage_error(f"--release-height must be at most {h_max * 1000:.4g} mm with --u "
                          f"reaching {u_top:g} m/s, --landing bounce and --t-max {p.t_max:g} s "
                          f"({rule}), got {shown(str(getattr(p, 'height_text', None)).strip())}")
    u_max = g * half / 2 - max(drop, 0.0) / half
    raise usage_error(f"--u must be at most {u_max:.3g} m/s {ctx}, got {shown(u_text.strip())}")


def check_coin(p: Physics, xi: float | None, dia: float, *, xi_text=None, diameter_text=None,
               thickness_text=None, count_text=None, quarters_text=None, coin_text=None,
               count: int | None = None, xi_low: float | None = None,
               command: str = "--landing bounce") -> None:
    """Refuse, naming the option as typed with its range, a coin MuJoCo cannot simulate: a
    diameter outside [the smallest with a mass and inertia MuJoCo takes at aspect ratio
    ``xi_low`` (default 100, the most), 10 m], or an aspect ratio (``xi`` None: not checked)
    outside [the thinnest for that diameter (:func:`coincli.core.bounce.engine.smallest_xi`),
    :data:`coincli.limits.BOUNCE_XI_MAX`].  The option blamed is the one that gave the aspect
    ratio: ``--thickness``, ``--count`` or ``--quarters`` (a stack of ``count`` coins; its
    range in coins), else ``--xi``.  ``command``: how the range's context is named."""
    bounce_engine = engine()
    low = BOUNCE_XI_MAX if xi_low is None else xi_low
    if not bounce_engine.smallest_diameter(xi=low) <= dia <= 10.0:
        lo = bounce_engine.round_up(bounce_engine.smallest_diameter(xi=low) * 1000)
        what = "--diameter" if diameter_text is not None else "the coin's diameter"
        got = repr(diameter_text) if diameter_text is not None else f"{dia * 1000:g} mm"
        sweep = "" if xi_low is None else f", down to xi = {xi_low:g}"
        raise usage_error(f"{what} must be from {lo:g} to 10000 mm with {command} "
                          f"({_BODY}{sweep}), got {got}")
    if xi is None:
        return
    lo = bounce_engine.smallest_xi(dia)
    if lo <= xi <= BOUNCE_XI_MAX:
        return
    if thickness_text is not None:
        raise usage_error(f"--thickness must be from "
                          f"{bounce_engine.round_up(lo * dia * 1000):g} to "
                          f"{BOUNCE_XI_MAX * dia * 1000:.4g} mm with {command} and a "
                          f"{dia * 1000:g} mm diameter ({_BODY}), got {thickness_text!r}")
    stack = count_text if count_text is not None else quarters_text
    if stack is not None and count:
        one = xi / count  # the aspect ratio of one coin of the stack
        what = "--count" if count_text is not None else "--quarters"
        c_lo, c_hi = max(1, math.ceil(lo / one)), math.floor(BOUNCE_XI_MAX / one)
        of = f" of {coin_text.strip()} coins" if count_text is not None and coin_text else ""
        raise usage_error(f"{what} must be from {c_lo} to {c_hi} with {command} (a stack{of} "
                          f"up to xi = {BOUNCE_XI_MAX:g}: {_BODY}), got {stack.strip()!r}")
    got = repr(xi_text) if xi_text is not None else f"{xi:g}"
    raise usage_error(f"--xi must be from {bounce_engine.round_up(lo):g} to "
                      f"{BOUNCE_XI_MAX:g} with {command} and D = {dia * 1000:g} mm ({_BODY}), "
                      f"got {got}")


