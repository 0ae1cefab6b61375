"""Bouncing runs on a Dask cluster (``--scheduler``) and checkpoints (``--checkpoint``).

A real ``dask scheduler`` and two ``dask worker`` processes (no nanny: a killed worker stays
dead) are started on 127.0.0.1 (a free port, every process stopped by the fixture's finalizer
whatever happens).  The tests run in this file's order on one cluster, which they wear down: a
worker killed, then a chunk that kills every worker, then the scheduler killed.  The runs are
about 600 tosses in all (about 17 ms of CPU each); the processes' start-up costs as much.
The reference is always the local pool (``--jobs 2``) of the same seed: the same bytes.
"""

from __future__ import annotations

import json
import os
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

import pytest

from tests.cli.cli_helpers import error, sigint_default

distributed = pytest.importorskip("distributed")
pytest.importorskip("mujoco")
# one worker: one cluster for the module; slow: the processes start in seconds each
pytestmark = [pytest.mark.xdist_group("cluster"), pytest.mark.slow]

ROOT = Path(__file__).resolve().parents[2]
COIN = [sys.executable, "-m", "coincli"]
#: 96 tosses: 6 chunks of 16 (the local pool's), from 1 block of the seed
RUN = ["simulate", "-n", "96", "--seed", "11", "--xi", "0.577", "--landing", "bounce", "-f",
       "csv"]
POISON_SEED = 666  #: a seed whose chunk 2 kills the worker that runs it (the preload below)

_PRELOAD = f"""
import os
from coincli.core.bounce import runs



def _poisoned(job):
    seed, block, start = job[1][0], job[1][1], job[1][2]
    if seed == {POISON_SEED} and block == 0 and start == 32:
        os._exit(1)  # a crash no Python handler sees, as a segfault would be
    return runs._unpoisoned(job)


if not hasattr(runs, "_unpoisoned"):  # a preload may run twice in one process
    runs._unpoisoned = runs.run_block
    runs.run_block = _poisoned
"""


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _env(**more) -> dict:
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(
        [str(ROOT), *filter(None, [os.environ.get("PYTHONPATH")])]), **more)
    env.pop("DASK_SCHEDULER_ADDRESS", None)
    return env


class Cluster:
    """A scheduler and its workers, each a subprocess in its own session."""

    def __init__(self, tmp: Path):
        self.tmp, self.procs, self.workers = tmp, [], []
        self.address = f"tcp://127.0.0.1:{_free_port()}"
        (tmp / "poison.py").write_text(_PRELOAD)

    def _start(self, argv, name):
        log = open(self.tmp / f"{name}.log", "ab")  # noqa: SIM115 - closed with the process
        p = subprocess.Popen(argv, stdout=log, stderr=subprocess.STDOUT, start_new_session=True,
                             env=_env(DASK_DISTRIBUTED__SCHEDULER__ALLOWED_FAILURES="1"),
                             cwd=self.tmp)
        log.close()
        self.procs.append(p)
        return p

    def start(self):
        port = self.address.rsplit(":", 1)[1]
        self._start([sys.executable, "-m", "distributed.cli.dask_scheduler", "--host",
                     "127.0.0.1", "--port", port, "--no-dashboard"], "scheduler")
        for k in range(2):
            self.add_worker(k)
        self.wait_for(2)

    def add_worker(self, k):
        self.workers.append(self._start(
            [sys.executable, "-m", "distributed.cli.dask_worker", self.address, "--nthreads",
             "1", "--no-dashboard", "--no-nanny", "--name", f"w{k}", "--preload",
             str(self.tmp / "poison.py"), "--host", "127.0.0.1"], f"worker{k}"))

    def wait_for(self, n, timeout=120):
        with distributed.Client(self.address, timeout=60, set_as_default=False) as client:
            client.wait_for_workers(n, timeout=timeout)

    def stop(self):
        for p in reversed(self.procs):
            if p.poll() is None:
                try:
                    os.killpg(p.pid, signal.SIGKILL)
                except ProcessLookupError:
                    pass
            p.wait()


