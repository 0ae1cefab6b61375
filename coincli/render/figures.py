r"""The paper's figures, with the user's design and data on them (``coin plot``).

Two layers:

- *data* functions (:func:`sides_data`, :func:`psi_data`, :func:`map_data`, :func:`phase_data`)
  evaluate the core (:mod:`coincli.core.models`, :mod:`coincli.core.averages`, :mod:`coincli.core.toss`) on a
  grid and return plain dataclasses of numpy arrays.  They know nothing of drawing, so the
  matplotlib figures and the text plots of :mod:`coincli.render.text` show the same numbers;
- *figure* builders (:func:`sides_figure`, :func:`psi_figure`, :func:`map_figure`,
  :func:`phase_figure`) turn that data into a :class:`matplotlib.figure.Figure` on an Agg
  canvas (no pyplot, no global backend switch, nothing shown on screen).

matplotlib is an optional extra (``pip install 'thickcoin[plot]'``) and is imported only inside
the builders; :func:`require_matplotlib` raises :class:`MatplotlibMissing` with the install
hint when it is absent.

Every artist that carries data has a ``gid`` (``curve:dynamic``, ``fair:geometric``,
``design-xi:0``, ``data``, ``mesh:heads`` ...) so that tests, and anyone scripting the figures,
can find it without relying on draw order.  The palette is Okabe & Ito's (distinguishable with
every common colour-vision deficiency); outcomes and models are also told apart by line style.
:func:`save_figure` writes PNG, SVG or PDF by the file's extension, byte-for-byte reproducible
(``svg.hashsalt`` fixed, no dates in the metadata); :func:`write_figure` is how a command saves
one (one line on stderr saying so, each failure one error line).
"""

from __future__ import annotations

import contextlib
import math
import sys
from collections.abc import Sequence
from dataclasses import dataclass, field

from coincli.io import notes
from coincli.core import models
from coincli.core.modelspec import ModelSpec, table_i_deg
from coincli.errors import MatplotlibMissing, compute_error, install_hint, usage_error

__all__ = [
    "OKABE_ITO",
    "OUTCOME_COLOURS",
    "FORMATS",
    "MatplotlibMissing",
    "require_matplotlib",
    "ModelSpec",
    "GEOMETRIC",
    "DYNAMIC",
    "psi_spec",
    "density_spec",
    "density_label",
    "ExperimentPoint",
    "experiment_points",
    "SidesData",
    "sides_data",
    "PsiData",
    "psi_data",
    "sides_figure",
    "psi_figure",
    "save_figure",
    "write_figure",
    "figure_format",
    "check_figure_size",
    "FigureTooSmall",
    "xi_range_rule",
    "figure_style",
    "new_figure",
    "note_figure",
    "check_range",
    "auto_range",
    "xi_grid",
    "marks_label",
    "short_g",
    "XI_AXIS_MAX",
    "XI_LOG_MIN",
    "MIN_SPAN",
    "U_AXIS_MAX",
    "OMEGA_AXIS_MAX",
    "FIGURE_INCHES",
    "DPI_RANGE",
    "MAX_PIXELS",
]

#: Okabe & Ito (2008), "Color Universal Design": safe for protan, deutan and tritan vision.
OKABE_ITO = {
    "black": "#000000",
    "orange": "#E69F00",
    "sky": "#56B4E9",
    "green": "#009E73",
    "yellow": "#F0E442",
    "blue": "#0072B2",
    "vermillion": "#D55E00",
    "purple": "#CC79A7",
}
OUTCOME_COLOURS = {"heads": OKABE_ITO["blue"], "sides": OKABE_ITO["vermillion"],
                   "tails": OKABE_ITO["green"]}
#: Fig. 2d: heads solid, sides small dashes, tails long dashes.
OUTCOME_STYLES = {"heads": "-", "sides": (0, (2, 2)), "tails": (0, (8, 3))}
#: Vertices of the ternary colour map: blue / orange is the contrast every eye keeps; tails is
#: told apart by lightness.
TERNARY_VERTICES = {"heads": (0x00 / 255, 0x72 / 255, 0xB2 / 255),
                    "sides": (0xE6 / 255, 0x9F / 255, 0x00 / 255),
                    "tails": (0.97, 0.97, 0.97)}
DESIGN_COLOUR = OKABE_ITO["vermillion"]
_EXTRA_COLOURS = ("orange", "purple", "sky", "green", "yellow")
_EXTRA_STYLES = ("-.", (0, (1, 1.5)), (0, (5, 1, 1, 1, 1, 1)), (0, (3, 1, 1, 1)), (0, (6, 2)))

FORMATS = {".png": "png", ".svg": "svg", ".pdf": "pdf"}  #: file extension -> format
INSTALL_HINT = install_hint("plot")

