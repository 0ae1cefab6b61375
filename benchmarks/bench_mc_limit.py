"""The Monte Carlo run limit of ``coin table --method mc|qmc --tol``: what it costs, what it buys.

Run from the repository root (a few minutes on a busy 2-CPU machine):

    python benchmarks/bench_mc_limit.py            # writes its section of docs/performance.md
    python benchmarks/bench_mc_limit.py --no-write # print only

- CPU seconds (``time.process_time``, median of ``--repeat`` runs) of one run's whole limit
  (``coincli.reports.accuracy.RUN_BUDGET`` tosses) of ``monte_carlo`` at xi = 0.5 for each of
  Table II's densities, against the baseline measured in the same run, interleaved: drawing the
  two uniform numbers per toss alone (``Generator.random`` in the same batches).
- The smallest ``--tol`` that ``--method mc`` meets within the limit for those densities (what
  ``coin`` names when it refuses a smaller one), and the CPU time of the command itself at a
  tolerance it refuses (``--tol 1e-5``) and at the smallest one it accepts (subprocesses, wall
  and CPU of the child, median).
- ``--method qmc`` at ``--tol 1e-5``, for comparison.
- Streamed batches: ``coin table`` over 10^6 xi and ``coin stack`` over 200,000 counts with
  ``--psi-dist normal`` (wall, CPU and peak resident memory of the child, once), against the
  same under the closed forms alone.
"""

from __future__ import annotations

import argparse
import os
import resource
import subprocess
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import _report  # noqa: E402

XI = 0.5
DENSITIES = ("uniform", "cosine", "normal")


def _cpu(fn) -> float:
    t = time.process_time()
    fn()
    return time.process_time() - t


def _child(argv: list[str]) -> tuple[float, float, int]:
    """(wall, child CPU seconds, exit code) of one ``coin`` run."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t = time.perf_counter()
    p = subprocess.run([sys.executable, "-m", "coincli", *argv], stdout=subprocess.DEVNULL,
                       stderr=subprocess.DEVNULL, env=dict(os.environ, NO_COLOR="1"))
    wall = time.perf_counter() - t
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu, p.returncode


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--repeat", type=int, default=3, help="repeats per figure (default 3)")
    ap.add_argument("--no-write", action="store_true", help="do not touch docs/performance.md")
    args = ap.parse_args(argv)

    import numpy as np

    from coincli.core import estimators as est
    from coincli.io.grammar import parse_density
    from coincli.reports.accuracy import RUN_BUDGET

    where = _report.machine()
    batch = 1 << 20

    def baseline():
        rng = np.random.default_rng(1)
        for _ in range(RUN_BUDGET // batch):
            rng.random(batch)
            rng.random(batch)

    rows = []
    for spec in DENSITIES:
        d = parse_density(spec)
        mc, base = [], []
        for r in range(args.repeat):
            base.append(_cpu(baseline))
            mc.append(_cpu(lambda d=d, r=r: est.monte_carlo(XI, d, n=RUN_BUDGET, seed=r)))
            print(f"  {spec}: {mc[-1]:.2f} s (baseline {base[-1]:.2f} s)", file=sys.stderr)
        m, b = _report.median(mc), _report.median(base)
        spread = est.chance_spread(est.quad(XI, d).value)
        rows.append([spec, f"{m:.2f} s", f"{b:.2f} s", f"{m / b:.1f}x",
                     f"{RUN_BUDGET / m / 1e6:.1f}",
                     f"{est.mc_smallest_tol([spread], RUN_BUDGET):g}"])

    normal = parse_density("normal")
    smallest = est.mc_smallest_tol([est.chance_spread(est.quad(XI, normal).value)], RUN_BUDGET)
    cmd = ["table", "--xi", str(XI), "--psi-dist", "normal", "-f", "csv"]
    mc = [*cmd, "--method", "mc", "--seed", "1", "--tol"]
    cases = [("`--method mc --tol 1e-5` (refused)", [*mc, "1e-5"]),
             (f"`--method mc --tol {smallest:g}` (the smallest accepted)",
              [*mc, f"{smallest:g}"]),
             ("`--method qmc --tol 1e-5`",
              [*cmd, "--method", "qmc", "--seed", "1", "--tol", "1e-5"]),
             ("`--method quad --tol 1e-5`", [*cmd, "--method", "quad", "--tol", "1e-5"])]
    cli = []
    for label, a in cases:
        runs = [_child(a) for _ in range(args.repeat)]
        cli.append([label, f"{_report.median([w for w, _, _ in runs]):.2f} s",
                    f"{_report.median([c for _, c, _ in runs]):.2f} s", str(runs[0][2])])
        print(f"  {label}: {cli[-1]}", file=sys.stderr)

    probe = ("import resource, subprocess, sys, time\n"
             "t = time.perf_counter()\n"
             "p = subprocess.run(sys.argv[1:], stdout=subprocess.DEVNULL)\n"
             "r = resource.getrusage(resource.RUSAGE_CHILDREN)\n"
             "print(time.perf_counter() - t, r.ru_utime + r.ru_stime, r.ru_maxrss, p.returncode)\n")
    batch = []
    for label, a in (("`table --xi 0.01:100:0.0001`, closed forms only",
                      ["table", "--xi", "0.01:100:0.0001"]),
                     ("`table --xi 0.01:100:0.0001 --psi-dist normal`",
                      ["table", "--xi", "0.01:100:0.0001", "--psi-dist", "normal"]),
                     ("`stack --count 1:200000:1`, closed form", ["stack", "--count",
                                                                  "1:200000:1"]),
                     ("`stack --count 1:200000:1 --psi-dist normal`",
                      ["stack", "--count", "1:200000:1", "--psi-dist", "normal"])):
        out = subprocess.run([sys.executable, "-c", probe, sys.executable, "-m", "coincli",
                              *a, "-f", "csv"], capture_output=True, text=True).stdout.split()
        batch.append([label, f"{float(out[0]):.1f} s", f"{float(out[1]):.1f} s",
                      f"{int(out[2]) / 1024:.0f} MiB", out[3]])
        print(f"  batch {label}: {batch[-1]}", file=sys.stderr)

    body = ["## The Monte Carlo run limit (`benchmarks/bench_mc_limit.py`)", "",
            f"Command: `python benchmarks/bench_mc_limit.py`.  {where}.", "",
            f"One run's limit is {RUN_BUDGET:,} tosses (2^{RUN_BUDGET.bit_length() - 1}), "
            f"shared by its densities.  CPU time of `monte_carlo` over the whole limit at xi = "
            f"{XI}, median of {args.repeat}, against drawing the two uniform numbers per toss "
            "alone (interleaved); the last column is the smallest `--tol` `--method mc` meets "
            "within the limit there (what `coin table` names when it refuses a smaller one).", "",
            _report.table(["density", "CPU, whole limit", "baseline", "ratio", "Mtosses/s",
                           "smallest --tol"], rows),
            f"`coin table --xi {XI} --psi-dist normal -f csv` with (subprocesses, "
            f"median of {args.repeat}; CPU of the child):", "",
            _report.table(["options", "wall", "CPU", "exit"], cli),
            "Streamed batches, `-f csv`, once each (999,901 xi; 200,000 counts): the rows are "
            "computed and written a chunk of coins at a time, psi-averaged or not, so the peak "
            "memory does not grow with them:", "",
            _report.table(["command", "wall", "CPU", "peak memory", "exit"], batch)]
    text = "\n".join(body)
    print(text)
    if not args.no_write:
        _report.write_section("bench_mc_limit", text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
