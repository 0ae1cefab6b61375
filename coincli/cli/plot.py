"""``coin plot sides|psi|map|phase``: the paper's figures with the user's design and data.

Thin: parse the options, compute the figure's data with :mod:`coincli.plot`, then either draw
it with matplotlib into ``--out FILE`` (PNG, SVG or PDF by extension) or, with ``--terminal``,
``--out -`` or no ``--out``, print a text plot (:mod:`coincli.textplot`).  Nothing heavy is
imported at module level: numpy, scipy, matplotlib and rich load only when a plot is made.
"""

from __future__ import annotations

import contextlib
import math
import sys
from typing import Annotated

import typer

from coincli import parse
from coincli.cli import _options, app
from coincli.cli._common import compute_error, usage_error

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
MAX_DIAMETER_M = 1e100  # the toss engine's largest diameter

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
# its messages do not say what is allowed.  Limits: coincli.plot.FIGURE_INCHES, DPI_RANGE and
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
    c = _options.resolve_coin(xi, coin, count, quarters, diameter, thickness, many=True,
                              required=False, max_values=MAX_MARKS, command="coin plot")
    return [] if c is None else [float(x) for x in c.xis]


def _one_coin(xi, coin, count, quarters, diameter, thickness) -> float:
    """The one coin of a figure; the dynamically fair coin 1/sqrt 3 when none is given."""
    c = _options.resolve_coin(xi, coin, count, quarters, diameter, thickness, required=False,
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
    from coincli.plot import DPI_RANGE, FIGURE_INCHES, MAX_PIXELS

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
    """--xi-range within coincli.plot's axis limits (matplotlib's tick arithmetic overflows,
    with warnings, near the double range)."""
    if text is None:
        return None
    from coincli.plot import MIN_SPAN, XI_AXIS_MAX, XI_LOG_MIN, xi_range_rule

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
            from coincli._files import check_output_path
            from coincli.plot import figure_format

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
        from coincli.plot import MatplotlibMissing, require_matplotlib

        try:
            require_matplotlib()
        except MatplotlibMissing as exc:
            raise compute_error(str(exc)) from None

    def save(self, fig, dpi: float) -> None:
        from coincli._files import FileKindError
        from coincli.plot import FigureTooSmall, save_figure

        try:
            save_figure(fig, self.path, dpi)
        except FigureTooSmall as exc:
            raise usage_error(f"{exc}: give a larger --width or --height") from None
        except FileKindError as exc:
            raise usage_error(f"--out: {exc}") from None
        except OSError as exc:
            raise compute_error(f"cannot write {self.path!r}: {exc.strerror or exc}") from None
        except MemoryError:
            raise compute_error(f"not enough memory to draw {self.path!r}: lower --dpi, "
                                "--width or --height") from None
        w, h = (float(v) for v in fig.get_size_inches())
        if self.fmt == "png":
            dims = f"{round(w * dpi)} x {round(h * dpi)} pixels"
        else:
            dims = f"{w:g} x {h:g} inches"
        sys.stderr.write(f"coin: wrote {self.path} ({dims})\n")

    def text_plot(self, build):
        from coincli.textplot import emit, plot_size

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
    from coincli._files import FileKindError, read_capped, read_regular
    from coincli.cli._common import stream_reader
    from coincli.stats import parse_experiments

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
):
    """P(sides) against the aspect ratio for the geometric and dynamic models (Fig. 5a).

    The fair coins of both models are marked; the coin options (--xi, --coin/--count,
    --quarters, --diameter/--thickness) and --p-sides mark your designs, --data your tosses
    with 95% Wilson intervals; --psi and --psi-dist add curves.

    Examples: coin plot sides --out sides.png ;  coin plot sides --p-sides 1/3 --log --terminal ;
    coin plot sides --quarters 6:10:1 --psi-dist normal:90:18 --out sides.svg
    """
    target = _Target(out, terminal)
    _one_stdin(xi=xi, count=count, quarters=quarters, data=data)
    xi_marks = _mark_coins(xi, coin, count, quarters, diameter, thickness)
    p_marks = _marks(p_sides, "--p-sides", parse.parse_probability)
    psi_curves = (_options.psi_angles(psi, max_rows=MAX_MARKS) if psi is not None else [])
    dens = _options.psi_densities(psi_dist) if psi_dist is not None else []
    rng = _xi_range(xi_range, log)
    exps = _read_data(data) if data is not None else []
    w, h, d = _figure_size(target, width, height, dpi, (7.0, 4.5))
    target.check_matplotlib()
    with _quiet():
        _sides(target, xi_marks, p_marks, psi_curves, dens, rng, exps, log, (w, h, d), title)


