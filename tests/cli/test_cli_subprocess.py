"""The real ``coin`` process: import budget, pipes, Ctrl-C, exit codes, terminal colour.

Each test starts ``python -m coincli`` (or a tiny wrapper around :func:`coincli.cli.run`) with
the interpreter running the tests, so it works in any venv.  No timing assertions.
"""

from __future__ import annotations

import json
import os
import re
import signal
import subprocess
import sys
import time

import pytest

from cli_helpers import sigint_default

from coincli.core import models

COIN = [sys.executable, "-m", "coincli"]

# The closed-form paths: geometric or dynamic model, single values.
CLOSED_FORM = [
    ["design", "--p-sides", "0.33"],
    ["design", "--p-sides", "1/3", "-q"],
    ["design", "--p-sides", "33%", "--model", "geometric", "--diameter", "0.955in"],
    ["design", "--p-sides", "0.4", "--thickness", "2", "--format", "json"],
    ["table", "--xi", "0.577"],
    ["table", "--quarters", "8", "--format", "csv"],
    ["table", "--coin", "nickel", "--count", "3"],
    ["table", "--xi", "0.577", "--psi", "60"],
    ["table", "--xi", "0.577", "--vs", "psi"],
    ["stack", "--coin", "quarter", "--count", "8"],
    ["stack", "--coin", "quarter", "--p-sides", "1/3"],
    ["stack", "--coin", "quarter", "--p-sides", "1/3", "--model", "geometric", "-q"],
    ["coins"],
    ["fair"],
    ["fair", "--diameter", "30", "-f", "tsv"],
]

_PROBE = r"""
import json, sys
from coincli.cli import run
report = []
for argv in json.loads(sys.argv[1]):
    code = run(argv)
    sys.stdout.flush()
    report.append([argv, code, [m for m in ("numpy", "scipy", "rich") if m in sys.modules]])
print(json.dumps(report), file=sys.stderr)
"""


def _probe(commands):
    """Run ``commands`` one after another in one process, stdout a pipe (not a terminal)."""
    p = subprocess.run([sys.executable, "-c", _PROBE, json.dumps(commands)],
                       capture_output=True, text=True, timeout=120)
    assert p.returncode == 0, p.stderr
    return json.loads(p.stderr.strip().splitlines()[-1]), p.stdout


def test_closed_form_commands_import_neither_numpy_scipy_nor_rich():
    report, out = _probe(CLOSED_FORM)
    assert "\x1b" not in out  # piped: no colour codes
    for argv, code, loaded in report:
        assert code == 0, argv
        assert loaded == [], f"coin {' '.join(argv)} imported {loaded}"


def test_the_probe_sees_numpy_when_it_is_loaded():
    # control: a list of targets is one numpy call; check's tails come from scipy.special
    report, _ = _probe([["design", "-p", "0.1,0.2"],
                        ["check", "--xi", "0.5", "--heads", "3", "--sides", "3", "--tails", "3"]])
    assert report[0][1] == 0 and "numpy" in report[0][2]
    assert report[1][1] == 0 and "scipy" in report[1][2]


def test_importtime_of_the_real_command():
    p = subprocess.run([*COIN[:1], "-X", "importtime", *COIN[1:], "design", "--p-sides", "0.33"],
                       capture_output=True, text=True, timeout=60)
    assert p.returncode == 0, p.stderr
    assert float(p.stdout.split("xi = h/D")[1].split()[0]) == pytest.approx(0.57039, abs=1e-5)
    imported = {line.split("|")[-1].strip().split(".")[0] for line in p.stderr.splitlines()
                if line.startswith("import time:") and "|" in line}
    assert "coincli" in imported and "typer" in imported
    assert not imported & {"numpy", "scipy", "rich"}, imported & {"numpy", "scipy", "rich"}


def test_exit_codes_and_one_line_errors():
    cases = [(["design", "-p", "1/3", "-q"], 0), (["stack", "--p-sides", "1"], 1),
             (["design", "-p", "1.5"], 2), (["design", "-p", "1/3", "--coin", "quater"], 2),
             (["table"], 2)]
    for argv, code in cases:
        p = subprocess.run([*COIN, *argv], capture_output=True, text=True, timeout=60)
        assert p.returncode == code, (argv, p.stderr)
        if code:
            assert p.stdout == "" and p.stderr.count("\n") == 1
            assert p.stderr.startswith("coin: error: ") and "Traceback" not in p.stderr
        else:
            assert float(p.stdout) == models.dynamic_inverse(1 / 3) and p.stderr == ""


def test_quiet_output_feeds_a_shell_variable():
    script = 'xi=$("$@" design --p-sides 1/3 -q) && echo "xi is $xi"'
    p = subprocess.run(["sh", "-c", script, "sh", *COIN], capture_output=True, text=True,
                       timeout=60)
    assert p.returncode == 0 and p.stdout == f"xi is {models.dynamic_inverse(1 / 3)!r}\n"


