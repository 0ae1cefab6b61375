"""Bouncing runs on a Dask cluster: the chunks of :func:`coincli.core.bounce.runs.simulate`
computed by the workers of a Dask scheduler (``--scheduler ADDRESS``), or of a ``LocalCluster``
on this machine (``--scheduler local``).

The work is the local pool's: chunk ``k`` of block ``b`` draws its launches from the seed
``(seed, b)`` (:func:`coincli.core.bounce.runs._block_launches`) and runs them
(:func:`coincli.core.bounce.runs.run_block`), whichever worker runs it, so the counts are those
of ``--jobs N`` byte for byte.  A task is a pure function of what it is sent (the coin, the
surface, the timestep, the launch distributions, the seed and the chunk's place): a chunk lost
with a worker is computed again elsewhere.  Each task checks that its worker runs the client's
``coin`` and ``mujoco-core``.

:class:`Cluster` is the executor that ``simulate`` takes (``blocks(args, work)``); every fault
is one :class:`coincli.errors.NotComputable` line: a scheduler not reached within ``timeout``
seconds, no worker for that long, the scheduler lost mid-run, a chunk that killed every worker
it ran on (Dask's ``KilledWorker``: the tosses are named), a worker of another version.
``distributed`` is imported only here, and only when a cluster is used (the ``cluster`` extra).
"""

from __future__ import annotations

import contextlib
import os
import threading
import time

from coincli.errors import NotComputable

__all__ = ["Cluster", "versions", "LOCAL"]

LOCAL = "local"  #: the address that starts a LocalCluster on this machine
POLL = 0.2  #: s at most between looks at the futures (Ctrl-C is seen); a result wakes it
LOOK = 1.0  #: s at most between looks at the scheduler and its workers while nothing arrives
FETCH = 2.0  #: s to fetch a finished chunk's rows before looking again (its worker may be gone)


#: Dask's settings for the LocalCluster of ``--scheduler local``: no statistical profiler in the
#: workers (it samples every thread every 10 ms, for a dashboard no one sees), and its monitors
#: once a second, not every 20 to 500 ms.  Idle, a LocalCluster of 2 workers then takes about
#: 2% of a core instead of 13% (measured here), CPU a run shares with its tosses.  The same
#: settings suit ``dask worker`` (docs/cluster.md).
QUIET = {"distributed.worker.profile.enabled": False,
         "distributed.admin.tick.interval": "1s",
         "distributed.worker.memory.monitor-interval": "1s",
         "distributed.admin.system-monitor.interval": "2s",
         "distributed.admin.system-monitor.gil.enabled": False}


def versions() -> dict:
    """What a worker must share with the client: ``coin``'s version and MuJoCo's."""
    import coincli
    from coincli.core.bounce.engine import require_mujoco

    return {"coin": coincli.__version__, "mujoco-core": require_mujoco().__version__}


_LOCK = threading.Lock()  # a worker with several threads runs one task at a time (one engine)
_ENGINE: list = [None, None]  # the args of the engine _chunk built, and that engine


class _Sent:
    """``fn`` and its ``task`` as one object: Dask's graph reads a tuple whose first item is a
    function as a task of its own and looks inside lists and tuples for keys; an object of
    this class it passes through as data (pickled as every argument is)."""

    __slots__ = ("fn", "task")

    def __init__(self, fn, task):
        self.fn, self.task = fn, task

    def __getstate__(self):
        return (self.fn, self.task)

    def __setstate__(self, state):
        self.fn, self.task = state


def _task(sent: _Sent, want):
    """``sent.fn(sent.task)`` on a worker, after checking that the worker runs the versions
    ``want``; one task at a time in a worker process (the engine is the process's)."""
    got = versions()
    if got != want:
        raise NotComputable(_mismatch(got, want, "a worker"))
    with _LOCK:
        return sent.fn(sent.task)


def _chunk(task):
    """One chunk of ``simulate``, ``task`` = ``(args, job)``: ``(k, rows)`` as
    :func:`coincli.core.bounce.runs.run_block` gives them.  The engine is built once a worker
    for a run's ``args`` (and again when another task, a calibration's, replaced it)."""
    from coincli.core.bounce import runs

    args, job = task
    if _ENGINE[0] != args or runs.WORKER.get("engine") is not _ENGINE[1]:
        runs.worker_init(args)
        _ENGINE[:] = [args, runs.WORKER["engine"]]
    return runs.run_block(job)


