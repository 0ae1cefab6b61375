"""What ``coin book`` prints: the paper's Problem 1, a tossed book or die (three different
moments).

:func:`book` parses the box (``--size`` in mm, or ``--moments``), the spin (rad/s about the
body axes, units allowed), the times and the toss options; calls :mod:`coincli.core.rigid`;
returns a :class:`coincli.io.table.Result`: the motion table, the ``--times`` series (streamed
by chunks) or the face chances of a ``--toss`` run.  A figure (``--out FILE.png``, ``.svg``,
``.pdf``) is drawn by :mod:`coincli.render.book_figures` and written here (through
:func:`coincli.io.table.write_figure`); nothing is then returned.  A ValueError from the core
is bad input: one line, exit 2.  The motion table imports no numpy; ``--times``, ``--toss`` and
``--out`` load numpy and ``scipy.special``; only a figure file loads matplotlib.
"""

from __future__ import annotations

import contextlib
import math
import os
import re

from coincli.errors import CoinError, compute_error, shown, usage_error
from coincli.io import grammar as parse
from coincli.io.batches import values_option
from coincli.io.options import (
    range_unit,
    report_seed,
    seed_value,
    tosses_value,
    typed_range_error,
    unit_at_end,
)
from coincli.io.table import CHUNK_ROWS, Column, Result, check_format
from coincli.limits import MAX_BOOK_TOSSES, MAX_PHASE, NORMAL_REACH

__all__ = ["book", "seed_note", "MAX_TOSSES", "FACES"]


MAX_TOSSES = MAX_BOOK_TOSSES  # tosses of one --toss run (a box costs ~10 coins)
FIGURE_POINTS = 2001  # samples of omega(t) in a figure without --times
FACES = ("+1", "-1", "+2", "-2", "+3", "-3")
STARTS = FACES + ("random",)
# angular speed units -> rad/s (exact factors as text where they are not 1)
_TIME_UNITS = {"s": 1.0, "ms": 1e-3}
_DIST_KINDS = ("normal", "uniform", "fixed")
_IMAGES = (".gif", ".jpg", ".jpeg", ".tif", ".tiff", ".bmp", ".webp", ".eps", ".ps")


def _usage(fn, *args, **kwargs):
    try:
        return fn(*args, **kwargs)
    except ValueError as exc:
        raise usage_error(str(exc)) from None


# --------------------------------------------------------------------------- parsing


def _time_seconds(text: str, what: str) -> float:
    """A time in s, with an optional unit (``0.5``, ``0.5s``, ``500ms``); ValueError if not."""
    num, unit = parse.split_unit(text, _TIME_UNITS)
    try:
        return parse.parse_number(num, what) * _TIME_UNITS[unit or "s"]
    except ValueError:
        raise ValueError(f"{what} must be a time with an optional unit (s, the default; ms), "
                         f"got {text!r}") from None


def _time_value(text: str, what: str) -> float:
    """:func:`_time_seconds`, or the one-line usage error."""
    try:
        return _time_seconds(text, what)
    except ValueError as exc:
        raise usage_error(str(exc)) from None


def _spin_value(text: str, what: str) -> float:
    """A signed angular velocity component in rad/s: coincli.io.grammar.parse_spin_rads (``40``,
    ``6.4rev/s``, ``2300rpm``, ``-90deg/s``) with a sign in front."""
    s = text.strip()
    sign = -1.0 if s.startswith("-") else 1.0
    body = s[1:] if s[:1] in "+-" else s
    try:
        return sign * parse.parse_spin_rads(body, what) + 0.0
    except ValueError:
        raise usage_error(f"{what} must be a finite number with an optional unit (rad/s, the "
                          f"default; rev/s, rpm, deg/s), got {text!r}") from None


