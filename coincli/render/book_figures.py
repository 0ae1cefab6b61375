"""Figures of ``coin book``: omega(t) with the face up, and the face chances of tossed boxes.

Builders only: they take the numbers :mod:`coincli.core.rigid` computed and return a
:class:`matplotlib.figure.Figure` on its own Agg canvas (through :mod:`coincli.render.figures`, whose
palette, style and :func:`coincli.render.figures.save_figure` they share).  Every artist that carries data
has a ``gid`` (``omega:1``, ``flip``, ``face-up``, ``bar:+3``, ``geometric``) so tests and
scripts can find it.
"""

from __future__ import annotations

import math

from coincli.render.figures import OKABE_ITO, figure_style, new_figure

__all__ = ["omega_figure", "omega_figure_of", "faces_figure", "PIXEL_COLUMNS", "THIN_ABOVE"]

FACES = ("+1", "-1", "+2", "-2", "+3", "-3")
_COLOURS = (OKABE_ITO["blue"], OKABE_ITO["vermillion"], OKABE_ITO["green"])
_STYLES = ("-", "--", ":")


#: pixel columns a long series is thinned to: more than the omega axes' width at 150 dpi (about
#: 1000 pixels of the 7.5 inch figure), so a PNG shows every column's full range of values
PIXEL_COLUMNS = 2048
#: a series of more samples than this is thinned (:func:`omega_figure_of`); a shorter one is
#: drawn as it is (the default figure, 2001 samples, among them)
THIN_ABOVE = 4 * PIXEL_COLUMNS
#: flip lines drawn one artist each up to this many; more are one collection
FLIP_LINES = 100


def omega_figure(t, omega, up, motion, label: str, start: str, rule: str):
    """omega_1, omega_2, omega_3 against t (top), the face up (bottom); for a spin near the
    middle axis the flips (sign changes of the middle component) as vertical lines."""
    axis = _flip_axis(motion)
    flips = _flips(t, omega[:, axis]) if axis is not None and len(t) > 1 else []
    return _draw([(t, omega[:, i]) for i in range(3)], (t, up), flips,
                 (float(t[0]), float(t[-1])) if len(t) else None, motion, label, start, rule)


def omega_figure_of(ts, omega_up, motion, label: str, start: str, rule: str,
                    chunk: int = 65536, columns: int = PIXEL_COLUMNS):
    """:func:`omega_figure` of the times ``ts`` (any order), with ``omega_up(t) -> (omega,
    up)`` computing a chunk of times at a time.  Up to :data:`THIN_ABOVE` times it is exactly
    :func:`omega_figure`; a longer series is thinned to ``columns`` pixel columns: in each, the
    first, smallest, largest and last value of every curve, in time order (the M4 rule: the
    line drawn covers the same pixels as the whole series), and at most one flip line.  Memory
    and file size then depend on ``columns``, not on the number of times."""
    import numpy as np

    ts = np.asarray(ts, dtype=float)
    if ts.size <= THIN_ABOVE:
        omega, up = omega_up(ts)
        return omega_figure(ts, omega, up, motion, label, start, rule)
    if np.any(ts[1:] < ts[:-1]):  # a list in any order: a curve against t is drawn in t order
        ts = np.sort(ts, kind="stable")
    t0, t1 = float(ts[0]), float(ts[-1])
    env = _Envelope(t0, t1, columns, 4)
    axis = _flip_axis(motion)
    flips, prev = [], None
    for i in range(0, ts.size, chunk):
        t = ts[i:i + chunk]
        omega, up = omega_up(t)
        env.add(t, np.column_stack([omega, np.asarray(up, dtype=float)]))
        if axis is not None:
            if prev is not None:  # a flip between the last chunk and this one
                t, w = np.r_[prev[0], t], np.r_[prev[1], omega[:, axis]]
            else:
                w = omega[:, axis]
            flips.extend(_flips(t, w))
            prev = (t[-1], w[-1])
    if flips:  # one line per pixel column: a denser set of lines is a band either way
        f = np.asarray(flips)
        col = env.column(f)
        flips = f[np.r_[True, col[1:] != col[:-1]]].tolist()
    curves = [env.series(k) for k in range(4)]
    up_t, up_v = curves[3]
    return _draw(curves[:3], (up_t, up_v.astype(int)), flips, (t0, t1), motion, label, start,
                 rule)


