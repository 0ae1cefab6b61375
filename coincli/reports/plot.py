"""``coin plot sides|psi|map|phase``: the paper's figures with the user's design and data.

Each report checks the options, computes the figure's data with :mod:`coincli.render.figures`
and either draws it with matplotlib into ``out`` (PNG, SVG or PDF by extension; ``coin: wrote
FILE`` on stderr) and returns None, or, with ``terminal``, ``out="-"`` or no ``out``, returns
the text plot (:mod:`coincli.render.text`) for :func:`coincli.render.text.emit` to print.
Nothing heavy is imported at module level: numpy, scipy, matplotlib and rich load only when a
plot is made.
"""

from __future__ import annotations

import contextlib
import math
import sys

from coincli.errors import compute_error, usage_error
from coincli.io import notes
from coincli.io import grammar as parse
from coincli.io import options
from coincli.limits import DEFAULT_DIAMETER, STANDARD_G
from coincli.reports import bounce as bounce_report
from coincli.reports import phase as phase_report
from coincli.reports.landing import landing_of, parse_physics

MAX_MARKS = 20  # designs marked on one figure
MAX_DATA_BYTES = 10_000_000


# --------------------------------------------------------------------------- shared


def _mark_coins(xi, coin, count, quarters, diameter, thickness) -> list[float]:
    """The coins to mark (the shared coin group; at most MAX_MARKS of them), or none."""
    c = options.resolve_coin(xi, coin, count, quarters, diameter, thickness, many=True,
                              required=False, max_values=MAX_MARKS, command="coin plot")
    return [] if c is None else [float(x) for x in c.xis]


def _one_coin(xi, coin, count, quarters, diameter, thickness) -> float:
    """The one coin of a figure; the dynamically fair coin 1/sqrt 3 when none is given."""
    c = options.resolve_coin(xi, coin, count, quarters, diameter, thickness, required=False,
                              command="coin plot")
    return 1 / math.sqrt(3) if c is None else c.xi


def _one_stdin(**texts) -> None:
    """Only one option may read stdin ('-')."""
    dashes = [f"--{k.replace('_', '-')}" for k, v in texts.items()
              if v is not None and v.strip() == "-"]
    if len(dashes) > 1:
        raise usage_error(f"{' and '.join(dashes)} both read stdin ('-'); give one of them a "
                          "value or a file")


def _marks(text: str | None, what: str, item) -> list[float]:
    if text is None:
        return []
    try:
        vals = parse.parse_values(text, what, item, max_rows=MAX_MARKS)
    except ValueError as exc:
        raise usage_error(str(exc)) from None
    return [float(v) for v in vals]


def _number_or(text: str, what: str, allowed: str) -> float:
    """A finite decimal number; anything else (nan, inf, words) is ``what must be allowed``."""
    try:
        return parse.parse_number(text, what)
    except ValueError:
        raise ValueError(f"{what} must be {allowed}, got {text!r}") from None


def _bounded(text: str, what: str, limits: tuple[float, float], unit: str) -> float:
    lo, hi = limits
    allowed = f"a number of {unit} from {lo:g} to {hi:g}"
    try:
        v = _number_or(text, what, allowed)
    except ValueError as exc:
        raise usage_error(str(exc)) from None
    if not lo <= v <= hi:
        raise usage_error(f"{what} must be {allowed}, got {text!r}")
    return v


def _figure_size(target, width: str | None, height: str | None, dpi: str,
                 default: tuple[float, float]) -> tuple[float, float, float]:
    """--width, --height (inches; ``default`` when not given) and --dpi, checked before any
    computing: each in its range and, for a figure file, at most MAX_PIXELS in all."""
    from coincli.render.figures import DPI_RANGE, FIGURE_INCHES, MAX_PIXELS

    w = default[0] if width is None else _bounded(width, "--width", FIGURE_INCHES, "inches")
    h = default[1] if height is None else _bounded(height, "--height", FIGURE_INCHES, "inches")
    d = _bounded(dpi, "--dpi", DPI_RANGE, "dots per inch")
    if not target.text and w * d * h * d > MAX_PIXELS:
        raise usage_error(
            f"a {w:g} x {h:g} inch figure (--width x --height) at --dpi {d:g} has "
            f"{round(w * d):,} x {round(h * d):,} pixels; at most {MAX_PIXELS:,} are allowed in "
            "all: lower --dpi, --width or --height")
    return w, h, d


def _range_of(text: str, what: str, rule: str, unit: str = ""):
    """LOW:HIGH as two finite numbers; any other text is one error stating ``rule``."""
    in_unit = f" ({unit})" if unit else ""
    bad = usage_error(f"{what} must be LOW:HIGH with {rule}{in_unit}, got {text!r}")
    parts = text.split(":")
    if len(parts) != 2:
        raise bad
    try:
        lo, hi = (parse.parse_number(p, what) for p in parts)
    except ValueError:
        raise bad from None
    return lo, hi, bad


