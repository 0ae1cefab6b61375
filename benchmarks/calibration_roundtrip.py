"""Round trip of ``coin fit --landing bounce``: tables the fit does not see, tossed by the
engine, calibrated, and compared with the truth.  Prints markdown; docs/calibration.md quotes it.

    python benchmarks/calibration_roundtrip.py surface          # the response surface (once)
    python benchmarks/calibration_roundtrip.py data [TABLES] [N] # N tosses a prototype, each table
    python benchmarks/calibration_roundtrip.py fit               # coverage of the 95% intervals

COIN_ROUNDTRIP_JACKKNIFE_ONLY=1 leaves the surface's lack of fit out of ``fit`` (the method
before it was carried), for comparison.

The prototypes are xi = 0.45 and 0.6 (either side of wood's fair 0.51), tossed by the hand toss
(coincli.core.toss.launch.HAND_TOSS) onto a surface with wood's torsional and rolling friction.
The true tables are drawn from restitution uniform on [0.15, 0.8] and friction log-uniform on
[0.08, 0.8] (inside the designed range, not on its grid), seed 20261127.  The surface is the
one ``coin fit --landing bounce --seed 1 --dt 2e-4 --design-tosses 128`` simulates for these
prototypes (4 x 4 design, 16 groups of 8 tosses a point; dt = 2e-4 s halves the cost: its
softer contact is another table than the default's (docs/bounce.md, "The step and the
contact's stiffness"), but the round trip simulates its true tables and fits them at the same
dt, which is all it tests); each table's tosses have
their own seed (1000 + table).  Stages
keep their counts in a cache (``--cache``, default /tmp/coin-calibration-roundtrip.json), so
that ``fit`` re-reads them.
"""

from __future__ import annotations

import json
import math
import os
import sys
import time

from coincli.core.bounce import calibrate as C
from coincli.core.bounce import engine as B
from coincli.core.bounce import runs as R
from coincli.core.toss.launch import HAND_TOSS

PROTOTYPES = (0.45, 0.6)
NAMES = ("restitution", "friction")
WOOD = B.SURFACES["wood"]
DT = 2e-4  # half the default's cost; the truth and the fit share it (see above)
FIXED = {"u": HAND_TOSS["u"], "omega": HAND_TOSS["omega"], "psi": HAND_TOSS["psi"],
         "torsional": WOOD.torsional, "rolling": WOOD.rolling, "dt": DT}
# 16 groups of 8: 128 tosses of each prototype at each design point (COIN_ROUNDTRIP_PER_GROUP=16
# gives the default 256, used with 1000 tosses a prototype)
PER_GROUP = int(os.environ.get("COIN_ROUNDTRIP_PER_GROUP", 8))
SEED = 1
DEGREE = int(os.environ.get("COIN_ROUNDTRIP_DEGREE", C.default_degree(len(NAMES))))
CACHE = os.environ.get("COIN_ROUNDTRIP_CACHE", "/tmp/coin-calibration-roundtrip.json")


def load():
    try:
        with open(CACHE) as fh:
            return json.load(fh)
    except FileNotFoundError:
        return {}


def save(cache):
    tmp = CACHE + ".tmp"
    with open(tmp, "w") as fh:
        json.dump(cache, fh)
    os.replace(tmp, CACHE)


def truths(k):
    import numpy as np

    rng = np.random.default_rng(20261127)
    out = []
    for _ in range(k):
        e = float(rng.uniform(0.15, 0.8))
        mu = float(math.exp(rng.uniform(math.log(0.08), math.log(0.8))))
        out.append((e, mu))
    return out


def surface(cache, jobs):
    t0, c0 = time.perf_counter(), time.process_time()
    pts = C.design_points(2, 4)
    counts = C.run_design(PROTOTYPES, NAMES, pts, seed=SEED, per_group=PER_GROUP, fixed=FIXED,
                          jobs=jobs, progress=lambda d, t: print(f"  {d}/{t}", file=sys.stderr,
                                                                 flush=True))
    cache["surface"] = {"points": pts, "counts": counts.tolist(),
                        "wall_s": time.perf_counter() - t0,
                        "cpu_s_parent": time.process_time() - c0}
    save(cache)
    print(f"surface: {counts[..., :3].sum()} tosses, {time.perf_counter() - t0:.0f} s wall")


