"""Text plots for ``coin plot --terminal`` (or ``--out -``): the figures on any machine.

A :class:`Canvas` is a grid of characters with a data range; curves are drawn one character a
column (consecutive points joined by a vertical run), marks on top, and :meth:`Canvas.render`
returns a :class:`rich.text.Text` with axes, tick labels, a legend and notes.  Each figure of
:mod:`coincli.render.figures` has a text version here (:func:`text_sides`, :func:`text_psi`,
:func:`text_map`, :func:`text_phase`) fed by the same data functions, so the numbers are the
core's.  Characters tell the series apart (colour is only a help: it disappears in a pipe and
with ``NO_COLOR``).  rich is imported only when a plot is rendered.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

__all__ = ["Canvas", "text_sides", "text_psi", "text_map", "text_phase", "phase_text",
           "phase_title", "plot_size", "emit"]

OUTCOME_STYLE = {"heads": "bold #0072B2", "sides": "bold #D55E00", "tails": "bold #009E73"}
OUTCOME_CHAR = {"heads": "H", "sides": "S", "tails": "T"}
DESIGN_STYLE = "bold #D55E00"
_CURVE_STYLES = {"geometric": "bold", "dynamic": "bold #0072B2"}
_EXTRA_STYLES = ("#E69F00", "#CC79A7", "#56B4E9", "#009E73", "#F0E442")
_EXTRA_CHARS = "abcdefghij"


@dataclass
class Canvas:
    """A character grid over ``xlim`` x ``ylim`` (x on a log scale if ``logx``)."""

    cols: int
    rows: int
    xlim: tuple[float, float]
    ylim: tuple[float, float]
    logx: bool = False
    cells: list = field(init=False)

    def __post_init__(self):
        self.cols, self.rows = max(int(self.cols), 10), max(int(self.rows), 5)
        self.cells = [[(" ", "", -1)] * self.cols for _ in range(self.rows)]

    # -- coordinates
    def xfrac(self, x: float) -> float:
        lo, hi = self.xlim
        if self.logx:
            if not x > 0:
                return -math.inf
            return math.log(x / lo) / math.log(hi / lo)
        return (x - lo) / (hi - lo)

    def col(self, x: float) -> int | None:
        f = self.xfrac(float(x))
        tol = 0.5 / (self.cols - 1) + 1e-9  # half a cell: the edges of the outer cells
        if not math.isfinite(f) or f < -tol or f > 1 + tol:
            return None
        return min(max(round(f * (self.cols - 1)), 0), self.cols - 1)

    def row(self, y: float) -> int | None:
        lo, hi = self.ylim
        f = (float(y) - lo) / (hi - lo)
        tol = 0.5 / (self.rows - 1) + 1e-9
        if not math.isfinite(f) or f < -tol or f > 1 + tol:
            return None
        return self.rows - 1 - min(max(round(f * (self.rows - 1)), 0), self.rows - 1)

    # -- drawing
    def put(self, c: int, r: int, ch: str, style: str = "", layer: int = 1) -> None:
        if 0 <= c < self.cols and 0 <= r < self.rows and layer >= self.cells[r][c][2]:
            self.cells[r][c] = (ch, style, layer)

    def plot(self, xs, ys, ch: str, style: str = "", layer: int = 2) -> None:
        """A curve: each point's cell, and a vertical run to the next point's row."""
        prev = None
        for x, y in zip(xs, ys, strict=True):
            c, r = self.col(x), self.row(y)
            if c is None or r is None:
                prev = None
                continue
            self.put(c, r, ch, style, layer)
            if prev is not None and abs(prev[1] - r) > 1 and abs(prev[0] - c) <= 1:
                pc, pr = prev
                mid = (pr + r) / 2
                step = 1 if r > pr else -1
                for rr in range(pr + step, r, step):
                    self.put(pc if (rr - mid) * step < 0 else c, rr, ch, style, layer)
            prev = (c, r)

    def point(self, x: float, y: float, ch: str, style: str = "", layer: int = 4) -> None:
        c, r = self.col(x), self.row(y)
        if c is not None and r is not None:
            self.put(c, r, ch, style, layer)

    def vline(self, x: float, ch: str = ":", style: str = "", layer: int = 0) -> None:
        c = self.col(x)
        if c is not None:
            for r in range(self.rows):
                self.put(c, r, ch, style, layer)

    def hline(self, y: float, ch: str = ".", style: str = "", layer: int = 0) -> None:
        r = self.row(y)
        if r is not None:
            for c in range(self.cols):
                self.put(c, r, ch, style, layer)

    def vbar(self, x: float, y0: float, y1: float, ch: str = "|", style: str = "",
             layer: int = 3) -> None:
        c, r0, r1 = self.col(x), self.row(y0), self.row(y1)
        if c is None or r0 is None or r1 is None:
            return
        for r in range(min(r0, r1), max(r0, r1) + 1):
            self.put(c, r, ch, style, layer)

    # -- output
    def render(self, *, title: str, xlabel: str, ylabel: str, xticks, yticks, legend=(),
               notes=()):
        """The plot as :class:`rich.text.Text`: title, y label, grid with axes, x ticks and
        label, legend entries ``(char, style, text)`` and notes."""
        from rich.text import Text

        ylab = {self.row(y): s for y, s in yticks if self.row(y) is not None}
        w = max([len(s) for s in ylab.values()] + [1])
        out = Text()
        out.append(title + "\n", style="bold")
        out.append(" " * (w + 1) + ylabel + "\n", style="italic")
        for r in range(self.rows):
            lab = ylab.get(r)
            out.append((lab.rjust(w) + " +") if lab is not None else (" " * w + " |"))
            row = self.cells[r]
            end = len(row)
            while end > 0 and row[end - 1][0] == " ":
                end -= 1  # no trailing blanks
            for ch, style, _ in row[:end]:
                out.append(ch, style=style or None)
            out.append("\n")
        out.append(" " * w + " +" + "-" * self.cols + "\n")
        line = [" "] * self.cols
        for x, s in xticks:
            c = self.col(x)
            if c is None:
                continue
            start = min(max(c - len(s) // 2, 0), self.cols - len(s))
            if start < 0 or any(ch != " " for ch in line[max(start - 1, 0):start + len(s) + 1]):
                continue
            line[start:start + len(s)] = list(s)
        out.append(" " * (w + 2) + "".join(line).rstrip() + "\n")
        out.append(" " * (w + 2) + xlabel.center(self.cols).rstrip() + "\n", style="italic")
        for ch, style, text in legend:
            out.append("  ")
            out.append(ch, style=style or None)
            out.append("  " + text.replace("\n", "\n     ") + "\n")
        for n in notes:
            out.append(f"  note: {n}\n", style="dim")
        return out


def plot_size(width: int | None = None, height: int | None = None,
              default_rows: int = 21) -> tuple[int, int]:
    """Columns and rows of the plot area: the terminal's width (:func:`coincli.io.terminal.
    terminal_width`, the same as the tables') less the axis labels, 30 to 110 columns."""
    if width is None:
        from coincli.io.terminal import terminal_width

        width = min(max(terminal_width() - 10, 30), 110)
    return max(int(width), 10), max(int(height or default_rows), 5)


def emit(text, out=None) -> None:
    """Print a rendered plot (colour on a terminal, plain text in a pipe or with NO_COLOR)."""
    # NO_COLOR (no-color.org, set to anything non-empty): rich drops colours by itself but keeps
    # bold, italic, dim and reverse; no colour system at all means no escape codes at all, as
    # the tables do (coincli.io.table).  The width is given: rich reads COLUMNS itself, and
    # COLUMNS=0 made it print nothing.
    # On a terminal, titles, legends and notes wrap at words to its width (the plot itself is
    # sized to fit); in a pipe nothing is wrapped.
    import sys

    from rich.console import Console

    from coincli.io.terminal import colour_allowed, terminal_width

    stream = out if out is not None else sys.stdout
    try:
        on_terminal = stream.isatty()
    except (AttributeError, ValueError):
        on_terminal = False
    plain = not colour_allowed()
    console = Console(file=out, highlight=False, soft_wrap=not on_terminal, emoji=False,
                      markup=False, color_system=None if plain else "auto",
                      width=terminal_width(stream))
    console.print(text, end="")


# --------------------------------------------------------------------------- the figures


def _ascii(text: str) -> str:
    """Labels of :mod:`coincli.render.figures` in the text plot's plain words."""
    return text.replace("ψ", "psi").replace("°", " deg").replace("ξ", "xi")


def axis_ticks(lo: float, hi: float, log: bool, n: int = 6):
    """Tick positions and labels: decades on a log axis, round steps (1, 2, 2.5, 5 x 10^k)
    giving about ``n`` ticks on a linear one."""
    if not (math.isfinite(lo) and math.isfinite(hi) and hi > lo and (lo > 0 or not log)):
        return []  # no axis to divide (the data functions refuse such ranges; no crash here)
    if log:
        a, b = math.ceil(math.log10(lo) - 1e-9), math.floor(math.log10(hi) + 1e-9)
        return [(10.0**k, f"{10.0**k:g}") for k in range(a, b + 1)]
    raw = (hi - lo) / max(n - 1, 1)
    if not raw > 0:  # a span of a few subnormals
        return [(lo, f"{lo:g}"), (hi, f"{hi:g}")]
    e = math.floor(math.log10(raw))
    step = next(m * 10.0**e for m in (1.0, 2.0, 2.5, 5.0, 10.0) if m * 10.0**e >= raw * 0.999)
    out = []
    k = math.ceil(lo / step - 1e-9)
    while k * step <= hi + 1e-9 * step:
        v = k * step
        out.append((v, f"{round(v, 10):g}"))
        k += 1
    return out


def _crosses(cv, legend, row, text: str) -> None:
    """A design's crosses (X) on the curves, and its legend line ``text``."""
    for m in row:
        cv.point(m.xi, m.p, "X", DESIGN_STYLE, layer=5)
    legend.append(("X", DESIGN_STYLE, text))


def text_sides(data, cols: int, rows: int):
    """Fig. 5a as text: one letter a model, F the fair coins, X the designs, o the tosses."""
    cv = Canvas(cols, rows, data.xlim, (0.0, 1.0), logx=data.log)
    legend = []
    chars = {}
    k_extra = 0
    for c in data.curves:
        if c.spec.key in ("geometric", "dynamic"):
            ch, style = c.spec.key[0].upper(), _CURVE_STYLES[c.spec.key]
        else:
            ch = _EXTRA_CHARS[k_extra % len(_EXTRA_CHARS)]
            style = _EXTRA_STYLES[k_extra % len(_EXTRA_STYLES)]
            k_extra += 1
        chars[c.spec.gid] = ch
        cv.plot(data.xi.tolist(), c.y.tolist(), ch, style)
        legend.append((ch, style, _ascii(c.spec.label)))
    if data.fair:
        cv.hline(1 / 3, ".", "dim")
    for m in data.fair:
        cv.point(m.xi, m.p, "F", "bold reverse")
    if data.fair:
        legend.append(("F", "bold reverse", "fair three-sided coin (1/3 each): " + ", ".join(
            f"{m.gid} xi = {m.xi:.4g}" for m in data.fair)))
    notes = list(data.skipped)
    for x, row in data.xi_marks:
        cv.vline(x, ":", DESIGN_STYLE)
        _crosses(cv, legend, row, f"your design xi = {x:.4g}: P(sides) " + ", ".join(
            f"{m.gid} {m.p:.4g}" for m in row))
    for p, row in data.p_marks:
        cv.hline(p, "-", DESIGN_STYLE)
        _crosses(cv, legend, row, f"your target P(sides) = {p:.4g}: xi " + ", ".join(
            f"{m.gid} {m.xi:.4g}" for m in row))
    from coincli.render.figures import group_label, point_groups

    for gid, pts in point_groups(data.experiments):
        ch, style = ("o", "bold #E69F00") if gid == "data" else ("s", "bold")
        for e in pts:
            cv.vbar(e.xi, e.low, e.high, "|", "")
            cv.point(e.xi, e.frequency, ch, style, layer=5 if gid == "data" else 4)
        legend.append((ch, style, _ascii(f"{group_label(gid, pts)}: frequency of sides, "
                                         "| = 95% Wilson interval")))
    return cv.render(
        title="coin plot sides: chance of landing on a side (Fig. 5a)",
        xlabel="aspect ratio xi = h/D (thickness / diameter)" + (", log scale" if data.log
                                                                   else ""),
        ylabel="P(sides)",
        xticks=axis_ticks(*data.xlim, data.log), yticks=axis_ticks(0.0, 1.0, False),
        legend=legend, notes=notes)


def text_psi(data, cols: int, rows: int):
    """Fig. 2d as text: H, S, T curves against psi; ':' marks the regime boundaries."""
    cv = Canvas(cols, rows, (0.0, 180.0), (0.0, 1.0))
    for b in data.bounds_deg:
        cv.vline(b, ":", "dim")
    cv.hline(1 / 3, ".", "dim")
    psi = data.psi_deg.tolist()
    for name in ("tails", "sides", "heads"):
        cv.plot(psi, getattr(data, name).tolist(), OUTCOME_CHAR[name], OUTCOME_STYLE[name])
    legend = [(OUTCOME_CHAR[n], OUTCOME_STYLE[n], f"P({n})") for n in ("heads", "sides", "tails")]
    # in terms of t = theta0/2 itself: 90 - t and 180 - t round to 90 and 180 for a thick coin
    t = data.bounds_deg[0]
    parts = []
    if t > 0:
        parts.append("all three within t of 90")
    if t < 45:
        parts.append("heads or sides from t to 90 - t and from 90 + t to 180 - t")
    if t > 0:
        parts.append("heads only below t and above 180 - t")
    legend.append((":", "dim", f"regimes (Table I), t = theta0/2 = {t:.6g} deg: "
                   + ";\n".join(parts)))
    for d, o in data.marks:
        cv.vline(d, "|", DESIGN_STYLE, layer=1)
        for v in o:
            cv.point(d, v, "X", DESIGN_STYLE, layer=5)
        legend.append(("X", DESIGN_STYLE, f"your toss psi = {d:.4g} deg: heads {o.heads:.4g}, "
                       f"sides {o.sides:.4g}, tails {o.tails:.4g}"))
    return cv.render(
        title=f"coin plot psi: heads, sides and tails against psi, xi = {data.xi:.4g} (Fig. 2d)",
        xlabel="psi, angle between angular momentum and normal (degrees)",
        ylabel="probability",
        xticks=[(d, str(d)) for d in range(0, 181, 30)], yticks=axis_ticks(0.0, 1.0, False),
        legend=legend)


def text_map(data, cols: int, rows: int):
    """Fig. 2a-c as text: the likeliest outcome in each cell (capital when above 1/2)."""
    import numpy as np

    cv = Canvas(cols, rows, data.xlim, (0.0, 180.0), logx=data.log)
    stack = np.stack([data.heads, data.sides, data.tails])
    best = np.argmax(stack, axis=0)
    top = np.max(stack, axis=0)
    names = ("heads", "sides", "tails")
    for i, psi in enumerate(data.psi_deg.tolist()):
        r = cv.row(psi)
        for j, x in enumerate(data.xi.tolist()):
            c = cv.col(x)
            if c is None or r is None:
                continue
            name = names[int(best[i, j])]
            ch = OUTCOME_CHAR[name]
            cv.put(c, r, ch if top[i, j] > 0.5 else ch.lower(), OUTCOME_STYLE[name], 1)
    legend = [(OUTCOME_CHAR[n], OUTCOME_STYLE[n], f"{n} likeliest (lower case: under 1/2)")
              for n in names]
    from coincli.core.models import FAIR_XI_DYNAMIC

    cv.point(FAIR_XI_DYNAMIC, 90.0, "*", "bold reverse", layer=6)
    legend.append(("*", "bold reverse", "fair three-sided coin: xi = 1/sqrt 3, psi = 90 deg"))
    for x in data.xi_marks:
        cv.vline(x, ":", DESIGN_STYLE, layer=2)
    for d in data.psi_marks:
        cv.hline(d, "-", DESIGN_STYLE, layer=2)
    for x in data.xi_marks:
        for d in data.psi_marks:
            cv.point(x, d, "X", DESIGN_STYLE, layer=7)
    if data.xi_marks or data.psi_marks:
        legend.append(("X", DESIGN_STYLE, "your design: " + ", ".join(
            [f"xi = {x:.4g}" for x in data.xi_marks] + [f"psi = {d:.4g} deg"
                                                       for d in data.psi_marks])))
    return cv.render(
        title="coin plot map: likeliest outcome over aspect ratio and psi (Fig. 2a-c)",
        xlabel="aspect ratio xi = h/D" + (", log scale" if data.log else ""),
        ylabel="psi (degrees)",
        xticks=axis_ticks(*data.xlim, data.log), yticks=[(d, str(d)) for d in range(0, 181, 45)],
        legend=legend, notes=list(getattr(data, "skipped", ())))



#: Cell colours of the phase picture: mid-tone blocks (Okabe-Ito blue, vermillion, bluish
#: green, the outcome colours of the other text plots) that stand out on a dark terminal as on
#: a light one; a boundary is a white dot on them, a marked toss a white X.
PHASE_BLOCK = {"heads": "on #0072B2", "sides": "on #D55E00", "tails": "on #009E73"}
PHASE_DOT = "bold #FFFFFF"


def _phase_curve_marks(data, np):
    """Boolean (rows, cols): the cells a boundary curve passes through, in the columns where it
    is at least two rows from its neighbours (denser curves would only paint every cell)."""
    u = np.asarray(data.u, dtype=float)
    (u0, u1), (w0, w1) = data.u_range, data.omega_range
    nw, nu = np.asarray(data.outcome).shape
    marks = np.zeros((nw, nu), dtype=bool)
    curves = sorted(data.curves, key=lambda b: b.phase)
    if not curves:
        return marks
    edges = u0 + (u1 - u0) / nu * np.arange(nu + 1)
    dw = (w1 - w0) / nw
    stack = np.array([np.asarray(b.omega, dtype=float) for b in curves])  # (curves, nu)
    with np.errstate(invalid="ignore"):
        gap = np.full(stack.shape, np.inf)
        if len(curves) > 1:
            d = np.abs(np.diff(stack, axis=0))
            gap[:-1] = np.fmin(gap[:-1], d)
            gap[1:] = np.fmin(gap[1:], d)
    for k, b in enumerate(curves):
        if b.phase <= 0:
            continue
        with np.errstate(divide="ignore", invalid="ignore"):
            # omega(u) sampled at the cell centres: its range over each column, from the values
            # interpolated at the column's edges.
            w_c = np.asarray(b.omega, dtype=float)
            w_e = np.interp(edges, u, w_c, left=np.nan, right=np.nan)
            w_e[0] = w_c[0] if not np.isfinite(w_e[0]) else w_e[0]
            w_e[-1] = w_c[-1] if not np.isfinite(w_e[-1]) else w_e[-1]
            lo = np.fmin(w_e[:-1], w_e[1:])
            hi = np.fmax(w_e[:-1], w_e[1:])
            lo = np.where(np.isfinite(lo), lo, w_c)
            hi = np.where(np.isfinite(hi), hi, w_c)
            r0 = np.floor((lo - w0) / dw)
            r1 = np.floor((hi - w0) / dw)
        for j in range(nu):
            if not (np.isfinite(r0[j]) and np.isfinite(r1[j])) or not gap[k, j] >= 2 * dw:
                continue
            a, z = int(max(r0[j], 0)), int(min(r1[j], nw - 1))
            if a <= z:
                marks[a:z + 1, j] = True
    return marks


def _round_ticks(lo: float, hi: float, cells: int, spacing: int):
    """Round values in [lo, hi] (1, 2, 2.5, 5 x 10^k steps), about one per ``spacing`` cells,
    each with the cell (0-based from ``lo``) that holds it; one tick a cell."""
    n = max(2, cells // max(spacing, 1) + 1)
    out, used = [], set()
    width = (hi - lo) / cells
    for v, label in axis_ticks(lo, hi, False, n):
        c = min(max(math.floor((v - lo) / width + 1e-9), 0), cells - 1)
        if c not in used:
            used.add(c)
            out.append((c, label))
    return out


def phase_text(data, *, colour: bool, title: str, width: int | None = None):
    """Fig. 3 in the terminal: one character a cell of ``data``
    (:class:`coincli.render.maps.PhaseData`), rows of omega (high at the top) by columns of u,
    round ticks on both axes.

    ``colour``: coloured blocks (:data:`PHASE_BLOCK`), boundaries as dots, returned as a
    :class:`rich.text.Text`; otherwise letters ``H S T`` (lower case where a boundary passes)
    as a plain ``str``, so that a pipe needs no rich.  The legend wraps at ``width`` columns
    (at least the picture's).
    """
    import numpy as np

    codes = np.asarray(data.outcome)
    nw, nu = codes.shape
    (u0, u1), (w0, w1) = data.u_range, data.omega_range
    marks = _phase_curve_marks(data, np)
    names = ("heads", "sides", "tails")
    yt = {nw - 1 - r: s for r, s in _round_ticks(w0, w1, nw, 4)}  # row index from the top
    lw = max([len(s) for s in yt.values()] + [1])
    du, dw = (u1 - u0) / nu, (w1 - w0) / nw
    toss_cells = {}
    for mu, mo in data.marks:
        if u0 <= mu <= u1 and w0 <= mo <= w1:
            toss_cells[(nw - 1 - min(int((mo - w0) / dw), nw - 1),
                        min(int((mu - u0) / du), nu - 1))] = True
    segs = []  # (text, style) pieces; "\n" ends a line

    def put(text, style=""):
        segs.append((text, style))

    import textwrap

    # A terminal's width (``width``) wraps the title and the notes; a pipe gets them whole.
    wrap_at = max(int(width), lw + 2 + nu, 20) if width else 10**6
    width = max(int(width or 0), lw + 2 + nu, 20)  # the legend: the picture's width at least
    put("\n".join(textwrap.wrap(title, wrap_at)) + "\n")
    put("omega (rad/s)\n")
    for i in range(nw):
        r = nw - 1 - i  # the grid's row of omega, from the bottom
        lab = yt.get(i)
        put(lab.rjust(lw) + " +" if lab is not None else " " * lw + " |")
        row = codes[r]
        if colour:
            j = 0
            while j < nu:  # runs of one style make short output
                code, on = int(row[j]), bool(marks[r, j]) or (i, j) in toss_cells
                k = j + 1
                while k < nu and int(row[k]) == code and not marks[r, k] and (i, k) not in \
                        toss_cells and not on:
                    k += 1
                if on:
                    ch = "X" if (i, j) in toss_cells else "•"
                    put(ch, f"{PHASE_DOT} {PHASE_BLOCK[names[code]]}")
                else:
                    put(" " * (k - j), PHASE_BLOCK[names[code]])
                j = k
        else:
            line = []
            for j in range(nu):
                ch = OUTCOME_CHAR[names[int(row[j])]]
                line.append("X" if (i, j) in toss_cells else (ch.lower() if marks[r, j]
                                                               else ch))
            put("".join(line))
        put("\n")
    xt = _round_ticks(u0, u1, nu, 10)
    axis = ["-"] * nu
    labels = [" "] * nu
    for c, s in xt:
        axis[c] = "+"
        start = min(max(c - len(s) // 2, 0), nu - len(s))
        if start < 0 or any(ch != " " for ch in labels[max(start - 1, 0):start + len(s) + 1]):
            continue
        labels[start:start + len(s)] = list(s)
    put(" " * lw + " +" + "".join(axis) + "\n")
    put(" " * (lw + 2) + "".join(labels).rstrip() + "\n")
    put(" " * (lw + 2) + "u (m/s)".center(nu).rstrip() + "\n")
    f, v = data.fractions, data.vigorous
    src = "exact t_f" if data.exact_curves else "eq. 10"
    items = []  # legend entries: (key text, key style, words)
    for n in names:
        key = "  " if colour else OUTCOME_CHAR[n]
        items.append((key, PHASE_BLOCK[n] if colour else "", f" {n} {getattr(f, n):.1%}"))
    if data.curves:
        items.append(("•" if colour else "h/s/t", PHASE_DOT if colour else "",
                      f" boundary ({src})"))
    if data.marks:
        items.append(("X", "", " your toss" + ("" if len(data.marks) == 1 else "es")))
    used = 0
    for key, style, words in items:
        size = 2 + len(key) + len(words)
        if used and used + size > width:
            put("\n")
            used = 0
        put("  ")
        put(key, style)
        put(words)
        used += size
    put("\n")
    put("\n".join(textwrap.wrap(f"vigorous limit (Table I): heads {v.heads:.3f}, sides "
                                f"{v.sides:.3f}, tails {v.tails:.3f}", wrap_at,
                                initial_indent="  ", subsequent_indent="  ")) + "\n")
    if not colour:
        return "".join(t for t, _ in segs)
    from rich.text import Text

    out = Text()
    for t, style in segs:
        out.append(t, style=style or None)
    return out


def text_phase(data, cols: int, rows: int, contact: str = "rim"):
    """``coin plot phase --terminal``: the picture of ``coin phase`` (:func:`phase_text`),
    coloured when stdout is a terminal without NO_COLOR."""
    import os
    import sys

    try:
        tty = sys.stdout.isatty()
    except (AttributeError, ValueError):
        tty = False
    colour = tty and not os.environ.get("NO_COLOR")
    from coincli.io.terminal import terminal_width

    return phase_text(data, colour=colour, title=phase_title(data, contact),
                      width=terminal_width() if tty else None)


def phase_title(data, contact: str = "rim") -> str:
    """The title of the phase picture, the same for ``coin phase`` and ``coin plot phase``."""
    return (f"Fig. 3: outcome over (u, omega); xi = {data.xi:.6g}, psi = {data.psi_deg:.6g} "
            f"deg, {contact} contact")