def chunk_for(n: int, workers: int) -> int:
    """The tosses of a chunk of a run of ``n`` tosses on ``workers`` workers: the largest power
    of two from :data:`coincli.core.bounce.runs.CHUNK` to a block (256) that still gives every
    worker :data:`PER_WORKER` chunks, so that a round trip to the scheduler is paid once per
    that many tosses while the last chunks still spread over the workers.  The tosses'
    numbers do not depend on it (nor does a checkpoint: :mod:`coincli.io.checkpoint`)."""
    from coincli.core.bounce.runs import BLOCK, CHUNK

    size = CHUNK
    while size * 2 <= BLOCK and -(-n // (size * 2)) >= PER_WORKER * max(1, workers):
        size *= 2
    return size


PER_WORKER = 4  #: chunks a worker at least, when the chunk is sized (:func:`chunk_for`)


def _mismatch(got: dict, want: dict, who: str) -> str:
    diff = ", ".join(f"{name} {got.get(name)}" for name in want if got.get(name) != want[name])
    here = ", ".join(f"{name} {want[name]}" for name in want if got.get(name) != want[name])
    return (f"{who} of the cluster runs {diff}, this client {here}: install the same versions "
            "on every worker")


def _what(fn, task) -> str:
    """What a task computes, for a message: the tosses of a chunk, numbered from 1 in the run;
    else the task's own ``describe`` (a design point of a calibration)."""
    from coincli.core.bounce.runs import BLOCK

    if fn is not _chunk:
        return getattr(fn, "describe", lambda t: "a task")(task)
    _, (seed, block, start, stop, _count, _dists, stream) = task[1]
    first, last = block * BLOCK + start + 1, block * BLOCK + stop
    which = f"toss {first}" if first == last else f"tosses {first} to {last}"
    where = f" of stream {','.join(map(str, stream))}" if stream else ""
    return f"{which}{where} (seed {seed})"


class Cluster:
    """A connection to a Dask scheduler (``address``: ``tcp://host:port``, ``host:port``, or
    :data:`LOCAL` for a ``LocalCluster`` of ``workers`` single-threaded processes, default
    every core), as a context manager; ``timeout`` (s) bounds the wait for the scheduler, for a
    worker and for a scheduler lost mid-run."""

    keep = None  #: chunks are never run by the client itself

    def __init__(self, address: str, timeout: float = 15.0, workers: int | None = None):
        self.address, self.timeout, self.workers = address, float(timeout), workers
        self.client = None
        self.local = None
        self.scratch = None  #: the LocalCluster's directory (TMPDIR/coin-dask-*), removed on close
        self.want = None
        self.nworkers = 1  #: the workers when the cluster was reached (the chunk's size)

    def __enter__(self):
        self.open()
        return self

    def __exit__(self, *exc):
        self.close()
        return False

    def open(self) -> None:
        """Connect (or start the LocalCluster), wait for a worker, check the versions; closed
        again whatever stops it (a fault, Ctrl-C, SIGTERM, SIGHUP), as ``__exit__`` does not run
        when ``__enter__`` raises."""
        try:
            self._open()
        except BaseException:
            self.close()
            raise

    def _open(self) -> None:
        import logging

        os.environ.setdefault("DASK_LOGGING__DISTRIBUTED", "critical")  # the workers we start
        os.environ.setdefault("DASK_DISTRIBUTED__LOGGING__DISTRIBUTED", "critical")
        import distributed

        _silence(logging)
        self.want = versions()
        where = "a LocalCluster" if self.address == LOCAL else f"the scheduler at {self.address}"
        if self.address != LOCAL:
            _probe(self.address, self.timeout)
        try:
            if self.address == LOCAL:
                import tempfile

                from coincli.core.bounce.runs import default_jobs

                import dask

                self.scratch = tempfile.mkdtemp(prefix="coin-dask-")
                with dask.config.set({**QUIET, "temporary-directory": self.scratch}), \
                        _held(STOPS):
                    self.local, stop = _started(lambda: distributed.LocalCluster(
                        n_workers=self.workers or default_jobs(), threads_per_worker=1,
                        processes=True, dashboard_address=None, silence_logs=logging.CRITICAL,
                        local_directory=self.scratch), self.timeout)
                    if stop is not None:  # the cluster (if it started) is closed by open()
                        raise stop
                self.client = distributed.Client(self.local, timeout=self.timeout)
            else:
                self.client = distributed.Client(self.address, timeout=self.timeout,
                                                 set_as_default=False)
        except Exception as exc:  # noqa: BLE001 - whatever Dask raises, one line
            self.close()
            raise NotComputable(f"cannot reach {where} within {self.timeout:g} s (--timeout): "
                                f"{_reason(exc)}") from None
        try:
            self.client.wait_for_workers(1, timeout=self.timeout)
        except (OSError, TimeoutError):
            self.close()
            raise NotComputable(f"no worker joined {where} within {self.timeout:g} s "
                                "(--timeout): start some with dask worker ADDRESS") from None
        try:
            seen = self.client.run(versions)
        except ImportError as exc:
            self.close()
            raise NotComputable(f"a worker of {where} cannot load coin ({_reason(exc)}): install "
                                f"thickcoin {self.want['coin']} with its physics extra on every "
                                "worker") from None
        self.nworkers = max(1, len(seen))
        for addr, got in sorted(seen.items()):
            if got != self.want:
                self.close()
                raise NotComputable(_mismatch(got, self.want, f"the worker {addr}"))

    def close(self) -> None:
        """Close the client and the LocalCluster (its workers joined), then remove the
        LocalCluster's scratch directory; a signal that arrives meanwhile waits until it is
        done (and then stops the run, if this is not already its cleanup)."""
        stop = None
        with _held(STOPS):
            for thing in (self.client, self.local):
                while thing is not None:
                    try:
                        thing.close()
                    except KeyboardInterrupt as exc:  # one more Ctrl-C: the cleanup goes on
                        stop = stop or exc
                        continue
                    except Exception:  # noqa: BLE001 - already gone: nothing left to close
                        pass
                    break
            self.client = self.local = None
            if self.scratch is not None:
                import shutil

                shutil.rmtree(self.scratch, ignore_errors=True)
                self.scratch = None
        if stop is not None:
            raise stop

    def chunk(self, n: int) -> int:
        """The chunk of a run of ``n`` tosses on this cluster (:func:`chunk_for` its workers
        when it was reached)."""
        return chunk_for(n, self.nworkers)

    def blocks(self, args, work):
        """Run the chunks ``work`` (``(k, job)`` pairs, as ``simulate`` cuts them) on the
        workers and yield ``(k, rows)`` as each completes, in any order."""
        for _, got in self.run(_chunk, [(k, (args, (k, job))) for k, job in work]):
            yield got

    def run(self, fn, items):
        """``fn(task)`` for the ``(k, task)`` pairs ``items`` on the workers (``fn`` module-level,
        pickled by name; ``task`` is all it is sent): ``(k, result)`` as each completes, in any
        order.  A task lost with a worker is computed again elsewhere; a fault is one line."""
        import distributed

        client = self.client
        stamp = f"{os.getpid()}-{time.time_ns()}"
        futures = client.map(_task, [_Sent(fn, t) for _, t in items],
                             [self.want] * len(items), pure=False,
                             key=[f"coin-{fn.__name__}-{stamp}-{k}" for k, _ in items])
        pending = dict(zip(futures, items, strict=True))
        ready = distributed.as_completed(futures, loop=client.loop)
        wake = getattr(ready, "thread_condition", None)  # notified as a task completes
        del futures  # a task's result is released on the cluster once it is here
        quiet_since = None  # since when the scheduler, or every worker, is gone
        looked = time.monotonic()
        try:
            while pending:
                done = ready.next_batch(block=False)
                if not done:
                    if wake is None:
                        time.sleep(POLL)
                    else:
                        with wake:
                            if ready.queue.empty():
                                wake.wait(POLL)
                    done = ready.next_batch(block=False)
                for fut in done:
                    k, task = pending[fut]
                    got = self._result(fut, fn, task)
                    if got is None:  # lost with its worker before it was fetched: again
                        ready.add(fut)
                        continue
                    del pending[fut]
                    yield k, got
                if not pending:
                    break
                now = time.monotonic()
                if done:
                    looked, quiet_since = now, None
                    continue
                if now - looked < LOOK:  # the scheduler is asked at most once a LOOK
                    continue
                looked = now
                lost = self._lost()
                if lost is None:
                    quiet_since = None
                elif quiet_since is None:
                    quiet_since = now
                elif now - quiet_since > self.timeout:
                    raise NotComputable(f"{lost} for {self.timeout:g} s (--timeout) in the "
                                        f"middle of the run; {len(pending)} tasks of "
                                        f"{len(items)} were not done")
        finally:
            if pending:  # Ctrl-C or a failure: take our tasks off the cluster
                try:
                    client.cancel(list(pending), force=True)
                except Exception:  # noqa: BLE001 - the scheduler may be gone
                    pass

    def _lost(self) -> str | None:
        """Why the run cannot progress now (the scheduler or every worker gone), or None."""
        client = self.client
        if client.status not in ("running", "newly-created"):
            return f"lost the scheduler at {self.address}"
        info = client.scheduler_info()
        if not info.get("workers"):
            return f"no worker at {self.address}"
        return None

    def _result(self, fut, fn, task):
        """The result of a completed task; None when it was lost with the worker that held it
        (Dask computes it again)."""
        import distributed

        if fut.status not in ("finished", "error", "cancelled"):
            return None
        try:
            return fut.result(timeout=FETCH)
        except TimeoutError:
            return None
        except distributed.KilledWorker as exc:
            raise NotComputable(f"{_what(fn, task)} killed every worker that ran them (Dask's "
                                f"KilledWorker: {_reason(exc)}); run them with --jobs 1 to see "
                                "the error") from None
        except distributed.client.FutureCancelledError:
            raise NotComputable(f"lost the scheduler at {self.address} in the middle of the "
                                "run") from None
        except OSError as exc:
            raise NotComputable(f"lost the scheduler at {self.address} in the middle of the "
                                f"run: {_reason(exc)}") from None


def _probe(address: str, timeout: float) -> None:
    """Before Dask's client is made (it can wait forever on a port that accepts and stays
    silent): the address takes a TCP connection within ``timeout`` s and, for ``tcp://``,
    answers as a Dask server does, with the length of its handshake (8 bytes, little-endian)."""
    import select
    import socket
    import struct

    scheme, _, rest = address.rpartition("://")
    host, _, port = rest.rpartition(":")
    host = host.strip("[]")
    deadline = time.monotonic() + timeout
    try:
        sock = socket.create_connection((host, int(port)), timeout=timeout)
    except TimeoutError:
        raise NotComputable(f"cannot reach the scheduler at {address} within {timeout:g} s "
                            "(--timeout): no answer") from None
    except OSError as exc:
        raise NotComputable(f"cannot reach the scheduler at {address}: "
                            f"{exc.strerror or _reason(exc)}") from None
    with sock:
        if scheme not in ("", "tcp"):
            return
        head = b""
        while len(head) < 8:
            left = deadline - time.monotonic()
            ready = select.select([sock], [], [], max(left, 0.0))[0] if left > 0 else []
            chunk = sock.recv(8 - len(head)) if ready else b""
            if not chunk:
                raise NotComputable(f"{address} took the connection but did not answer as a "
                                    f"Dask scheduler within {timeout:g} s (--timeout)")
            head += chunk
        size = struct.unpack("<Q", head)[0]
        if not 0 < size < 1 << 24:
            raise NotComputable(f"{address} answered, but not as a Dask scheduler")


#: the signals that stop a run (Ctrl-C, SIGTERM, a closed terminal's SIGHUP)
STOPS = ("SIGINT", "SIGTERM", "SIGHUP")


@contextlib.contextmanager
def _held(names):
    """The signals ``names`` blocked in this thread while the block runs; one that arrives
    meanwhile is delivered (and raises, coin's handlers being in place) when it ends.

    Around the start of the LocalCluster, so that every thread that Dask starts then (its
    event loop, the nannies' process watchers), and so every process those threads spawn (the
    workers, multiprocessing's resource tracker), has them blocked for good: the signal that a
    terminal sends its whole process group (Ctrl-C, a closed window) reaches coin alone, whose
    cleanup then closes the cluster and its workers (they are stopped through their nannies'
    queues, not by signals).  Otherwise each worker ends on its own, a traceback each, and a
    resource tracker killed by SIGHUP is started again and prints a KeyError for every
    semaphore it never saw.  Around the close too, so that it is not cut short.  Where
    threads have no signal mask (not POSIX), nothing is blocked."""
    import signal

    before = _block(names)
    try:
        yield
    finally:
        if before is not None:
            signal.pthread_sigmask(signal.SIG_SETMASK, before)


def _started(make, timeout: float):
    """``make()`` (the LocalCluster) in a thread of its own, which has :data:`STOPS` blocked
    as this thread has (:func:`_held`), and so every thread and process it starts: ``(its
    result, None)``.  A stop that arrives meanwhile (pending here, or raised here by a handler
    that another thread of coin's ran) waits for the end of the start, so that the cluster
    exists to be closed: ``(the cluster, the stop)``, the stop an exception to raise; if the
    start has not ended ``timeout`` s after the stop, ``(None, the stop)``, what was started
    left to Dask.  A start that a stop cut short left a cluster that Dask's atexit hook then
    failed to close (``AssertionError: Status.init``)."""
    import signal

    box = {}
    done = threading.Event()  # not Thread.join: a join a signal interrupts may end for good

    def start():
        try:
            _start_tracker()
            box["made"] = make()
        except BaseException as exc:  # noqa: BLE001 - raised again in the caller's thread
            box["error"] = exc
        finally:
            done.set()

    thread = threading.Thread(target=start, name="coin: LocalCluster start", daemon=True)
    nums = {getattr(signal, name) for name in STOPS if hasattr(signal, name)}
    pending = getattr(signal, "sigpending", set)
    stop = since = None
    thread.start()
    while not done.is_set():
        try:
            done.wait(POLL)
            if since is None and nums & pending():
                since = time.monotonic()
        except KeyboardInterrupt as exc:  # Ctrl-C, SIGTERM or SIGHUP (signals.Stopped)
            stop = stop or exc
            since = since or time.monotonic()
        if since is not None and time.monotonic() - since > timeout:
            return None, stop or KeyboardInterrupt()
    if "error" in box and stop is None:
        raise box["error"]
    return box.get("made"), stop


def _block(names):
    """Block the signals ``names`` in this thread: the mask before, or None (no masks)."""
    import signal

    nums = {getattr(signal, name) for name in names if hasattr(signal, name)}
    if not hasattr(signal, "pthread_sigmask") or not nums:
        return None
    return signal.pthread_sigmask(signal.SIG_BLOCK, nums)


def _start_tracker() -> None:
    """Start multiprocessing's resource tracker now, in this thread, with :data:`STOPS`
    blocked (:func:`_held`, :func:`_started`), so that it keeps SIGHUP blocked; and block them
    again here.  Started later, by the first worker's spawn in one of Dask's threads, it would unblock
    SIGINT and SIGTERM in that thread on its way out (``ensure_running`` does), and the
    workers spawned from it would take a Ctrl-C while importing Dask (a traceback each)."""
    try:
        from multiprocessing import resource_tracker

        resource_tracker.ensure_running()
    except Exception:  # noqa: BLE001 - no tracker here: nothing it could unblock
        pass
    _block(STOPS)


def _silence(logging) -> None:
    """No log line of Dask's reaches stderr (each of its loggers has its own level): a fault is
    the one line this module raises."""
    names = [n for n in list(logging.root.manager.loggerDict) if n.split(".")[0] in
             ("distributed", "tornado", "asyncio", "dask")]
    for name in {"distributed", "tornado", "asyncio", "dask", *names}:
        logger = logging.getLogger(name)
        logger.setLevel(logging.CRITICAL + 1)
        for handler in logger.handlers:
            handler.setLevel(logging.CRITICAL + 1)


def _reason(exc) -> str:
    """An exception as one short line."""
    text = " ".join(str(exc).split()) or type(exc).__name__
    return text if len(text) <= 200 else text[:197] + "..."