def _dist(text: str, what: str, number, default: str, lo: float, units, example: str):
    """A value or a distribution ``normal:MEAN:SD`` / ``uniform:LOW:HIGH`` (``fixed:V``) whose
    numbers may carry units: one after every number, or once at the end for all of them
    (``normal:6:1rev/s``, as ``coin simulate --omega`` reads it); returned as a
    :class:`coincli.core.toss.launch.Dist` in the default unit."""
    from coincli.core.toss import launch as toss_launch

    parts = [p.strip() for p in text.split(":")]
    head = parts[0].lower()
    if head in _DIST_KINDS or (len(parts) > 1 and head.isalpha()):
        if head not in _DIST_KINDS:
            raise usage_error(f"{what}: unknown distribution {text!r}; expected a value, "
                              "normal:MEAN:SD or uniform:LOW:HIGH")
        nums = unit_at_end(parts[1:], units, what, example, text)
        nums = [number(p, what) for p in nums]
        spec = ":".join([head] + [repr(v) for v in nums])
    else:
        if len(parts) != 1:
            raise usage_error(f"{what}: cannot read {text!r}; expected a value, normal:MEAN:SD "
                              "or uniform:LOW:HIGH")
        spec = repr(number(parts[0], what))
    try:
        return toss_launch.parse_dist(spec, what, lo, math.inf, default)
    except ValueError as exc:
        raise usage_error(str(exc).replace(repr(spec), repr(text.strip()))) from None


def _three(text: str, what: str) -> list[str]:
    parts = [p.strip() for p in text.split(",")]
    if len(parts) != 3 or not all(parts):
        raise usage_error(f"{what} needs three components separated by commas (about body "
                          f"axes 1, 2, 3), got {text!r}")
    return parts


def _size_mm(text: str) -> tuple[float, float, float]:
    parts = [p.strip() for p in re.split(r"[x×X*]", text.strip())]
    if len(parts) != 3 or not all(parts):
        raise usage_error(f"--size must be three lengths AxBxC (mm, or with units: "
                          f"23.5cmx15.5cmx3cm), got {text!r}")
    out = []
    for k, p in enumerate(parts, start=1):
        v = _usage(parse.parse_length_mm, p, f"--size side {k}")
        out.append(v)
    return tuple(out)


def _moments(text: str) -> tuple[float, float, float]:
    out = []
    for k, p in enumerate(_three(text, "--moments"), start=1):
        try:
            v = parse.parse_number(p, f"--moments I{k}")
        except ValueError:
            v = math.nan
        if not (math.isfinite(v) and v > 0):
            raise usage_error(f"--moments I{k} must be a finite number > 0 (any unit, kg m^2), "
                              f"got {p!r}")
        out.append(v)
    return tuple(out)


def _time_item(text: str, what: str) -> float:
    v = _time_seconds(text, what)  # ValueError: a stdin batch names the line
    if not v >= 0:
        raise ValueError(f"{what} must be a time >= 0 s, got {text!r}")
    return v


def _typed(text: str, units, unit: str) -> str:
    """A value or distribution as typed, with the default unit appended when it has none."""
    t = text.strip()
    return t if parse.split_unit(t.split(":")[-1], units)[1] is not None else f"{t} {unit}"


def _times(text: str):
    """--times: a value, a list, a range or - (coincli.io.table.values_option), each time
    with an optional unit; a range takes its unit once at the end (``0:500:100ms``, as
    ``coin simulate --omega 38:40:1rev/s`` does) or the same unit after every number."""
    t = text.strip()
    if ":" in t:
        head, unit = range_unit(t, _TIME_UNITS, "--times", "0:500:100ms")
        try:
            return _time_range(head, 1.0 if unit is None else _TIME_UNITS[unit], text)
        except CoinError as exc:  # a range error shows the range as typed, with its unit
            raise typed_range_error(exc, head, t) from None
    return values_option(t, "--times", _time_item)


def _time_range(head: str, factor: float, text: str):
    """A range of times as an array, the values coincli.io.grammar.parse_values gives
    (:meth:`coincli.io.grammar.Range.chunk`), times the unit's factor, computed at once rather than
    parsed back one by one (10^6 times: 0.05 s, not 7 s)."""
    import numpy as np

    try:
        rng = parse.parse_range(head, "--times")
    except ValueError as exc:
        raise usage_error(str(exc)) from None
    vals = rng.chunk(0, rng.count)
    if factor != 1.0:
        vals = vals * factor
    if not (np.all(np.isfinite(vals)) and vals[0] >= 0):
        raise usage_error(f"--times must be times >= 0 s, got {text.strip()!r}")
    return vals