#: Figure size limits: inches on a side, dots per inch, and pixels in all (width x dpi times
#: height x dpi, the PNG or a rasterized map inside an SVG/PDF).  50 million pixels is about
#: 300 MB and a few seconds to draw; beyond that a figure could exhaust the machine's memory.
FIGURE_INCHES = (1.0, 100.0)
DPI_RANGE = (10.0, 2000.0)
MAX_PIXELS = 50_000_000
#: Axis limits: matplotlib's tick arithmetic overflows (and warns) near the double range, and an
#: axis narrower than a millionth has no ticks to label.  xi = h/D of a million is a wire a
#: kilometre long per millimetre of diameter; the launch speed is capped as the toss engine's
#: (:data:`coincli.core.toss.flight.U_MAX`); 1e12 rad/s is past any toss the engine can follow.
XI_AXIS_MAX = 1e6
XI_LOG_MIN = 1e-6  #: the lowest low end of a log xi axis
MIN_SPAN = 1e-6  #: the narrowest axis: HIGH - LOW, in the axis' units
U_AXIS_MAX = 1e8  #: m/s
OMEGA_AXIS_MAX = 1e12  #: rad/s

_RC = {
    "svg.hashsalt": "coincli",  # ids in SVG output do not change from run to run
    "svg.fonttype": "path",
    "font.size": 10.0,
    "axes.titlesize": 11.0,
    "axes.labelsize": 10.0,
    "legend.fontsize": 8.5,
    "legend.framealpha": 0.9,
    "axes.grid": False,
    "grid.alpha": 0.3,
    "grid.linewidth": 0.6,
    "lines.linewidth": 1.8,
    "image.cmap": "viridis",
    "path.simplify": False,  # keep every computed point in vector output
}
_METADATA = {"png": {"Software": None}, "svg": {"Date": None},
             "pdf": {"CreationDate": None, "ModDate": None}}


# --------------------------------------------------------------------------- matplotlib



def require_matplotlib():
    """Import and return matplotlib, or raise :class:`MatplotlibMissing` with the hint.

    The import is shielded from the user's environment, so that the same figure gives the same
    bytes everywhere and nothing but the result reaches stderr: matplotlib's logger is set to
    CRITICAL (an unusable MPLCONFIGDIR or HOME, or an rc file with bad keys, is logged as a
    warning at import), ``MATPLOTLIBRC`` points at matplotlib's own default file during the
    import (a user's file could set ``text.usetex`` or be a FIFO that blocks the read),
    ``MPLBACKEND`` is ignored (the figures draw on their own Agg canvas), and a
    ``./matplotlibrc`` that is not a regular file is not opened.  :func:`figure_style` resets every
    setting to matplotlib's defaults plus coin's own while a figure is drawn.
    """
    if sys.modules.get("matplotlib") is None:
        _shielded_import()
    try:
        import matplotlib
    except ImportError:
        raise MatplotlibMissing(
            f"drawing a figure file needs matplotlib: {INSTALL_HINT} "
            "(or --terminal for a text plot)"
        ) from None
    return matplotlib


def _shielded_import() -> None:
    """Import matplotlib away from the user's environment (see :func:`require_matplotlib`);
    nothing when it is not installed (the caller says so)."""
    import importlib.util
    import logging
    import os

    logging.getLogger("matplotlib").setLevel(logging.CRITICAL)
    try:
        spec = importlib.util.find_spec("matplotlib")
    except (ImportError, ValueError):
        spec = None
    if spec is None or spec.origin is None:
        return
    data = os.path.join(os.path.dirname(spec.origin), "mpl-data")
    saved = {k: os.environ.get(k) for k in ("MATPLOTLIBRC", "MPLBACKEND")}
    os.environ["MATPLOTLIBRC"] = os.path.join(data, "matplotlibrc")
    os.environ.pop("MPLBACKEND", None)
    cwd = None
    try:
        import stat

        if not stat.S_ISREG(os.stat("matplotlibrc").st_mode):
            cwd = os.getcwd()
            os.chdir(data)  # matplotlib reads ./matplotlibrc first: here, its own default
    except OSError:
        pass
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        pass
    finally:
        if cwd is not None:
            os.chdir(cwd)
        for k, v in saved.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v


@contextlib.contextmanager
def figure_style():
    """matplotlib's default settings and coin's (:data:`_RC`) while a figure is drawn and
    saved, whatever the user's matplotlibrc says."""
    matplotlib = require_matplotlib()
    with matplotlib.rc_context():
        matplotlib.rcdefaults()
        matplotlib.rcParams.update(_RC)
        yield


def new_figure(width: float, height: float):
    """A Figure on its own Agg canvas: no pyplot state, no GUI, no global backend change."""
    require_matplotlib()
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    lo, hi = FIGURE_INCHES
    for name, v in (("width", width), ("height", height)):
        if not (isinstance(v, (int, float)) and lo <= v <= hi):  # False for nan
            raise ValueError(f"figure {name} must be {lo:g} to {hi:g} inches, got {v!r}")
    fig = Figure(figsize=(float(width), float(height)), layout="constrained")
    FigureCanvasAgg(fig)
    return fig


