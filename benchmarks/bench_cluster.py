"""Bouncing runs on a Dask cluster (issue 26): the cost of the cluster and of a checkpoint.

The same run (the hand toss onto wood, xi = 0.577, seed 1) timed, interleaved, on:

- the local pool, ``jobs=2`` (the baseline: ``coin simulate --landing bounce --jobs 2``);
- a ``LocalCluster`` of 2 single-threaded worker processes (``--scheduler local``);
- each again with a checkpoint (``--checkpoint``; a file in a temporary directory, fsynced a
  chunk at a time);
- the local pool with the cluster's chunks (what the chunk's size does without a cluster);
- the cluster with chunks of 16 (the local pool's) to 256 tosses (the block size's effect);
- a ``LocalCluster`` of 1 worker (the scale-out: 1 against 2 workers, the same chunks).

The cluster's default chunk is sized from the run and its workers
(:func:`coincli.core.bounce.cluster.chunk_for`).

Wall clock and CPU (the client's and every worker's); medians.  The cluster's start-up (a
``LocalCluster``, or a connection) is timed once apart: it is paid once a command.  Finally the
scheduler's cost per task (chunks of one toss) gives the chunk size that keeps 100 workers busy.

    python benchmarks/bench_cluster.py [TOSSES] [REPEATS]   # rewrites the bench_cluster
                                                            # section of docs/performance.md
    python benchmarks/bench_cluster.py pairs [TOSSES] [PAIRS]   # the headline alone:
                                # --jobs 2 against the cluster's default, pair by pair
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


def _load() -> str:
    return ", ".join(f"{v:.2f}" for v in os.getloadavg())


def pairs(n: int, reps: int) -> None:
    """Only the headline: ``--jobs 2`` against the cluster's default, ``reps`` pairs, the order
    alternated (AB, BA, ...) so that a drift of the machine's load falls on both."""
    head = machine()
    two = C.Cluster(C.LOCAL, workers=2).__enter__()
    run(32, cl=two)
    sized = two.chunk(n)
    ratios, base, clus, loads = [], [], [], [_load()]
    for i in range(reps):
        order = [("base", {"jobs": 2}), ("cluster", {"cl": two})]
        got = {}
        for name, kw in (order if i % 2 == 0 else order[::-1]):
            got[name] = run(n, **kw)
            print(f"{name}: {got[name][0]:.2f} s wall, {got[name][1]:.2f} s CPU", file=sys.stderr)
        assert got["base"][2] == got["cluster"][2]
        base.append(got["base"][:2])
        clus.append(got["cluster"][:2])
        ratios.append((got["cluster"][0] / got["base"][0], got["cluster"][1] / got["base"][1]))
        loads.append(_load())
    # a task's cost: chunks of 1 toss on the cluster against the local pool's chunks of 1 (the
    # same tosses, the same work a chunk), pair by pair; the difference over the tasks
    m = 64
    per_task = []
    for _ in range(reps):
        a, b = run(m, cl=two, chunk=1), run(m, jobs=2, chunk=1)
        per_task.append(((a[0] - b[0]) * 2 / m, (a[1] - b[1]) / m))  # 2 workers share the wall
    loads.append(_load())
    two.close()
    rw, rc = sorted(r[0] for r in ratios), sorted(r[1] for r in ratios)
    rows = [["`--jobs 2` (chunks of 16)", f"{median([b[0] for b in base]):.2f} s",
             f"{median([b[1] for b in base]) / n * 1e3:.1f} ms", "", ""],
            [f"LocalCluster, 2 workers (chunks of {sized})",
             f"{median([c[0] for c in clus]):.2f} s",
             f"{median([c[1] for c in clus]) / n * 1e3:.1f} ms",
             f"{median(rw):.3f} ({rw[0]:.3f} to {rw[-1]:.3f})",
             f"{median(rc):.3f} ({rc[0]:.3f} to {rc[-1]:.3f})"]]
    body = "\n".join([
        "### The cluster's overhead, pair by pair (`bench_cluster.py pairs`)",
        "",
        head,
        "",
        f"{reps} pairs of runs of {n} tosses (the hand toss onto wood, xi = {XI}, seed {SEED}), "
        "`--jobs 2` and `--scheduler local` (2 workers, its default chunks) one after the "
        "other, the order alternated; the ratio of each pair, then their median (and range). "
        f"Load averages (1, 5, 15 min) after each pair: {'; '.join(loads)}.",
        "",
        table(["run", "wall (median)", "CPU per toss (median)", "wall / --jobs 2",
               "CPU / --jobs 2"], rows),
        "",
        f"A task's cost ({reps} pairs of {m} tosses in chunks of 1, the cluster against the "
        f"local pool; medians): {median([w for w, _ in per_task]) * 1e3:.1f} ms of wall time "
        f"and {median([c for _, c in per_task]) * 1e3:.1f} ms of CPU (client, scheduler and "
        "worker together) a task.",
    ])
    write_section("bench_cluster_pairs", body)


