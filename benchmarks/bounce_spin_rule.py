"""The spin rule of the bounce engine checked (issue 25): tosses run to the end without it,
its first early decision recorded, and compared with how each toss ended.  docs/bounce.md
quotes the table.

Each toss runs with the rules of 0.2.0 (the energy and rolling rules: ``Engine.spin_rest`` off)
until they settle it; at every check the quantities of the spin rule are recorded
(:meth:`coincli.core.bounce.engine.Engine._spin_locked`, the contacts, the side the tilt is in).
Then, for each variant of the rule, the first check at which it would have decided: earlier
than the toss settled, and on the side it ended on (else "wrong").  The variants: at one check
(``1 check``), at two checks in a row and touching at the second (``2 checks, touching``, the
rule the engine uses).  Steps saved: the simulated time saved over dt, a share of the steps.

    python benchmarks/bounce_spin_rule.py [SEED] [DT,DT,...]  # seed 11, dt 1e-4 and 2e-4
"""

from __future__ import annotations

import math
import sys

import numpy as np

from coincli.core.bounce import engine as B
from coincli.core.bounce import runs as R
from coincli.core.toss import flight as T
from coincli.core.toss import launch as TL

CASES = [("wood", 0.577, 1500), ("wood", 0.3, 800), ("wood", 1.0, 800), ("hard-floor", 0.577, 500),
         ("felt", 0.577, 300)]


class Recorder(B.Engine):
    """The engine of 0.2.0's rules, recording the spin rule's quantities at every check."""

    def __init__(self, *a, **k):
        super().__init__(*a, **k)
        self.spin_rest, self.real_rolling, self.rolling_rest = False, self.rolling_rest, True

    def _rolling(self):  # called at every check (the coin is above the barrier there)
        d = self.d
        self.rows.append((float(d.time), self._energy(), self._spin_locked(), d.ncon,
                          int(T.classify(self._tilt(), self.coin.xi))))
        return super()._rolling() if self.real_rolling else 0.0

    def run(self, launch, **kw):
        self.rows = []
        return super().run(launch, **kw), np.array(self.rows).reshape(-1, 5)


def check(surface, xi, n, seed, dt):
    coin = B.Coin(xi)
    eng = Recorder(coin, B.SURFACES[surface], dt=dt)
    h = TL.HAND_TOSS
    dists = {"u": TL.as_dist(h["u"], "u", 0, 20), "omega": TL.as_dist(h["omega"], "omega", 0, 1e5),
             "psi": TL.as_dist(h["psi"], "psi", 0, math.pi),
             "height": TL.as_dist(0.0, "height", 0, 1), "vx": TL.as_dist(0.0, "vx", 0, 1),
             "z0": TL.as_dist(T.default_z0(xi, coin.diameter, "thick"), "z0", 0, 1)}
    launches = []
    for k in range(-(-n // R.BLOCK)):
        launches += R._block_launches(seed, k, min(R.BLOCK, n - k * R.BLOCK), dists, coin)
    found = {"1 check": [0, 0, 0.0], "2 checks, touching": [0, 0, 0.0]}
    steps = 0
    for launch, t_f in zip(launches, eng.first_contacts(launches), strict=True):
        r, rows = eng.run(launch, t_contact=t_f)
        steps += r.steps
        if not len(rows):
            continue
        below = rows[:, 1] - rows[:, 2] < eng.barrier
        held = below.copy()
        held[0] = False
        held[1:] &= below[:-1]
        end = r.t_settle if r.code != B.UNSETTLED else rows[-1, 0]
        for name, rule in (("1 check", below), ("2 checks, touching", held & (rows[:, 3] > 0))):
            hit = np.flatnonzero(rule)
            if hit.size and rows[hit[0], 0] < end:
                f = found[name]
                f[0] += 1
                f[1] += r.code != B.UNSETTLED and int(rows[hit[0], 4]) != r.code
                f[2] += end - rows[hit[0], 0]
    cells = [f"{f[0]} | {f[1]} | {f[2] / dt / steps:.0%}" for f in found.values()]
    print(f"| {surface} | {xi:g} | {dt:g} | {n} | {steps / n:.0f} | {' | '.join(cells)} |",
          flush=True)


def main():
    seed = int(sys.argv[1]) if len(sys.argv) > 1 else 11
    dts = [float(x) for x in sys.argv[2].split(",")] if len(sys.argv) > 2 else [1e-4, 2e-4]
    print(f"Hand tosses (coincli.core.toss.launch.HAND_TOSS), seed {seed}, run to the end by the "
          "rules of 0.2.0.\n")
    print("| surface | xi | dt (s) | tosses | steps per toss | 1 check: early | wrong | steps "
          "saved | 2 checks, touching: early | wrong | steps saved |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for dt in dts:
        for surface, xi, n in CASES:
            check(surface, xi, n, seed, dt)
    return 0


if __name__ == "__main__":
    sys.exit(main())