def figure_format(path: str) -> str:
    """``png``, ``svg`` or ``pdf`` from the file name; ValueError for anything else."""
    import os

    ext = os.path.splitext(str(path))[1].lower()
    base = os.path.basename(str(path)).lower()
    if not ext and base in FORMATS:  # '.png': a hidden file with no extension, not a PNG
        raise ValueError(f"{path!r} is an extension without a file name; give a name such as "
                         f"figure{base}")
    if ext not in FORMATS:
        raise ValueError(
            f"cannot tell the figure format from {path!r}: the file name must end in "
            ".png, .svg or .pdf"
        )
    return FORMATS[ext]


def check_figure_size(width: float, height: float, dpi: float) -> None:
    """ValueError unless the size (inches) and ``dpi`` are within :data:`FIGURE_INCHES`,
    :data:`DPI_RANGE` and :data:`MAX_PIXELS` (width x dpi times height x dpi)."""
    (wlo, whi), (dlo, dhi) = FIGURE_INCHES, DPI_RANGE
    for name, v, lo, hi, unit in (("width", width, wlo, whi, "inches"),
                                  ("height", height, wlo, whi, "inches"),
                                  ("dpi", dpi, dlo, dhi, "dots per inch")):
        if not (isinstance(v, (int, float)) and lo <= v <= hi):  # False for nan
            raise ValueError(f"{name} must be {lo:g} to {hi:g} {unit}, got {v!r}")
    if width * dpi * height * dpi > MAX_PIXELS:
        raise ValueError(f"a {width:g} x {height:g} inch figure at {dpi:g} dpi has "
                         f"{round(width * dpi):,} x {round(height * dpi):,} pixels; at most "
                         f"{MAX_PIXELS:,} pixels in all")


class FigureTooSmall(ValueError):
    """The figure is too small for its titles, labels and legend (nothing was written)."""


def save_figure(fig, path: str, dpi: float = 150.0) -> int:
    """Write ``fig`` to ``path`` as PNG, SVG or PDF (by extension); return the bytes written.

    The output is reproducible: the same figure gives the same bytes (SVG ids are salted with a
    constant, and no creation date is recorded).  The size must pass :func:`check_figure_size`.
    The figure is rendered in memory first: if matplotlib's constrained layout gives up (its
    warning "axes sizes collapsed to zero": the figure is too small for its titles, labels and
    legend, which would be drawn over the axes), :class:`FigureTooSmall` is raised and no file
    is written.  Any other warning is passed on.  The file is written by
    :func:`coincli.io.files.write_atomic`: whole or not at all, the old file intact on failure;
    a path that is not a regular file raises :class:`coincli.io.files.FileKindError`.
    """
    import io
    import warnings

    fmt = figure_format(path)
    width, height = (float(v) for v in fig.get_size_inches())
    check_figure_size(width, height, dpi)
    buf = io.BytesIO()
    with figure_style(), warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        fig.savefig(buf, format=fmt, dpi=float(dpi), metadata=_METADATA[fmt])
    if any("collapsed" in str(w.message) for w in caught):
        raise FigureTooSmall(f"a {width:g} x {height:g} inch figure is too small for its "
                             "titles, labels and legend")
    for w in caught:
        warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
    from coincli.io.files import write_atomic

    return write_atomic(path, buf.getbuffer())


def write_figure(fig, path: str, dpi: float = 150.0, too_small: str = "") -> None:
    """Save a figure through :func:`save_figure` (whole or not at all, the old file intact on
    failure) and say so on stderr (``coin: wrote sides.png (1050 x 675 pixels)``), as every command that writes a figure does; each failure is one line (a path
    that is not a regular file is a usage error; ``too_small`` is the hint for a figure too
    small for its labels)."""
    from coincli.io.files import FileKindError

    try:
        save_figure(fig, path, dpi)
    except FigureTooSmall as exc:
        raise usage_error(f"{exc}{too_small}") from None
    except FileKindError as exc:
        raise usage_error(f"--out: {exc}") from None
    except OSError as exc:
        raise compute_error(f"cannot write {path!r}: {exc.strerror or exc}") from None
    except MemoryError:
        raise compute_error(f"not enough memory to draw {path!r}") from None
    w, h = (float(v) for v in fig.get_size_inches())
    dims = (f"{round(w * dpi)} x {round(h * dpi)} pixels" if figure_format(path) == "png" else
            f"{w:g} x {h:g} inches")
    notes.wrote(path, dims)


# --------------------------------------------------------------------------- models


GEOMETRIC = ModelSpec.geometric()
DYNAMIC = ModelSpec.dynamic("dynamic (Keller flip, ψ = 90°, eq. 12)")


def psi_spec(psi_rad: float) -> ModelSpec:
    """Table I at a fixed angle (radians)."""
    models.check_psi(psi_rad)
    return ModelSpec.fixed_psi(float(psi_rad), f"ψ = {math.degrees(psi_rad):.6g}° (Table I)")