def _reach(dist) -> float:
    """The largest |value| a distribution draws: a fixed value, a uniform's ends, a normal's
    |MEAN| + 10 SD (beyond it the chance is below 1e-23 a draw)."""
    if dist.kind == "fixed" or dist.p2 == 0:
        return abs(dist.p1)
    if dist.kind == "uniform":
        return max(abs(dist.p1), abs(dist.p2))
    return abs(dist.p1) + NORMAL_REACH * dist.p2


def _fmt(v: float) -> str:
    short = f"{v:.6g}"
    return short if float(short) == v else repr(float(v))


# --------------------------------------------------------------------------- --out: checked, figures


def _is_figure(path: str | None) -> bool:
    return path is not None and os.path.splitext(path)[1].lower() in (".png", ".svg", ".pdf")


def _check_out(path: str | None) -> None:
    """Before any computing: an --out path that is a FIFO, a device or a directory, or in a
    missing directory, is refused (coincli.io.files.check_output_path)."""
    if path is None or path == "-":
        return
    from coincli.io.files import refuse_unwritable

    refuse_unwritable(path, "--out")


def _require_matplotlib() -> None:
    """A figure file needs matplotlib: exit 1 with the install hint (as coin plot does)."""
    from coincli.render import figures

    try:
        figures.require_matplotlib()
    except figures.MatplotlibMissing as exc:
        raise compute_error(str(exc)) from None


def _figure(path: str, build) -> None:
    """Draw and save a figure through the shared writer (io.table.write_figure: atomic,
    one-line errors, ``coin: wrote FILE (W x H pixels)`` as coin plot says)."""
    from coincli.render.figures import write_figure

    _require_matplotlib()
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fig = build()
        try:
            write_figure(fig, path)
        except (ValueError, OverflowError, RuntimeError) as exc:  # the figure: nothing written
            words = " ".join(str(exc).split())  # matplotlib's messages run over lines
            raise compute_error(f"cannot draw {path!r}: {words}") from None


# --------------------------------------------------------------------------- the report


def book(*, size: str | None = None, moments: str | None = None, spin: str | None = None,
         times: str | None = None, toss: bool = False, tosses: str | None = None,
         seed: str | None = None, flight: str | None = None, start: str | None = None,
         rule: str | None = None, out: str | None = None, fmt: str = "table",
         quiet: bool = False, progress=None):
    """What ``coin book`` prints: the motion table of a box launched with ``spin``, its
    ``times`` series, or (``toss``) the face chances of many tossed boxes.

    The options' text as ``coin book`` takes it (``tosses`` is ``-n``).  Returns one
    :class:`Result` (the series streamed by chunks, computed when written).  ``out`` is checked
    before any computing; a figure path (``.png``, ``.svg``, ``.pdf``) is drawn and written
    here, and nothing is returned (an empty list); any other path is the caller's to write the
    Result to.  ``progress``, a function of the number of tosses returning a context manager
    that yields ``tick(done)``, shows a --toss run's progress (default: none).  Raises
    InputError for a wrong input, NotComputable when a file cannot be written or drawn.
    """
    check_format(fmt)
    box = _box(size, moments)
    figure = _is_figure(out)
    if out is not None and not figure and os.path.splitext(out)[1].lower() in _IMAGES:
        raise usage_error(f"--out: figures are written as .png, .svg or .pdf, got {out!r}")
    _check_out(out)
    if figure:
        _require_matplotlib()  # before any computing (10^7 tosses take a minute)
    if not (toss or times is not None or flight is not None or figure):
        for opt, given in (("--start", start), ("--rule", rule)):
            if given is not None:
                raise usage_error(f"{opt} is for --times, --flight, --toss or a figure (which "
                                  "face is up)")
    start_v = (start or "+3").strip().lower()
    if start_v not in STARTS:
        raise usage_error(f"--start must be one of {', '.join(STARTS)}, got {start!r}")
    rule_v = (rule or "centre").strip().lower()
    if rule_v == "center":
        rule_v = "centre"
    if rule_v not in ("centre", "normal"):
        raise usage_error(f"--rule must be centre or normal, got {rule!r}")
    if spin is None:
        raise usage_error("give --spin W1,W2,W3 (rad/s about body axes 1, 2, 3), e.g. "
                          "--spin 0,0,40")
    if toss:
        if times is not None:
            raise usage_error("--times is for one motion; --toss tosses many (give one of them)")
        return _toss(box, spin, tosses, seed, flight, start_v, rule_v, out if figure else None,
                     progress)
    for opt, given in (("-n", tosses is not None), ("--seed", seed is not None)):
        if given:
            raise usage_error(f"{opt} is for --toss (many random tosses)")
    w = tuple(_spin_value(p, f"--spin component {k}")
              for k, p in enumerate(_three(spin, "--spin"), start=1))
    if times is not None or figure:
        return _series(box, w, times, start_v, rule_v, out if figure else None)
    tf = None
    if flight is not None:
        tf = _usage(_time_item, flight, "--flight") if ":" not in flight else None
        if tf is None:
            raise usage_error("--flight takes one time (s) without --toss, got "
                              f"{flight!r}")
    return _motion(box, w, tf, start_v, rule_v)