@pytest.fixture(scope="module")
def cluster(tmp_path_factory):
    c = Cluster(tmp_path_factory.mktemp("cluster"))
    try:
        c.start()
        yield c
    finally:
        c.stop()


@pytest.fixture(scope="module")
def reference():
    """The bytes of RUN on the local pool."""
    p = subprocess.run([*COIN, *RUN, "--jobs", "2"], capture_output=True, text=True,
                       timeout=300, env=_env())
    assert p.returncode == 0 and p.stderr == "", p.stderr
    return p.stdout


def _coin(*argv, timeout=300):
    p = subprocess.run([*COIN, *argv], capture_output=True, text=True, timeout=timeout,
                       env=_env())
    return p.returncode, p.stdout, p.stderr


def test_a_cluster_run_is_byte_for_byte_the_local_pools(cluster, reference):
    assert reference.startswith("outcome,count,") and ",11," in reference
    rc, out, err = _coin(*RUN, "--scheduler", cluster.address)
    assert (rc, err) == (0, ""), err
    assert out == reference


TABLE = ["table", "--landing", "bounce", "--xi", "0.45,0.6", "--surface", "wood",
         "--friction", "0.2,0.4", "-n", "24", "--seed", "11", "-f", "csv"]


def test_a_table_study_on_the_cluster_is_the_local_pools(cluster, tmp_path):
    """coin table --landing bounce (a parameter study) takes the cluster and the checkpoint as
    simulate does: the same bytes as the local pool, and a re-run from its checkpoint too."""
    local = _coin(*TABLE, "--jobs", "2")
    assert local[0] == 0 and local[1].count("\n") == 5, local
    ck = tmp_path / "study.ck"
    on = _coin(*TABLE, "--scheduler", cluster.address, "--checkpoint", str(ck))
    assert on == local
    again = _coin(*TABLE, "--jobs", "1", "--checkpoint", str(ck))  # every chunk from the file
    assert again == local
    other = _coin(*[a if a != "0.2,0.4" else "0.2,0.5" for a in TABLE], "--checkpoint", str(ck))
    assert other[0] == 2 and "cells" in other[2] and other[2].count("\n") == 1, other


def _records(path: Path) -> int:
    return max(0, len(path.read_text().splitlines()) - 1) if path.exists() else 0


def test_a_checkpoint_resumes_a_killed_client_with_the_same_bytes(cluster, reference,
                                                                  tmp_path):
    ck = tmp_path / "run.ckpt"
    p = subprocess.Popen([*COIN, *RUN, "--scheduler", cluster.address, "--checkpoint", str(ck)],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                         start_new_session=True, env=_env())
    try:
        t0 = time.monotonic()
        while _records(ck) < 2 and p.poll() is None and time.monotonic() - t0 < 120:
            time.sleep(0.05)
        os.killpg(p.pid, signal.SIGKILL)  # the client dies at once, mid-run
    finally:
        p.communicate()
    held = _records(ck)
    assert 2 <= held < 6, held  # some chunks recorded, not all
    lines = ck.read_text().splitlines()
    header = json.loads(lines[0])
    assert header["options"]["--seed"] == "11" and header["command"].startswith("coin simulate")
    rc, out, err = _coin(*RUN, "--scheduler", cluster.address, "--checkpoint", str(ck))
    assert (rc, err) == (0, ""), err
    assert out == reference
    assert _records(ck) == 6
    assert ck.read_text().splitlines()[:held + 1] == lines[:held + 1]  # appended, never rewritten

    # without a scheduler: a torn last line and a damaged one are recomputed by the local pool
    lines = ck.read_text().splitlines(keepends=True)
    damaged = lines[2].replace('"rows": [[', '"rows": [[9')
    ck.write_text("".join([lines[0], lines[1], damaged, *lines[3:5], lines[5][:40]]))
    rc, out, err = _coin(*RUN, "--jobs", "2", "--checkpoint", str(ck))
    assert (rc, err) == (0, ""), err
    assert out == reference and _records(ck) == 6

    # another command line: refused in one line naming what differs
    other = [a if a != "11" else "12" for a in RUN]
    err = error(_coin(*other, "--jobs", "1", "--checkpoint", str(ck)), 2, "--checkpoint",
                "--seed 11 there, 12 here")
    assert "-n" not in err


