"""One signal policy (issue 28, items 1-2): SIGTERM and SIGHUP end every command as Ctrl-C does.

Each test runs ``coin`` as a real process in a session of its own and sends the signal after a
readiness sign it waits for (the workers at work, the temporary file present), never after a
fixed sleep.  The process must then exit 143 (SIGTERM) or 129 (SIGHUP) with one line on stderr
that names the drawn seed, leave no ``.FILE.xxxx.tmp`` and no process of its session alive (a
scan of /proc: no psutil).  About 20 s of one core in all.
"""

from __future__ import annotations

import os
import re
import signal
import subprocess
import sys
import time

import pytest

pytestmark = pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc")

TERM, HUP = signal.SIGTERM, signal.SIGHUP
CODE = {TERM: 143, HUP: 129}
WORDS = {TERM: "terminated (SIGTERM)", HUP: "hung up (SIGHUP)"}
SEED = re.compile(r" \(seed (\d+): --seed \1 repeats this run\)")


def _stat(pid: int):
    """(state, session, CPU ticks) of a process from /proc/PID/stat, or None if it is gone."""
    try:
        with open(f"/proc/{pid}/stat") as f:
            fields = f.read().rsplit(")", 1)[1].split()
    except (FileNotFoundError, ProcessLookupError, IndexError):
        return None
    return fields[0], int(fields[3]), int(fields[11]) + int(fields[12])


def _alive_in_session(sid: int) -> list[int]:
    """Every live (not zombie) process of session ``sid``."""
    out = []
    for name in os.listdir("/proc"):
        if name.isdigit():
            st = _stat(int(name))
            if st is not None and st[1] == sid and st[0] not in "ZX":
                out.append(int(name))
    return out


def _children(pid: int) -> list[int]:
    try:
        with open(f"/proc/{pid}/task/{pid}/children") as f:
            return [int(k) for k in f.read().split()]
    except FileNotFoundError:
        return []


def _wait_for(ready, p, what: str, limit: float = 60.0):
    t0 = time.monotonic()
    while not ready():
        if p.poll() is not None:
            pytest.fail(f"coin ended before {what}: {p.returncode} {p.stderr.read()[:500]}")
        if time.monotonic() - t0 > limit:
            pytest.fail(f"no sign of {what} after {limit} s")
        time.sleep(0.05)


def _start(args, cwd, env=None, driver=None):
    cmd = [sys.executable, "-m", "coincli", *args] if driver is None else \
        [sys.executable, "-c", driver, *args]
    return subprocess.Popen(cmd, cwd=cwd, env=env, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, start_new_session=True)


def _finish(p, sig, seed: bool, tmp_path):
    """The run's end after ``sig``: the code, one line (with the seed when drawn), nothing of
    the session alive, no temporary file."""
    try:
        out, err = p.communicate(timeout=30)
    finally:
        if p.poll() is None:
            os.killpg(p.pid, signal.SIGKILL)
            p.wait()
    assert p.returncode == CODE[sig], (p.returncode, err[-2000:])
    assert err.count("\n") == 1 and err.startswith(f"coin: error: {WORDS[sig]}"), err[-2000:]
    assert "Traceback" not in err and "BrokenPipe" not in err
    assert bool(SEED.search(err)) == seed, err
    t0 = time.monotonic()
    while _alive_in_session(p.pid) and time.monotonic() - t0 < 10:
        time.sleep(0.05)
    assert _alive_in_session(p.pid) == []
    assert [f for f in os.listdir(tmp_path) if f.endswith(".tmp")] == []
    return out


def _at_work(p, ticks: int = 10):
    """Two workers, each having used ``ticks`` clock ticks of CPU (simulating)."""
    def ready():
        kids = _children(p.pid)
        stats = [_stat(k) for k in kids]
        return len(kids) >= 2 and all(s is not None and s[2] >= ticks for s in stats)
    return ready


BOUNCE = {
    "simulate": ["simulate", "--landing", "bounce", "-n", "2000", "--xi", "0.577", "-j", "2"],
    "design": ["design", "-p", "1/3", "--landing", "bounce", "-j", "2", "--no-table"],
    "plot sides": ["plot", "sides", "--landing", "bounce", "-j", "2", "--out", "s.png"],
}