def _xi_range(text: str | None, log: bool):
    """--xi-range within coincli.render.figures's axis limits (matplotlib's tick arithmetic
    overflows, with warnings, near the double range)."""
    if text is None:
        return None
    from coincli.render.figures import MIN_SPAN, XI_AXIS_MAX, XI_LOG_MIN, xi_range_rule

    what = "--xi-range with --log" if log else "--xi-range"
    lo, hi, bad = _range_of(text, what, xi_range_rule(log))
    if not ((XI_LOG_MIN if log else 0.0) <= lo < hi <= XI_AXIS_MAX and hi - lo >= MIN_SPAN):
        raise bad
    return lo, hi


class _Target:
    """Where the plot goes: a figure file, or a text plot on stdout."""

    def __init__(self, out: str | None, terminal: bool):
        if terminal and out not in (None, "-"):
            raise usage_error("give --out FILE (a figure) or --terminal (a text plot), not both")
        self.text = terminal or out in (None, "-")
        self.path = None if self.text else out
        if self.path is not None:
            from coincli.io.files import check_output_path
            from coincli.render.figures import figure_format

            try:
                self.fmt = figure_format(self.path)
                check_output_path(self.path)  # a FIFO, device or directory: refused up front
            except ValueError as exc:
                raise usage_error(f"--out: {exc}") from None
            except OSError as exc:
                raise compute_error(f"cannot write {self.path!r}: {exc.strerror or exc}") \
                    from None

    def check_matplotlib(self):
        """Before any computing: a figure file needs matplotlib (exit 1 with the hint)."""
        if self.text:
            return
        from coincli.render.figures import MatplotlibMissing, require_matplotlib

        try:
            require_matplotlib()
        except MatplotlibMissing as exc:
            raise compute_error(str(exc)) from None

    def save(self, fig, dpi: float) -> None:
        from coincli.render.figures import write_figure

        write_figure(fig, self.path, dpi, too_small=": give a larger --width or --height")

    def text_plot(self, build):
        """The text plot ``build(cols, rows)`` makes in the terminal's size, to print."""
        from coincli.render.text import plot_size

        cols, rows = plot_size()
        return build(cols, rows)


@contextlib.contextmanager
def _quiet():
    """No library warning reaches stderr (the rule: nothing but the result on success).

    The options are checked up front so that the figure is right without them (matplotlib's
    tick arithmetic overflows near the double range, numpy warns on an overflow inside the core
    before the core refuses the value); this is the belt to those braces: Python warnings are
    dropped and matplotlib's logger, which prints through logging's last-resort handler when
    nothing is configured, is silenced below CRITICAL.
    """
    import logging
    import warnings

    log = logging.getLogger("matplotlib")
    level = log.level
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        log.setLevel(logging.CRITICAL)
        try:
            yield
        finally:
            log.setLevel(level)


def _compute(fn, *args, **kwargs):
    """Run a data function; a ValueError from the core is exit 1 (valid input, no answer)."""
    try:
        return fn(*args, **kwargs)
    except ValueError as exc:
        raise compute_error(str(exc)) from None


# --------------------------------------------------------------------------- sides


def _read_data(path: str):
    from coincli.io.experiments import parse_experiments
    from coincli.io.files import Unreadable, read_text

    name = "stdin" if path == "-" else path
    if path == "-" and sys.stdin is None:
        raise usage_error("--data -: reads your tosses from standard input, but there is none "
                          "(it is closed)")
    try:
        text = read_text(sys.stdin if path == "-" else path, MAX_DATA_BYTES)
    except Unreadable as exc:
        raise usage_error({
            "kind": f"--data: cannot read {name!r}: it is {exc.detail}, not a regular file; give "
                    "a CSV file, or '-' to read a pipe",
            "system": f"--data: cannot read {name!r}: {exc.detail}",
            "size": f"--data: {name!r} is larger than {MAX_DATA_BYTES} bytes",
            "nul": f"--data: {name!r} contains a NUL byte; expected a CSV text file",
            "utf8": f"--data: {name!r} is not UTF-8 text",
        }[exc.reason]) from None
    try:
        exps = parse_experiments(text)
    except ValueError as exc:
        raise usage_error(f"--data {name}: {exc}") from None
    caught = next((e for e in exps if getattr(e.counts, "caught", False)), None)
    if caught is not None:
        raise usage_error(f"--data {name}: line {caught.line} is caught flips (faces only), "
                          "with no sides to plot; coin fit reads them")
    return exps