def _resumed_from(path: Path) -> list:
    return [json.loads(line) for line in path.read_text().splitlines()[1:]]


def test_a_checkpoint_of_other_chunks_resumes_toss_by_toss(cluster, reference, tmp_path):
    """A checkpoint holds tosses, not a chunking: one written in chunks of 16 (the local pool)
    and rewritten in chunks of 32, one of them lost and half of it held in a chunk of 16, is
    resumed on the cluster computing only the one chunk of 16 it does not hold."""
    ck = tmp_path / "run.ckpt"
    assert _coin(*RUN, "--jobs", "2", "--checkpoint", str(ck)) == (0, reference, "")
    head, *recs = ck.read_text().splitlines(keepends=True)
    from coincli.io.checkpoint import _line

    by = {json.loads(r)["start"]: json.loads(r) for r in recs}
    assert sorted(by) == [0, 16, 32, 48, 64, 80]  # one block, the local pool's chunks of 16
    key = by[0]["key"]
    pairs = [_line({"key": key, "start": s, "rows": by[s]["rows"] + by[s + 16]["rows"]})
             for s in (0, 64)]  # tosses 1-32 and 65-96 in chunks of 32; 33-48 alone
    ck.write_text("".join([head, *pairs, _line({"key": key, "start": 32,
                                                 "rows": by[32]["rows"]})]))
    rc, out, err = _coin(*RUN, "--scheduler", cluster.address, "--checkpoint", str(ck))
    assert (rc, err) == (0, ""), err
    assert out == reference
    added = _resumed_from(ck)[3:]
    assert [(r["start"], r["rows"]) for r in added] == [(48, by[48]["rows"])]


def test_ctrl_c_on_a_cluster_run_keeps_the_checkpoint_and_the_seed(cluster, tmp_path):
    """SIGINT to the client of a cluster run: exit 130 at once, one line with the drawn seed,
    whole lines in the checkpoint; that seed and checkpoint then give the uninterrupted
    bytes."""
    ck = tmp_path / "run.ckpt"
    run = [a for a in RUN if a not in ("--seed", "11")]
    run[run.index("96")] = "128"  # 8 chunks of 16 on 2 workers
    p = subprocess.Popen([*COIN, *run, "--scheduler", cluster.address, "--checkpoint", str(ck)],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                         start_new_session=True, env=_env(), preexec_fn=sigint_default)
    try:
        t0 = time.monotonic()
        while _records(ck) < 2 and p.poll() is None and time.monotonic() - t0 < 120:
            time.sleep(0.05)
        p.send_signal(signal.SIGINT)
        out, err = p.communicate(timeout=60)
    finally:
        if p.poll() is None:
            os.killpg(p.pid, signal.SIGKILL)
            p.communicate()
    assert (p.returncode, out) == (130, ""), err
    seed = json.loads(ck.read_text().splitlines()[0])["options"]["--seed"]
    assert err == f"coin: error: interrupted (seed {seed}: --seed {seed} repeats this run)\n"
    held = ck.read_text().splitlines(keepends=True)
    assert 2 <= len(held) - 1 < 8 and all(line.endswith("\n") for line in held)
    for line in held:
        json.loads(line)
    rc, out, err = _coin(*run, "--seed", seed, "--scheduler", cluster.address, "--checkpoint",
                         str(ck))
    assert (rc, err) == (0, ""), err
    assert ck.read_text().splitlines(keepends=True)[:len(held)] == held
    assert _records(ck) == 8
    assert (0, out, "") == _coin(*run, "--seed", seed, "--jobs", "2")