def _sides(target, xi_marks, p_marks, psi_curves, dens, rng, exps, log, size, title):
    from coincli import plot as P

    models = [P.GEOMETRIC, P.DYNAMIC]
    models += [P.psi_spec(math.pi if d == 180 else math.radians(d)) for d in psi_curves]
    models += [P.density_spec(d) for d in dens]
    points = _compute(P.experiment_points, exps) if exps else []

    def build(n):
        return _compute(P.sides_data, models, xi_marks=xi_marks, p_marks=p_marks,
                        experiments=points, log=log, xi_range=rng, points=n)

    if target.text:
        from coincli.textplot import text_sides

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
    marks = _options.psi_angles(psi, max_rows=MAX_MARKS) if psi is not None else []
    w, h, d = _figure_size(target, width, height, dpi, (7.0, 4.5))
    target.check_matplotlib()
    with _quiet():
        from coincli import plot as P

        if target.text:
            from coincli.textplot import text_psi

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
    psi_marks = _options.psi_angles(psi, max_rows=MAX_MARKS) if psi is not None else []
    rng = _xi_range(xi_range, log)
    from coincli.plot import MAP_SIZES

    w, h, dots = _figure_size(target, width, height, dpi, MAP_SIZES[st])
    target.check_matplotlib()
    with _quiet():
        from coincli import plot as P

        if target.text:
            from coincli.textplot import text_map

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


def _pair(text: str | None, what: str, default, unit: str, top: float):
    """A phase axis LOW:HIGH up to ``top`` and at least coincli.plot.MIN_SPAN wide."""
    if text is None:
        return default
    from coincli.plot import MIN_SPAN, short_g

    rule = f"0 <= LOW < HIGH <= {short_g(top)} and HIGH - LOW >= {short_g(MIN_SPAN)}"
    lo, hi, bad = _range_of(text, what, rule, unit)
    if not (0 <= lo < hi <= top and hi - lo >= MIN_SPAN):
        raise bad
    return lo, hi


def _tosses(text: str | None) -> list[tuple[float, float]]:
    if text is None:
        return []
    out = []
    for item in text.split(","):
        bad = usage_error("--toss must be U:OMEGA, finite numbers >= 0 in m/s and rad/s (a list "
                          f"a:b,c:d for several); got {item!r}")
        parts = item.split(":")
        if len(parts) != 2:
            raise bad
        try:
            u, w = (parse.parse_number(p, "--toss") for p in parts)
        except ValueError:
            raise bad from None
        if u < 0 or w < 0:
            raise bad
        out.append((u, w))
    if len(out) > MAX_MARKS:
        raise usage_error(f"--toss marks at most {MAX_MARKS} tosses")
    return out


