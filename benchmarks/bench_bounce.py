"""Speed of the bounce engine (coincli.core.bounce.engine, MuJoCo): tosses per CPU-second,
against the floor of MuJoCo's own steps, before and after, in one run.

The goal of issue 25: the mean bouncing toss of the fair coin (xi = 0.577, wood, the hand toss
of ``coin simulate``: u ~ normal:2.4:0.3 m/s, omega ~ normal:38:4 rev/s, psi ~ normal(90, 10)
deg; a quarter-sized coin, D = 24.26 mm) costs at most 1.2 times the CPU of **the floor**: 1000
MuJoCo steps of the same coin lying flat and sliding (from 0.3 m/s) on wood at dt = 1e-4 s, timed in
the same process.  Each revision runs in a child process of its own (``--measure``), the two
alternately, ``--repeats`` times: the same launches (seed 1, as ``coin simulate`` draws them),
one process, CPU time (``time.process_time``), each engine at its own defaults.  The machine is
shared, so the table gives medians, and the ratio to the median floor of all the runs.

    python benchmarks/bench_bounce.py                     # against af0b52d (before issue 25)
    python benchmarks/bench_bounce.py --against REV -n 400 --repeats 3
    python benchmarks/bench_bounce.py --design 5          # and coin design's wall time, seeds 1-5
    python benchmarks/bench_bounce.py --write             # rewrite docs/performance.md's section

``--design K`` times ``coin design --p-sides 1/3 --landing bounce --surface wood --seed S``
(S = 1..K, every core) at ``--against`` and at this checkout, seed by seed, alternately: wall
and CPU time (all processes), the tosses simulated and those from the precomputed table (a
design on a preset starts from it since issue 25), the answer, the load; ``--no-tosses`` times the designs
alone (its own section of docs/performance.md), ``--max-tosses N`` shortens them.

    python benchmarks/bench_bounce.py --against main --design 5 --no-tosses --write
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import statistics
import subprocess
import sys
import tarfile
import tempfile
import time
from pathlib import Path

sys.path.insert(0, os.path.dirname(__file__))

from _report import machine, table, write_section  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
#: the engine before issue 25 (main at the time): dt = 1e-4, the energy and rolling rules only
BEFORE = "af0b52d"
XI = 0.577
GOAL = 1.2  #: CPU per toss / CPU of the floor


def floor_ms(B, repeats=15):
    """CPU ms of 1000 steps of the coin lying flat and sliding on wood, dt = 1e-4 s (median)."""
    eng = B.Engine(B.Coin(XI), B.SURFACES["wood"], dt=1e-4)
    mj, m, d = eng.mujoco, eng.m, eng.d
    out = []
    for _ in range(repeats):
        mj.mj_resetData(m, d)
        d.qpos[2] = eng.coin.hh - eng.mass * eng.g / (eng.mass * eng.k_spring)  # at rest depth
        d.qvel[0] = 0.3  # sliding 0.1 s (to 0.03 m/s), in micrometre hops and on 3 contacts
        mj.mj_forward(m, d)
        c0 = time.process_time()
        mj.mj_step(m, d, nstep=1000)
        out.append(time.process_time() - c0)
        if d.qpos[2] - eng.coin.hh > 1e-4 or eng._tilt() > 0.01:
            raise AssertionError("the floor's coin is not sliding flat on the surface")
    return 1e3 * statistics.median(out)


def measure(n, seed, old_rules=False):
    """Run in a child: n tosses in this process at the imported coincli's defaults; JSON out."""
    import math

    from coincli.core.bounce import engine as B
    from coincli.core.bounce import runs as R
    from coincli.core.toss import flight as T
    from coincli.core.toss import launch as TL

    coin = B.Coin(XI)
    dt = 1e-4 if old_rules else B.DEFAULT_DT
    eng = B.Engine(coin, B.SURFACES["wood"], dt=dt)
    if old_rules:
        eng.spin_rest = False
    h = TL.HAND_TOSS
    dists = {"u": TL.as_dist(h["u"], "u", 0, 20), "omega": TL.as_dist(h["omega"], "omega", 0, 1e5),
             "psi": TL.as_dist(h["psi"], "psi", 0, math.pi),
             "height": TL.as_dist(0.0, "height", 0, 1), "vx": TL.as_dist(0.0, "vx", 0, 1),
             "z0": TL.as_dist(T.default_z0(XI, coin.diameter, "thick"), "z0", 0, 1)}
    fl = floor_ms(B)
    c0 = time.process_time()
    steps, codes = [], [0, 0, 0, 0]
    for k in range(-(-n // R.BLOCK)):
        launches = R._block_launches(seed, k, min(R.BLOCK, n - k * R.BLOCK), dists, coin)
        for launch, t_f in zip(launches, eng.first_contacts(launches), strict=True):
            r = eng.run(launch, t_contact=t_f)
            steps.append(r.steps)
            codes[r.code] += 1
    cpu = time.process_time() - c0
    fl = statistics.median([fl, floor_ms(B)])  # before and after the tosses
    print(json.dumps({"cpu_ms": 1e3 * cpu / n, "floor_ms": fl, "steps": steps, "codes": codes,
                      "dt": dt}))


def child(tree: Path, n, seed, old_rules=False):
    env = {**os.environ, "PYTHONPATH": str(tree)}
    argv = [sys.executable, str(ROOT / "benchmarks" / "bench_bounce.py"), "--measure", str(n),
            "--seed", str(seed)] + (["--old-rules"] if old_rules else [])
    out = subprocess.run(argv, env=env, cwd=tree, capture_output=True, text=True)
    if out.returncode:
        raise RuntimeError(f"{tree}: {out.stderr}")
    return json.loads(out.stdout.strip().splitlines()[-1])


def summary(runs, floor):
    """Medians over the runs of one revision; ``floor``: the median floor of every run (the
    floor's model is the same at both revisions, and on a shared machine one run's floor
    varies by 1.5x, so each toss is divided by the pooled one)."""
    import numpy as np

    steps = np.array(runs[0]["steps"])
    cpu = statistics.median(r["cpu_ms"] for r in runs)
    return {"cpu": cpu, "ratio": cpu / floor, "floor": floor,
            "rate": 1e3 / cpu, "mean": steps.mean(), "median": float(np.median(steps)),
            "p99": float(np.percentile(steps, 99)), "codes": runs[0]["codes"],
            "dt": runs[0]["dt"]}


def design_run(tree: Path, seed, max_tosses=None):
    """One ``coin design --p-sides 1/3 --landing bounce --surface wood --seed S`` at ``tree``,
    every core: wall and CPU time (all its processes), its JSON row, the load after it."""
    argv = [sys.executable, "-m", "coincli", "design", "--p-sides", "1/3", "--landing",
            "bounce", "--surface", "wood", "--seed", str(seed), "--format", "json",
            "--time-limit", "100000"]  # the answer never cut by the load (default 300 s)
    if max_tosses:
        argv += ["--max-tosses", str(max_tosses)]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    out = subprocess.run(argv, cwd=tree, env={**os.environ, "PYTHONPATH": str(tree)},
                         capture_output=True, text=True, check=True)
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu, json.loads(out.stdout)[0], os.getloadavg()[0]


def design_walls(seeds, trees, max_tosses=None):
    """The design at each tree (``(label, path)`` pairs), seed by seed, the trees alternately:
    table rows."""
    rows = []
    for s in range(1, seeds + 1):
        for label, tree in trees:
            wall, cpu, row, load = design_run(tree, s, max_tosses)
            simulated = row["tosses"] - row.get("table_tosses", 0)  # (a table's: precomputed)
            rows.append([str(s), label, f"{wall:.1f} s", f"{cpu:.1f} s", str(simulated),
                         str(row.get("table_tosses", 0)),
                         f"{1e3 * cpu / simulated:.1f} ms" if simulated else "-",
                         f"{row['xi']:.4f} [{row['xi_low']:.4f}, {row['xi_high']:.4f}]",
                         f"{load:.1f}"])
            print(rows[-1], file=sys.stderr, flush=True)
    return rows


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--against", default=BEFORE, help="the revision to compare with")
    ap.add_argument("-n", type=int, default=400, help="tosses a run")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--design", type=int, default=0,
                    help="also time coin design, seeds 1..K, here and at --against")
    ap.add_argument("--max-tosses", type=int, help="the designs' --max-tosses (a shorter run)")
    ap.add_argument("--no-tosses", action="store_true",
                    help="time the designs only, not the tosses")
    ap.add_argument("--write", action="store_true", help="rewrite docs/performance.md's section")
    ap.add_argument("--measure", type=int, help=argparse.SUPPRESS)
    ap.add_argument("--old-rules", action="store_true", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.measure:
        measure(args.measure, args.seed, args.old_rules)
        return 0
    head = machine()
    with tempfile.TemporaryDirectory() as tmp:
        old = Path(tmp)
        archive = subprocess.run(["git", "-C", str(ROOT), "archive", args.against],
                                 check=True, capture_output=True).stdout
        (old / "old.tar").write_bytes(archive)
        with tarfile.open(old / "old.tar") as tar:
            tar.extractall(old, filter="data")
        runs = {"new": [], "old": []}
        for _ in range(0 if args.no_tosses else args.repeats):
            for key, tree in (("new", ROOT), ("old", old)):
                runs[key].append(child(tree, args.n, args.seed))
                print(key, {k: v for k, v in runs[key][-1].items() if k != "steps"},
                      file=sys.stderr, flush=True)
        designs = (design_walls(args.design, [(args.against, old), ("this checkout", ROOT)],
                                args.max_tosses) if args.design else [])
    body = [] if args.no_tosses else tosses_section(args, head, runs)
    if args.design:
        if args.no_tosses:
            body += ["## A bouncing design (`benchmarks/bench_bounce.py --design`)", "",
                     f"Command: `python benchmarks/bench_bounce.py --against {args.against} "
                     f"--design {args.design} --no-tosses"
                     f"{' --max-tosses ' + str(args.max_tosses) if args.max_tosses else ''} "
                     "--write`."]
        body += ["", f"`coin design --p-sides 1/3 --landing bounce --surface wood --seed S"
                 f"{' --max-tosses ' + str(args.max_tosses) if args.max_tosses else ''} "
                 "--time-limit 100000` at "
                 f"{args.against} and at this checkout, seed by seed, the two alternately, "
                 "every core (2); wall time and the CPU time of all its processes (the "
                 "machine is shared: the load average when each run ended is given).  "
                 f"{head}.", "",
                 table(["seed", "revision", "wall", "CPU (all processes)", "tosses simulated",
                        "from the table", "CPU per toss simulated", "xi [95%]", "load"],
                       designs)]
    text = "\n".join(body)
    print(text)
    if args.write:
        write_section("bench_bounce_design" if args.no_tosses else "bench_bounce", text)
    return 0


def tosses_section(args, head, runs):
    """The per-toss table, as docs/performance.md gives it: lines of Markdown."""
    floor = statistics.median(r["floor_ms"] for v in runs.values() for r in v)
    floors = sorted(r["floor_ms"] for v in runs.values() for r in v)
    s = {k: summary(v, floor) for k, v in runs.items()}
    rows = []
    for key, label in (("old", f"before ({args.against})"), ("new", "this checkout")):
        r = s[key]
        rows.append([label, f"{r['dt']:g}", f"{r['cpu']:.2f} ms", f"{r['rate']:.0f}",
                     f"{r['ratio']:.2f}", f"{r['mean']:.0f}",
                     f"{r['median']:.0f}", f"{r['p99']:.0f}",
                     " / ".join(str(c) for c in r["codes"])])
    speed = s["old"]["ratio"] / s["new"]["ratio"]
    body = ["## The bounce engine (`benchmarks/bench_bounce.py`)", "",
            f"Command: `python benchmarks/bench_bounce.py --against {args.against} -n {args.n} "
            f"--repeats {args.repeats} --write`.  {head}.", "",
            f"{args.n} hand tosses of the fair coin (xi = {XI}, D = 24.26 mm) onto wood, seed "
            f"{args.seed}, one process, CPU time; each revision at its own defaults, in its own "
            f"process, the two alternately, medians of {args.repeats} runs.  The floor: 1000 "
            "MuJoCo steps of the same coin lying flat and sliding from 0.3 m/s, dt = 1e-4 s, "
            "timed in each run; the goal (issue 25) is a mean toss of at most "
            f"{GOAL} floors.", "",
            table(["engine", "dt (s)", "CPU per toss", "tosses per CPU-second",
                   "toss / floor", "steps per toss (mean)", "median", "99th percentile",
                   "heads / sides / tails / unsettled"], rows),
            f"The floor: {floor:.2f} ms, the median of the {len(floors)} runs' floors "
            f"({floors[0]:.2f} to {floors[-1]:.2f} ms: the machine is shared).  Tosses per "
            f"CPU-second: **{speed:.2f}x** the engine before; the goal of {GOAL} floors a toss "
            f"is {'met' if s['new']['ratio'] <= GOAL else 'missed'}."]
    return body


if __name__ == "__main__":
    sys.exit(main())
