"""Figures of ``coin book``: omega(t) with the face up, and the face chances of tossed boxes.

Builders only: they take the numbers :mod:`coincli.core.rigid` computed and return a
:class:`matplotlib.figure.Figure` on its own Agg canvas (through :mod:`coincli.render.figures`, whose
palette, style and :func:`coincli.render.figures.save_figure` they share).  Every artist that carries data
has a ``gid`` (``omega:1``, ``flip``, ``face-up``, ``bar:+3``, ``geometric``) so tests and
scripts can find it.
"""

from __future__ import annotations

import math

from coincli.render.figures import OKABE_ITO, _new_figure, _style

__all__ = ["omega_figure", "faces_figure"]

FACES = ("+1", "-1", "+2", "-2", "+3", "-3")
_COLOURS = (OKABE_ITO["blue"], OKABE_ITO["vermillion"], OKABE_ITO["green"])
_STYLES = ("-", "--", ":")


def omega_figure(t, omega, up, motion, label: str, start: str, rule: str):
    """omega_1, omega_2, omega_3 against t (top), the face up (bottom); for a spin near the
    middle axis the flips (sign changes of the middle component) as vertical lines."""
    import numpy as np

    with _style():
        fig = _new_figure(7.5, 5.2)
        ax, ax2 = fig.subplots(2, 1, sharex=True, height_ratios=[3, 1.3])
        for i in range(3):
            ax.plot(t, omega[:, i], color=_COLOURS[i], linestyle=_STYLES[i], linewidth=1.4,
                    label=f"ω{i + 1}", gid=f"omega:{i + 1}")
        sep = motion.kind == "separatrix"
        if (motion.gamma_kind == "growth" or sep) and len(t) > 1:
            # the flips are the sign changes of the middle axis's component
            b = motion.spin_axis if not sep else sorted(range(3),
                                                        key=lambda k: motion.moments[k])[1]
            s = np.sign(omega[:, b])
            idx = np.nonzero(s[1:] * s[:-1] < 0)[0]
            for k, j in enumerate(idx):
                # the crossing, interpolated linearly between the samples
                w0, w1 = omega[j, b], omega[j + 1, b]
                tc = t[j] + (t[j + 1] - t[j]) * w0 / (w0 - w1)
                ax.axvline(tc, color=OKABE_ITO["grey"] if "grey" in OKABE_ITO else "0.5",
                           linewidth=0.8, linestyle=(0, (2, 2)), gid="flip",
                           label="flip" if k == 0 else None)
                ax2.axvline(tc, color="0.5", linewidth=0.8, linestyle=(0, (2, 2)))
        ax.axhline(0.0, color="0.6", linewidth=0.6)
        ax.set_ylabel("ω (rad/s, body axes)")
        ax.legend(loc="upper right", fontsize="small", ncols=4)
        ax.set_title(_title(motion, label), fontsize="medium")
        ax2.step(t, up, where="post", color=OKABE_ITO["black"], linewidth=1.2, gid="face-up")
        ax2.set_yticks(range(6), FACES)
        ax2.set_ylim(5.5, -0.5)
        ax2.set_ylabel(f"face up\n({rule})")
        ax2.set_xlabel(f"t (s) after launch, face {start} up")
        if len(t):
            ax2.set_xlim(float(t[0]), float(t[-1]) if t[-1] > t[0] else float(t[0]) + 1.0)
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
    with _style():
        fig = _new_figure(7.0, 4.2)
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
