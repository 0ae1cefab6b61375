"""coin's bounce engine against the published figures (shared/data/bounce-references.md) and its
sensitivity to what a user cannot control.  Prints markdown; docs/bounce.md quotes it.

    python benchmarks/bounce_compare.py compare [N]      # the sources' set-ups
    python benchmarks/bounce_compare.py sensitivity [N]  # one setting at a time from wood

Each row simulates N tosses (default 300) at three aspect ratios (0.45, 0.7 and the row's
xi), fits the probit of coincli.core.bounce.design.fit_sides to them, and reports P(sides) at the
source's xi (or at 0.577) with its 95% Wilson interval and the fitted fair xi
(P(sides) = 1/3) with its 95% interval.  Seed 1, every core.  The hand toss of ``coin
simulate`` (coincli.core.toss.launch.HAND_TOSS) unless said: u ~ normal:2.4:0.3 m/s, omega ~ normal:38:4
rev/s, psi ~ normal(90, 10) deg.
"""

from __future__ import annotations

import math
import sys
import time

from coincli.core.bounce import design as D
from coincli.core.bounce import engine as B
from coincli.core.bounce import runs as R
from coincli.core.toss.launch import HAND_TOSS, Dist

DEG = math.pi / 180
HAND = dict(HAND_TOSS)
TUMBLE = {**HAND, "psi": f"uniform:0:{math.pi!r}"}  # random axis: every psi alike
XIS = (0.45, 0.7)


def row(label, surf, launch, n, at=0.577, xis=XIS, **kw):
    t0 = time.perf_counter()
    pts, here = [], None
    grid = sorted(set(xis) | {at})
    for j, x in enumerate(grid):
        r = R.simulate(n, 1, xi=x, surf=surf, stream=(j,), **launch, **kw)
        pts.append((x, r.settled, r.counts[1]))
        if x == at:
            here = r.frequencies[1]
    fit = D.fit_sides(pts)
    fair = fit.inverse(1 / 3)
    lo, hi = fit.interval(1 / 3)
    out = (f"| {label} | {surf.restitution:g} | {surf.friction:g} | {at:g} | "
           f"{here.p:.3f} [{here.lo:.3f}, {here.hi:.3f}] | {fair:.3f} [{lo:.3f}, {hi:.3f}] | "
           f"{fit.p_value:.2f} |")
    print(out, flush=True)
    print(f"  ({time.perf_counter() - t0:.0f} s)", file=sys.stderr, flush=True)


HEAD = ("| set-up | restitution | friction | xi | P(sides) at xi [95%] | fair xi [95%] | "
        "fit p |\n|---|---|---|---|---|---|---|")


def compare(n):
    print(HEAD)
    wood = B.SURFACES["wood"]
    row("coin: hand toss onto wood (default)", wood, HAND, n)
    row("coin: tumbling toss onto wood", wood, TUMBLE, n)
    # iaroslav-ai: Bullet multiplies the two restitutions (0.3 x 0.603) and frictions
    row("iaroslav-ai (Blender/Bullet): e = 0.3 x 0.603, mu 0.44, tumbling",
        B.Surface(0.18, 0.44), TUMBLE, n, at=0.49)
    row("timjolson (pybullet): e 0.8, mu 1, tumbling", B.Surface(0.8, 1.0), TUMBLE, n, at=0.479)
    row("LeonZamel (pybullet): e 0.7, h/D 0.5, tumbling", B.Surface(0.7, 0.5), TUMBLE, n,
        at=0.5)
    row("imois.in blog: e 0.15, tumbling", B.Surface(0.15, 0.5), TUMBLE, n, at=0.425)
    row("rice (the paper's catch surface), hand toss", B.SURFACES["rice"], HAND, n)


def nickel(n):
    """Murray & Teare: a US nickel on a hard surface, about 1 in 6000 on edge."""
    print("| set-up | tosses | on edge | rate [95%] | 1 in |\n|---|---|---|---|---|")
    for label, surf, launch in (("hand toss onto hard-floor", B.SURFACES["hard-floor"], HAND),
                                ("tumbling toss onto hard-floor", B.SURFACES["hard-floor"],
                                 TUMBLE),
                                ("hand toss onto wood", B.SURFACES["wood"], HAND)):
        r = R.simulate(n, 1, xi=1.95 / 21.21, diameter=0.02121, surf=surf, **launch)
        f = r.frequencies[1]
        print(f"| {label} | {r.settled} | {f.count} | {f.p:.2e} [{f.lo:.1e}, {f.hi:.1e}] | "
              f"{1 / f.p if f.p else math.inf:.0f} |", flush=True)


def rev(mean, sd):
    """omega ~ normal(mean, sd) rev/s, in rad/s."""
    return Dist("normal", 2 * math.pi * mean, 2 * math.pi * sd, 0.0, math.inf)


def sensitivity(n):
    print(HEAD)
    wood = B.SURFACES["wood"]
    row("wood, hand toss (baseline)", wood, HAND, n)
    for e in (0.3, 0.7):
        row(f"restitution {e}", B.surface("wood", restitution=e), HAND, n)
    for mu in (0.15, 0.6):
        row(f"friction {mu}", B.surface("wood", friction=mu), HAND, n)
    row("rolling resistance x10 (1 mm)", B.surface("wood", rolling=1e-3), HAND, n)
    row("slow toss: u ~ normal:1.5:0.2", wood, {**HAND, "u": "normal:1.5:0.2"}, n)
    row("fast toss: u ~ normal:3.5:0.4", wood, {**HAND, "u": "normal:3.5:0.4"}, n)
    row("less spin: omega ~ normal:25:3 rev/s", wood, {**HAND, "omega": rev(25, 3)}, n)
    row("more spin: omega ~ normal:50:5 rev/s", wood, {**HAND, "omega": rev(50, 5)}, n)
    row("Keller flip: psi = 90 exactly", wood, {**HAND, "psi": math.pi / 2}, n)
    row("psi ~ normal(90, 20) deg", wood, {**HAND, "psi": f"normal:{math.pi / 2!r}:"
                                            f"{20 * DEG!r}"}, n)
    row("dropped 30 cm: --release-height 300", wood, HAND, n, height=0.3)


if __name__ == "__main__":
    what = sys.argv[1] if len(sys.argv) > 1 else "compare"
    n = int(sys.argv[2]) if len(sys.argv) > 2 else 300
    {"compare": compare, "sensitivity": sensitivity, "nickel": nickel}[what](n)