def test_stdin_batch_through_a_real_pipe():
    seq = "".join(f"{k / 100:.2f}\n" for k in range(1, 100))
    p = subprocess.run([*COIN, "design", "--p-sides", "-", "--format", "csv"], input=seq,
                       capture_output=True, text=True, timeout=60)
    assert p.returncode == 0 and p.stderr == ""
    lines = p.stdout.splitlines()
    assert len(lines) == 100 and lines[0].startswith("p_sides,xi,")
    assert [line.split(",")[0] for line in lines[1:]] == [repr(float(v)) for v in seq.split()]
    p = subprocess.run([*COIN, "design", "--p-sides", "-", "--format", "csv"],
                       input=seq.replace("0.42\n", "0.42x\n"), capture_output=True, text=True,
                       timeout=60)
    assert p.returncode == 2 and p.stdout == ""
    assert p.stderr.startswith("coin: error: stdin line 42:") and p.stderr.count("\n") == 1


def test_head_closing_the_pipe_early_exits_0_quietly():
    # coin table --xi 0.01:100:0.001 | head -3   (10^5 coins, 2*10^5 rows)
    for fmt in ("table", "csv"):
        p = subprocess.Popen([*COIN, "table", "--xi", "0.01:100:0.001", "--format", fmt],
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE)
        head = [p.stdout.readline() for _ in range(3)]
        p.stdout.close()
        err = p.stderr.read()
        assert p.wait(timeout=60) == 0, err
        assert err == b"" and all(head)


def test_a_reader_gone_before_the_first_write_exits_0_quietly():
    for argv in (["table", "--xi", "0.01:100:0.001", "-f", "csv"], ["design", "-p", "0.3"],
                 ["design", "-p", "0.3", "-q"]):
        r, w = os.pipe()
        os.close(r)
        try:
            p = subprocess.run([*COIN, *argv], stdout=w, stderr=subprocess.PIPE, timeout=60)
        finally:
            os.close(w)
        assert (p.returncode, p.stderr) == (0, b""), argv


_WAIT_FOR_STDIN = r"""
import sys
from coincli.cli import run
sys.stderr.write("ready\n")
sys.stderr.flush()
sys.exit(run(sys.argv[1:]))
"""


def test_ctrl_c_exits_130_without_a_traceback():
    # the command blocks reading a stdin batch that never ends; SIGINT arrives while it waits
    p = subprocess.Popen([sys.executable, "-c", _WAIT_FOR_STDIN, "design", "-p", "-"],
                         stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                         preexec_fn=sigint_default)
    try:
        assert p.stderr.readline() == b"ready\n"
        p.stdin.write(b"0.1\n0.2\n")
        p.stdin.flush()
        time.sleep(0.5)  # run() parses its options and blocks in read()
        p.send_signal(signal.SIGINT)
        assert p.wait(timeout=30) == 130
        assert b"Traceback" not in p.stderr.read() and p.stdout.read() == b""
    finally:
        if p.poll() is None:
            p.kill()
        p.stdin.close()


@pytest.mark.slow
@pytest.mark.parametrize("seed", [None, "5"])
def test_an_interrupted_run_reports_the_seed_it_drew(seed):
    """Ctrl-C on a random run that drew its seed: the one line names the seed, so the run can
    be repeated; a seed the user gave is not repeated back."""
    argv = ["simulate", "-n", "100000000", "--xi", "0.577"] + ([] if seed is None else
                                                               ["--seed", seed])
    p = subprocess.Popen([sys.executable, "-c", _WAIT_FOR_STDIN, *argv], stdin=subprocess.DEVNULL,
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                         preexec_fn=sigint_default)
    try:
        assert p.stderr.readline() == b"ready\n"
        time.sleep(1.0)  # well into the tosses (10^8 take tens of seconds)
        p.send_signal(signal.SIGINT)
        assert p.wait(timeout=30) == 130
        err = p.stderr.read().decode()
        assert p.stdout.read() == b""
    finally:
        if p.poll() is None:
            p.kill()
    if seed is None:
        m = re.fullmatch(r"coin: error: interrupted \(seed (\d+): --seed (\d+) repeats this "
                         r"run\)\n", err)
        assert m and m.group(1) == m.group(2), err
    else:
        assert err == "coin: error: interrupted\n"


_INTERRUPT_WHILE_IMPORTING = """
import builtins
real_import = builtins.__import__

def interrupted(name, *args, **kwargs):
    if name == "coincli.cli":  # Ctrl-C lands while typer and click are still being imported
        raise KeyboardInterrupt
    return real_import(name, *args, **kwargs)

builtins.__import__ = interrupted
from coincli._entry import main
main()
"""


def test_ctrl_c_during_start_up_exits_130_without_a_traceback():
    r = subprocess.run([sys.executable, "-c", _INTERRUPT_WHILE_IMPORTING], capture_output=True,
                       timeout=60)
    assert r.returncode == 130
    assert r.stderr == b"coin: error: interrupted\n" and r.stdout == b""


