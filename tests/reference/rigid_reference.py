r"""An mpmath reference for the free rigid body next to (and on) the separatrix.

Independent of :mod:`coincli.core.rigid` altogether: Euler's equations and the quaternion kinematics
integrated by mpmath's Taylor-series solver (``mpmath.odefun``) at 20 digits.  Double-precision
integrators cannot serve here: the distance to the separatrix is a small difference of the
energy and the angular momentum, and their drift (1e-13 relative for DOP853 at its tightest)
moves it by 1e-13 / m1 relative, which shifts every later flip.

Run ``python tests/rigid_reference.py --write`` to regenerate
``tests/data/rigid_reference.json`` (about two minutes); the tests read that file and recompute
one case live.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import mpmath as mp

DPS = 20
DATA = Path(__file__).resolve().parent / "data" / "rigid_reference.json"

#: (moments, omega at launch, end time, number of samples): m1 ~ 1e-6 over two periods (four
#: flips), m1 ~ 1e-12 with the axes in another order, the other side of the separatrix
#: (circulating about the smallest axis), and exactly on it (k = 1: one flip, never back).
CASES = [
    ((1.0, 2.0, 3.0), (2e-3, 2.0, 1e-3), 61.0, 17),
    ((3.0, 1.0, 2.0), (1e-6, 2e-6, 2.0), 40.0, 17),
    ((1.0, 2.0, 3.0), (1e-3, 2.0, 3e-3), 61.0, 17),
    ((2.0, 5.0, 8.0), (2.0, 1.0, 1.0), 25.0, 17),
]


def solve(moments, omega, t_end, samples, dps=DPS):
    """Rows (t, omega1, omega2, omega3, qw, qx, qy, qz) at ``samples`` equally spaced times."""
    mp.mp.dps = dps
    Im = [mp.mpf(v) for v in moments]

    def f(t, y):
        w1, w2, w3, qw, qx, qy, qz = y
        return [(Im[1] - Im[2]) * w2 * w3 / Im[0], (Im[2] - Im[0]) * w3 * w1 / Im[1],
                (Im[0] - Im[1]) * w1 * w2 / Im[2],
                (-qx * w1 - qy * w2 - qz * w3) / 2, (qw * w1 + qy * w3 - qz * w2) / 2,
                (qw * w2 - qx * w3 + qz * w1) / 2, (qw * w3 + qx * w2 - qy * w1) / 2]

    sol = mp.odefun(f, 0, [mp.mpf(v) for v in omega] + [mp.mpf(1), 0, 0, 0])
    rows = []
    for k in range(samples):
        t = t_end * k / (samples - 1)
        rows.append([t] + [float(v) for v in sol(mp.mpf(t))])
    return rows


def build():
    return [{"moments": list(I), "omega": list(w), "rows": solve(I, w, T, n)}
            for I, w, T, n in CASES]


def load():
    return json.loads(DATA.read_text())


if __name__ == "__main__":
    if "--write" in sys.argv[1:]:
        DATA.write_text(json.dumps({"dps": DPS, "cases": build()}, indent=1) + "\n")
        print(f"wrote {DATA}")
    else:
        print(__doc__)