def seed_note(result, seed: str | None, quiet: bool) -> None:
    """After a --toss run's output under ``quiet`` (whose note, naming the seed, is not shown):
    a drawn seed on stderr (:func:`coincli.io.options.report_seed`)."""
    if quiet and isinstance(result, Result) and result.title == "coin book --toss":
        report_seed(result.rows[0][-1], seed is not None)


class _Box:
    __slots__ = ("moments", "sides", "label", "unit", "size_mm")


def _box(size, moments) -> _Box:
    from coincli.core import rigid

    if (size is None) == (moments is None):
        raise usage_error("give --size AxBxC (mm) or --moments I1,I2,I3, one of them")
    b = _Box()
    if size is not None:
        mm = _size_mm(size)
        b.size_mm = mm
        try:
            b.moments = rigid.box_moments(tuple(v / 1000 for v in mm))  # per kg, m^2
        except ValueError as exc:
            small = f" (a cube needs sides of at least {rigid.SMALLEST_CUBE * 1000:.2g} mm)" \
                if "too small" in str(exc) else ""
            raise usage_error(f"--size: {exc}{small}, got {shown(size)}") from None
        top = max(mm)
        b.sides = tuple(v / top for v in mm)
        b.label = " x ".join(_fmt(v) for v in mm) + " mm"
        b.unit = "kg m^2 per kg"
    else:
        b.size_mm = None
        b.moments = _moments(moments)
        b.sides = _usage(rigid.box_sides, b.moments)
        b.label = "moments " + ", ".join(_fmt(v) for v in b.moments)
        b.unit = "as given"
    _usage(rigid.check_moments, b.moments)  # before any computing (and any toss)
    return b


def face_size(box: _Box, face: int) -> str:
    k = face // 2
    i, j = (k + 1) % 3, (k + 2) % 3
    i, j = min(i, j), max(i, j)
    if box.size_mm is not None:
        return f"{_fmt(box.size_mm[i])} x {_fmt(box.size_mm[j])} mm"
    return f"{box.sides[i]:.4g} x {box.sides[j]:.4g} (relative)"


_AXIS_ROLE = {"smallest": "smallest moment", "middle": "middle moment",
              "largest": "largest moment", "tied": "moment equal to another's"}