FIT = ["fit", "--landing", "bounce", "--fit", "friction", "--design-tosses", "32", "--dt",
       "2e-4", "--t-max", "2.5", "--seed", "3", "-f", "json"]  # 5 points x 32 tosses


def test_a_calibration_on_the_cluster_is_the_local_pools(cluster, tmp_path):
    """coin fit --landing bounce: the design's tosses on the cluster, then from its
    checkpoint, give the bytes of --jobs 2; the checkpoint of another design is refused."""
    data = tmp_path / "tosses.csv"
    data.write_text("label,coin,count,heads,sides,tails\nthree quarters,quarter,3,14,3,15\n")
    local = _coin(*FIT[:1], str(data), *FIT[1:], "--jobs", "2")
    assert local[0] == 0 and json.loads(local[1])[0]["simulated"] == 160, local
    ck = tmp_path / "fit.ckpt"
    on = _coin(*FIT[:1], str(data), *FIT[1:], "--scheduler", cluster.address, "--checkpoint",
               str(ck))
    assert on == local
    assert _records(ck) == 5  # one line a design point
    from coincli import api

    rows = api.fit(str(data), landing="bounce", fit="friction", design_tosses=32, dt=2e-4,
                   t_max=2.5, seed=3, checkpoint=str(ck), jobs=1)  # every point from the file
    assert rows == json.loads(local[1])
    other = [a if a != "32" else "48" for a in FIT]
    error(_coin(*other[:1], str(data), *other[1:], "--checkpoint", str(ck)), 2,
          "--design-tosses 32 there, 48 here")


def test_a_worker_killed_mid_run_changes_nothing(cluster, reference, tmp_path):
    ck = tmp_path / "run.ckpt"
    p = subprocess.Popen([*COIN, *RUN, "--scheduler", cluster.address, "--checkpoint", str(ck)],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=_env())
    try:
        t0 = time.monotonic()
        while _records(ck) < 1 and p.poll() is None and time.monotonic() - t0 < 120:
            time.sleep(0.05)
        os.killpg(cluster.workers[0].pid, signal.SIGKILL)  # no nanny: it does not come back
        out, err = p.communicate(timeout=300)
    finally:
        if p.poll() is None:
            p.kill()
            p.communicate()
    assert (p.returncode, err) == (0, ""), err
    assert out == reference


def test_a_chunk_that_kills_every_worker_is_named(cluster):
    cluster.add_worker(2)  # one more: the poisoned chunk is tried twice (allowed failures 1)
    cluster.wait_for(2)
    poisoned = ["simulate", "-n", "64", "--seed", str(POISON_SEED), "--xi", "0.577",
                "--landing", "bounce", "--scheduler", cluster.address]
    err = error(_coin(*poisoned), 1, "tosses 33 to 48", f"seed {POISON_SEED}", "KilledWorker")
    assert len(err) < 400


def test_an_unreachable_scheduler_is_one_line_well_within_the_timeout():
    address = f"tcp://127.0.0.1:{_free_port()}"  # nothing listens there
    t0 = time.monotonic()
    error(_coin(*RUN, "--scheduler", address, timeout=60), 1,
          f"cannot reach the scheduler at {address}")
    assert time.monotonic() - t0 < 60
    # a port that takes the connection and never answers: the --timeout, then one line
    with socket.socket() as silent:
        silent.bind(("127.0.0.1", 0))
        silent.listen()
        address = f"tcp://127.0.0.1:{silent.getsockname()[1]}"
        error(_coin(*RUN, "--scheduler", address, "--timeout", "1", timeout=60), 1,
              "did not answer as a Dask scheduler within 1 s (--timeout)")


