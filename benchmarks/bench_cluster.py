"""Bouncing runs on a Dask cluster (issue 26): the cost of the cluster and of a checkpoint.

The same run (the hand toss onto wood, xi = 0.577, seed 1) timed, interleaved, on:

- the local pool, ``jobs=2`` (the baseline: ``coin simulate --landing bounce --jobs 2``);
- a ``LocalCluster`` of 2 single-threaded worker processes (``--scheduler local``);
- each again with a checkpoint (``--checkpoint``; a file in a temporary directory, fsynced a
  chunk at a time);
- a ``LocalCluster`` of 1 worker (the scale-out: 1 against 2 workers);
- the cluster with chunks of 16 (the default) and 64 tosses (the block size's effect).

Wall clock and CPU (the client's and every worker's); medians.  The cluster's start-up (a
``LocalCluster``, or a connection) is timed once apart: it is paid once a command.  Finally the
scheduler's cost per task (chunks of one toss) gives the chunk size that keeps 100 workers busy.

    python benchmarks/bench_cluster.py [TOSSES] [REPEATS]   # rewrites the bench_cluster
                                                            # section of docs/performance.md
"""

from __future__ import annotations

import os
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(__file__))

from _report import machine, median, table, write_section  # noqa: E402

from coincli.core.bounce import cluster as C  # noqa: E402
from coincli.core.bounce import runs as R  # noqa: E402
from coincli.core.toss import launch as TL  # noqa: E402
from coincli.io import checkpoint as K  # noqa: E402

XI, SEED = 0.577, 1


def _cpu_workers(cl) -> float:
    return sum(cl.client.run(time.process_time).values()) if cl is not None else 0.0


def _children_cpu() -> float:
    import resource

    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def run(n, *, jobs=2, cl=None, checkpoint=False, chunk=None):
    """One run: (wall s, CPU s, counts)."""
    ex = cl
    tmp = None
    if checkpoint:
        tmp = tempfile.mkdtemp()
        ck = K.Checkpoint(os.path.join(tmp, "run.ckpt"), {
            "versions": C.versions(), "command": "bench", "options": {"-n": str(n)}}, inner=cl)
        ck.open()
        ex = ck
    w0, c0, k0 = _cpu_workers(cl), time.process_time(), _children_cpu()
    t0 = time.perf_counter()
    sim = R.simulate(n, SEED, xi=XI, u=TL.HAND_TOSS["u"], omega=TL.HAND_TOSS["omega"],
                     psi=TL.HAND_TOSS["psi"], jobs=jobs, executor=ex, chunk=chunk)
    wall = time.perf_counter() - t0
    cpu = time.process_time() - c0 + _children_cpu() - k0 + _cpu_workers(cl) - w0
    if checkpoint:
        ck.close()
    return wall, cpu, sim.counts


def main():
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 256
    reps = int(sys.argv[2]) if len(sys.argv) > 2 else 3
    head = machine()
    t0 = time.perf_counter()
    two = C.Cluster(C.LOCAL, workers=2).__enter__()
    start2 = time.perf_counter() - t0
    t0 = time.perf_counter()
    one = C.Cluster(C.LOCAL, workers=1).__enter__()
    start1 = time.perf_counter() - t0
    for cl in (one, two):  # each worker builds its engine once: not part of a run
        run(32, cl=cl)
    configs = [("local pool, jobs=2 (baseline)", {"jobs": 2}),
               ("LocalCluster, 2 workers", {"cl": two}),
               ("local pool, jobs=2, checkpoint", {"jobs": 2, "checkpoint": True}),
               ("LocalCluster, 2 workers, checkpoint", {"cl": two, "checkpoint": True}),
               ("LocalCluster, 1 worker", {"cl": one}),
               ("LocalCluster, 2 workers, chunks of 64", {"cl": two, "chunk": 64})]
    times = {name: [] for name, _ in configs}
    counts = set()
    for _ in range(reps):
        for name, kw in configs:
            wall, cpu, c = run(n, **kw)
            times[name].append((wall, cpu))
            counts.add(c)
            print(f"{name}: {wall:.2f} s wall, {cpu:.2f} s CPU", file=sys.stderr)
    assert len(counts) == 1, counts  # the same tosses everywhere
    base_wall = median([w for w, _ in times[configs[0][0]]])
    base_cpu = median([c for _, c in times[configs[0][0]]])
    rows = []
    for name, _ in configs:
        wall = median([w for w, _ in times[name]])
        cpu = median([c for _, c in times[name]])
        rows.append([name, f"{wall:.2f} s", f"{n / wall:.1f}", f"{wall / base_wall:.3f}",
                     f"{cpu / n * 1e3:.1f} ms", f"{cpu / base_cpu:.3f}"])
    # the scheduler's cost a task: chunks of 1 toss against chunks of 16, same tosses
    m = 32
    w1 = median([run(m, cl=two, chunk=1)[0] for _ in range(reps)])
    w16 = median([run(m, cl=two, chunk=16)[0] for _ in range(reps)])
    per_task = max(w1 - w16, 0.0) * 2 / (m - m / 16)  # 2 workers share the extra tasks
    one.close()
    two.close()
    per_toss = base_cpu / n
    body = "\n".join([
        "## A Dask cluster (`benchmarks/bench_cluster.py`)",
        "",
        head,
        "",
        f"The hand toss onto wood, xi = {XI}, seed {SEED}, {n} tosses a run, {reps} runs of "
        "each configuration interleaved, medians; CPU counts the client, the pool's processes "
        "and every worker.  The machine is shared with other work, so the wall clock can be "
        "several times the CPU; the ratios compare runs made side by side.  Every run gives "
        "the same counts (checked).",
        "",
        table(["run", "wall", "tosses/s", "wall / baseline", "CPU per toss",
               "CPU / baseline"], rows),
        "",
        f"Start-up, paid once a command: a LocalCluster of 2 workers {start2:.2f} s, of 1 "
        f"worker {start1:.2f} s (the workers import numpy, MuJoCo and Dask); a connection to a "
        "running scheduler is a fraction of that.",
        "",
        f"The scheduler's cost a task (chunks of 1 toss against 16, {m} tosses): about "
        f"{per_task * 1e3:.1f} ms of wall time a task.  A chunk of 16 tosses is about "
        f"{16 * per_toss * 1e3:.0f} ms of CPU, so one scheduler keeps about "
        f"{16 * per_toss / per_task if per_task > 0 else float('inf'):.0f} workers busy with "
        "chunks of 16.",
    ])
    write_section("bench_cluster", body)


if __name__ == "__main__":
    main()