def sides(*, xi=None, coin=None, count=None, quarters=None, diameter=None, thickness=None,
          p_sides=None, psi=None, psi_dist=None, data=None, log=False, xi_range=None, out=None,
          terminal=False, dpi="150", width=None, height=None, title=None, landing="catch",
          surface=None, restitution=None, friction=None, seed=None, tosses=None, jobs=None,
          calibration=None, scheduler=None, checkpoint=None, timeout=None):
    """``coin plot sides``: P(sides) against the aspect ratio for the geometric and dynamic
    models (Fig. 5a), the user's designs, data and psi curves marked; with
    ``landing="bounce"``, points simulated onto a surface and the probit fitted to them (said
    on stderr).  The text plot, or None when ``out`` was written."""
    physics = parse_physics(landing_of(landing), surface=surface, restitution=restitution,
                            friction=friction, jobs=jobs, calibration=calibration,
                            scheduler=scheduler, checkpoint=checkpoint, timeout=timeout)
    if physics is None and (seed is not None or tosses is not None):
        raise usage_error("--seed and -n go with --landing bounce")
    target = _Target(out, terminal)
    _one_stdin(xi=xi, count=count, quarters=quarters, data=data)
    xi_marks = _mark_coins(xi, coin, count, quarters, diameter, thickness)
    p_marks = _marks(p_sides, "--p-sides", parse.parse_probability)
    psi_curves = (options.psi_angles(psi, max_rows=MAX_MARKS) if psi is not None else [])
    dens = options.psi_densities(psi_dist) if psi_dist is not None else []
    rng = _xi_range(xi_range, log)
    exps = _read_data(data) if data is not None else []
    w, h, d = _figure_size(target, width, height, dpi, (7.0, 4.5))
    target.check_matplotlib()
    bounce = None
    if physics is not None:
        from coincli.reports.calibrated import bounce_launch_for
        from coincli.reports.physics import bounce_tosses

        count = 400 if tosses is None else bounce_tosses(tosses, high=100_000)
        seed_v = options.seed_value(seed)
        u_spec, w_spec, psi_spec, labels = bounce_launch_for(physics, None, None, None, None)
        lo, hi = rng if rng is not None else (0.1, 2.0)
        lo, hi = max(lo, bounce_report.PLOT_XI[0]), min(hi, bounce_report.PLOT_XI[1])
        if not lo < hi:
            raise usage_error(f"--xi-range {xi_range.strip()!r} holds no aspect ratio that "
                              f"--landing bounce simulates ({bounce_report.PLOT_XI[0]:g} to "
                              f"{bounce_report.PLOT_XI[1]:g}); give a range that overlaps it")
        import numpy as np

        xis = [float(x) for x in np.geomspace(lo, hi, 8)]
        pts, fitted, why = bounce_report.sides_points(physics, seed=seed_v, n=count, xis=xis,
                                                      u=u_spec, omega=w_spec, psi=psi_spec,
                                                      diameter=DEFAULT_DIAMETER, g=STANDARD_G)
        bounce = (pts, fitted)
        if fitted is None:
            curve = f"no curve: {why}"
        elif fitted.rejected:
            curve = (f"the probit fitted to them is rejected by them (fit p-value "
                     f"{fitted.fit.p_value:.3g}): drawn dashed, for reference only")
        else:
            curve = (f"the curve is the probit fitted to them (fit p-value "
                     f"{fitted.fit.p_value:.3g})")
        if fitted is not None and why:  # tosses that did not settle
            curve += f"; {why}"
        notes.note(f"simulated points: {count} tosses at each of 8 xi from {lo:.4g} to "
                   f"{hi:.4g} onto {physics.describe()}, {labels}; seed {seed_v}; {curve}")
    with _quiet():
        return _sides(target, xi_marks, p_marks, psi_curves, dens, rng, exps, log, (w, h, d),
                      title, bounce)


def _sides(target, xi_marks, p_marks, psi_curves, dens, rng, exps, log, size, title,
           bounce=None):
    from coincli.render import figures

    models = [figures.GEOMETRIC, figures.DYNAMIC]
    models += [figures.psi_spec(math.pi if d == 180 else math.radians(d)) for d in psi_curves]
    models += [figures.density_spec(d) for d in dens]
    points = _compute(figures.experiment_points, exps) if exps else []
    if bounce is not None:
        if bounce[1] is not None:
            models.append(bounce[1])
        points = points + bounce[0]

    def build(n):
        return _compute(figures.sides_data, models, xi_marks=xi_marks, p_marks=p_marks,
                        experiments=points, log=log, xi_range=rng, points=n)

    if target.text:
        from coincli.render.text import text_sides

        return target.text_plot(lambda c, r: text_sides(build(c), c, r))
    data = build(401)
    w, h, dpi = size
    fig = figures.sides_figure(data, width=w, height=h, title=title)
    target.save(fig, dpi)
    _notes(data.skipped)