@pytest.mark.parametrize("sig", [TERM, HUP], ids=["TERM", "HUP"])
@pytest.mark.parametrize("command", list(BOUNCE))
def test_a_signal_ends_every_worker_running_command_cleanly(command, sig, tmp_path):
    """The pool is terminated (no orphan prints BrokenPipeError tracebacks), one line with the
    drawn seed, 143/129, no temporary figure file."""
    from coincli.core.bounce.runs import default_jobs

    if default_jobs() < 2:
        pytest.skip("needs two cores (--jobs is capped at the cores)")
    pytest.importorskip("mujoco")
    p = _start(BOUNCE[command], tmp_path)
    _wait_for(_at_work(p), p, "two workers at work")
    p.send_signal(sig)
    assert _finish(p, sig, True, tmp_path) == ""
    assert os.listdir(tmp_path) == []


def test_workers_die_with_a_killed_parent(tmp_path):
    """SIGKILL cannot be handled: the kernel ends the workers (PR_SET_PDEATHSIG) at once."""
    from coincli.core.bounce.runs import default_jobs

    if default_jobs() < 2:
        pytest.skip("needs two cores")
    pytest.importorskip("mujoco")
    p = _start(BOUNCE["simulate"] + ["--seed", "1"], tmp_path)
    try:
        _wait_for(_at_work(p), p, "two workers at work")
        kids = _children(p.pid)
        p.kill()
        p.wait(timeout=10)
        t0 = time.monotonic()
        while _alive_in_session(p.pid) and time.monotonic() - t0 < 10:
            time.sleep(0.05)
        assert _alive_in_session(p.pid) == []
        assert kids and all(_stat(k) is None or _stat(k)[0] in "ZX" for k in kids)
        assert p.stderr.read() == ""  # no traceback from the workers either
    finally:
        if _alive_in_session(p.pid):
            os.killpg(p.pid, signal.SIGKILL)


@pytest.mark.parametrize("sig", [TERM, HUP], ids=["TERM", "HUP"])
def test_a_signal_while_book_streams_its_out_file_removes_the_temporary(sig, tmp_path):
    """The issue's case: 10^6 rows streamed into .b.json.xxxx.tmp when the signal comes."""
    (tmp_path / "b.json").write_text("old\n")
    p = _start(["book", "--moments", "1,2,3", "--spin", "1,2,3", "--times", "0:999999:1", "-f",
                "json", "--out", "b.json"], tmp_path)
    _wait_for(lambda: any(f.endswith(".tmp") for f in os.listdir(tmp_path)), p,
              "the temporary file")
    p.send_signal(sig)
    _finish(p, sig, False, tmp_path)
    assert (tmp_path / "b.json").read_text() == "old\n"  # the old file, untouched


# A signal at the worst moment of every command that writes a file: sent by the process to
# itself while the file is being written (at the fsync of the temporary file), through the
# console script's own entry point.
DRIVER = """
import os, signal, sys
sig = int(os.environ["COIN_TEST_SIGNAL"])
real = os.fsync
def fsync(fd):
    os.fsync = real
    os.kill(os.getpid(), sig)
    real(fd)
os.fsync = fsync
sys.argv = ["coin", *sys.argv[1:]]
from coincli._entry import main
main()
"""

WRITERS = {
    "plot psi": (["plot", "psi", "--xi", "0.5", "--out", "f.png"], False),
    "phase": (["phase", "--xi", "0.5", "--out", "f.svg"], False),
    "book figure": (["book", "--size", "200x150x30", "--spin", "0.1,8,0.1", "--out", "f.pdf"],
                    False),
    "book --toss": (["book", "--size", "200x150x30", "--spin", "0.1,8,0.1", "--toss",
                     "--tosses", "50", "-f", "csv", "--out", "f.csv"], True),
    "simulate --trajectory": (["toss", "--landing", "bounce", "--xi", "0.577", "--psi", "30",
                               "--u", "2", "--omega", "40", "--trajectory", "f.csv", "-q"],
                              False),
}


