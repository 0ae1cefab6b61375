"""``coin plot sides|psi|map|phase``: the paper's figures with the user's design and data.

Thin: parse the options, compute the figure's data with :mod:`coincli.render.figures`, then either draw
it with matplotlib into ``--out FILE`` (PNG, SVG or PDF by extension) or, with ``--terminal``,
``--out -`` or no ``--out``, print a text plot (:mod:`coincli.render.text`).  Nothing heavy is
imported at module level: numpy, scipy, matplotlib and rich load only when a plot is made.
"""

from __future__ import annotations

import contextlib
import math
import sys
from typing import Annotated

import typer

from coincli.cli import _bounce as BO
from coincli.cli import _options, _phase, app
from coincli.errors import compute_error
from coincli.io import grammar as parse
from coincli.io import options
from coincli.io.table import usage_error
from coincli.render.figures import write_figure

plot_app = typer.Typer(
    name="plot",
    help="Draw the paper's figures with your design and data on them: sides (Fig. 5a), psi "
    "(Fig. 2d), map (Fig. 2a-c), phase (Fig. 3).  PNG, SVG or PDF by the --out file's "
    "extension (needs matplotlib: pip install 'coincli\\[plot]'); a text plot in the terminal "
    "otherwise.  Example: coin plot sides --p-sides 1/3 --out sides.png",
    no_args_is_help=True,
    context_settings={"help_option_names": ["-h", "--help"]},
)
app.add_typer(plot_app, name="plot")

MAX_MARKS = 20  # designs marked on one figure
MAX_DATA_BYTES = 10_000_000

# --------------------------------------------------------------------------- shared options

OutOpt = Annotated[
    str | None,
    typer.Option("--out", "-o", help="Figure file .png, .svg or .pdf; - or none: a text "
                 "plot.", metavar="FILE"),
]
TerminalOpt = Annotated[
    bool, typer.Option("--terminal", help="A text plot on stdout (needs no matplotlib).")
]
# Sizes are parsed here, not by click: click's FloatRange lets nan through (nan < 1 is False) and
# its messages do not say what is allowed.  Limits: coincli.render.figures.FIGURE_INCHES, DPI_RANGE and
# MAX_PIXELS (width x dpi times height x dpi, so a figure cannot exhaust the memory).
DpiOpt = Annotated[str, typer.Option("--dpi", help="Dots per inch of a PNG, 10 to 2000 (50 "
                                     "Mpixel at most).", metavar="DPI")]
WidthOpt = Annotated[
    str | None, typer.Option("--width", help="Figure width, 1 to 100 inches.",
                             metavar="INCHES")
]
HeightOpt = Annotated[
    str | None, typer.Option("--height", help="Figure height, 1 to 100 inches.",
                             metavar="INCHES")
]
TitleOpt = Annotated[str | None, typer.Option("--title", help="Replace the figure's title.")]
LogOpt = Annotated[bool, typer.Option("--log", help="Logarithmic xi axis (0.01 to 100).")]
XiRangeOpt = Annotated[
    str | None, typer.Option("--xi-range", help="The xi axis LOW:HIGH (default: 0:2, widened "
                             "to show your marks).", metavar="LOW:HIGH")
]
PsiMarkOpt = Annotated[
    str | None, typer.Option("--psi", help="Mark tossing angles psi, degrees [0, 180]: a "
                             "value, a list a,b or a range.", metavar="DEG")
]


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


def _xi_item(s: str, what: str) -> float:
    allowed = "a finite number >= 0 (the aspect ratio h/D)"
    v = _number_or(s, what, allowed)
    if not v >= 0:
        raise ValueError(f"{what} must be {allowed}, got {s!r}")
    return v