def data(cache, k, n, jobs):
    tables = cache.setdefault("tables", [])
    for i, (e, mu) in enumerate(truths(k)):
        if i < len(tables) and tables[i]["n"] == n:
            continue
        t0 = time.perf_counter()
        surf = B.surface(None, restitution=e, friction=mu, torsional=WOOD.torsional,
                         rolling=WOOD.rolling)
        rows = []
        for j, xi in enumerate(PROTOTYPES):
            r = R.simulate(n, 1000 + i, xi=xi, surf=surf, jobs=jobs, u=FIXED["u"],
                           omega=FIXED["omega"], psi=FIXED["psi"], dt=DT, stream=(j,))
            rows.append(list(r.counts))
        entry = {"restitution": e, "friction": mu, "n": n, "counts": rows,
                 "wall_s": time.perf_counter() - t0}
        if i < len(tables):
            tables[i] = entry
        else:
            tables.append(entry)
        save(cache)
        print(f"table {i}: e {e:.3f} mu {mu:.3f} {rows} ({entry['wall_s']:.0f} s)",
              file=sys.stderr, flush=True)


def fit(cache):
    import numpy as np

    s = cache["surface"]
    pts, counts = [tuple(p) for p in s["points"]], np.array(s["counts"])
    for j, xi in enumerate(PROTOTYPES):
        sf = C.fit_surface(pts, counts[j].sum(axis=1), degree=DEGREE)
        print(f"surface at xi = {xi}: deviance {sf.deviance:.1f} on {sf.df} df, lack of fit "
              f"tau2 = {C.discrepancy(sf, counts[j][:, :, :3].sum() / len(pts)):.2e}")
    print("| table | true restitution | fitted [95%] | true friction | fitted [95%] | fit p | "
          "surface's share | fair xi: true table, calibrated |\n|---|---|---|---|---|---|---|---|")
    hold = dict.fromkeys(NAMES, 0)
    pv, gaps = [], []
    for i, t in enumerate(cache["tables"]):
        data = [(c[0], c[1], c[2], c[0] + c[1] + c[2]) for c in t["counts"]]
        f = C.fit_table(NAMES, pts, counts, data, degree=DEGREE,
                        lack_of_fit=not os.environ.get("COIN_ROUNDTRIP_JACKKNIFE_ONLY"))
        cells = []
        for name in NAMES:
            ok = f.low[name] <= t[name] <= f.high[name]
            hold[name] += ok
            cells += [f"{t[name]:.3f}", f"{f.estimate[name]:.3f} [{f.low[name]:.3f}, "
                      f"{f.high[name]:.3f}]{'' if ok else ' MISS'}"]
        pv.append(f.p_value)
        share = "/".join(f"{f.surface_share[n]:.2f}" for n in NAMES)
        ft, fc = fair_xi(f.surfaces, t), fair_xi(f.surfaces, f.estimate)
        gaps.append(abs(math.log(fc / ft)))
        print(f"| {i} | " + " | ".join(cells) + f" | {f.p_value:.2f} | {share} | {ft:.3f}, "
              f"{fc:.3f} |")
    k = len(cache["tables"])
    print(f"\ncoverage of the 95% intervals: restitution {hold['restitution']}/{k}, friction "
          f"{hold['friction']}/{k}; fit p < 0.05 in {sum(p < 0.05 for p in pv)}/{k}")
    gaps.sort()
    print(f"fair xi, calibrated against true (both read off the surface, probit in ln xi "
          f"through the two prototypes): median |ln ratio| {gaps[len(gaps) // 2]:.3f}, "
          f"largest {gaps[-1]:.3f}")


def fair_xi(surfaces, params):
    """The xi at which P(sides) = 1/3 on a table: the surface's P(sides) at the two
    prototypes, a straight line in (ln xi, probit), solved (extrapolated when 1/3 lies
    outside)."""
    import numpy as np
    from scipy.special import ndtri

    u = np.array([[C.to_coords(n, params[n]) for n in NAMES]])
    z = [float(ndtri(s.probs(u)[0][1])) for s in surfaces]
    x = [math.log(v) for v in PROTOTYPES]
    slope = (z[1] - z[0]) / (x[1] - x[0])
    return math.exp(x[0] + (float(ndtri(1 / 3)) - z[0]) / slope)


def main(argv):
    jobs = R.default_jobs()
    cache = load()
    what = argv[0] if argv else "fit"
    if what == "surface":
        surface(cache, jobs)
    elif what == "data":
        data(cache, int(argv[1]) if len(argv) > 1 else 20, int(argv[2]) if len(argv) > 2
             else 250, jobs)
    elif what == "fit":
        fit(cache)
    else:
        raise SystemExit(__doc__)


if __name__ == "__main__":
    main(sys.argv[1:])