@plot_app.command("phase")
def phase_cmd(
    xi: Annotated[
        str | None, typer.Option("--xi", "-x", help="The coin's aspect ratio h/D (default "
                                 "1/sqrt 3 = 0.57735, the paper's Fig. 3).")
    ] = None,
    psi: Annotated[
        str, typer.Option("--psi", help="Angle between angular momentum and normal, degrees "
                          "[0, 180] (default 90: the Keller flip).", metavar="DEG")
    ] = "90",
    u_range: Annotated[
        str | None, typer.Option("--u-range", help="Launch speeds LOW:HIGH in m/s (default "
                                 "0:2).", metavar="LOW:HIGH")
    ] = None,
    omega_range: Annotated[
        str | None, typer.Option("--omega-range", help="Precession rates LOW:HIGH in rad/s "
                                 "(default 0:60).", metavar="LOW:HIGH")
    ] = None,
    diameter: Annotated[
        str | None, typer.Option("--diameter", "-d", help="Coin diameter (mm, or with a unit: "
                                 "0.955in, 2.4cm; default a US quarter, 24.26 mm).")
    ] = None,
    contact: Annotated[
        str, typer.Option("--contact", help="rim (the paper's: the rim of the mid-plane disc "
                          "touches down) or thick (the lowest corner of the cylinder).")
    ] = "rim",
    exact_curves: Annotated[
        bool, typer.Option("--exact-curves", help="Draw the boundaries at the exact contact "
                           "time instead of eq. 10's t_f = 2u/g.")
    ] = False,
    toss: Annotated[
        str | None, typer.Option("--toss", help="Mark your toss as U:OMEGA (m/s:rad/s); a list "
                                 "a:b,c:d for several.", metavar="U:OMEGA")
    ] = None,
    resolution: Annotated[
        int, typer.Option("--resolution", help="Grid cells along each axis of a figure file.",
                          min=10, max=2000)
    ] = 400,
    out: OutOpt = None,
    terminal: TerminalOpt = False,
    dpi: DpiOpt = "150",
    width: WidthOpt = None,
    height: HeightOpt = None,
    title: TitleOpt = None,
):
    """The outcome over launch speed and precession rate for one coin (Fig. 3).

    Each cell is one finite toss (the engine of `coin phase`: the coin starts heads up, flies
    and is caught at the first contact); the dashed curves are eq. 10's hyperbolae
    omega = (2n +- theta0/pi) pi g / (2u).  Far from the origin the bands thin out and the
    shares approach the vigorous limit of Table I.

    Examples: coin plot phase --out phase.png ;  coin plot phase --xi 0.3 --psi 70 --terminal ;
    coin plot phase --toss 1.2:40 --u-range 0:3 --omega-range 0:100 --out phase.svg
    """
    target = _Target(out, terminal)
    if xi is None:
        x = 1 / math.sqrt(3)
    else:
        try:
            x = _xi_item(xi, "--xi")
        except ValueError as exc:
            raise usage_error(str(exc)) from None
    try:
        psi_deg = _deg_item(psi, "--psi")
    except ValueError as exc:
        raise usage_error(str(exc)) from None
    ct = contact.strip().lower()
    if ct not in ("rim", "thick"):
        raise usage_error(f"--contact must be rim or thick, got {contact!r}")
    if ct == "thick" and not x <= 1e100:  # the toss engine's limit for a thick coin
        raise usage_error(f"--xi with --contact thick must be at most 1e100, got {xi!r}")
    from coincli.plot import OMEGA_AXIS_MAX, U_AXIS_MAX

    ur = _pair(u_range, "--u-range", (0.0, 2.0), "m/s", U_AXIS_MAX)
    wr = _pair(omega_range, "--omega-range", (0.0, 60.0), "rad/s", OMEGA_AXIS_MAX)
    dia_m = 0.02426
    if diameter is not None:
        try:
            dia_m = parse.parse_length_mm(diameter, "--diameter") / 1000.0
        except ValueError as exc:
            raise usage_error(str(exc)) from None
        if not dia_m <= MAX_DIAMETER_M:
            raise usage_error("--diameter must be a length > 0 and at most 1e100 m, got "
                              f"{diameter!r}")
    marks = _tosses(toss)
    w, h, d = _figure_size(target, width, height, dpi, (9.5, 5.5))
    target.check_matplotlib()
    with _quiet():
        from coincli import plot as P

        def build(nu, nw):
            return _compute(P.phase_data, x, psi_deg, u_range=ur, omega_range=wr, nu=nu, nw=nw,
                            marks=marks, exact_curves=exact_curves, diameter=dia_m, contact=ct)

        if target.text:
            from coincli.textplot import text_phase

            target.text_plot(lambda c, r: text_phase(build(c, r), c, r))
            return
        fig = P.phase_figure(build(resolution, resolution), width=w, height=h, title=title)
        target.save(fig, d)