def density_spec(density) -> ModelSpec:
    """psi averaged over a :class:`coincli.core.densities.Density` (eq. 15)."""
    return ModelSpec.psi_density(density, f"{density_label(density)} (averaged, eq. 15)")


def density_label(density) -> str:
    """A short human name: ``ψ ~ normal, mean 90°, sd 40.5°``, ``ψ ~ uniform``."""
    from coincli.core.densities import Normal, Table

    if isinstance(density, Normal):
        if density.is_paper:
            return "ψ ~ normal (paper)"
        return (f"ψ ~ normal, mean {math.degrees(density.mean):.4g}°, "
                f"sd {math.degrees(density.sd):.3g}°")
    if isinstance(density, Table) and density.spec.startswith("table:"):
        return f"ψ ~ table {density.label}"
    return f"ψ ~ {density.spec}"


# --------------------------------------------------------------------------- experiments


@dataclass(frozen=True)
class ExperimentPoint:
    """An experiment's frequency of sides with its 95% Wilson interval: the user's tosses, or
    (``simulated``) tosses ``coin plot sides --landing bounce`` made itself."""

    label: str
    xi: float
    n: int
    sides: int
    frequency: float
    low: float
    high: float
    simulated: bool = False


def point_groups(points) -> list[tuple[str, list[ExperimentPoint]]]:
    """The points in their groups, each with its legend text: ``("data", your tosses)`` and
    ``("simulated", the simulated tosses)``, the empty ones left out.  The two never share a
    marker, a legend entry or a fit statistic."""
    mine = [p for p in points if not p.simulated]
    sims = [p for p in points if p.simulated]
    groups = []
    if mine:
        groups.append(("data", mine))
    if sims:
        groups.append(("simulated", sims))
    return groups


def group_label(gid: str, points) -> str:
    """The legend text of one group of points (see :func:`point_groups`): ``your tosses (3
    rows)``, ``simulated bounce on wood (8 points, 400 settled tosses each)``."""
    n = len(points)
    if gid == "simulated":
        ns = sorted({p.n for p in points})
        each = f"{ns[0]:,}" if len(ns) == 1 else f"{ns[0]:,} to {ns[-1]:,}"
        return (f"{points[0].label} ({n} point{'s' if n > 1 else ''}, {each} settled "
                f"tosses each)")
    return f"your tosses ({n} row{'s' if n > 1 else ''})"


def _wrap(label: str, width: int = 64) -> str:
    """A legend label folded at ``width`` characters (each of its own lines), so that a long
    label does not make the legend wider than the axes."""
    import textwrap

    return "\n".join(textwrap.fill(line, width, subsequent_indent="  ")
                     for line in label.split("\n"))


def is_rejected(spec) -> bool:
    """Whether a curve is a fit that its own points reject (drawn dashed and labelled so)."""
    return bool(getattr(spec, "rejected", False))


def experiment_points(experiments, confidence: float = 0.95) -> list[ExperimentPoint]:
    """Frequencies of sides of :class:`coincli.core.stats.counts.Experiment` rows, with Wilson
    intervals (all rows in one call of :func:`coincli.core._numerics.wilson.wilson_interval`)."""
    import numpy as np

    from coincli.core._numerics.wilson import wilson_interval

    if not experiments:
        return []
    k = np.array([e.counts.sides for e in experiments], dtype=float)
    n = np.array([e.counts.n for e in experiments], dtype=float)
    low, high = wilson_interval(k, n, confidence)
    return [ExperimentPoint(e.label, float(e.xi), e.counts.n, e.counts.sides,
                            e.counts.sides / e.counts.n, lo, hi)
            for e, lo, hi in zip(experiments, low.tolist(), high.tolist(), strict=True)]


# --------------------------------------------------------------------------- sides (Fig. 5a)

DEFAULT_XI_RANGE = (0.0, 2.0)
DEFAULT_LOG_XI_RANGE = (0.01, 100.0)


@dataclass
class Curve:
    spec: ModelSpec
    y: object  #: P(sides) at :attr:`SidesData.xi`


@dataclass
class Mark:
    """A point on a curve: where a design meets a model."""

    gid: str  #: the curve's gid
    xi: float
    p: float


@dataclass
class SidesData:
    xi: object  #: the grid (ndarray)
    curves: list[Curve]
    log: bool
    xlim: tuple[float, float]
    fair: list[Mark]  #: the fair three-sided coins of the geometric and dynamic models
    xi_marks: list[tuple[float, list[Mark]]] = field(default_factory=list)
    p_marks: list[tuple[float, list[Mark]]] = field(default_factory=list)
    experiments: list[ExperimentPoint] = field(default_factory=list)
    skipped: list[str] = field(default_factory=list)  #: designs that could not be marked


def short_g(v: float) -> str:
    """``1e6`` and ``1e-6`` rather than ``1e+06`` and ``1e-06`` (limits in messages)."""
    m, e, x = f"{v:g}".partition("e")
    return f"{m}e{int(x)}" if e else m


