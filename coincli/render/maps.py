"""The outcome maps of the paper, with the user's coins and data on them (``coin plot map`` and
``coin plot phase``, ``coin phase``): Fig. 2a-c, the outcome over (xi, psi) (:func:`map_data`,
:func:`map_figure`), and Fig. 3, the outcome over the launch speed and spin (:func:`phase_data`,
:func:`phase_figure`).

As in :mod:`coincli.render.figures` (whose style, canvas and axis rules these use): the data
functions evaluate the core on a grid and know nothing of drawing (the text plots of
:mod:`coincli.render.text` show the same numbers); the figure builders import matplotlib
inside, on an Agg canvas.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from coincli.core import models
from coincli.core.modelspec import table_i_deg
from coincli.render.figures import (
    DEFAULT_LOG_XI_RANGE,
    DEFAULT_XI_RANGE,
    OKABE_ITO,
    TERNARY_VERTICES,
    auto_range,
    check_range,
    figure_style,
    marks_label,
    new_figure,
    note_figure,
    xi_grid,
)

__all__ = ["MapData", "map_data", "map_figure", "ternary_colours", "MAP_SIZES", "PhaseData",
           "phase_data", "phase_figure", "PHASE_COLOURS", "OUTCOME_CODES"]

MAP_SIZES = {"panels": (12.0, 4.4), "ternary": (8.0, 5.0)}  #: default inches of map_figure


# --------------------------------------------------------------------------- map (Fig. 2a-c)


@dataclass
class MapData:
    xi: object  #: cell centres along xi (ndarray, nx)
    psi_deg: object  #: cell centres along psi in degrees (ndarray, ny)
    heads: object  #: (ny, nx): the core at (xi[j], radians(psi_deg[i]))
    sides: object
    tails: object
    log: bool
    xlim: tuple[float, float]
    xi_marks: list[float] = field(default_factory=list)
    psi_marks: list[float] = field(default_factory=list)  #: degrees
    skipped: list[str] = field(default_factory=list)  #: marks that could not be drawn


def map_data(*, xi_range=None, log: bool = False, nx: int = 301, ny: int = 361, xi_marks=(),
             psi_marks_deg=()) -> MapData:
    """The three chances of Table I over the (xi, psi) plane, psi in degrees from 0 to 180."""
    import numpy as np

    xi_marks = [float(models.check_xi(x)) for x in xi_marks]
    psi_marks = [float(d) for d in psi_marks_deg]
    for d in psi_marks:
        if not 0.0 <= d <= 180.0:
            raise ValueError(f"psi must be an angle in [0, 180] degrees, got {d:g}")
    if xi_range is None:
        lo, hi = auto_range(xi_marks, log, DEFAULT_LOG_XI_RANGE if log else DEFAULT_XI_RANGE)
    else:
        lo, hi = xi_range
    lo, hi = check_range(lo, hi, log)
    xi = xi_grid(lo, hi, log, int(nx))
    psi_deg = np.linspace(0.0, 180.0, int(ny))
    o = table_i_deg(xi[None, :], psi_deg[:, None])
    skipped = [f"xi = {x:g} is outside the plotted range {lo:g} to {hi:g}" for x in xi_marks
               if not lo <= x <= hi]
    return MapData(xi, psi_deg, o.heads, o.sides, o.tails, log, (lo, hi), xi_marks, psi_marks,
                   skipped)


def ternary_colours(heads, sides, tails):
    """RGB colours (..., 3) mixing the :data:`TERNARY_VERTICES` in proportion to the chances."""
    import numpy as np

    out = np.zeros(np.shape(heads) + (3,))
    for name, w in (("heads", heads), ("sides", sides), ("tails", tails)):
        out += np.asarray(w)[..., None] * np.asarray(TERNARY_VERTICES[name])
    return np.clip(out, 0.0, 1.0)


def _boundary_lines(ax, data: MapData, colour: str):
    """The regime boundaries psi = theta0/2, 90 -+ theta0/2, 180 - theta0/2 over xi."""
    import numpy as np

    xs = xi_grid(max(data.xlim[0], 1e-12) if data.log else data.xlim[0], data.xlim[1],
                  data.log, 400)
    t = np.degrees(np.arctan2(1.0, xs)) / 2
    for k, y in enumerate((t, 90 - t, 90 + t, 180 - t)):
        ax.plot(xs, y, color=colour, linewidth=0.8, linestyle=(0, (3, 2)), zorder=3,
                gid=f"boundary:{k}", label="regime boundaries (Table I)" if k == 0 else None)


def _map_marks(ax, data: MapData, colour: str, legend: bool):
    ax.plot([models.FAIR_XI_DYNAMIC], [90.0], marker="*", markersize=12, color=OKABE_ITO["yellow"],
            markeredgecolor="black", linestyle="none", zorder=6, gid="fair:dynamic",
            label="fair three-sided coin: ξ = 1/√3, ψ = 90°" if legend else None)
    inside = _inside(data)
    designs = marks_label("your design", "your designs", "ξ = ", [f"{x:.4g}" for x in inside])
    for k, x in enumerate(inside):
        ax.axvline(x, color=colour, linewidth=1.2, linestyle=":", zorder=4, gid=f"design-xi:{k}",
                   label=designs if legend and k == 0 else None)
    tosses = marks_label("your toss", "your tosses", "ψ = ", [f"{d:.4g}°" for d in data.psi_marks])
    for k, d in enumerate(data.psi_marks):
        ax.axhline(d, color=colour, linewidth=1.2, linestyle=(0, (4, 2)), zorder=4,
                   gid=f"design-psi:{k}", label=tosses if legend and k == 0 else None)
    pts = [(x, d) for x in inside for d in data.psi_marks]
    if pts:
        ax.plot([p[0] for p in pts], [p[1] for p in pts], marker="D", markersize=6,
                color=colour, markeredgecolor="black", linestyle="none", zorder=6,
                gid="design-point")


def _inside(data: MapData) -> list[float]:
    lo, hi = data.xlim
    return [x for x in data.xi_marks if lo <= x <= hi]


def _map_axes(ax, data: MapData, ylabel: bool = True):
    if data.log:
        ax.set_xscale("log")
    ax.set_xlim(*data.xlim)
    ax.set_ylim(0.0, 180.0)
    ax.set_yticks(range(0, 181, 30))
    ax.set_xlabel("aspect ratio ξ = h/D")
    if ylabel:
        ax.set_ylabel("ψ (degrees)")


def map_figure(data: MapData, *, style: str = "panels", width: float | None = None,
               height: float | None = None, title: str | None = None):
    """Fig. 2a-c: the chances over (xi, psi), as three panels or one ternary colour map."""
    if style not in ("panels", "ternary"):
        raise ValueError(f"map style must be panels or ternary, got {style!r}")
    default = MAP_SIZES[style]
    width = default[0] if width is None else width
    height = default[1] if height is None else height
    with figure_style():
        fig = new_figure(width, height)
        if style == "panels":
            axes = fig.subplots(1, 3, sharey=True)
            mesh = None
            for k, (ax, name) in enumerate(zip(axes, ("heads", "sides", "tails"), strict=True)):
                z = getattr(data, name)
                mesh = ax.pcolormesh(data.xi, data.psi_deg, z, shading="nearest", vmin=0.0,
                                     vmax=1.0, cmap="viridis", rasterized=True,
                                     gid=f"mesh:{name}")
                cs = ax.contour(data.xi, data.psi_deg, z, levels=[1 / 3], colors="white",
                                linewidths=0.9, linestyles="-")
                cs.set_gid(f"contour:{name}")
                _boundary_lines(ax, data, "0.85")
                _map_marks(ax, data, OKABE_ITO["vermillion"], legend=(k == 0))
                _map_axes(ax, data, ylabel=(k == 0))
                ax.set_title(f"({'abc'[k]}) P({name})")
            fig.colorbar(mesh, ax=list(axes), label="probability (white contour: 1/3)",
                         shrink=0.9)
            axes[0].legend(loc="lower left", fontsize=7, framealpha=0.85)
            fig.suptitle(title or "Heads, sides and tails over aspect ratio and ψ "
                         "(Yong & Mahadevan, Fig. 2a-c)", parse_math=False)
        else:
            gs = fig.add_gridspec(1, 2, width_ratios=(4.2, 1.0))
            ax = fig.add_subplot(gs[0, 0])
            rgb = ternary_colours(data.heads, data.sides, data.tails)
            ax.pcolormesh(data.xi, data.psi_deg, rgb, shading="nearest", rasterized=True,
                          gid="mesh:ternary")
            _boundary_lines(ax, data, "0.25")
            _map_marks(ax, data, OKABE_ITO["vermillion"], legend=True)
            _map_axes(ax, data)
            ax.legend(loc="lower right", fontsize=7, framealpha=0.85)
            ax.set_title(title or "Heads, sides and tails over aspect ratio and ψ "
                         "(Yong & Mahadevan, Fig. 2a-c)", parse_math=False)
            _ternary_key(fig.add_subplot(gs[0, 1]))
        note_figure(fig, data.skipped)
    return fig


def _ternary_key(ax):
    """The colour key: a triangle with heads, sides and tails at its corners."""
    import numpy as np

    n = 60
    corners = {"heads": (0.0, 0.0), "tails": (1.0, 0.0), "sides": (0.5, math.sqrt(3) / 2)}
    ys, xs = np.mgrid[0:n + 1, 0:n + 1] / n
    xs, ys = xs, ys * math.sqrt(3) / 2
    # barycentric coordinates of each pixel centre
    s = ys / (math.sqrt(3) / 2)
    t = xs - 0.5 * s
    h = 1 - s - t
    inside = (h >= -1e-9) & (t >= -1e-9) & (s >= -1e-9)
    rgb = ternary_colours(np.clip(h, 0, 1), np.clip(s, 0, 1), np.clip(t, 0, 1))
    rgba = np.concatenate([rgb, inside[..., None].astype(float)], axis=-1)
    ax.imshow(rgba, origin="lower", extent=(0, 1, 0, math.sqrt(3) / 2), interpolation="nearest",
              gid="ternary-key")
    for name, (x, y) in corners.items():
        ax.annotate(name, (x, y), xytext=(0, -12 if y == 0 else 5), textcoords="offset points",
                    ha="center", fontsize=8)
    ax.plot([1 / 2], [math.sqrt(3) / 6], marker="+", color="black", markersize=8,
            gid="ternary-key-fair")
    ax.set_xlim(-0.15, 1.15)
    ax.set_ylim(-0.15, 1.0)
    ax.set_aspect("equal")
    ax.axis("off")
    ax.set_title("colour key\n(+ = 1/3 each)", fontsize=8)


# --------------------------------------------------------------------------- phase (Fig. 3)


@dataclass
class PhaseData:
    """The outcome over the plane of launch speed and spin (Fig. 3), and eq. 10's boundaries."""

    xi: float
    psi_deg: float
    u: object  #: cell centres along the launch speed, m/s (ndarray, nu)
    omega: object  #: cell centres along the spin, rad/s (ndarray, nw)
    outcome: object  #: (nw, nu) codes of :func:`coincli.core.toss.batch.toss_many`: 0 heads, 1 sides, 2 tails
    curves: list = field(default_factory=list)  #: :class:`coincli.core.toss.phase.Boundary` over ``u``
    fractions: object = None  #: Outcome: the share of the grid's cells of each outcome
    vigorous: object = None  #: Outcome: the vigorous limit (Table I at this xi and psi)
    marks: list = field(default_factory=list)  #: [(u, omega)] the user's tosses
    exact_curves: bool = False
    u_range: tuple = (0.0, 2.0)  #: the plotted range, m/s (the outer cells' edges)
    omega_range: tuple = (0.0, 60.0)
    u_label: str = "launch speed u (m/s)"
    omega_label: str = "precession rate ω (rad/s)"