def test_the_console_script_and_python_m_share_the_guarded_entry_point():
    import tomllib
    from pathlib import Path

    root = Path(__file__).resolve().parents[2]
    scripts = tomllib.loads((root / "pyproject.toml").read_text())["project"]["scripts"]
    assert scripts["coin"] == "coincli._entry:main"
    assert "from coincli._entry import main" in (root / "coincli" / "__main__.py").read_text()


@pytest.mark.skipif(not hasattr(os, "openpty"), reason="needs a pseudo-terminal")
def test_terminal_gets_a_rich_table_and_no_color_removes_every_escape():
    def on_a_terminal(extra_env):
        master, slave = os.openpty()
        env = {k: v for k, v in os.environ.items() if k not in ("NO_COLOR", "FORCE_COLOR")}
        env.update({"TERM": "xterm-256color", "COLUMNS": "120", **extra_env})
        try:
            p = subprocess.run([*COIN, "table", "--xi", "0.577"], stdout=slave,
                               stderr=subprocess.PIPE, env=env, timeout=60)
        finally:
            os.close(slave)
        chunks = []
        while True:
            try:
                data = os.read(master, 65536)
            except OSError:  # EIO: the terminal has no more writers
                break
            if not data:
                break
            chunks.append(data)
        os.close(master)
        assert p.returncode == 0, p.stderr
        return b"".join(chunks).decode()

    styled = on_a_terminal({})
    assert "\x1b[" in styled and "geometric" in styled
    plain = on_a_terminal({"NO_COLOR": "1"})
    assert "\x1b" not in plain and "geometric" in plain and "0.499772" in plain


# The real-toss commands need typer and numpy only: one vectorized root refinement (no
# scipy.optimize), truncated normals and the vigorous limit without scipy, and a picture that
# is plain text in a pipe (no rich); never matplotlib without --out; never numpy.ma (numpy 2's
# np.unique imports it: some 30 ms of simulate's start-up, once); never secrets or hashlib
# (numpy.random is imported without them, coincli.core._numerics.backend.numpy_random: 7 ms), never
# numpy.polynomial (the Gauss-Legendre rule is coincli.core.averages' own: 2 ms), never the whole of
# coincli.core.stats.tests (the Wilson interval is coincli.core._numerics.wilson: 2 ms).
TOSS_COMMANDS = [
    ["toss", "--xi", "0.577", "--psi", "90", "--u", "2", "--omega", "40"],
    ["toss", "--xi", "0.577"],
    ["toss", "--coin", "quarter", "--psi", "90", "--u", "240cm/s", "--omega", "38:40:1rev/s",
     "-f", "csv"],
    ["toss", "--xi", "0.577", "--psi", "90", "--u", "2", "--omega", "40", "-q"],
    ["simulate", "--xi", "0.577", "-n", "2000", "--seed", "1"],
    ["simulate", "--xi", "0.577", "-n", "2000", "--seed", "1", "--psi-dist", "cosine", "-f",
     "json"],
    ["simulate", "--xi", "0.577", "-n", "2000", "--seed", "1", "--u", "normal:-5:1", "--omega",
     "uniform:30:40", "--psi-dist", "normal:80:5"],
    ["simulate", "--xi", "0.577", "-n", "50", "--seed", "1", "--psi", "90", "--stream"],
    ["phase", "--cols", "30", "--rows", "8"],
    ["phase", "--cols", "5", "--rows", "5", "-f", "csv"],
]

_TOSS_PROBE = _PROBE.replace('("numpy", "scipy", "rich")',
                             '("scipy", "rich", "matplotlib", "numpy.ma", "secrets", "hashlib", '
                             '"numpy.polynomial", "coincli.core.stats.tests")')


def test_toss_simulate_phase_import_neither_scipy_nor_rich_nor_matplotlib():
    assert _TOSS_PROBE != _PROBE
    p = subprocess.run([sys.executable, "-c", _TOSS_PROBE, json.dumps(TOSS_COMMANDS)],
                       capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stderr
    report = json.loads(p.stderr.strip().splitlines()[-1])
    assert "\x1b" not in p.stdout  # piped: no colour codes
    for argv, code, loaded in report:
        assert code == 0, argv
        assert loaded == [], f"coin {' '.join(argv)} imported {loaded}"


_GC_DURING_THE_COMMAND = """
import gc, sys
import coincli.reports.design as design
from coincli._entry import main

real = design.models.dynamic_inverse

def probe(*args, **kwargs):  # the command's own work: is the collector back?
    sys.stderr.write(f"enabled={gc.isenabled()} frozen={gc.get_freeze_count() > 10000}\\n")
    return real(*args, **kwargs)

design.models.dynamic_inverse = probe
sys.argv = ["coin", "design", "--p-sides", "0.33", "-q"]
main()
"""


def test_the_console_script_pauses_the_collector_only_while_starting():
    # coincli._entry disables gc for the imports and the command's building; the command
    # itself runs with collection on, start-up's objects frozen (never scanned again)
    r = subprocess.run([sys.executable, "-c", _GC_DURING_THE_COMMAND], capture_output=True,
                       timeout=60, text=True)
    assert r.returncode == 0, r.stderr
    assert "enabled=True frozen=True" in r.stderr