def xi_range_rule(log: bool) -> str:
    """The allowed xi axis, in words (for error messages)."""
    low = f"{short_g(XI_LOG_MIN)} <= LOW" if log else "0 <= LOW"
    return f"{low} < HIGH <= {short_g(XI_AXIS_MAX)} and HIGH - LOW >= {short_g(MIN_SPAN)}"


def check_range(lo: float, hi: float, log: bool) -> tuple[float, float]:
    """The xi axis within :data:`XI_AXIS_MAX`, :data:`XI_LOG_MIN` and :data:`MIN_SPAN`."""
    floor = XI_LOG_MIN if log else 0.0
    if not (floor <= lo < hi <= XI_AXIS_MAX and hi - lo >= MIN_SPAN):  # False for nan
        raise ValueError(f"the xi axis{' (log)' if log else ''} needs {xi_range_rule(log)}, "
                         f"got {lo:g}:{hi:g}")
    return float(lo), float(hi)


def xi_grid(lo: float, hi: float, log: bool, points: int):
    import numpy as np

    if log:
        return np.geomspace(lo, hi, points)
    return np.linspace(lo, hi, points)


def auto_range(values, log: bool, default: tuple[float, float]) -> tuple[float, float]:
    """The default range widened to show every finite value (xi > 0 on a log axis), but not
    beyond :data:`XI_LOG_MIN` and :data:`XI_AXIS_MAX` (a value further out is left off the
    axis, with a note)."""
    lo, hi = default
    vals = [v for v in values if math.isfinite(v) and (v > 0 or not log)]
    if vals:
        if log:
            lo, hi = min(lo, min(vals) / 1.5), max(hi, max(vals) * 1.5)
        elif max(vals) * 1.05 > hi:
            hi = _nice_ceil(min(max(vals) * 1.05, XI_AXIS_MAX))
    return max(lo, XI_LOG_MIN) if log else lo, min(hi, XI_AXIS_MAX)


def _nice_ceil(v: float) -> float:
    """The smallest of 1, 1.2, 1.5, 2, 2.5, 3, 4, 5, 6, 8 times a power of ten that is >= v."""
    e = math.floor(math.log10(v))
    for m in (1.0, 1.2, 1.5, 2.0, 2.5, 3.0, 4.0, 5.0, 6.0, 8.0, 10.0):
        if m * 10.0**e >= v:
            return m * 10.0**e
    return 10.0 ** (e + 1)


def sides_data(specs: Sequence[ModelSpec] = (GEOMETRIC, DYNAMIC), *, xi_marks=(), p_marks=(),
               experiments=(), log: bool = False, xi_range=None, points: int = 401) -> SidesData:
    """P(sides) against xi for each model, with the fair coins, the designs and the data.

    ``xi_marks``: aspect ratios to mark (each meets every curve); ``p_marks``: target chances
    (the xi each model needs); ``experiments``: :class:`ExperimentPoint` rows.  Without
    ``xi_range`` the axis runs over ``[0, 2]`` (``[0.01, 100]`` on a log axis), widened to show
    every mark and experiment.
    """
    import numpy as np

    specs = list(specs)
    p_marks = [float(models.check_p(p, "p_sides")) for p in p_marks]
    xi_marks = [float(models.check_xi(x)) for x in xi_marks]
    p_found: list[tuple[float, list[Mark]]] = []
    skipped: list[str] = []
    for p in p_marks:
        row = []
        for s in specs:
            try:
                x = float(s.inverse(p))
            except ValueError as exc:
                skipped.append(f"P(sides) = {p:g} under {s.gid}: {exc}")
                continue
            row.append(Mark(s.gid, x, p))
        p_found.append((p, row))
    if xi_range is None:
        default = DEFAULT_LOG_XI_RANGE if log else DEFAULT_XI_RANGE
        lo, hi = auto_range([*xi_marks, *(m.xi for _, r in p_found for m in r),
                              *(e.xi for e in experiments)], log, default)
    else:
        lo, hi = xi_range
    lo, hi = check_range(lo, hi, log)
    xi = xi_grid(lo, hi, log, int(points))
    curves = [Curve(s, np.asarray(s.forward(xi).sides, dtype=float)) for s in specs]
    fair = [Mark("geometric", models.FAIR_XI_GEOMETRIC, models.geometric(
                models.FAIR_XI_GEOMETRIC).sides),
            Mark("dynamic", models.FAIR_XI_DYNAMIC, models.dynamic(models.FAIR_XI_DYNAMIC).sides)]
    fair = [m for m in fair if any(c.spec.gid == m.gid for c in curves)]
    xm = [(x, [Mark(s.gid, x, float(s.forward(x).sides)) for s in specs]) for x in xi_marks]
    for x in xi_marks:
        if not lo <= x <= hi:
            skipped.append(f"xi = {x:g} is outside the plotted range {lo:g} to {hi:g}")
    for _, row in p_found:
        for m in row:
            if not lo <= m.xi <= hi:
                skipped.append(f"P(sides) = {m.p:g} under {m.gid} needs xi = {m.xi:g}, outside "
                               f"the plotted range {lo:g} to {hi:g}")
    for e in experiments:
        if not lo <= e.xi <= hi:
            skipped.append(f"the tosses {e.label!r} at xi = {e.xi:g} are outside the plotted "
                           f"range {lo:g} to {hi:g}")
    return SidesData(xi, curves, log, (lo, hi), fair, xm, p_found, list(experiments), skipped)