class _Envelope:
    """The first, smallest, largest and last value (with their times) of ``k`` curves in each
    of ``columns`` equal columns of [t0, t1], fed in time order, a chunk at a time."""

    def __init__(self, t0: float, t1: float, columns: int, k: int):
        import numpy as np

        self.t0, self.columns = t0, columns
        self.scale = columns / (t1 - t0) if t1 > t0 else 0.0
        shape = (columns, k)
        self.seen = np.zeros(columns, dtype=bool)
        # [first, min, max, last]: times and values
        self.t = np.full((4, *shape), np.nan)
        self.v = np.full((4, *shape), np.nan)

    def column(self, t):
        import numpy as np

        c = np.floor((np.asarray(t, dtype=float) - self.t0) * self.scale)
        return np.clip(c, 0, self.columns - 1).astype(np.int64)

    def add(self, t, v) -> None:
        import numpy as np

        m = t.size
        if not m:
            return
        col = self.column(t)
        starts = np.flatnonzero(np.r_[True, col[1:] != col[:-1]])
        ends = np.r_[starts[1:], m] - 1
        cols = col[starts]  # distinct: the times are in order
        lens = ends - starts + 1
        new = ~self.seen[cols]
        self.t[0, cols[new]] = t[starts[new], None]
        self.v[0, cols[new]] = v[starts[new]]
        self.t[3, cols] = t[ends, None]
        self.v[3, cols] = v[ends]
        self.seen[cols] = True
        idx = np.arange(m)
        for role, reduce, better in ((1, np.minimum, np.less), (2, np.maximum, np.greater)):
            seg = reduce.reduceat(v, starts, axis=0)  # (segments, k)
            at = np.where(v == np.repeat(seg, lens, axis=0), idx[:, None], m)
            first = np.minimum.reduceat(at, starts, axis=0)  # the first sample reaching it
            held = self.v[role, cols]
            take = np.isnan(held) | better(seg, held)
            rows, ks = np.nonzero(take)
            self.v[role, cols[rows], ks] = seg[rows, ks]
            self.t[role, cols[rows], ks] = t[first[rows, ks]]

    def series(self, k: int):
        """Curve ``k`` thinned: (times, values), in time order, repeated points dropped."""
        import numpy as np

        t = self.t[:, self.seen, k].T  # (columns seen, 4)
        v = self.v[:, self.seen, k].T
        order = np.argsort(t, axis=1, kind="stable")
        t = np.take_along_axis(t, order, axis=1).ravel()
        v = np.take_along_axis(v, order, axis=1).ravel()
        keep = np.r_[True, (t[1:] != t[:-1]) | (v[1:] != v[:-1])]
        return t[keep], v[keep]


def _flip_axis(motion):
    """The axis whose sign changes are the flips (a spin near the middle axis, or on the
    separatrix), or None."""
    sep = motion.kind == "separatrix"
    if motion.gamma_kind == "growth" or sep:
        return motion.spin_axis if not sep else sorted(range(3),
                                                       key=lambda k: motion.moments[k])[1]
    return None


def _flips(t, w) -> list:
    """The times where ``w`` changes sign, interpolated linearly between the samples."""
    import numpy as np

    s = np.sign(w)
    idx = np.nonzero(s[1:] * s[:-1] < 0)[0]
    return [float(t[j] + (t[j + 1] - t[j]) * w[j] / (w[j] - w[j + 1])) for j in idx]


