"""Speed of real tosses (coincli.toss and coin simulate/phase): prints a markdown table.

Run from the repository root, in the environment where ``coin`` is installed:

    python benchmarks/toss_bench.py            # 10^6 tosses, 3 repeats (about a minute)
    python benchmarks/toss_bench.py --quick    # 10^5 tosses, 1 repeat

Measured (wall-clock median, and process CPU time beside it, since a loaded machine stretches
wall time more than CPU time):

- ``toss_many`` on the issue's ordinary tosses (u ~ N(2.4, 0.3) m/s, omega ~ N(38, 4) rad/s,
  psi ~ N(90, 10) deg, xi = 0.577), rim and thick contact;
- the same with initial conditions drawn (``simulate``, the whole core of ``coin simulate``);
- a stress mix (xi in {0, 1e6} or [0, 3], u in 1e-6..30 m/s, omega in 1e-3..1e6 rad/s, log-
  uniform), where grazing and zero-length windows are common;
- one toss (``flight_time``, the scalar brentq path) ordinary and extreme;
- ``phase_map`` on a 200 x 200 grid (Fig. 3);
- the command ``coin simulate -n N --seed 7 ...`` end to end (start-up included).

Nothing here asserts a time; the figures go to the report of the change.
"""

from __future__ import annotations

import argparse
import math
import resource
import shutil
import subprocess
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import _report  # noqa: E402


def timed(fn, repeats):
    walls, cpus = [], []
    out = None
    for _ in range(repeats):
        c0, t0 = time.process_time(), time.perf_counter()
        out = fn()
        walls.append(time.perf_counter() - t0)
        cpus.append(time.process_time() - c0)
    return _report.median(walls), _report.median(cpus), out


def child_timed(argv, repeats):
    walls, cpus = [], []
    for _ in range(repeats):
        r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
        t0 = time.perf_counter()
        subprocess.run(argv, check=True, stdout=subprocess.DEVNULL)
        walls.append(time.perf_counter() - t0)
        r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpus.append(r1.ru_utime - r0.ru_utime + r1.ru_stime - r0.ru_stime)
    return _report.median(walls), _report.median(cpus)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="10^5 tosses, one repeat")
    args = ap.parse_args()
    n = 100_000 if args.quick else 1_000_000
    reps = 1 if args.quick else 3

    import numpy as np

    from coincli import toss as T

    rng = np.random.default_rng(7)
    psi_dist = T.parse_dist("normal:90:10", "psi", 0, 180).scaled(math.pi / 180)
    c = T.sample_conditions(n, rng, u="normal:2.4:0.3", omega="normal:38:4", psi=psi_dist)
    rows = []

    def add(what, wall, cpu, count, extra=""):
        rows.append([what, f"{count:,}", f"{wall:.3f}", f"{cpu:.3f}",
                     f"{1e6 * wall / count:.2f}", extra])

    T.toss_many(0.577, 1.0, 2.0, 40.0)  # warm up imports
    T.flight_time(0.577, 1.0, 2.0, 40.0)
    for contact in T.CONTACTS:
        w, p, res = timed(lambda contact=contact: T.toss_many(0.577, c["psi"], c["u"],
                                                               c["omega"], contact=contact),
                          reps)
        h, s, t = (v / n for v in res.counts())
        add(f"toss_many, ordinary tosses, {contact}", w, p, n,
            f"H {h:.4f} S {s:.4f} T {t:.4f}")
    w, p, sim = timed(lambda: T.simulate(n, 7, xi=0.577, u="normal:2.4:0.3",
                                         omega="normal:38:4", psi=psi_dist), reps)
    add("simulate (draws + tosses + counts)", w, p, n,
        "vigorous limit " + ", ".join(f"{v:.4f}" for v in sim.vigorous))

    m = n // 5
    xi = np.where(rng.random(m) < 0.1, rng.choice([0.0, 1e6], m), rng.uniform(0, 3, m))
    psi = rng.uniform(0, math.pi, m)
    u = 10 ** rng.uniform(-6, 1.5, m)
    om = 10 ** rng.uniform(-3, 6, m)
    for contact in T.CONTACTS:
        w, p, _ = timed(lambda contact=contact: T.toss_many(xi, psi, u, om, contact=contact),
                        reps)
        add(f"toss_many, stress mix, {contact}", w, p, m)

    k = 2000 if args.quick else 10_000
    for label, a in (("ordinary (0.577, 90 deg, 2 m/s, 40 rad/s)", (0.577, math.pi / 2, 2.0,
                                                                    40.0)),
                     ("omega 1e6 rad/s, u 1e-6 m/s", (0.577, math.pi / 2, 1e-6, 1e6)),
                     ("omega 1e6 rad/s, u 2 m/s (9e4 turns)", (0.577, 1.2, 2.0, 1e6))):
        w, p, _ = timed(lambda a=a: [T.flight_time(*a) for _ in range(k)], reps)
        add(f"flight_time (scalar), {label}", w, p, k)

    w, p, _ = timed(lambda: T.phase_map(0.577, math.pi / 2, (0, 3), (0, 60), (200, 200)), reps)
    add("phase_map 200 x 200 (Fig. 3)", w, p, 40_000)

    coin = shutil.which("coin")
    if coin:
        argv = [coin, "simulate", "-n", str(n), "--seed", "7", "--xi", "0.577", "--u",
                "normal:2.4:0.3", "--omega", "normal:38:4", "--psi-dist", "normal:90:10"]
        w, p = child_timed(argv, reps)
        add("`coin simulate -n N --seed 7 ...` (whole command)", w, p, n)
        w, p = child_timed(argv + ["--stream"], reps)
        add("the same with --stream (N lines on stdout)", w, p, n)

    print(_report.machine())
    print()
    print(_report.table(["what", "count", "wall s", "CPU s", "wall us each", "result"], rows))


if __name__ == "__main__":
    main()
