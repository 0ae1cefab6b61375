"""Caught flips (faces only, issue 27): speed of ``coin fit`` on tossers' files, flat memory
of a 10^5-row file, and the coverage of each tosser's interval.

    python benchmarks/bench_faces.py            # a few minutes
    python benchmarks/bench_faces.py --quick    # fewer rounds and tossers

1. 50 rows of 10^4 caught flips (5 coins), ``coin fit FILE --format csv`` with every interval:
   median CPU time (user + system of the child) of 5 runs, against the floor of the same
   process doing nothing (``coin --version``) in the same run.
2. Streaming: ``coin fit FILE --format csv > /dev/null`` on 10^4 and 10^5 rows of caught flips
   (10 coins, 1000 flips each) and of three-outcome tosses (10 coins, 100 tosses each, one
   row in five sides and n only, as ``bench_stats.py`` writes them): peak resident memory of
   the child (ru_maxrss) and the ratio.  ``--memory`` runs it alone; ``--root DIR`` makes the
   children import the ``coincli`` of another checkout (a baseline).
3. Coverage (``--coverage`` runs it alone): synthetic tossers at sd 0 to 30 deg of psi (1000
   flips to 10^4 each), the share of 95% intervals that cover the true sd, with its binomial
   standard error.

Synthetic data only, drawn here (numpy seed 27).
"""

from __future__ import annotations

import argparse
import math
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, ROOT)

from coincli.core.coins import get_coin  # noqa: E402
from coincli.core.stats import caught as cs  # noqa: E402

CHILD_ROOT = ROOT  #: the checkout the children import (--root)

COINS = ["quarter", "euro-1", "euro-2", "euro-50c", "euro-20c", "cent", "nickel", "dime",
         "euro-10c", "euro-5c"]


def _write(path, rows, flips, coins, rng):
    qs = {}
    with open(path, "w") as f:
        f.write("label,coin,same,different\n")
        for i in range(rows):
            name = coins[i % len(coins)]
            c = get_coin(name)
            sig = math.radians(9.0) * math.exp(0.35 * rng.standard_normal())
            key = (name, round(sig, 2))
            if key not in qs:
                qs[key] = float(cs.same_chance(c.thickness_mm / c.diameter_mm, key[1]))
            s = int(rng.binomial(flips, qs[key]))
            f.write(f"t{i},{name},{s},{flips - s}\n")


def _write_tosses(path, rows, rng):
    """Three-outcome rows (heads, sides, tails; every fifth sides and n only), 10 coins."""
    xi = np.repeat(np.linspace(0.1, 1.5, 10), rows // 10 + 1)[:rows]
    c = rng.multinomial(100, [0.4, 0.2, 0.4], size=rows)
    with open(path, "w") as f:
        f.write("label,xi,heads,sides,tails,n\n")
        for i in range(rows):
            x = float(xi[i])
            f.write(f"r{i},{x!r},,{c[i, 1]},,100\n" if i % 5 == 4 else
                    f"r{i},{x!r},{c[i, 0]},{c[i, 1]},{c[i, 2]},\n")


def _child(argv):
    """CPU seconds, wall seconds and peak RSS (MiB) of one child."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t = time.perf_counter()
    with open(os.devnull, "w") as null:
        p = subprocess.run(argv, stdout=null, stderr=subprocess.PIPE, text=True,
                           env={**os.environ, "PYTHONPATH": CHILD_ROOT}, cwd=CHILD_ROOT)
    wall = time.perf_counter() - t
    if p.returncode != 0:
        raise SystemExit(f"{argv}: {p.stderr}")
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return cpu, wall, after.ru_maxrss / 1024


def _peak(argv):
    """Peak RSS of one child alone (ru_maxrss of RUSAGE_CHILDREN is the max over all children,
    so each measurement runs in its own grandchild), run in the checkout it imports (``python
    -m`` puts the working directory first on the path)."""
    code = ("import resource,subprocess,sys,os;"
            "subprocess.run(sys.argv[1:],stdout=subprocess.DEVNULL,check=True);"
            "print(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss/1024)")
    out = subprocess.run([sys.executable, "-c", code, *argv], capture_output=True, text=True,
                         env={**os.environ, "PYTHONPATH": CHILD_ROOT}, cwd=CHILD_ROOT,
                         check=True).stdout
    return float(out)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--coverage", action="store_true", help="the coverage study alone")
    ap.add_argument("--memory", action="store_true", help="the streaming measurement alone")
    ap.add_argument("--root", help="the checkout whose coincli the children import (default: "
                    "this one)")
    args = ap.parse_args()
    global CHILD_ROOT
    CHILD_ROOT = os.path.abspath(args.root) if args.root else ROOT
    rng = np.random.default_rng(27)
    tmp = tempfile.mkdtemp()
    coin = [sys.executable, "-m", "coincli"]
    if args.coverage:
        return _coverage(rng, 400 if args.quick else 2000)
    if args.memory:
        return _memory(rng, tmp, coin)
    # 1. speed
    f50 = os.path.join(tmp, "t50.csv")
    _write(f50, 50, 10_000, COINS[:5], rng)
    runs = 3 if args.quick else 5
    fit, floor = [], []
    for _ in range(runs):
        fit.append(_child([*coin, "fit", f50, "--format", "csv"]))
        floor.append(_child([*coin, "--version"]))
    cf = statistics.median(r[0] for r in fit)
    c0 = statistics.median(r[0] for r in floor)
    wf = statistics.median(r[1] for r in fit)
    print(f"50 rows x 10^4 caught flips, coin fit --format csv: CPU {cf:.2f} s (wall {wf:.2f} "
          f"s); coin --version {c0:.2f} s; fit - floor {cf - c0:.2f} s")
    _memory(rng, tmp, coin)
    _coverage(rng, 400 if args.quick else 2000)


def _memory(rng, tmp, coin):
    """2. Peak RSS of coin fit FILE --format csv at 10^4 and 10^5 rows, caught and three-outcome."""
    sizes = (10_000, 100_000)
    for kind in ("caught", "three-outcome"):
        peaks = []
        for rows in sizes:
            path = os.path.join(tmp, f"{kind}{rows}.csv")
            if kind == "caught":
                _write(path, rows, 1000, COINS, rng)
            else:
                _write_tosses(path, rows, rng)
            t = time.perf_counter()
            peaks.append(_peak([*coin, "fit", path, "--format", "csv"]))
            print(f"{kind}, {rows} rows: peak RSS {peaks[-1]:.0f} MiB, wall "
                  f"{time.perf_counter() - t:.1f} s")
        print(f"{kind}: peak ratio 10^5 / 10^4 rows: {peaks[1] / peaks[0]:.2f}")


def _coverage(rng, k):
    print("coverage of 95% profile intervals (true sd, share covering, standard error):")
    for sd in (0.0, 2.0, 5.0, 10.0, 20.0, 30.0):
        sig = math.radians(sd)
        xi = 0.075
        q = float(cs.same_chance(xi, sig))
        n = rng.integers(1000, 10_001, k)
        s = rng.binomial(n, q)
        f = cs.fit_rows(np.full(k, xi), s, n)
        cover = float(np.mean((f.low <= sig) & (sig <= f.high)))
        print(f"  sd {sd:4.0f} deg: {cover:.3f} +- {math.sqrt(cover * (1 - cover) / k):.3f}")


if __name__ == "__main__":
    main()
