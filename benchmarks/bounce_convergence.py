"""Timestep convergence of the bounce engine (issue 16): P(heads, sides, tails) against dt.

For each aspect ratio, the same seeded tosses (the hand toss of coincli.core.toss.launch.HAND_TOSS onto
wood, `coin simulate --landing bounce`'s defaults) at dt = 2e-4, 1e-4 and 5e-5 s (or those
given); the contact stiffness follows dt (omega_n dt = 0.3) and the restitution is
recalibrated at each dt, so a smaller dt is also a harder contact.  Prints a markdown table
with 95% Wilson intervals and the CPU time per toss; docs/bounce.md quotes it.

    python benchmarks/bounce_convergence.py [N] [XI,XI,...] [DT,DT,...]
"""

from __future__ import annotations

import resource
import sys

from coincli.core.bounce import runs
from coincli.core.toss.launch import HAND_TOSS, HAND_TOSS_TEXT

LAUNCH = HAND_TOSS


def cpu_s():
    """CPU seconds of this process and its finished workers."""
    me, kids = (resource.getrusage(w) for w in (resource.RUSAGE_SELF, resource.RUSAGE_CHILDREN))
    return me.ru_utime + me.ru_stime + kids.ru_utime + kids.ru_stime


def main():
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 1000
    xis = [float(x) for x in sys.argv[2].split(",")] if len(sys.argv) > 2 else [0.3, 0.577, 1.0]
    dts = ([float(x) for x in sys.argv[3].split(",")] if len(sys.argv) > 3 else
           [2e-4, 1e-4, 5e-5])
    print(f"{n} tosses a cell, seed 1, wood, u ~ {HAND_TOSS_TEXT['u']}, omega ~ "
          f"{HAND_TOSS_TEXT['omega']}, psi ~ {HAND_TOSS_TEXT['psi']}, every core\n")
    print("| xi | dt (s) | P(heads) | P(sides) | P(tails) | unsettled | mean bounces | "
          "steps/toss | CPU ms/toss |")
    print("|---|---|---|---|---|---|---|---|---|")
    for xi in xis:
        for dt in dts:
            c0 = cpu_s()
            r = runs.simulate(n, 1, xi=xi, dt=dt, **LAUNCH)
            cpu = cpu_s() - c0
            cells = [f"{f.p:.4f} [{f.lo:.4f}, {f.hi:.4f}]" for f in r.frequencies]
            print(f"| {xi:g} | {dt:g} | {' | '.join(cells)} | {r.counts[3]} | "
                  f"{r.mean_bounces:.2f} | {r.steps / n:.0f} | {1e3 * cpu / n:.1f} |",
                  flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