def _deg_item(s: str, what: str) -> float:
    allowed = "an angle in [0, 180] degrees"
    v = _number_or(s, what, allowed)
    if not 0.0 <= v <= 180.0:
        raise ValueError(f"{what} must be {allowed}, got {s!r}")
    return v


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
    """--xi-range within coincli.render.figures's axis limits (matplotlib's tick arithmetic overflows,
    with warnings, near the double range)."""
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
        write_figure(fig, self.path, dpi, too_small=": give a larger --width or --height")

    def text_plot(self, build):
        from coincli.render.text import emit, plot_size

        cols, rows = plot_size()
        emit(build(cols, rows))


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
    from coincli.io.files import FileKindError, read_capped, read_regular, stream_reader

    name = "stdin" if path == "-" else path
    try:
        if path == "-":
            if sys.stdin is None:
                raise usage_error("--data -: reads your tosses from standard input, but there "
                                  "is none (it is closed)")
            data, why = read_capped(stream_reader(sys.stdin), MAX_DATA_BYTES)
        else:
            data, why = read_regular(path, MAX_DATA_BYTES)
    except FileKindError as exc:
        raise usage_error(f"--data: cannot read {name!r}: it is {exc.kind}, not a regular file; "
                          "give a CSV file, or '-' to read a pipe") from None
    except OSError as exc:
        raise usage_error(f"--data: cannot read {name!r}: {exc.strerror or exc}") from None
    if why == "size":
        raise usage_error(f"--data: {name!r} is larger than {MAX_DATA_BYTES} bytes")
    if why == "nul":
        raise usage_error(f"--data: {name!r} contains a NUL byte; expected a CSV text file")
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError:
        raise usage_error(f"--data: {name!r} is not UTF-8 text") from None
    try:
        return parse_experiments(text)
    except ValueError as exc:
        raise usage_error(f"--data {name}: {exc}") from None


@plot_app.command("sides")
def sides(
    xi: _options.XisOpt = None,
    coin: _options.CoinOpt = None,
    count: _options.CountsOpt = None,
    quarters: _options.QuartersManyOpt = None,
    diameter: _options.DiameterOpt = None,
    thickness: _options.ThicknessOpt = None,
    p_sides: Annotated[
        str | None, typer.Option("--p-sides", "-p", metavar="P", help="Mark target chances of "
                                 "a side (0.33, 1/3, 33%; a list a,b).")
    ] = None,
    psi: _options.PsisOpt = None,
    psi_dist: _options.PsiDistsOpt = None,
    data: Annotated[
        str | None, typer.Option("--data", help="Your tosses, a coin fit CSV, or - (stdin).",
                                 metavar="FILE")
    ] = None,
    log: LogOpt = False,
    xi_range: XiRangeOpt = None,
    out: OutOpt = None,
    terminal: TerminalOpt = False,
    dpi: DpiOpt = "150",
    width: WidthOpt = None,
    height: HeightOpt = None,
    title: TitleOpt = None,
    landing: BO.LandingOpt = "catch",
    surface: BO.SurfaceOpt = None,
    restitution: BO.RestitutionOpt = None,
    friction: BO.FrictionOpt = None,
    seed: _options.SeedOpt = None,
    tosses: _options.TossesOpt = None,
    jobs: BO.JobsOpt = None,
):
    """P(sides) against the aspect ratio for the geometric and dynamic models (Fig. 5a).

    The fair coins of both models are marked; the coin options (--xi, --coin/--count,
    --quarters, --diameter/--thickness) and --p-sides mark your designs, --data your tosses
    with 95% Wilson intervals; --psi and --psi-dist add curves.

    --landing bounce adds tosses simulated onto a surface (MuJoCo; the hand toss of coin
    simulate: u ~ normal:2.4:0.3 m/s, omega ~ normal:38:4 rev/s, psi ~ normal:90:10 deg):
    points with 95% intervals at 8 aspect ratios and the probit curve fitted to them.

    Examples: coin plot sides --out sides.png ;  coin plot sides --p-sides 1/3 --log --terminal ;
    coin plot sides --quarters 6:10:1 --psi-dist normal:90:18 --out sides.svg ;
    coin plot sides --landing bounce --surface wood --seed 1 --out bounce.png
    """
    physics = BO.parse_physics(BO.landing_of(landing), surface=surface, restitution=restitution,
                               friction=friction, jobs=jobs)
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
        from coincli.cli.toss import bounce_launch

        count = 400 if tosses is None else options.tosses_value(tosses, high=100_000)
        seed_v = options.seed_value(seed)
        u_spec, w_spec, psi_spec, labels = bounce_launch(None, None, None, None)
        lo, hi = rng if rng is not None else (0.1, 2.0)
        lo, hi = max(lo, BO.PLOT_XI[0]), min(hi, BO.PLOT_XI[1])
        if not lo < hi:
            raise usage_error(f"--xi-range {xi_range.strip()!r} holds no aspect ratio that "
                              f"--landing bounce simulates ({BO.PLOT_XI[0]:g} to "
                              f"{BO.PLOT_XI[1]:g}); give a range that overlaps it")
        import numpy as np

        xis = [float(x) for x in np.geomspace(lo, hi, 8)]
        pts, fitted, why = BO.sides_points(physics, seed=seed_v, n=count, xis=xis, u=u_spec,
                                           omega=w_spec, psi=psi_spec, diameter=0.02426, g=9.81)
        bounce = (pts, fitted)
        curve = (f"the curve is the probit fitted to them (fit p-value "
                 f"{fitted.fit.p_value:.3g})" if fitted is not None else f"no curve: {why}")
        sys.stderr.write(f"coin: note: simulated points: {count} tosses at each of 8 xi from "
                         f"{lo:.4g} to {hi:.4g} onto {physics.describe()}, {labels}; seed "
                         f"{seed_v}; {curve}\n")
    with _quiet():
        _sides(target, xi_marks, p_marks, psi_curves, dens, rng, exps, log, (w, h, d), title,
               bounce)