OUTCOME_CODES = ("heads", "sides", "tails")
DEFAULT_U_RANGE = (0.0, 2.0)  #: m/s
DEFAULT_OMEGA_RANGE = (0.0, 60.0)  #: rad/s


def phase_data(xi: float = models.FAIR_XI_DYNAMIC, psi_deg: float = 90.0, *,
               u_range=DEFAULT_U_RANGE, omega_range=DEFAULT_OMEGA_RANGE, nu: int = 400,
               nw: int = 400, marks=(), exact_curves: bool = False, **toss_options) -> PhaseData:
    """Fig. 3: the outcome of each (u, omega) cell by :func:`coincli.core.toss.phase.phase_map`.

    ``toss_options`` go to it (``diameter`` in m, ``g``, ``contact``, ``z0``).  The boundary
    curves are eq. (10) (or the exact contact-time curves with ``exact_curves``).
    """
    from coincli.core.toss import phase as toss_phase

    psi_deg = float(psi_deg)
    if not 0.0 <= psi_deg <= 180.0:
        raise ValueError(f"psi must be an angle in [0, 180] degrees, got {psi_deg:g}")
    psi = math.pi if psi_deg == 180.0 else math.radians(psi_deg)
    pm = toss_phase.phase_map(xi, psi, u_range, omega_range, (int(nu), int(nw)),
                        exact_curves=exact_curves, **toss_options)
    return PhaseData(float(xi), psi_deg, pm.u, pm.omega, pm.codes, list(pm.curves),
                     pm.fractions(), table_i_deg(float(xi), psi_deg),
                     [(float(a), float(b)) for a, b in marks], exact_curves,
                     tuple(map(float, u_range)), tuple(map(float, omega_range)))