def test_scheduler_options_refused_before_any_work(coin, monkeypatch, tmp_path):
    sim = ["simulate", "-n", "16", "--seed", "1", "--xi", "0.577", "--landing", "bounce"]
    error(coin(*sim, "--scheduler", "local", "--jobs", "2"), 2,
          "--scheduler and --jobs do not go together")
    error(coin(*sim, "--scheduler", "tcp://host"), 2, "--scheduler must be tcp://HOST:PORT",
          "'tcp://host'")
    error(coin(*sim, "--timeout", "0.5", "--scheduler", "local"), 2,
          "--timeout must be a number from 1 to 3600")
    error(coin(*sim, "--jobs", "1", "--timeout", "5"), 2, "--timeout goes with --scheduler")
    error(coin(*sim[:-2], "--scheduler", "local"), 2, "--scheduler goes with --landing bounce")
    error(coin(*sim, "--checkpoint", str(tmp_path)), 2, "--checkpoint")
    monkeypatch.setenv("DASK_SCHEDULER_ADDRESS", "nowhere")
    error(coin(*sim), 2, "DASK_SCHEDULER_ADDRESS must be tcp://HOST:PORT", "'nowhere'")
    import importlib.util

    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec",
                        lambda name, *a: None if name == "distributed" else real(name, *a))
    monkeypatch.delenv("DASK_SCHEDULER_ADDRESS")
    error(coin(*sim, "--scheduler", "local"), 1,
          "pip install -U 'thickcoin[cluster]'")


def test_a_worker_of_another_version_is_refused_naming_it():
    from coincli.core.bounce import cluster
    from coincli.errors import NotComputable

    want = {**cluster.versions(), "coin": "0.0.1"}
    with pytest.raises(NotComputable, match=r"runs coin \d.*this client coin 0\.0\.1"):
        cluster._task(b"", want)


def test_no_toss_depends_on_the_chunks_and_a_checkpoint_takes_any(monkeypatch, tmp_path):
    """Blocks of 16 tosses (patched, to be cheap): the rows of every toss, recorded in
    checkpoints, are the same in chunks of 1, 4 or 16 (the cluster's chunks are sized, the local
    pool's are 16); a run in chunks of 16 takes a checkpoint written in chunks of 4 without
    computing a toss; the cluster's chunk grows with the tosses a worker."""
    from coincli.core.bounce import cluster, runs
    from coincli.core.toss.launch import HAND_TOSS
    from coincli.io.checkpoint import Checkpoint

    monkeypatch.setattr(runs, "BLOCK", 16)
    head = {"versions": cluster.versions(), "command": "test", "options": {}}

    def sim(chunk, path):
        with Checkpoint(str(path), head) as ck:
            return runs.simulate(40, 7, xi=0.577, jobs=1, chunk=chunk, executor=ck,
                                 **{k: HAND_TOSS[k] for k in ("u", "omega", "psi")}), ck.held

    def tosses(path):
        return {(r["key"], r["start"] + i): row for r in _resumed_from(path)
                for i, row in enumerate(r["rows"])}

    first, _ = sim(4, tmp_path / "c4")
    assert len(tosses(tmp_path / "c4")) == 40 and first.counts[3] < 40
    for chunk in (1, 16):
        again, _ = sim(chunk, tmp_path / f"c{chunk}")
        assert tosses(tmp_path / f"c{chunk}") == tosses(tmp_path / "c4")
        assert (again.counts, again.steps) == (first.counts, first.steps)

    def no_toss(job):
        raise AssertionError(f"computed {job}")

    monkeypatch.setattr(runs, "run_block", no_toss)
    resumed, held = sim(16, tmp_path / "c4")
    assert held == 10 and (resumed.counts, resumed.steps) == (first.counts, first.steps)
    monkeypatch.undo()
    assert [cluster.chunk_for(n, w) for n, w in ((96, 2), (768, 2), (768, 1), (10**5, 100),
                                                  (10**6, 100))] == [16, 64, 128, 128, 256]