def _sides(target, xi_marks, p_marks, psi_curves, dens, rng, exps, log, size, title,
           bounce=None):
    from coincli.render import figures as P

    models = [P.GEOMETRIC, P.DYNAMIC]
    models += [P.psi_spec(math.pi if d == 180 else math.radians(d)) for d in psi_curves]
    models += [P.density_spec(d) for d in dens]
    points = _compute(P.experiment_points, exps) if exps else []
    if bounce is not None:
        if bounce[1] is not None:
            models.append(bounce[1])
        points = points + bounce[0]

    def build(n):
        return _compute(P.sides_data, models, xi_marks=xi_marks, p_marks=p_marks,
                        experiments=points, log=log, xi_range=rng, points=n)

    if target.text:
        from coincli.render.text import text_sides

        target.text_plot(lambda c, r: text_sides(build(c), c, r))
        return
    data = build(401)
    w, h, dpi = size
    fig = P.sides_figure(data, width=w, height=h, title=title)
    target.save(fig, dpi)
    _notes(data.skipped)


def _notes(notes) -> None:
    """What could not be drawn (a design off the axis), one line each on stderr."""
    for n in notes:
        sys.stderr.write(f"coin: note: {n}\n")


# --------------------------------------------------------------------------- psi


@plot_app.command("psi")
def psi_cmd(
    xi: _options.XiOpt = None,
    coin: _options.CoinOpt = None,
    count: _options.CountOpt = None,
    quarters: _options.QuartersOpt = None,
    diameter: _options.DiameterOpt = None,
    thickness: _options.ThicknessOpt = None,
    psi: PsiMarkOpt = None,
    out: OutOpt = None,
    terminal: TerminalOpt = False,
    dpi: DpiOpt = "150",
    width: WidthOpt = None,
    height: HeightOpt = None,
    title: TitleOpt = None,
):
    """P(heads), P(sides), P(tails) against psi for one coin, regimes shaded (Fig. 2d).

    Below theta0/2 the coin always lands heads, up to 90 - theta0/2 heads or sides, within
    theta0/2 of 90 degrees all three.  The coin defaults to xi = 1/sqrt 3; --psi marks your
    tossing angles.

    Examples: coin plot psi --xi 0.577 --out psi.png ;
    coin plot psi --quarters 8 --psi 70 --terminal
    """
    target = _Target(out, terminal)
    x = _one_coin(xi, coin, count, quarters, diameter, thickness)
    marks = options.psi_angles(psi, max_rows=MAX_MARKS) if psi is not None else []
    w, h, d = _figure_size(target, width, height, dpi, (7.0, 4.5))
    target.check_matplotlib()
    with _quiet():
        from coincli.render import figures as P

        if target.text:
            from coincli.render.text import text_psi

            target.text_plot(lambda c, r: text_psi(_compute(P.psi_data, x, marks, points=c), c,
                                                   r))
            return
        fig = P.psi_figure(_compute(P.psi_data, x, marks), width=w, height=h, title=title)
        target.save(fig, d)


# --------------------------------------------------------------------------- map