def sse(data: SidesData, gid: str) -> float | None:
    """The paper's sum of squared errors of the user's side frequencies against one curve's
    model (the simulated points of ``--landing bounce`` are not data: they never count)."""
    mine = [e for e in data.experiments if not e.simulated]
    if not mine:
        return None
    import numpy as np

    spec = next(c.spec for c in data.curves if c.spec.gid == gid)
    xi = np.array([e.xi for e in mine])
    ux, inv = np.unique(xi, return_inverse=True)  # the model once per distinct coin, vectorized
    p = np.atleast_1d(np.asarray(spec.forward(ux).sides, dtype=float))[inv.ravel()]
    f = np.array([e.frequency for e in mine])
    return math.fsum(((f - p) ** 2).tolist())


def _spread(values, gap: float) -> list[float]:
    """Label heights (axes fraction) near ``values`` (data = axes fraction on [0, 1]), at least
    ``gap`` apart, in the order of the values."""
    order = sorted(range(len(values)), key=lambda k: values[k])
    out = [0.0] * len(values)
    last = -math.inf
    for k in order:
        out[k] = last = max(values[k], last + gap)
    top = max(out, default=0.0)
    if top > 0.98:  # pushed off the top: shift the whole run down
        shift = top - 0.98
        out = [v - shift for v in out]
    return out


def _axes_x(data, x: float) -> float:
    """x as a fraction of the axes' width."""
    lo, hi = data.xlim
    if data.log:
        return math.log(x / lo) / math.log(hi / lo)
    return (x - lo) / (hi - lo)


def _fmt(v: float) -> str:
    return "∞" if v == math.inf else f"{v:.3g}"


def marks_label(one: str, many: str, name: str, values: Sequence[str],
                per_line: int = 5) -> str:
    """One legend entry naming every mark: ``your designs: ξ = 0.5, 0.577`` (``name`` before
    the first value; a new line every ``per_line`` values, so that twenty marks do not make the
    legend wider than the figure)."""
    vals = [f"{name}{v}" if k == 0 else v for k, v in enumerate(values)]
    head = f"{one if len(vals) == 1 else many}: "
    lines = [", ".join(vals[k:k + per_line]) for k in range(0, len(vals), per_line)]
    return head + ",\n".join(lines)


def note_figure(fig, notes: Sequence[str]) -> None:
    """What the figure could not show (a mark off the axis), written into the figure itself
    under the axes, as the text plot lists it: the file tells the whole story."""
    if notes:
        t = fig.supxlabel("not shown: " + "; ".join(notes), fontsize=7, color="0.3",
                          wrap=True)
        t.set_gid("notes")


_LABEL_BOX = {"boxstyle": "round,pad=0.1", "facecolor": "white", "edgecolor": "none",
              "alpha": 0.8}
_LEADER = {"arrowstyle": "-", "linewidth": 0.5, "color": "0.4", "shrinkA": 0, "shrinkB": 3}


def _curve_style(k: int, spec: ModelSpec):
    """(colour, linestyle) of the k-th curve: the paper's solid geometric and dashed dynamic."""
    if spec.key == "geometric":
        return OKABE_ITO["black"], "-"
    if spec.key == "dynamic":
        return OKABE_ITO["blue"], "--"
    j = (k - 2) % len(_EXTRA_COLOURS)
    return OKABE_ITO[_EXTRA_COLOURS[j]], _EXTRA_STYLES[j]


