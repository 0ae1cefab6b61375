"""Many tosses onto a surface: seeded random launches, run by worker processes, counted.

:func:`simulate` draws the launches block by block (:data:`BLOCK` tosses, block ``k`` seeded
``(seed, k)``), runs them through one :class:`coincli.core.bounce.engine.Engine` per worker
process (:func:`worker_init`, :func:`run_block`; both module-level, so that a pool pickles them
by name) and counts the outcomes into a :class:`BounceSimulation`.  The counts do not depend on
the number of workers nor on how blocks are cut into chunks.  The physics of one toss is
:mod:`coincli.core.bounce.engine`.
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable
from dataclasses import dataclass, field

from coincli.core.bounce.engine import (
    DEFAULT_DENSITY,
    DEFAULT_DT,
    DEFAULT_T_MAX,
    SURFACES,
    Coin,
    Engine,
    Launch,
    Surface,
    calibrate,
)
from coincli.core.toss.flight import DEFAULT_DIAMETER, NAMES, STANDARD_G, U_MAX, default_z0
from coincli.core.toss.launch import as_dist, sample_conditions
from coincli.core.toss.simulate import Frequency, wilson_interval

__all__ = ["BounceSimulation", "simulate", "simulate_many", "Workers", "default_jobs",
           "capped_jobs", "BLOCK", "CHUNK"]

BLOCK = 256  #: tosses per random block: the seed of block k is (seed, k), whatever the workers
CHUNK = 16  #: tosses a worker simulates between progress reports (a fraction of a second)


@dataclass
class BounceSimulation:
    """Result of :func:`simulate`."""

    n: int
    counts: tuple  #: heads, sides, tails, unsettled
    frequencies: list  #: :class:`coincli.core.toss.flight.Frequency` of heads, sides, tails among settled
    catch_counts: tuple  #: what the catch (first contact, eq. 7) would have said, same tosses
    agree: int  #: tosses whose outcome is the catch's
    mean_bounces: float
    mean_t_settle: float  #: s, among settled tosses
    steps: int
    seed: int
    landing: str
    surface: Surface
    damping: float
    dt: float
    level: float = 0.95
    vigorous: object = None  #: the closed-form (catch) prediction for the psi distribution
    extra: dict = field(default_factory=dict)

    @property
    def settled(self):
        return self.n - self.counts[3]


_DOMAINS = {"height": (0.0, 100.0), "vx": (0.0, 100.0), "z0": (0.0, 100.0)}


def _block_launches(seed, block, count, dists, coin, stream=(), start=0):
    """The launches ``start`` to ``count`` of block ``block`` of a run: its own generator,
    seeded ``(seed, block)``, so a toss's conditions do not depend on how blocks are shared
    among workers or cut into chunks.  Draws u, omega, psi (as
    :func:`coincli.core.toss.flight.sample_conditions`), then height, horizontal speed, its azimuth, and z0,
    always a full block."""
    import numpy as np

    rng = np.random.default_rng([seed, *stream, block])
    c = sample_conditions(BLOCK, rng, u=dists["u"], omega=dists["omega"], psi=dists["psi"])
    extra = {k: dists[k].sample(rng, BLOCK) for k in ("height", "vx", "z0")}
    az = rng.uniform(0.0, 2 * math.pi, BLOCK)
    out = []
    for i in range(start, count):
        def pick(v, i=i):
            return float(v if isinstance(v, float) else v[i])
        out.append(Launch(pick(c["u"]), pick(c["omega"]), pick(c["psi"]), pick(extra["z0"]),
                          pick(extra["height"]), pick(extra["vx"]), float(az[i])))
    return out


WORKER: dict = {}


def worker_init(args, parent=None):
    """One engine for this process.  ``parent``: the pid of the process that owns the pool,
    when this is a pool worker (:func:`_bind_to_parent`)."""
    if parent is not None:
        _bind_to_parent(parent)
    coin, surf, dt, g, landing, t_max, flight, damping = args
    WORKER["engine"] = Engine(coin, surf, dt=dt, g=g, landing=landing, t_max=t_max,
                               flight=flight, damping=damping)
    WORKER["args"] = args  # what it was built for (:func:`_run_job` reuses it)


def _bind_to_parent(parent: int) -> None:
    """A pool worker lives and dies with the process that started it.  Ctrl-C and SIGHUP go to
    the whole process group: the parent handles them (it terminates the pool), so the worker
    ignores them; SIGTERM, which the parent's ``pool.terminate()`` sends, ends it at once, with
    no traceback (the default action, not the parent's handler it inherited).  If the parent
    dies without ending the pool (SIGKILL), the kernel kills the worker (Linux's
    ``PR_SET_PDEATHSIG``); elsewhere a thread checks every second that the parent is alive."""
    import signal

    signal.signal(signal.SIGINT, signal.SIG_IGN)
    if hasattr(signal, "SIGHUP"):
        signal.signal(signal.SIGHUP, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    if not _parent_death_signal():
        import threading
        import time

        def watch():
            while os.getppid() == parent:
                time.sleep(1.0)
            os._exit(1)

        threading.Thread(target=watch, daemon=True).start()
    if os.getppid() != parent:  # the parent died before the kernel was told to watch it
        os._exit(1)


def _parent_death_signal() -> bool:
    """Ask Linux to SIGKILL this process when its parent dies; False where that is not
    available."""
    import sys

    if not sys.platform.startswith("linux"):
        return False
    try:
        import ctypes
        import signal

        libc = ctypes.CDLL(None, use_errno=True)
        return libc.prctl(1, int(signal.SIGKILL), 0, 0, 0) == 0  # 1: PR_SET_PDEATHSIG
    except (OSError, AttributeError):
        return False


def run_block(job):
    """Tosses ``start`` to ``stop`` of one block (a chunk): ``(k, rows)``, ``k`` the chunk's
    index.  The first contacts are found for the whole block's launches, then sliced, so that a
    toss's numbers do not depend on the chunking."""
    k, (seed, block, start, stop, count, dists, stream) = job
    eng = WORKER["engine"]
    rows = []
    launches = _block_launches(seed, block, count, dists, eng.coin, stream)
    t_first = eng.first_contacts(launches) if eng.flight == "exact" else [None] * count
    for launch, t_f in zip(launches[start:stop], t_first[start:stop], strict=True):
        r = eng.run(launch, t_contact=t_f)
        rows.append((r.code, r.catch_code, r.bounces, r.t_settle, r.steps))
    return k, rows


def default_jobs():
    """Every core this process may use."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # pragma: no cover - not Linux
        return os.cpu_count() or 1


def capped_jobs(jobs: int) -> int:
    """``jobs`` workers, at most :func:`default_jobs` (every core this process may use): a
    simulated toss is pure computation, so more workers than cores only take turns, each one
    process more.  The results do not depend on the number."""
    return max(1, min(int(jobs), default_jobs()))


@dataclass
class _Plan:
    """One run of :func:`simulate`, cut into chunks: what the workers need (``args``, the
    ``work``) and what its summary needs."""

    n: int
    seed: int
    coin: Coin
    surf: Surface
    dt: float
    g: float
    landing: str
    t_max: float
    flight: str
    dists: dict
    level: float
    work: list
    damping: float = math.nan

    @property
    def args(self):
        return (self.coin, self.surf, self.dt, self.g, self.landing, self.t_max, self.flight,
                self.damping)


def _plan(n, seed, *, xi, u, omega, psi, surf=None, landing="bounce", height=0.0, vx=0.0,
          z0=None, diameter=DEFAULT_DIAMETER, density=DEFAULT_DENSITY, g=STANDARD_G,
          dt=DEFAULT_DT, t_max=DEFAULT_T_MAX, level=0.95, flight="exact", stream=(),
          chunk=None, executor=None) -> _Plan:
    """A run's launches distributions and chunks, its input checked (its contact damping is
    found later, :func:`_calibrate_all`); ``executor``: a cluster sizes the chunks."""
    from coincli.core.toss.flight import check_count

    n = check_count(n)
    coin = Coin(float(xi), float(diameter), float(density))
    surf = SURFACES["wood"] if surf is None else surf
    if z0 is None:
        z0 = default_z0(coin.xi, coin.diameter, "thick")
    dists = {"u": as_dist(u, "u", 0.0, U_MAX), "omega": as_dist(omega, "omega", 0.0, 1e5),
             "psi": as_dist(psi, "psi", 0.0, math.pi)}
    for name, val in (("height", height), ("vx", vx), ("z0", z0)):
        lo, hi = _DOMAINS[name]
        dists[name] = as_dist(val, name, lo, hi)
    if chunk is None:  # a cluster sizes its chunks from the run and its workers
        chunk = executor.chunk(n) if hasattr(executor, "chunk") else CHUNK
    chunk = int(chunk)
    if not 1 <= chunk <= BLOCK:
        raise ValueError(f"chunk must be from 1 to {BLOCK}, got {chunk}")
    work = []
    for b in range(-(-n // BLOCK)):
        count = min(BLOCK, n - b * BLOCK)
        for s in range(0, count, chunk):
            work.append((len(work), (seed, b, s, min(s + chunk, count), count, dists,
                                     tuple(stream))))
    return _Plan(n, seed, coin, surf, dt, g, landing, t_max, flight, dists, level, work)


def _check_jobs(jobs):
    jobs = default_jobs() if jobs is None else int(jobs)
    if jobs < 1:
        raise ValueError(f"jobs must be >= 1, got {jobs}")
    return capped_jobs(jobs)


class Workers:
    """Worker processes shared by the runs of :func:`simulate_many` calls (a design's rounds),
    started when first needed: a context manager that ends them.  ``jobs``: as
    :func:`simulate` takes it.  One process (``jobs`` 1) runs everything here, in this
    process.  A worker keeps the engine of the run it last worked on, so chunks of several
    runs (other coins, other surfaces) can be mixed; the counts never depend on which worker
    runs which chunk."""

    def __init__(self, jobs=None):
        self.jobs = _check_jobs(jobs)
        self.pool = None

    def __enter__(self):
        return self

    def __exit__(self, kind, exc, tb):
        self.close(kind is not None)

    def close(self, failed=False):
        """End the workers: at once when ``failed`` (Ctrl-C, SIGTERM, a failed toss)."""
        pool, self.pool = self.pool, None
        if pool is not None:
            if failed:
                pool.terminate()
            else:
                pool.close()
            pool.join()

    def map(self, fn, items, size):
        """``(i, fn(items[i]))`` as each completes, in any order; in this process when one
        worker (or one item) is enough.  ``size``: the processes the pool would start at most
        (``min(jobs, items)`` for a single run, as :func:`simulate` always did)."""
        if self.jobs == 1 or size <= 1 and self.pool is None:
            for i, item in enumerate(items):
                yield i, fn(item)
            return
        import multiprocessing as mp

        if self.pool is None:
            ctx = mp.get_context("fork" if "fork" in mp.get_all_start_methods() else "spawn")
            self.pool = ctx.Pool(min(self.jobs, size), initializer=_bind_to_parent,
                                 initargs=(os.getpid(),))
        try:
            it = self.pool.imap_unordered(_indexed, [(fn, i, item) for i, item in
                                                     enumerate(items)])
            for _ in items:
                while True:  # a timeout, so that Ctrl-C is seen at once on every platform
                    try:
                        yield it.next(timeout=0.2)
                        break
                    except mp.TimeoutError:
                        continue
        except BaseException:  # Ctrl-C, SIGTERM, SIGHUP or a failed toss: stop the workers now
            self.close(failed=True)
            raise


def _indexed(task):
    fn, i, item = task
    return i, fn(item)


def _run_job(item):
    """A chunk of any run: ``(args, (k, job))`` -> ``rows`` (the worker's engine rebuilt when
    the run changes)."""
    args, job = item
    if WORKER.get("args") != args:
        worker_init(args)
    return run_block(job)[1]


def _calibration(key):
    coin, surf, dt, g = key
    return calibrate(coin, surf, dt, g)


def _calibrate_all(plans, workers, parallel=True):
    """Each run's contact damping (:func:`coincli.core.bounce.engine.calibrate`): those not
    known in this process yet are found by the workers, side by side (a calibration is
    deterministic: the same number wherever it runs), and kept here; ``parallel`` False: all
    here, one after another."""
    from coincli.core.bounce import engine

    def key(p):
        return (p.coin, p.surf, p.dt, p.g)

    missing = []
    for p in plans if parallel else ():
        if engine.calibration_key(*key(p)) not in engine.CALIBRATION and key(p) not in missing:
            missing.append(key(p))
    if len(missing) > 1:
        for i, b in workers.map(_calibration, missing, len(missing)):
            engine.CALIBRATION[engine.calibration_key(*missing[i])] = b
    for p in plans:
        p.damping = calibrate(p.coin, p.surf, p.dt, p.g)


def simulate_many(runs, *, jobs=None, workers=None, executor=None,
                  progress: Callable[[int], None] | None = None) -> list:
    """Several :func:`simulate` runs at once: ``runs``, the keyword arguments of each
    (``n``, ``seed``, ``xi``, ...: those of :func:`simulate` but ``jobs``, ``progress``,
    ``executor``), share ``workers`` (a :class:`Workers`; by default one for this call, of
    ``jobs`` processes), their calibrations run side by side and their chunks in one queue, so
    that no worker waits for another run's last chunk.  Each result is the one
    :func:`simulate` gives for the same arguments, byte for byte.  ``progress(done)``: the
    tosses done, all runs together.  With an ``executor`` (a checkpoint or a cluster) the runs
    go one after another, each through it as :func:`simulate` sends it."""
    plans = [_plan(**kw, executor=executor) for kw in runs]
    if workers is None:
        with Workers(jobs) as own:
            return simulate_many(runs, workers=own, executor=executor, progress=progress)
    _calibrate_all(plans, workers, parallel=executor is None)  # (a cluster: no local pool)
    results = [[None] * len(p.work) for p in plans]
    done = 0

    def tick(rows):
        nonlocal done
        done += len(rows)
        if progress is not None:
            progress(done)

    if executor is not None:  # chunks from a checkpoint or a cluster; the rest run here
        for p, res in zip(plans, results, strict=True):
            for k, rows in executor.blocks(p.args, p.work):
                res[k] = rows
                tick(rows)
            rest = [job for job in p.work if res[job[0]] is None]
            for i, rows in workers.map(_run_job, [(p.args, job) for job in rest], len(rest)):
                res[rest[i][0]] = rows
                executor.keep(rest[i][0], rows)
                tick(rows)
    else:
        items = [(j, job) for j, p in enumerate(plans) for job in p.work]
        for i, rows in workers.map(_run_job, [(plans[j].args, job) for j, job in items],
                                   len(items)):
            j, (k, _) = items[i]
            results[j][k] = rows
            tick(rows)
    return [_summary(p, res) for p, res in zip(plans, results, strict=True)]


def simulate(n, seed, *, xi, u, omega, psi, surf=None, landing="bounce", height=0.0, vx=0.0,
             z0=None, diameter=DEFAULT_DIAMETER, density=DEFAULT_DENSITY, g=STANDARD_G,
             dt=DEFAULT_DT, t_max=DEFAULT_T_MAX, jobs=None, level=0.95, flight="exact",
             progress: Callable[[int], None] | None = None, stream=(),
             chunk=None, executor=None, workers=None) -> BounceSimulation:
    """Toss ``n`` coins onto ``surf`` (a :class:`Surface`, default wood) with seeded random
    launches and count the outcomes.

    ``u``, ``omega``, ``psi`` are as :func:`coincli.core.toss.flight.sample_conditions` takes them (numbers,
    spec strings or :class:`coincli.core.toss.launch.Dist`; SI, radians); ``height`` (surface below the
    launch plane, m), ``vx`` (horizontal speed, m/s) and ``z0`` (centre above the launch plane,
    m; default the paper's for a thick coin, ``(sqrt 3/2) a + h/2``) likewise.  ``jobs`` worker
    processes (default, and at most: every core, :func:`capped_jobs`); block ``k`` of 256
    tosses draws from the seed ``(seed, k)``, so the counts are the same for any number of
    workers.  ``stream`` (a tuple of whole numbers) names an independent stream of the same
    seed (:func:`coincli.core.bounce.design.design` uses one per simulated point).
    Workers take chunks of ``chunk`` tosses (default :data:`CHUNK`; a cluster's
    ``executor.chunk(n)``) and ``progress(done)`` is called as each completes; the results
    do not depend on ``chunk`` or ``jobs``.
    ``executor`` (a checkpoint, :mod:`coincli.io.checkpoint`, or a Dask cluster,
    :mod:`coincli.core.bounce.cluster`) supplies chunks first: ``executor.blocks(args, work)``
    yields ``(k, rows)`` of the chunks it has or computes; the rest run here and are handed to
    ``executor.keep(k, rows)``.  ``workers``: a :class:`Workers` to run on (several runs
    sharing their processes); ``jobs`` is then theirs.
    """
    kw = {"n": n, "seed": seed, "xi": xi, "u": u, "omega": omega, "psi": psi, "surf": surf,
          "landing": landing, "height": height, "vx": vx, "z0": z0, "diameter": diameter,
          "density": density, "g": g, "dt": dt, "t_max": t_max, "level": level,
          "flight": flight, "stream": stream, "chunk": chunk}
    return simulate_many([kw], jobs=jobs, workers=workers, executor=executor,
                         progress=progress)[0]


def _summary(plan: _Plan, results) -> BounceSimulation:
    """The counts of a run from its chunks' rows (in chunk order)."""
    import numpy as np

    from coincli.core.toss.simulate import vigorous_limit

    n, level, coin = plan.n, plan.level, plan.coin
    rows = np.array([r for block in results for r in block], dtype=float)
    code = rows[:, 0].astype(int)
    catch = rows[:, 1].astype(int)
    counts = tuple(int(np.sum(code == i)) for i in range(4))
    catch_counts = tuple(int(np.sum(catch == i)) for i in range(3))
    settled = code < 3
    ns = int(settled.sum())
    freqs = []
    for i in range(3):
        if ns:
            lo, hi = wilson_interval(counts[i], ns, level)
            freqs.append(Frequency(NAMES[i], counts[i], counts[i] / ns, lo, hi))
        else:
            freqs.append(Frequency(NAMES[i], 0, math.nan, 0.0, 1.0))
    return BounceSimulation(
        n=n, counts=counts, frequencies=freqs, catch_counts=catch_counts,
        agree=int(np.sum(code == catch)), mean_bounces=float(rows[:, 2].mean()),
        mean_t_settle=float(rows[settled, 3].mean()) if ns else math.nan,
        steps=int(rows[:, 4].sum()), seed=plan.seed, landing=plan.landing, surface=plan.surf,
        damping=plan.damping, dt=plan.dt, level=level,
        vigorous=vigorous_limit(coin.xi, plan.dists["psi"]))