_PROBE = r"""
import json, sys
from coincli.cli import run
codes = [run(argv) for argv in json.loads(sys.argv[1])]
print(json.dumps([codes, "distributed" in sys.modules, "mujoco" in sys.modules]),
      file=sys.stderr)
"""


def test_runs_without_a_scheduler_never_import_distributed(tmp_path):
    sim = ["simulate", "-n", "16", "--seed", "1", "--xi", "0.577", "--landing", "bounce",
           "--jobs", "1"]
    commands = [sim, [*sim, "--checkpoint", str(tmp_path / "c.ckpt")],
                ["toss", "--xi", "0.577", "--psi", "90", "--u", "2", "--omega", "40",
                 "--landing", "bounce"], ["design", "-p", "1/3"]]
    p = subprocess.run([sys.executable, "-c", _PROBE, json.dumps(commands)],
                       capture_output=True, text=True, timeout=300, env=_env())
    codes, loaded, mujoco = json.loads(p.stderr.strip().splitlines()[-1])
    assert codes == [0, 0, 0, 0] and mujoco and not loaded


def test_a_scheduler_lost_mid_run_is_one_line_and_the_checkpoint_stays(cluster, tmp_path):
    """Last: it ends the module's cluster."""
    cluster.add_worker(3)  # the others were killed above
    cluster.wait_for(1)
    ck = tmp_path / "run.ckpt"
    p = subprocess.Popen([*COIN, *RUN, "--scheduler", cluster.address, "--checkpoint", str(ck),
                          "--timeout", "3"], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                         text=True, env=_env())
    try:
        t0 = time.monotonic()
        while _records(ck) < 1 and p.poll() is None and time.monotonic() - t0 < 120:
            time.sleep(0.05)
        os.killpg(cluster.procs[0].pid, signal.SIGKILL)  # the scheduler
        out, err = p.communicate(timeout=120)
    finally:
        if p.poll() is None:
            p.kill()
            p.communicate()
    error((p.returncode, out, err), 1, f"lost the scheduler at {cluster.address}")
    assert 1 <= _records(ck) < 6
    json.loads(ck.read_text().splitlines()[-1])  # whole lines only


# --scheduler local and a terminal's signals (issue 38, item 2).  A terminal sends Ctrl-C
# (SIGINT) or, closed, SIGHUP to its whole foreground process group, so to the LocalCluster's
# workers too; SIGTERM comes from `kill -- -PGID` or timeout(1) of a group.  The run must end
# as with --jobs 2: one line, 128 + the signal, nothing left in TMPDIR (a private one here),
# no process of its session alive.  About 10 s each (a LocalCluster of 2 workers; chunks of 64).

LOCAL = ["simulate", "--landing", "bounce", "-n", "1024", "--seed", "1", "--xi", "0.5",
         "--scheduler", "local", "-f", "csv"]
STOP_WORDS = {signal.SIGINT: "interrupted", signal.SIGTERM: "terminated (SIGTERM)",
              signal.SIGHUP: "hung up (SIGHUP)"}


def _session(sid: int) -> list[int]:
    """Every live (not zombie) process of session ``sid`` (a scan of /proc)."""
    alive = []
    for name in os.listdir("/proc"):
        if name.isdigit():
            try:
                with open(f"/proc/{name}/stat") as f:
                    fields = f.read().rsplit(")", 1)[1].split()
            except (OSError, IndexError):
                continue
            if int(fields[3]) == sid and fields[0] not in "ZX":
                alive.append(int(name))
    return alive


def _kids(pid: int) -> list[int]:
    """The children of ``pid``, whichever of its threads started them."""
    kids = []
    try:
        for tid in os.listdir(f"/proc/{pid}/task"):
            with open(f"/proc/{pid}/task/{tid}/children") as f:
                kids += [int(k) for k in f.read().split()]
    except OSError:
        pass
    return kids