def sides_figure(data: SidesData, *, width: float = 7.0, height: float = 4.5,
                 title: str | None = None):
    """Fig. 5a: P(sides) against xi, fair coins, designs and experiments (a Figure)."""
    with figure_style():
        fig = new_figure(width, height)
        ax = fig.add_subplot()
        colours = {}
        for k, c in enumerate(data.curves):
            colour, ls = _curve_style(k, c.spec)
            colours[c.spec.gid] = colour
            label = c.spec.label
            err = sse(data, c.spec.gid)
            if err is not None:
                label += f", SSE {err:.3g} (your tosses)"
            lw = None  # the style's
            if c.spec.key == "fitted":  # a fit to simulated points: solid, dashed if rejected
                ls, lw = ("--", 1.0) if is_rejected(c.spec) else ("-", None)
            ax.plot(data.xi, c.y, color=colour, linestyle=ls, linewidth=lw, label=_wrap(label),
                    gid=f"curve:{c.spec.gid}", zorder=2)
        if data.fair:
            ax.axhline(1 / 3, color="0.6", linewidth=0.8, linestyle=":", zorder=1,
                       gid="fair-level")
        for m in data.fair:
            colour = OKABE_ITO["black"] if m.gid == "geometric" else OKABE_ITO["blue"]
            ax.plot([m.xi], [m.p], marker="o", markersize=7, markerfacecolor="white",
                    markeredgecolor=colour, markeredgewidth=1.6, linestyle="none",
                    gid=f"fair:{m.gid}", zorder=4,
                    label=f"fair three-sided coin, {m.gid}: ξ = {m.xi:.3f}")
        label_gap = 11.0 / (72.0 * height * 0.75)  # ~11 points, as a fraction of the axes
        inside = [x for x, _ in data.xi_marks if data.xlim[0] <= x <= data.xlim[1]]
        legend = marks_label("your design", "your designs", "ξ = ", [f"{x:.4g}" for x in inside])
        for k, (x, row) in enumerate(data.xi_marks):
            if not data.xlim[0] <= x <= data.xlim[1]:
                continue
            ax.axvline(x, color=DESIGN_COLOUR, linewidth=1.0, linestyle=":", zorder=1,
                       gid=f"design-xi-line:{k}")
            ax.plot([m.xi for m in row], [m.p for m in row], marker="D", markersize=6,
                    color=DESIGN_COLOUR, linestyle="none", gid=f"design-xi:{k}", zorder=5,
                    label=legend)
            legend = None  # one legend entry names them all
            ys = _spread([m.p for m in row], label_gap)
            for m, y in zip(row, ys, strict=True):
                xf = _axes_x(data, m.xi) + 0.02
                ax.annotate(f"{m.p:.3f}", (m.xi, m.p), xytext=(xf, y),
                            textcoords="axes fraction", fontsize=7.5, va="center",
                            color=colours.get(m.gid, DESIGN_COLOUR), arrowprops=_LEADER,
                            bbox=_LABEL_BOX)
        targets = marks_label("your target", "your targets", "P(sides) = ",
                              [f"{p:.4g}" for p, _ in data.p_marks])
        for k, (p, row) in enumerate(data.p_marks):
            ax.axhline(p, color=DESIGN_COLOUR, linewidth=1.0, linestyle=(0, (4, 2)), zorder=1,
                       gid=f"design-p-line:{k}")
            shown = [m for m in row if data.xlim[0] <= m.xi <= data.xlim[1]]
            ax.plot([m.xi for m in shown], [m.p for m in shown], marker="v", markersize=7,
                    color=DESIGN_COLOUR, linestyle="none", gid=f"design-p:{k}", zorder=5,
                    label=targets if k == 0 else None)
            xs = _spread([_axes_x(data, m.xi) for m in shown], 11.0 / (72.0 * width * 0.85))
            for m, xf in zip(shown, xs, strict=True):
                ax.annotate(f"ξ = {_fmt(m.xi)}", (m.xi, m.p), xytext=(xf, m.p + 0.045),
                            textcoords=("axes fraction", "data"), fontsize=7.5, rotation=90,
                            ha="center", va="bottom", color=colours.get(m.gid, DESIGN_COLOUR),
                            arrowprops=_LEADER, bbox=_LABEL_BOX)
        for gid, pts in point_groups(data.experiments):
            import numpy as np

            ex = np.array([e.xi for e in pts])
            fy = np.array([e.frequency for e in pts])
            lo = np.array([e.low for e in pts])
            hi = np.array([e.high for e in pts])
            face, marker, size = ((OKABE_ITO["orange"], "o", 5.5) if gid == "data"
                                  else ("white", "s", 4.5))
            eb = ax.errorbar(ex, fy, yerr=np.vstack([fy - lo, hi - fy]), fmt=marker,
                             color=OKABE_ITO["black"] if gid == "data" else "0.35",
                             markerfacecolor=face, markersize=size, capsize=3, elinewidth=1.0,
                             zorder=6 if gid == "data" else 5,
                             label=_wrap(f"{group_label(gid, pts)}: frequency of sides, "
                                         "95% Wilson interval"))
            eb.lines[0].set_gid(gid)
            for k, coll in enumerate(eb.lines[2]):
                coll.set_gid(f"{gid}-errorbars" if k == 0 else f"{gid}-errorbars:{k}")
        if data.log:
            ax.set_xscale("log")
        ax.set_xlim(*data.xlim)
        ax.set_ylim(0.0, 1.0)
        ax.grid(True, which="major")
        ax.set_xlabel("aspect ratio ξ = h/D (thickness / diameter, dimensionless)")
        ax.set_ylabel("P(sides)")
        ax.set_title(title or "Chance of landing on a side (Yong & Mahadevan, Fig. 5a)",
                     parse_math=False)
        ax.legend(loc="upper left" if data.log or data.xlim[1] > 3 else "lower right")
        note_figure(fig, data.skipped)
    return fig


