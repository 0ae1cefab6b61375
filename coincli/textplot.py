"""Text plots for ``coin plot --terminal`` (or ``--out -``): the figures on any machine.

A :class:`Canvas` is a grid of characters with a data range; curves are drawn one character a
column (consecutive points joined by a vertical run), marks on top, and :meth:`Canvas.render`
returns a :class:`rich.text.Text` with axes, tick labels, a legend and notes.  Each figure of
:mod:`coincli.plot` has a text version here (:func:`text_sides`, :func:`text_psi`,
:func:`text_map`, :func:`text_phase`) fed by the same data functions, so the numbers are the
core's.  Characters tell the series apart (colour is only a help: it disappears in a pipe and
with ``NO_COLOR``).  rich is imported only when a plot is rendered.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

__all__ = ["Canvas", "text_sides", "text_psi", "text_map", "text_phase", "plot_size", "emit"]

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
    """Columns and rows of the plot area: the terminal's width (:func:`coincli._terminal.
    terminal_width`, the same as the tables') less the axis labels, 30 to 110 columns."""
    if width is None:
        from coincli._terminal import terminal_width

        width = min(max(terminal_width() - 10, 30), 110)
    return max(int(width), 10), max(int(height or default_rows), 5)


def emit(text, out=None) -> None:
    """Print a rendered plot (colour on a terminal, plain text in a pipe or with NO_COLOR)."""
    from rich.console import Console

    from coincli._terminal import colour_allowed, terminal_width

    # NO_COLOR (no-color.org, set to anything non-empty): rich drops colours by itself but keeps
    # bold, italic, dim and reverse; no colour system at all means no escape codes at all, as
    # the tables do (coincli.cli._common).  The width is given: rich reads COLUMNS itself, and
    # COLUMNS=0 made it print nothing.
    plain = not colour_allowed()
    console = Console(file=out, highlight=False, soft_wrap=True, emoji=False, markup=False,
                      color_system=None if plain else "auto", width=terminal_width(out))
    console.print(text, end="")


# --------------------------------------------------------------------------- the figures


def _ascii(text: str) -> str:
    """Labels of :mod:`coincli.plot` in the text plot's plain words."""
    return text.replace("ψ", "psi").replace("°", " deg").replace("ξ", "xi")


def _ticks(lo: float, hi: float, log: bool, n: int = 6):
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
        for m in row:
            cv.point(m.xi, m.p, "X", DESIGN_STYLE, layer=5)
        legend.append(("X", DESIGN_STYLE, f"your design xi = {x:.4g}: P(sides) " + ", ".join(
            f"{m.gid} {m.p:.4g}" for m in row)))
    for p, row in data.p_marks:
        cv.hline(p, "-", DESIGN_STYLE)
        for m in row:
            cv.point(m.xi, m.p, "X", DESIGN_STYLE, layer=5)
        legend.append(("X", DESIGN_STYLE, f"your target P(sides) = {p:.4g}: xi " + ", ".join(
            f"{m.gid} {m.xi:.4g}" for m in row)))
    for e in data.experiments:
        cv.vbar(e.xi, e.low, e.high, "|", "")
        cv.point(e.xi, e.frequency, "o", "bold #E69F00", layer=5)
    if data.experiments:
        n = len(data.experiments)
        legend.append(("o", "bold #E69F00", f"your tosses ({n} row{'s' if n > 1 else ''}): "
                       "frequency of sides, | = 95% Wilson interval"))
    return cv.render(
        title="coin plot sides: chance of landing on a side (Fig. 5a)",
        xlabel="aspect ratio xi = h/D (thickness / diameter)" + (", log scale" if data.log
                                                                   else ""),
        ylabel="P(sides)",
        xticks=_ticks(*data.xlim, data.log), yticks=_ticks(0.0, 1.0, False),
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
    t1, t2, t3, t4 = data.bounds_deg
    parts = []
    if t3 > t2:
        parts.append(f"all three {t2:.4g}-{t3:.4g} deg")
    if t2 > t1:
        parts.append(f"heads or sides {t1:.4g}-{t2:.4g} and {t3:.4g}-{t4:.4g}")
    if t1 > 0:
        parts.append(f"heads only below {t1:.4g} and above {t4:.4g}")
    legend.append((":", "dim", "regimes (Table I): " + ";\n".join(parts)))
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
        xticks=[(d, str(d)) for d in range(0, 181, 30)], yticks=_ticks(0.0, 1.0, False),
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
    from coincli.models import FAIR_XI_DYNAMIC

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
        xticks=_ticks(*data.xlim, data.log), yticks=[(d, str(d)) for d in range(0, 181, 45)],
        legend=legend, notes=list(getattr(data, "skipped", ())))


def text_phase(data, cols: int, rows: int):
    """Fig. 3 as text: the outcome of each (u, omega) cell."""
    import numpy as np

    u = np.asarray(data.u, dtype=float)
    om = np.asarray(data.omega, dtype=float)
    cv = Canvas(cols, rows, (float(u[0]), float(u[-1])), (float(om[0]), float(om[-1])))
    names = ("heads", "sides", "tails")
    codes = np.asarray(data.outcome)
    for i, w in enumerate(om.tolist()):
        r = cv.row(w)
        for j, x in enumerate(u.tolist()):
            c = cv.col(x)
            if c is None or r is None or codes[i, j] < 0:
                continue
            name = names[int(codes[i, j])]
            cv.put(c, r, OUTCOME_CHAR[name], OUTCOME_STYLE[name], 1)
    f, v = data.fractions, data.vigorous
    legend = [(OUTCOME_CHAR[n], OUTCOME_STYLE[n],
               f"{n}: {getattr(f, n):.1%} of the plotted cells "
               f"(vigorous limit {getattr(v, n):.3f})")
              for n in names]
    for mu, mo in data.marks:
        cv.point(mu, mo, "X", DESIGN_STYLE, layer=7)
    if data.marks:
        legend.append(("X", DESIGN_STYLE, "your toss: " + ", ".join(
            f"u = {mu:.4g} m/s, omega = {mo:.4g} rad/s" for mu, mo in data.marks)))
    (lo_u, hi_u), (lo_w, hi_w) = data.u_range, data.omega_range
    return cv.render(
        title=f"coin plot phase: outcome over launch speed and spin, xi = {data.xi:.4g}, "
              f"psi = {data.psi_deg:.4g} deg (Fig. 3)",
        xlabel="launch speed u (m/s)", ylabel="precession rate omega (rad/s)",
        xticks=_ticks(lo_u, hi_u, False), yticks=_ticks(lo_w, hi_w, False), legend=legend)