def _scratch_made(scratch: Path) -> bool:
    """Dask's scheduler made its ``dask-scratch-space`` (in TMPDIR, or in a directory there)."""
    return any(path.name == "dask-scratch-space" for path in scratch.rglob("*"))


def _local_run(tmp_path, *more):
    """coin LOCAL in a session of its own, SIGINT at its default, a private TMPDIR."""
    scratch = tmp_path / "tmpdir"
    scratch.mkdir()
    p = subprocess.Popen([*COIN, *LOCAL, *more], stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, text=True, start_new_session=True,
                         cwd=tmp_path, env=_env(TMPDIR=str(scratch)), preexec_fn=sigint_default)
    return p, scratch


def _wait(ready, p, what, limit=120.0):
    t0 = time.monotonic()
    while not ready():
        if p.poll() is not None:
            pytest.fail(f"coin ended before {what}: {p.returncode} {p.stderr.read()[-800:]}")
        if time.monotonic() - t0 > limit:
            pytest.fail(f"no sign of {what} after {limit} s")
        time.sleep(0.02)


def _stopped(p, sig, scratch):
    """One line, 128 + sig, nothing on stdout, nothing left in TMPDIR nor in the session."""
    try:
        out, err = p.communicate(timeout=90)
    finally:
        if p.poll() is None:
            os.killpg(p.pid, signal.SIGKILL)
            p.communicate()
    assert (p.returncode, out) == (128 + sig, ""), (p.returncode, err[-3000:])
    assert err == f"coin: error: {STOP_WORDS[sig]}\n", err[-3000:]
    t0 = time.monotonic()
    while _session(p.pid) and time.monotonic() - t0 < 20:
        time.sleep(0.05)
    assert _session(p.pid) == []
    assert sorted(os.listdir(scratch)) == []


needs_proc = pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc")


@needs_proc
@pytest.mark.slow
@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM, signal.SIGHUP],
                         ids=["INT", "TERM", "HUP"])
def test_a_signal_to_the_group_of_a_local_cluster_run_is_one_line(sig, tmp_path):
    """The signal to the whole process group once the workers are at work (a chunk in the
    checkpoint): the workers, which got it too, print nothing; the LocalCluster's directory
    is removed."""
    ck = tmp_path / "run.ckpt"
    p, scratch = _local_run(tmp_path, "--checkpoint", str(ck))
    _wait(lambda: _records(ck) >= 1, p, "a chunk done")
    os.killpg(p.pid, sig)
    _stopped(p, sig, scratch)


@needs_proc
@pytest.mark.slow
@pytest.mark.parametrize(("sig", "group", "moment"), [
    (signal.SIGINT, True, "scheduler"), (signal.SIGINT, True, "workers"),
    (signal.SIGHUP, True, "workers"), (signal.SIGINT, False, "workers")],
    ids=["INT-group-scheduler", "INT-group-workers", "HUP-group-workers", "INT-coin-workers"])
def test_a_signal_while_the_local_cluster_starts_is_one_line(sig, group, moment, tmp_path):
    """The signal while the LocalCluster is starting: as soon as its scheduler made its
    directory in TMPDIR, or once its workers are spawned (still importing Dask); to the whole
    group, or to coin alone.  No traceback from a worker, nor from Dask's atexit hook
    (``AssertionError: Status.init``)."""
    p, scratch = _local_run(tmp_path)
    if moment == "scheduler":
        _wait(lambda: _scratch_made(scratch), p, "the scheduler's directory")
    else:
        _wait(lambda: len(_kids(p.pid)) >= 3, p, "the workers spawned")  # and the tracker
    if group:
        os.killpg(p.pid, sig)
    else:
        p.send_signal(sig)
    _stopped(p, sig, scratch)
