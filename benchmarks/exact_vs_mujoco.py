"""The exact engine (issue 39, stage 2) against MuJoCo, toss by toss on the same launches.

    PYTHONPATH=$PWD python benchmarks/exact_vs_mujoco.py --n 200 --xi 0.354,0.5,0.577,0.7

The launches are coin's hand toss (u ~ normal:2.4:0.3 m/s, omega ~ normal:38:4 rev/s, psi ~
normal:90:10 deg, the paper's z0 for a thick coin, no horizontal speed), drawn block by block
from the seed exactly as :func:`coincli.core.bounce.runs.simulate` draws them
(:func:`coincli.core.bounce.runs._block_launches`); the coin is a quarter's diameter
(cupronickel); the surface the wood preset (restitution 0.5, friction 0.3, torsional and rolling
0.1 mm).  Both engines toss every launch in this one process, one after the other, and the CPU
time of each (``time.process_time``) is summed per engine, so that tosses per CPU-second are
measured on the same machine under the same load.  MuJoCo's calibration of its damping is made
before the clock starts (it is cached by the product too).

Printed, per xi: H/S/T/unsettled counts of each engine with 95% Wilson intervals of P(heads),
P(sides), P(tails) among settled tosses; the agreement (the fraction of launches both engines
send to the same outcome); and tosses per CPU-second of each engine.  A toss the exact engine
cannot finish (an ``ArithmeticError``: a regime without a law, e.g. a Painleve jam) is counted
as ``failed`` and listed.
"""

from __future__ import annotations

import argparse
import math
import time

from coincli.core.bounce import engine as E
from coincli.core.bounce import runs as R
from coincli.core.bounce.exact.toss import ExactEngine, Tolerances
from coincli.core.toss.flight import default_z0
from coincli.core.toss.launch import HAND_TOSS, as_dist
from coincli.core.toss.simulate import wilson_interval


def dists_for(xi):
    coin = E.Coin(xi)
    d = {k: as_dist(HAND_TOSS[k], k, 0.0, lim) for k, lim in
         (("u", 20.0), ("omega", 1e5), ("psi", math.pi))}
    for name, val in (("height", 0.0), ("vx", 0.0),
                      ("z0", default_z0(coin.xi, coin.diameter, "thick"))):
        d[name] = as_dist(val, name, 0.0, 100.0)
    return d


def launches(n, seed, xi):
    coin, dists = E.Coin(xi), dists_for(xi)
    out = []
    for k in range(-(-n // R.BLOCK)):
        out += R._block_launches(seed, k, min(R.BLOCK, n - k * R.BLOCK), dists, coin)
    return out


def run(xi, n, seed, surf, tol, mujoco=True):
    """Both engines on the same ``n`` launches: per-toss codes and CPU seconds of each."""
    ls = launches(n, seed, xi)
    ex = ExactEngine(xi, surf, tol=tol)
    codes_x, failed = [], []
    c0 = time.process_time()
    for i, launch in enumerate(ls):
        try:
            codes_x.append(ex.run(launch).code)
        except ArithmeticError as err:
            codes_x.append(-1)
            failed.append((i, str(err)[:80]))
    cpu_x = time.process_time() - c0
    codes_m, cpu_m = None, math.nan
    if mujoco:
        eng = E.Engine(E.Coin(xi), surf)  # calibrated here, before the clock
        c0 = time.process_time()
        t_first = eng.first_contacts(ls)
        codes_m = [eng.run(launch, t_contact=t).code for launch, t in zip(ls, t_first,
                                                                        strict=True)]
        cpu_m = time.process_time() - c0
    return codes_x, cpu_x, codes_m, cpu_m, failed


def describe(codes):
    counts = [sum(1 for c in codes if c == k) for k in range(4)]
    settled = sum(counts[:3])
    cells = []
    for k in range(3):
        lo, hi = wilson_interval(counts[k], settled) if settled else (math.nan, math.nan)
        p = counts[k] / settled if settled else math.nan
        cells.append(f"{counts[k]} ({p:.3f} [{lo:.3f}, {hi:.3f}])")
    return counts, cells


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=200)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--xi", default="0.354,0.5,0.577,0.7")
    ap.add_argument("--refine", type=float, default=1.0,
                    help="divide every tolerance of the exact engine by this")
    ap.add_argument("--no-mujoco", action="store_true")
    args = ap.parse_args(argv)
    surf = E.SURFACES["wood"]
    tol = Tolerances().refined(args.refine)
    print(f"wood: {surf.describe()}; quarter diameter {E.Coin(0.5).diameter} m; hand toss; "
          f"n = {args.n} a point, seed {args.seed}; exact tolerances {tol}")
    print()
    print("| xi | engine | heads | sides | tails | unsettled | failed | agreement | "
          "tosses / CPU-s |")
    print("|---|---|---|---|---|---|---|---|---|")
    for xi in (float(x) for x in args.xi.split(",")):
        cx, tx, cm, tm, failed = run(xi, args.n, args.seed, surf, tol, not args.no_mujoco)
        counts, cells = describe(cx)
        agree = "" if cm is None else (
            f"{sum(a == b for a, b in zip(cx, cm, strict=True)) / len(cx):.3f}")
        print(f"| {xi:g} | exact | {' | '.join(cells)} | {counts[3]} | {len(failed)} | "
              f"{agree} | {len(cx) / tx:.1f} |")
        if cm is not None:
            counts_m, cells_m = describe(cm)
            print(f"| {xi:g} | MuJoCo | {' | '.join(cells_m)} | {counts_m[3]} | 0 | | "
                  f"{len(cm) / tm:.1f} |")
        for i, msg in failed:
            print(f"<!-- xi {xi:g}: toss {i} failed: {msg} -->")


if __name__ == "__main__":
    main()