@plot_app.command("map")
def map_cmd(
    style: Annotated[
        str, typer.Option("--style", help="panels (three maps, one per outcome) or ternary "
                          "(one map, colours mixed by the three chances).")
    ] = "panels",
    xi: _options.XisOpt = None,
    coin: _options.CoinOpt = None,
    count: _options.CountsOpt = None,
    quarters: _options.QuartersManyOpt = None,
    diameter: _options.DiameterOpt = None,
    thickness: _options.ThicknessOpt = None,
    psi: PsiMarkOpt = None,
    log: LogOpt = False,
    xi_range: XiRangeOpt = None,
    out: OutOpt = None,
    terminal: TerminalOpt = False,
    dpi: DpiOpt = "150",
    width: WidthOpt = None,
    height: HeightOpt = None,
    title: TitleOpt = None,
):
    """The chances of heads, sides and tails over the (xi, psi) plane (Fig. 2a-c).

    Table I on a grid; regime boundaries dashed, the white contour is 1/3, the star is the
    fair three-sided coin (xi = 1/sqrt 3, psi = 90).  The coin options and --psi mark your
    designs.

    Examples: coin plot map --out map.png ;
    coin plot map --style ternary --xi 0.5 --psi 80 --out map.pdf ;  coin plot map --terminal
    """
    target = _Target(out, terminal)
    st = style.strip().lower()
    if st not in ("panels", "ternary"):
        raise usage_error(f"--style must be panels or ternary, got {style!r}")
    _one_stdin(xi=xi, count=count, quarters=quarters)
    xi_marks = _mark_coins(xi, coin, count, quarters, diameter, thickness)
    psi_marks = options.psi_angles(psi, max_rows=MAX_MARKS) if psi is not None else []
    rng = _xi_range(xi_range, log)
    from coincli.render.figures import MAP_SIZES

    w, h, dots = _figure_size(target, width, height, dpi, MAP_SIZES[st])
    target.check_matplotlib()
    with _quiet():
        from coincli.render import figures as P

        if target.text:
            from coincli.render.text import text_map

            def build(c, r):
                d = _compute(P.map_data, xi_range=rng, log=log, nx=c, ny=r, xi_marks=xi_marks,
                             psi_marks_deg=psi_marks)
                return text_map(d, c, r)

            target.text_plot(build)
            return
        d = _compute(P.map_data, xi_range=rng, log=log, xi_marks=xi_marks,
                     psi_marks_deg=psi_marks)
        fig = P.map_figure(d, style=st, width=w, height=h, title=title)
        target.save(fig, dots)
        _notes(d.skipped)


# --------------------------------------------------------------------------- phase


@plot_app.command("phase")
def phase_cmd(
    xi: _options.XiOpt = None,
    coin: _options.CoinOpt = None,
    count: _options.CountOpt = None,
    quarters: _options.QuartersOpt = None,
    diameter: _options.DiameterOpt = None,
    thickness: _options.ThicknessOpt = None,
    psi: _phase.PsiOpt = "90",
    u: _phase.URangeOpt = None,
    omega: _phase.OmegaRangeOpt = None,
    cols: _phase.ColsOpt = None,
    rows: _phase.RowsOpt = None,
    exact: _phase.ExactOpt = False,
    no_curves: _phase.NoCurvesOpt = False,
    toss: _phase.TossMarkOpt = None,
    g: _phase.GOpt = "9.81",
    contact: _phase.ContactOpt = "rim",
    u_range: _phase.OldURangeOpt = None,
    omega_range: _phase.OldOmegaRangeOpt = None,
    exact_curves: _phase.OldExactOpt = False,
    resolution: _phase.OldResolutionOpt = None,
    out: OutOpt = None,
    terminal: TerminalOpt = False,
    dpi: DpiOpt = "150",
    width: WidthOpt = None,
    height: HeightOpt = None,
    title: TitleOpt = None,
):
    """The outcome over launch speed and spin for one coin (Fig. 3): coin phase as a figure.

    The same picture and the same options as `coin phase` (which see): each cell is one
    finite toss; the dashed curves are eq. 10's hyperbolae omega = (2n +- theta0/pi) pi g /
    (2u).  Far from the origin the shares approach the vigorous limit of Table I.

    Examples: coin plot phase --out phase.png ;  coin plot phase --xi 0.3 --psi 70 --terminal ;
    coin plot phase --toss 1.2:40 --u 0:3 --omega 0:100 --out phase.svg
    """
    target = _Target(out, terminal)
    ph = _phase.resolve(xi=xi, coin=coin, count=count, quarters=quarters, diameter=diameter,
                        thickness=thickness, psi=psi, u=u, omega=omega, cols=cols, rows=rows,
                        exact=exact, no_curves=no_curves, toss=toss, g=g, contact=contact,
                        old_u=u_range, old_omega=omega_range, old_exact=exact_curves,
                        old_resolution=resolution)
    w, h, d = _figure_size(target, width, height, dpi, (9.5, 5.5))
    target.check_matplotlib()
    with _quiet():
        if target.text:
            from coincli.render.text import emit, text_phase

            nu, nw = _phase.text_size(ph)
            emit(text_phase(_phase.data(ph, nu, nw), nu, nw, ph.contact))
            return
        from coincli.render import figures as P

        data = _phase.data(ph, ph.cols or _phase.FIGURE_CELLS, ph.rows or _phase.FIGURE_CELLS,
                           figure=True)
        fig = P.phase_figure(data, width=w, height=h, title=title)
        target.save(fig, d)
