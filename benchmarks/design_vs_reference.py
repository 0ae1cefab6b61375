"""README's bouncing recipe against a separate reference run of the engine (issue 37).

The recipe, ``coin design --p-sides 1/3 --diameter 30 --landing bounce --surface wood --seed S
--tol 0.05`` (no shipped table for a 30 mm coin: every toss simulated), at seeds 1 to 10, and
its 95% interval of xi, against the engine's own fair xi measured apart: ``coin simulate
--landing bounce`` (the same hand toss, coin and surface) at aspect ratios around it, a probit
in ln xi fitted to those counts (:func:`coincli.core.bounce.design.fit_sides`), and its xi at
P(sides) = 1/3 with Fieller's 95% interval.  Seeds of the reference: 1000 + point.

    python benchmarks/design_vs_reference.py [TOSSES_PER_POINT] [SEEDS] [XI,LOW,HIGH] > recipe.md

``XI,LOW,HIGH``: a reference measured before (its fair xi and interval), not measured again.

CPU: the reference is 6 x TOSSES_PER_POINT tosses (default 4000: about 8 CPU-minutes), each
design about 3000 tosses (a minute).
"""

from __future__ import annotations

import sys
import time

from coincli import api
from coincli.core.bounce.design import fit_sides

RECIPE = dict(p_sides="1/3", diameter=30, landing="bounce", surface="wood", tol=0.05)
REFERENCE_XI = (0.46, 0.48, 0.50, 0.52, 0.54, 0.56)


def reference(n: int):
    points = []
    for j, xi in enumerate(REFERENCE_XI):
        rows = api.simulate(xi=xi, diameter=30, landing="bounce", surface="wood", tosses=n,
                            seed=1000 + j)
        counts = {r["outcome"]: r["count"] for r in rows}
        settled = counts["heads"] + counts["sides"] + counts["tails"]
        points.append((xi, settled, counts["sides"]))
    fit = fit_sides(points)
    return points, fit, fit.inverse(1 / 3), fit.interval(1 / 3)


def main(argv):
    n = int(argv[1]) if len(argv) > 1 else 4000
    seeds = range(1, int(argv[2]) + 1) if len(argv) > 2 else range(1, 11)
    if len(argv) > 3:
        x_ref, lo_ref, hi_ref = (float(v) for v in argv[3].split(","))
        print(f"Reference (measured before): fair xi {x_ref:.4f} [{lo_ref:.4f}, {hi_ref:.4f}]."
              "\n")
    else:
        t0 = time.monotonic()
        points, fit, x_ref, (lo_ref, hi_ref) = reference(n)
        t_ref = time.monotonic() - t0
        print(f"Reference: `coin simulate --landing bounce --surface wood --diameter 30 -n {n}` "
              f"at {len(points)} aspect ratios (seeds 1000-{999 + len(points)}), {t_ref:.0f} s "
              "of wall:\n")
        print("| xi | settled | sides | P(sides) |\n|---|---|---|---|")
        for xi, s, k in points:
            print(f"| {xi:g} | {s} | {k} | {k / s:.4f} |")
        print(f"\nProbit in ln xi over these points: deviance {fit.deviance:.2f} on {fit.df} "
              f"df (p = {fit.p_value:.3f}); fair xi (P(sides) = 1/3) **{x_ref:.4f}** "
              f"[{lo_ref:.4f}, {hi_ref:.4f}] (Fieller 95%).\n")
    print("| seed | xi | 95% interval | holds the reference | tosses | wall s |")
    print("|---|---|---|---|---|---|")
    held = 0
    for s in seeds:
        t0 = time.monotonic()
        row = api.design(**RECIPE, seed=s)[0]
        wall = time.monotonic() - t0
        ok = row["xi_low"] <= x_ref <= row["xi_high"]
        held += ok
        print(f"| {s} | {row['xi']:.4f} | [{row['xi_low']:.4f}, {row['xi_high']:.4f}] | "
              f"{'yes' if ok else 'no'} | {row['tosses']} | {wall:.0f} |")
    print(f"\nThe recipe's interval holds the reference's fair xi in {held} of {len(seeds)} "
          "seeds.")


if __name__ == "__main__":
    main(sys.argv)