def main():
    if sys.argv[1:2] == ["pairs"]:
        pairs(int(sys.argv[2]) if len(sys.argv) > 2 else 768,
              int(sys.argv[3]) if len(sys.argv) > 3 else 6)
        return
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
    sized = two.chunk(n)  # the chunk a run of n tosses takes on 2 workers (chunk_for)
    configs = [("local pool, jobs=2, chunks of 16 (baseline: --jobs 2)", {"jobs": 2}),
               (f"LocalCluster, 2 workers, chunks of {sized} (--scheduler's default)",
                {"cl": two}),
               ("local pool, jobs=2, checkpoint", {"jobs": 2, "checkpoint": True}),
               (f"LocalCluster, 2 workers, chunks of {sized}, checkpoint",
                {"cl": two, "checkpoint": True}),
               (f"local pool, jobs=2, chunks of {sized}", {"jobs": 2, "chunk": sized})]
    configs += [(f"LocalCluster, 2 workers, chunks of {c}", {"cl": two, "chunk": c})
                for c in (16, 32, 128, 256) if c != sized]
    configs += [(f"LocalCluster, 1 worker, chunks of {sized}", {"cl": one, "chunk": sized})]
    times = {name: [] for name, _ in configs}
    counts = set()
    loads = [_load()]
    for _ in range(reps):
        for name, kw in configs:
            wall, cpu, c = run(n, **kw)
            times[name].append((wall, cpu))
            counts.add(c)
            print(f"{name}: {wall:.2f} s wall, {cpu:.2f} s CPU", file=sys.stderr)
        loads.append(_load())
    assert len(counts) == 1, counts  # the same tosses everywhere, whatever the chunks
    base_wall = median([w for w, _ in times[configs[0][0]]])
    base_cpu = median([c for _, c in times[configs[0][0]]])
    rows = []
    for name, _ in configs:
        wall = median([w for w, _ in times[name]])
        cpu = median([c for _, c in times[name]])
        # the ratio of each repetition to the baseline timed just before it, then the median
        rw = median([w / b[0] for (w, _), b in zip(times[name], times[configs[0][0]],
                                                                  strict=True)])
        rc = median([c / b[1] for (_, c), b in zip(times[name], times[configs[0][0]],
                                                                  strict=True)])
        rows.append([name, f"{wall:.2f} s", f"{n / wall:.1f}", f"{wall / base_wall:.3f}",
                     f"{rw:.3f}", f"{cpu / n * 1e3:.1f} ms", f"{cpu / base_cpu:.3f}",
                     f"{rc:.3f}"])
    # the scheduler's cost a task: chunks of 1 toss against chunks of 16, same tosses
    m = 32
    w1 = median([run(m, cl=two, chunk=1)[0] for _ in range(reps)])
    w16 = median([run(m, cl=two, chunk=16)[0] for _ in range(reps)])
    per_task = max(w1 - w16, 0.0) * 2 / (m - m / 16)  # 2 workers share the extra tasks
    loads.append(_load())
    one.close()
    two.close()
    per_toss = base_cpu / n
    busy = {c: c * per_toss / per_task if per_task > 0 else float("inf")
            for c in (16, 64, 256)}
    body = "\n".join([
        "## A Dask cluster (`benchmarks/bench_cluster.py`)",
        "",
        head,
        "",
        f"The hand toss onto wood, xi = {XI}, seed {SEED}, {n} tosses a run, {reps} runs of "
        "each configuration interleaved, medians; CPU counts the client, the pool's processes "
        "and every worker.  The machine is shared with other work, so the wall clock can be "
        "several times the CPU; the ratios compare runs made side by side (\"median ratio\": "
        "the median over the repetitions of each run's ratio to the baseline run just before "
        "it).  Every run gives the same counts (checked), whatever its chunks.  Load averages "
        f"(1, 5, 15 min) after each round: {'; '.join(loads)}.",
        "",
        table(["run", "wall", "tosses/s", "wall / baseline", "median ratio", "CPU per toss",
               "CPU / baseline", "median ratio"], rows),
        "",
        f"Start-up, paid once a command: a LocalCluster of 2 workers {start2:.2f} s, of 1 "
        f"worker {start1:.2f} s (the workers import numpy, MuJoCo and Dask); a connection to a "
        "running scheduler is a fraction of that.",
        "",
        f"The scheduler's cost a task (chunks of 1 toss against 16, {m} tosses): about "
        f"{per_task * 1e3:.1f} ms of wall time a task.  A toss is about {per_toss * 1e3:.0f} ms "
        f"of CPU, so one such scheduler keeps about {busy[16]:.0f} workers busy with chunks of "
        f"16, {busy[64]:.0f} with chunks of 64 and {busy[256]:.0f} with chunks of 256.",
    ])
    write_section("bench_cluster", body)


if __name__ == "__main__":
    main()