# --------------------------------------------------------------------------- psi (Fig. 2d)


@dataclass
class PsiData:
    xi: float
    psi_deg: object  #: grid in degrees; the core is evaluated at ``numpy.radians(psi_deg)``
    heads: object
    sides: object
    tails: object
    bounds_deg: tuple[float, float, float, float]  #: theta0/2, 90 - theta0/2, 90 + .., 180 - ..
    marks: list[tuple[float, models.Outcome]] = field(default_factory=list)  #: (deg, outcome)


def psi_data(xi: float, psi_marks_deg=(), points: int = 721) -> PsiData:
    """P(heads), P(sides), P(tails) against psi (degrees, 0 to 180) for one coin: Fig. 2d.

    The grid is ``points`` evenly spaced angles plus the four regime boundaries of Table I, where
    the curves have kinks.
    """
    import numpy as np

    xi = float(models.check_xi(xi))
    t = math.degrees(models.theta0(xi)) / 2
    bounds = (t, 90.0 - t, 90.0 + t, 180.0 - t)
    psi_deg = np.unique(np.concatenate([np.linspace(0.0, 180.0, int(points)),
                                        np.clip(bounds, 0.0, 180.0)]))
    o = table_i_deg(xi, psi_deg)
    marks = []
    for d in psi_marks_deg:
        d = float(d)
        if not 0.0 <= d <= 180.0:
            raise ValueError(f"psi must be an angle in [0, 180] degrees, got {d:g}")
        marks.append((d, table_i_deg(xi, d)))
    return PsiData(xi, psi_deg, np.asarray(o.heads), np.asarray(o.sides), np.asarray(o.tails),
                   bounds, marks)


REGIME_SHADES = {"heads only": "0.95", "heads or sides": "0.86", "all three": "0.74"}


def psi_figure(data: PsiData, *, width: float = 7.0, height: float = 4.5,
               title: str | None = None):
    """Fig. 2d: the three chances against psi with the regimes of Table I shaded."""
    t1, t2, t3, t4 = data.bounds_deg
    with figure_style():
        fig = new_figure(width, height)
        ax = fig.add_subplot()
        spans = [(0.0, t1, "heads only"), (t1, t2, "heads or sides"), (t2, t3, "all three"),
                 (t3, t4, "heads or sides"), (t4, 180.0, "heads only")]
        seen = set()
        for k, (a, b, name) in enumerate(spans):
            if b <= a:
                continue
            ax.axvspan(a, b, color=REGIME_SHADES[name], linewidth=0, zorder=0,
                       gid=f"regime:{k}:{name}",
                       label=f"regime: {name}" if name not in seen else None)
            seen.add(name)
        for name in ("heads", "sides", "tails"):
            ax.plot(data.psi_deg, getattr(data, name), color=OUTCOME_COLOURS[name],
                    linestyle=OUTCOME_STYLES[name], label=f"P({name})", gid=f"curve:{name}",
                    zorder=3)
        tosses = marks_label("your toss", "your tosses", "ψ = ",
                             [f"{d:.4g}°" for d, _ in data.marks])
        for k, (d, o) in enumerate(data.marks):
            ax.axvline(d, color=DESIGN_COLOUR, linewidth=1.0, linestyle=":", zorder=2,
                       gid=f"design-psi-line:{k}")
            ax.plot([d, d, d], [o.heads, o.sides, o.tails], marker="D", markersize=6,
                    color=DESIGN_COLOUR, linestyle="none", zorder=5, gid=f"design-psi:{k}",
                    label=tosses if k == 0 else None)
            names = ("heads", "sides", "tails")
            vals = [getattr(o, name) for name in names]
            # each value in its outcome's colour, the labels pushed apart where values meet
            ys = _spread([v / 1.02 for v in vals], 11.0 / (72.0 * height * 0.75))
            for name, v, y in zip(names, vals, ys, strict=True):
                ax.annotate(f"{v:.3f}", (d, v), xytext=(d + 3.0, y),
                            textcoords=("data", "axes fraction"), fontsize=7.5, va="center",
                            color=OUTCOME_COLOURS[name], bbox=_LABEL_BOX, arrowprops=_LEADER,
                            gid=f"design-psi-value:{k}:{name}")
        ax.axhline(1 / 3, color="0.45", linewidth=0.7, linestyle=":", zorder=1, gid="fair-level")
        ax.set_xlim(0.0, 180.0)
        ax.set_ylim(0.0, 1.02)
        ax.set_xticks(range(0, 181, 30))
        ax.set_xlabel("ψ, angle between angular momentum and the coin's normal (degrees)")
        ax.set_ylabel("probability")
        ax.set_title(title or f"Heads, sides and tails against ψ for ξ = {data.xi:.4g} "
                     "(Yong & Mahadevan, Fig. 2d)", parse_math=False)
        ax.legend(loc="upper center", ncols=2, fontsize=8)
    return fig