def _motion(box, w, tf, start, rule) -> Result:
    from coincli.core import rigid

    mo = _usage(rigid.motion, box.moments, w)
    face = None
    if tf is not None:
        import numpy as np

        _check_phase(max(abs(v) for v in w) * (math.sqrt(3) * tf), "--flight", f"{tf:g} s")
        q0 = _start_quaternion(start)
        o = _usage(rigid.orbit, box.moments, np.asarray(w, dtype=float))
        q = rigid.attitude_at(o, tf, q0)
        face = FACES[int(rigid.face_up(rigid.up_vector(q), box.sides, rule))]
    cols, vals = [], []

    def add(name, header, value, style="g10"):
        cols.append(Column(name, header, style))
        vals.append(value)

    ax = lambda i: f"{i + 1} ({_AXIS_ROLE[rigid.axis_roles(box.moments)[i]]})"  # noqa: E731
    add("box", "box", box.label, "text")
    for i in range(3):
        add(f"I{i + 1}", f"I{i + 1} ({box.unit})", box.moments[i])
    for i in range(3):
        add(f"omega{i + 1}_0", f"omega{i + 1} at launch (rad/s)", w[i])
    kind_text = {"rest": "at rest", "steady": "steady spin (omega constant)",
                 "periodic": "periodic", "separatrix": "on the separatrix (one flip, never back)"}
    add("motion", "motion", kind_text[mo.kind], "text")
    add("spin_axis", "spin axis (nearest L at launch)",
        ax(mo.spin_axis) if mo.kind != "rest" else None, "text")  # at rest there is no L
    add("circulates_about", "omega circulates about axis",
        ax(mo.axis) if mo.kind in ("periodic", "separatrix") else None, "text")
    for i in range(3):
        add(f"omega{i + 1}_min", f"omega{i + 1} min (rad/s)", mo.omega_min[i])
        add(f"omega{i + 1}_max", f"omega{i + 1} max (rad/s)", mo.omega_max[i])
    period = mo.period
    if mo.kind == "steady":
        period = 2 * math.pi / mo.gamma if mo.gamma_kind == "oscillation" and mo.gamma else \
            math.inf
    elif mo.kind == "rest":
        period = math.inf
    add("period", "period of omega (s)", period)
    add("frequency", "exact frequency 2 pi/period (rad/s)",
        mo.frequency if mo.frequency is not None else (0.0 if period == math.inf else None))
    osc = mo.gamma_kind == "oscillation" and mo.kind != "rest"
    growth = mo.gamma_kind == "growth" and mo.kind != "rest"
    add("gamma", "paper's Gamma (rad/s)", mo.gamma if osc else None)
    add("gamma_shift", "exact/Gamma - 1", mo.gamma_shift if osc else None)
    add("gamma_shift_2", "  second-order prediction", mo.gamma_shift_2 if osc else None)
    add("lambda", "growth rate lambda (1/s)", mo.gamma if growth else None)
    flips = (growth and mo.kind in ("periodic", "separatrix", "steady")) or \
        mo.kind == "separatrix"
    add("flip_time", "time between flips (s)",
        (mo.half_period if mo.kind != "steady" else math.inf) if flips else None)
    add("flip_asymptote", "  separatrix asymptote (s)", mo.flip_asymptote if flips else None)
    add("first_flip", "first flip at (s)",
        (mo.first_flip if mo.kind != "steady" else math.inf) if flips else None)
    add("m", "elliptic parameter m", mo.m)
    if tf is not None:
        add("flight", "flight time (s)", tf)
        add("face_up", f"face up at the catch ({rule} rule, start {start})", face, "text")
    note = _motion_note(mo, box)
    names = [c.name for c in cols]
    main = face if tf is not None else vals[names.index("flip_time" if flips else "period")]
    return Result("coin book", cols, [tuple(vals)], note, quiet=main, vertical=True)


def _motion_note(mo, box) -> str:
    base = ("Euler's equations of the free body solved exactly (Jacobi elliptic functions); "
            "Yong & Mahadevan, arXiv:1008.4559, Problem 1.")
    if mo.kind == "rest":
        return base + "  No spin: nothing moves."
    if mo.kind == "separatrix":
        return base + ("  Exactly on the separatrix (L^2 = 2 E I, I the middle moment): omega "
                       "tends to a spin about the middle axis, and the body turns over at most "
                       "once (the first flip, inf when it was before launch), never back; the "
                       "period is infinite.")
    if mo.gamma_kind == "oscillation":
        return base + ("  A spin about the largest or the smallest axis is stable: the other two "
                       "components stay bounded and oscillate at nearly Gamma, Gamma^2 = "
                       "(Ic-Ia)(Ic-Ib)/(Ia Ib) omega0^2; exact/Gamma - 1 is second order in the "
                       "perturbation (see the prediction).")
    if mo.gamma_kind == "growth":
        return base + ("  A spin about the middle axis is unstable: a small perturbation grows "
                       "like exp(lambda t), lambda^2 = (I3-I2)(I2-I1)/(I1 I3) omega0^2, and the "
                       "body flips over every half period (the tennis-racket flip); the time "
                       "between flips grows like ln(1/perturbation)/lambda.")
    return base + "  The spin axis's moment equals another's: a neutral (symmetric) spin."