def phase_figure(data: PhaseData, *, width: float = 9.5, height: float = 5.5,
                 title: str | None = None):
    """Fig. 3: the pre-images of heads (white), sides (black) and tails (blue) over (u, omega),
    with the boundary curves of eq. (10) dashed."""
    import numpy as np

    with figure_style():
        from matplotlib.colors import BoundaryNorm, ListedColormap
        from matplotlib.lines import Line2D
        from matplotlib.patches import Patch

        fig = new_figure(width, height)
        ax = fig.add_subplot()
        colours = PHASE_COLOURS
        cmap = ListedColormap([colours["heads"], colours["sides"], colours["tails"]])
        ax.pcolormesh(data.u, data.omega, np.asarray(data.outcome, dtype=float),
                      shading="nearest", cmap=cmap, norm=BoundaryNorm([-0.5, 0.5, 1.5, 2.5], 3),
                      rasterized=True, gid="mesh:phase")
        styles = {"heads|sides": (OKABE_ITO["orange"], (0, (4, 2))),
                  "sides|tails": (OKABE_ITO["vermillion"], (0, (1, 1.5)))}
        for k, b in enumerate(data.curves):
            colour, ls = styles.get(b.kind, (OKABE_ITO["orange"], "--"))
            ax.plot(data.u, b.omega, color=colour, linewidth=0.9, linestyle=ls, zorder=3,
                    gid=f"hyperbola:{k}")
        for k, (mu, mo) in enumerate(data.marks):
            ax.plot([mu], [mo], marker="D", markersize=7, color=OKABE_ITO["yellow"],
                    markeredgecolor="black", linestyle="none", gid=f"design:{k}", zorder=5)
        f = data.fractions
        handles = [Patch(facecolor=colours[n], edgecolor="0.3",
                         label=f"{n}: {getattr(f, n):.1%} of the plotted area")
                   for n in OUTCOME_CODES]
        src = "contact-time curves" if data.exact_curves else "eq. 10, t_f = 2u/g"
        handles += [Line2D([], [], color=c, linestyle=ls, label=f"{kind} boundary ({src})")
                    for kind, (c, ls) in styles.items()
                    if any(b.kind == kind for b in data.curves)]
        if data.marks:
            handles.append(Line2D([], [], marker="D", color=OKABE_ITO["yellow"],
                                  markeredgecolor="black", linestyle="none", label="your toss"))
        fig.legend(handles=handles, loc="outside right upper", fontsize=8, frameon=False,
                   title=f"vigorous limit (Table I):\nheads {data.vigorous.heads:.3f}, sides "
                   f"{data.vigorous.sides:.3f},\ntails {data.vigorous.tails:.3f}",
                   title_fontsize=8, alignment="left")
        ax.set_xlim(*data.u_range)
        ax.set_ylim(*data.omega_range)
        ax.set_xlabel(data.u_label)
        ax.set_ylabel(data.omega_label)
        ax.set_title(title or f"Phase space of a toss: ξ = {data.xi:.4g}, ψ = "
                     f"{data.psi_deg:.4g}° (Yong & Mahadevan, Fig. 3)", parse_math=False)
    return fig


PHASE_COLOURS = {"heads": "#FFFFFF", "sides": "#1A1A1A", "tails": OKABE_ITO["sky"]}