def _notes(skipped) -> None:
    """What could not be drawn (a design off the axis), one note each."""
    for n in skipped:
        notes.note(n)


# --------------------------------------------------------------------------- psi


def psi(*, xi=None, coin=None, count=None, quarters=None, diameter=None, thickness=None,
        psi=None, out=None, terminal=False, dpi="150", width=None, height=None, title=None):
    """``coin plot psi``: P(heads), P(sides), P(tails) against psi for one coin, regimes
    shaded (Fig. 2d), ``psi`` marked.  The text plot, or None when ``out`` was written."""
    target = _Target(out, terminal)
    x = _one_coin(xi, coin, count, quarters, diameter, thickness)
    marks = options.psi_angles(psi, max_rows=MAX_MARKS) if psi is not None else []
    w, h, d = _figure_size(target, width, height, dpi, (7.0, 4.5))
    target.check_matplotlib()
    with _quiet():
        from coincli.render import figures

        if target.text:
            from coincli.render.text import text_psi

            return target.text_plot(
                lambda c, r: text_psi(_compute(figures.psi_data, x, marks, points=c), c, r))
        fig = figures.psi_figure(_compute(figures.psi_data, x, marks), width=w, height=h,
                                 title=title)
        target.save(fig, d)
    return None


# --------------------------------------------------------------------------- map


def map(*, style="panels", xi=None, coin=None, count=None, quarters=None, diameter=None,
        thickness=None, psi=None, log=False, xi_range=None, out=None, terminal=False,
        dpi="150", width=None, height=None, title=None):
    """``coin plot map``: the chances of heads, sides and tails over the (xi, psi) plane
    (Fig. 2a-c), as three panels or one ternary map.  The text plot, or None when ``out`` was
    written."""
    target = _Target(out, terminal)
    st = style.strip().lower()
    if st not in ("panels", "ternary"):
        raise usage_error(f"--style must be panels or ternary, got {style!r}")
    _one_stdin(xi=xi, count=count, quarters=quarters)
    xi_marks = _mark_coins(xi, coin, count, quarters, diameter, thickness)
    psi_marks = options.psi_angles(psi, max_rows=MAX_MARKS) if psi is not None else []
    rng = _xi_range(xi_range, log)
    from coincli.render.maps import MAP_SIZES

    w, h, dots = _figure_size(target, width, height, dpi, MAP_SIZES[st])
    target.check_matplotlib()
    with _quiet():
        from coincli.render import maps

        if target.text:
            from coincli.render.text import text_map

            def build(c, r):
                d = _compute(maps.map_data, xi_range=rng, log=log, nx=c, ny=r,
                             xi_marks=xi_marks, psi_marks_deg=psi_marks)
                return text_map(d, c, r)

            return target.text_plot(build)
        d = _compute(maps.map_data, xi_range=rng, log=log, xi_marks=xi_marks,
                     psi_marks_deg=psi_marks)
        fig = maps.map_figure(d, style=st, width=w, height=h, title=title)
        target.save(fig, dots)
        _notes(d.skipped)
    return None


# --------------------------------------------------------------------------- phase


def phase(*, xi=None, coin=None, count=None, quarters=None, diameter=None, thickness=None,
          psi="90", u=None, omega=None, cols=None, rows=None, exact=False, no_curves=False,
          toss=None, g="9.81", contact="rim", u_range=None, omega_range=None,
          exact_curves=False, resolution=None, out=None, terminal=False, dpi="150", width=None,
          height=None, title=None):
    """``coin plot phase``: the picture of ``coin phase`` (:mod:`coincli.reports.phase`) as a
    figure, or as a text plot.  The text plot, or None when ``out`` was written."""
    target = _Target(out, terminal)
    ph = phase_report.resolve(xi=xi, coin=coin, count=count, quarters=quarters, diameter=diameter,
                    thickness=thickness, psi=psi, u=u, omega=omega, cols=cols, rows=rows,
                    exact=exact, no_curves=no_curves, toss=toss, g=g, contact=contact,
                    old_u=u_range, old_omega=omega_range, old_exact=exact_curves,
                    old_resolution=resolution)
    w, h, d = _figure_size(target, width, height, dpi, (9.5, 5.5))
    target.check_matplotlib()
    with _quiet():
        if target.text:
            from coincli.render.text import text_phase

            nu, nw = phase_report.text_size(ph)
            return text_phase(phase_report.data(ph, nu, nw), nu, nw, ph.contact)
        from coincli.render import maps

        cells = phase_report.FIGURE_CELLS
        data = phase_report.data(ph, ph.cols or cells, ph.rows or cells, figure=True)
        fig = maps.phase_figure(data, width=w, height=h, title=title)
        target.save(fig, d)
    return None