def _start_quaternion(start):
    from coincli.core import rigid

    if start == "random":
        raise usage_error("--start random is for --toss (a single launch needs a face up)")
    return rigid.start_quaternion(start)


def _check_phase(phase: float, what: str, shown: str) -> None:
    if not phase <= MAX_PHASE:
        raise usage_error(f"{what} {shown} is too long for this spin: the box would turn "
                          f"{phase:.3g} rad; at most {MAX_PHASE:.0e} rad (|omega| t) can be "
                          "followed before rounding makes the attitude noise")


# --------------------------------------------------------------------------- time series


def _series(box, w, times, start, rule, figure: str | None):
    """The --times series (a streamed Result), or the figure of omega(t) written to
    ``figure`` (then nothing is returned)."""
    import numpy as np

    from coincli.core import rigid

    mo = _usage(rigid.motion, box.moments, w)
    if times is None:
        span = _default_span(mo)
        ts = np.linspace(0.0, span, FIGURE_POINTS)
    else:
        ts = np.asarray(_times(times), dtype=float)
        if ts.size and not (np.all(np.isfinite(ts)) and ts.min() >= 0):
            raise usage_error("--times must be times >= 0 s")
    wmax = max(abs(v) for v in w)
    if ts.size:
        _check_phase(wmax * (math.sqrt(3) * float(ts.max())), "--times up to",
                     f"{float(ts.max()):g} s")
    q0 = _start_quaternion(start)
    o = _usage(rigid.orbit, box.moments, np.asarray(w, dtype=float))

    def block(t):
        om = rigid.omega_at(o, t)
        q = rigid.attitude_at(o, t, q0)
        return om, q, rigid.face_up(rigid.up_vector(q), box.sides, rule)

    if figure is not None:
        from coincli.render import book_figures

        def omega_up(t):
            om, _, up = block(t)
            return om, up

        # a long series is thinned to the figure's pixel columns, a chunk at a time: memory
        # and file size stay bounded (10^6 times: 2.4 GB and an Agg error before)
        _figure(figure, lambda: book_figures.omega_figure_of(ts, omega_up, mo, box.label, start,
                                                         rule, chunk=CHUNK_ROWS))
        return []
    faces = np.array(FACES)

    def chunks():  # computed, formatted and written a block at a time: memory stays flat
        for i in range(0, ts.size, CHUNK_ROWS):
            t = ts[i:i + CHUNK_ROWS]
            om, q, up = block(t)
            yield [t] + [om[:, k] for k in range(3)] + [q[:, k] for k in range(4)] + \
                [faces[up].tolist()]

    cols = [Column("t", "t (s)", "g10")] + [
        Column(f"omega{i + 1}", f"omega{i + 1} (rad/s)", "g10") for i in range(3)] + [
        Column(f"q{c}", f"q{c}", "g10") for c in "wxyz"] + [Column("up", "face up", "text")]
    note = (f"{box.label}; spin {', '.join(_fmt(v) for v in w)} rad/s at launch, face {start} "
            f"up; attitude as a unit quaternion (w, x, y, z), w >= 0, turning body axes into the "
            f"lab's (z up); face up by the {rule} rule.")
    return Result("coin book --times", cols, [], note, quiet=len(cols) - 1, chunks=chunks())


def _default_span(mo) -> float:
    """Three periods of omega (or, near the middle axis, three flips past the first)."""
    if mo.kind == "rest":
        return 1.0
    if mo.kind in ("periodic",) and math.isfinite(mo.period):
        if mo.gamma_kind == "growth":
            return mo.first_flip + 2.5 * mo.period
        return 3 * mo.period
    if mo.gamma_kind == "oscillation" and mo.gamma > 0:
        return 3 * 2 * math.pi / mo.gamma
    rate = mo.rate or mo.gamma or max(abs(v) for v in mo.omega0)
    return 20 / rate