def _draw(curves, up_curve, flips, span, motion, label, start, rule):
    with figure_style():
        fig = new_figure(7.5, 5.2)
        ax, ax2 = fig.subplots(2, 1, sharex=True, height_ratios=[3, 1.3])
        for i, (t, w) in enumerate(curves):
            ax.plot(t, w, color=_COLOURS[i], linestyle=_STYLES[i], linewidth=1.4,
                    label=f"ω{i + 1}", gid=f"omega:{i + 1}")
        grey = OKABE_ITO["grey"] if "grey" in OKABE_ITO else "0.5"
        if len(flips) <= FLIP_LINES:
            for k, tc in enumerate(flips):
                ax.axvline(tc, color=grey, linewidth=0.8, linestyle=(0, (2, 2)), gid="flip",
                           label="flip" if k == 0 else None)
                ax2.axvline(tc, color="0.5", linewidth=0.8, linestyle=(0, (2, 2)))
        else:  # one collection each: thousands of lines as one artist
            ax.vlines(flips, 0, 1, transform=ax.get_xaxis_transform(), colors=grey,
                      linewidth=0.8, linestyles=(0, (2, 2)), gid="flip", label="flip")
            ax2.vlines(flips, 0, 1, transform=ax2.get_xaxis_transform(), colors="0.5",
                       linewidth=0.8, linestyles=(0, (2, 2)))
        ax.axhline(0.0, color="0.6", linewidth=0.6)
        ax.set_ylabel("ω (rad/s, body axes)")
        ax.legend(loc="upper right", fontsize="small", ncols=4)
        ax.set_title(_title(motion, label), fontsize="medium")
        ax2.step(up_curve[0], up_curve[1], where="post", color=OKABE_ITO["black"],
                 linewidth=1.2, gid="face-up")
        ax2.set_yticks(range(6), FACES)
        ax2.set_ylim(5.5, -0.5)
        ax2.set_ylabel(f"face up\n({rule})")
        ax2.set_xlabel(f"t (s) after launch, face {start} up")
        if span is not None:
            ax2.set_xlim(span[0], span[1] if span[1] > span[0] else span[0] + 1.0)
    return fig


def _title(m, label: str) -> str:
    if m.kind == "separatrix":
        return f"{label}: on the separatrix (one flip at most, never back)"
    if m.gamma_kind == "oscillation" and m.frequency:
        return (f"{label}: stable spin about axis {m.spin_axis + 1}; "
                f"Γ = {m.gamma:.4g} rad/s, exact {m.frequency:.4g} rad/s")
    if m.gamma_kind == "growth":
        flips = (f", flips every {m.half_period:.4g} s" if m.half_period and
                 math.isfinite(m.half_period) else "")
        return (f"{label}: spin near the middle axis {m.spin_axis + 1}; "
                f"λ = {m.gamma:.4g} /s{flips}")
    return label


def faces_figure(rows, label: str, n: int, seed: int, rule: str):
    """Bars: each face's frequency with its 95% interval; dots: the geometric model."""
    with figure_style():
        fig = new_figure(7.0, 4.2)
        ax = fig.subplots()
        x = list(range(len(rows)))
        freq = [r[3] for r in rows]
        lo = [r[3] - r[4] for r in rows]
        hi = [r[5] - r[3] for r in rows]
        geo = [r[6] for r in rows]
        for k, r in enumerate(rows):
            ax.bar(k, r[3], color=OKABE_ITO["sky"], edgecolor=OKABE_ITO["blue"], width=0.6,
                   gid=f"bar:{r[0]}", label="tossed (95% interval)" if k == 0 else None)
        ax.errorbar(x, freq, yerr=[lo, hi], fmt="none", ecolor=OKABE_ITO["black"], capsize=3,
                    gid="interval")
        ax.plot(x, geo, linestyle="none", marker="D", color=OKABE_ITO["vermillion"],
                label="geometric (solid angle)" if rule == "centre" else "geometric (1/6)",
                gid="geometric")
        # "0.7192 x 0.4152 (relative)" (a box from --moments): "(relative)" on a line of its
        # own, and a smaller font where a line is still long, so that six fit side by side
        ticks = [f"{r[0]}\n{str(r[1]).replace(' (', chr(10) + '(')}" for r in rows]
        longest = max(len(line) for t in ticks for line in t.splitlines())
        ax.set_xticks(x, ticks, fontsize="small" if longest <= 12 else "x-small")
        ax.set_ylabel("chance of the face up")
        ax.set_ylim(0, max(max(freq), max(geo)) * 1.15 + 1e-9)
        ax.set_title(f"{label}: {n:,} tosses, seed {seed}", fontsize="medium")
        ax.legend(loc="upper right", fontsize="small")
    return fig