@pytest.mark.parametrize("name", list(WRITERS))
def test_a_signal_while_any_file_is_written_leaves_the_old_file(name, tmp_path):
    args, seeded = WRITERS[name]
    if "bounce" in args:
        pytest.importorskip("mujoco")
    sig = (TERM, HUP)[list(WRITERS).index(name) % 2]
    target = tmp_path / args[args.index("--out" if "--out" in args else "--trajectory") + 1]
    target.write_bytes(b"old")
    env = {**os.environ, "COIN_TEST_SIGNAL": str(int(sig))}
    p = _start(args, tmp_path, env=env, driver=DRIVER)
    _finish(p, sig, seeded, tmp_path)
    assert target.read_bytes() == b"old"
    assert sorted(os.listdir(tmp_path)) == [target.name]


def test_the_library_installs_no_signal_handler():
    """Only the command line catches SIGTERM and SIGHUP; importing coincli.api (and calling
    it) leaves a program's handlers as they were, and a run puts back what it replaced."""
    script = """
import signal
before = {s: signal.getsignal(s) for s in (signal.SIGTERM, signal.SIGHUP, signal.SIGINT)}
import coincli, coincli.api
coincli.api.fair()
assert {s: signal.getsignal(s) for s in before} == before, "import or api changed a handler"
from coincli.cli import run
import contextlib, io
with contextlib.redirect_stdout(io.StringIO()):
    assert run(["fair", "-q"]) == 0
assert {s: signal.getsignal(s) for s in before} == before, "run() left a handler"
"""
    r = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                       timeout=60)
    assert (r.returncode, r.stderr) == (0, "")


# --------------------------------------------------------------------------- item 13: --jobs


@pytest.mark.slow
def test_jobs_beyond_the_cores_are_capped_with_a_note(coin, monkeypatch):
    """--jobs 1024 on a machine of 2 cores ran 1024 workers; now the cores, said in a note, and
    the same bytes as --jobs 2 (the results never depend on the workers)."""
    pytest.importorskip("mujoco")
    monkeypatch.setattr(os, "sched_getaffinity", lambda pid: {0, 1}, raising=False)
    run = ["simulate", "--landing", "bounce", "-n", "16", "--xi", "0.577", "--seed", "3", "-f",
           "csv"]
    code, out, err = coin(*run, "--jobs", "1024")
    assert (code, err) == (0, "coin: note: --jobs 1024 capped at 2, the cores this process may "
                              "use\n")
    assert coin(*run, "--jobs", "2") == (0, out, "")
    from coincli.core.bounce.runs import capped_jobs

    assert [capped_jobs(j) for j in (1, 2, 3, 1024)] == [1, 2, 2, 2]


def test_jobs_1024_starts_no_more_workers_than_cores(tmp_path):
    from coincli.core.bounce.runs import default_jobs

    pytest.importorskip("mujoco")
    p = _start(BOUNCE["simulate"][:-1] + ["1024"], tmp_path)
    try:
        _wait_for(lambda: len(_children(p.pid)) >= min(2, default_jobs()), p, "the workers")
        most = 0
        for _ in range(10):  # the pool is complete once the first worker is at work
            most = max(most, len(_children(p.pid)))
            time.sleep(0.05)
        p.send_signal(TERM)
        err = p.communicate(timeout=30)[1]
    finally:
        if p.poll() is None:
            os.killpg(p.pid, signal.SIGKILL)
            p.wait()
    assert most <= default_jobs()
    assert err.splitlines()[0] == (f"coin: note: --jobs 1024 capped at {default_jobs()}, the "
                                   "cores this process may use")
    assert p.returncode == 143


def test_the_exit_codes_are_128_plus_the_signal():
    from coincli.errors import ExitCode

    assert (ExitCode.HUNG_UP, ExitCode.INTERRUPTED, ExitCode.TERMINATED) == (
        128 + signal.SIGHUP, 128 + signal.SIGINT, 128 + signal.SIGTERM) == (129, 130, 143)