# --------------------------------------------------------------------------- tosses


def _toss(box, spin, n, seed, flight, start, rule, figure: str | None, progress):
    """The face chances of ``n`` tossed boxes (a Result), or their figure written to
    ``figure`` (then nothing is returned)."""
    count = tosses_value("10000" if n is None else n, high=MAX_TOSSES)
    seed_v = seed_value(seed)
    comps = _three(spin, "--spin")
    dists = [_dist(p, f"--spin component {k}", _spin_value, "rad/s", -math.inf,
                   parse.SPIN_UNITS, "normal:6:1rev/s")
             for k, p in enumerate(comps, start=1)]
    flight_text = "0.5" if flight is None else flight
    fd = _dist(flight_text, "--flight", _time_value, "s", 0.0, _TIME_UNITS,
               "normal:500:50ms")
    # every toss must be one the core can follow, checked at the top of the distributions
    wtop = max(_reach(d) for d in dists)  # |omega| <= sqrt(3) times this, as the core checks
    ttop = _reach(fd)
    _check_phase(wtop * (math.sqrt(3) * ttop), "--flight",
                 f"{flight_text.strip()} (up to {ttop:g} s) with --spin {spin.strip()} (up to "
                 f"{wtop:g} rad/s a component)")
    import numpy as np

    from coincli.core import rigid
    from coincli.core.toss.simulate import wilson_interval

    counts = np.zeros(6, dtype=np.int64)
    bar = progress(count) if progress is not None else contextlib.nullcontext(_no_tick)
    with bar as tick:
        done = 0
        chunks = rigid.toss_chunks(count, seed_v, moments=box.moments, sides=box.sides, spin=dists,
                               flight=fd, start=start, rule=rule)
        while True:
            try:  # a motion the core cannot follow is the input's fault: nothing is printed
                codes = next(chunks, None)
            except ValueError as exc:
                raise usage_error(f"toss {done + 1} to {min(done + rigid.CHUNK, count)}: "
                                  f"{exc}") from None
            if codes is None:
                break
            counts += np.bincount(codes, minlength=6)
            done += codes.size
            tick(done)
    geo = rigid.face_shares(box.sides, rule)
    rows = []
    for k in range(6):
        c = int(counts[k])
        lo, hi = wilson_interval(c, count)
        rows.append((FACES[k], face_size(box, k), c, c / count, lo, hi, geo[k],
                     c / count - geo[k], seed_v))
    columns = [
        Column("face", "face", "text"), Column("face_size", "face size", "text"),
        Column("count", "count", "int"), Column("frequency", "frequency"),
        Column("ci_low", "95% low"), Column("ci_high", "95% high"),
        Column("geometric", "geometric"), Column("difference", "freq - geometric"),
        Column("seed", "seed", "int"),
    ]
    fl = "0.5 s (default)" if flight is None else _typed(flight, _TIME_UNITS, "s")
    spins = ", ".join(_typed(c, parse.SPIN_UNITS, "rad/s") for c in comps)
    note = (f"{count} tosses, seed {seed_v}: {box.label}; spin ~ ({spins}) "
            f"about body axes 1, 2, 3; flight {fl}; face {start} up at launch; {rule} rule.  "
            "95% Wilson intervals.  Geometric: every orientation equally likely (each face's "
            + ("solid angle from the centre / 4 pi)." if rule == "centre" else "1/6).")
            + "  The two differ where the conserved angular momentum keeps some faces from "
            "coming up: a spin about a stable axis turns the box about that axis only.")
    result = Result("coin book --toss", columns, rows, note, quiet=[r[3] for r in rows])
    if figure is not None:
        from coincli.render import book_figures

        _figure(figure, lambda: book_figures.faces_figure(rows, box.label, count, seed_v, rule))
        return []
    return result


def _no_tick(done: int) -> None:
    """No progress shown."""
