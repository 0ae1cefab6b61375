"""The shared process and I/O layer: tables on real terminals of every width, output formats,
help, files written whole, files read only when regular, closed and odd file descriptors, shell
completion, hostile environments, and batches that stream in flat memory."""

from __future__ import annotations

import csv
import io
import json
import os
import re
import resource
import select
import stat
import subprocess
import sys
import time
from pathlib import Path

import pytest
from cli_helpers import error as _error
from cli_helpers import ok as _ok

COIN = [sys.executable, "-m", "coincli"]
ROOT = Path(__file__).resolve().parents[2]
TOSSES = ROOT / "tests" / "data" / "tosses.csv"
WIDTHS = (40, 60, 80, 100, 200)

# One invocation of every command that prints a table (the reviewer's cases first).
TABLES = {
    "fair": ["fair"],
    "check": ["check", "--xi", "0.583", "--heads", "35", "--sides", "33", "--tails", "32"],
    "toss": ["toss", "--xi", "0.577", "--psi", "90", "--u", "2", "--omega", "38:40:1"],
    "simulate": ["simulate", "--xi", "0.577", "--u", "2.4", "--omega", "38", "--psi", "90",
                 "--n", "2000", "--seed", "7"],
    "fit": ["fit", str(TOSSES)],
    "coins": ["coins"],
    "design": ["design", "-p", "1/3"],
    "design batch": ["design", "-p", "0.1,0.2,0.3"],
    "table": ["table", "--xi", "0.3,0.577", "--all"],
    "stack": ["stack", "--coin", "quarter", "--count", "8"],
}
PLOTS = {"plot psi": ["plot", "psi"], "phase": ["phase", "--cols", "30", "--rows", "10"]}


def _env(**extra):
    env = {k: v for k, v in os.environ.items()
           if k not in ("NO_COLOR", "FORCE_COLOR", "COLUMNS", "LINES")}
    env.update({"TERM": "xterm-256color", **extra})
    return env


def on_a_pty(argv, cols: int, rows: int = 50, env=None, timeout=120) -> tuple[int, str, str]:
    """Run ``coin argv`` with stdout on a real pseudo-terminal of ``cols`` x ``rows`` (set with
    TIOCSWINSZ, as a terminal emulator does; COLUMNS unset); (code, screen text, stderr)."""
    import fcntl
    import struct
    import termios

    master, slave = os.openpty()
    fcntl.ioctl(slave, termios.TIOCSWINSZ, struct.pack("HHHH", rows, cols, 0, 0))
    attrs = termios.tcgetattr(slave)
    attrs[1] &= ~termios.ONLCR  # no \r added to each \n: the bytes as coin wrote them
    termios.tcsetattr(slave, termios.TCSANOW, attrs)
    p = subprocess.Popen([*COIN, *argv], stdout=slave, stderr=subprocess.PIPE,
                         stdin=subprocess.DEVNULL, env=env if env is not None else _env())
    os.close(slave)
    chunks, deadline = [], time.monotonic() + timeout
    while time.monotonic() < deadline:
        ready, _, _ = select.select([master], [], [], 1.0)
        if ready:
            try:
                data = os.read(master, 65536)
            except OSError:  # EIO: no writer left
                break
            if not data:
                break
            chunks.append(data)
        elif p.poll() is not None:
            break
    os.close(master)
    err = p.stderr.read().decode()
    p.wait(timeout=30)
    return p.returncode, b"".join(chunks).decode(), err


_NUMBER = re.compile(r"(?<![\w.])[-+]?(?:\d+\.?\d*|\.\d+)(?:e[-+]?\d+)?%?(?![\w.])")
_ESC = re.compile(r"\x1b\[[0-9;]*m")


def _unbreakable(line: str) -> bool:
    """One word that may not be broken: a number, or text without a '/' to break a web
    address at (coin coins' source addresses run past 40 columns)."""
    words = line.split()
    return len(words) == 1 and not ("/" in words[0] and any(c.isalpha() for c in words[0]))


def _numbers(text: str) -> list[str]:
    return sorted(_NUMBER.findall(_ESC.sub("", text)))


@pytest.mark.slow
@pytest.mark.skipif(not hasattr(os, "openpty"), reason="needs a pseudo-terminal")
@pytest.mark.parametrize("name", list(TABLES))
def test_no_number_is_cut_at_any_terminal_width(name):
    """At every width the terminal shows the same numbers, each whole, as the plain table
    written to a pipe (nothing ellipsized: a number is one word, and words are never cut), and
    no line runs past the width unless it is one word too long for it."""
    argv = TABLES[name]
    piped = subprocess.run([*COIN, *argv], capture_output=True, text=True, env=_env(),
                           timeout=120)
    assert piped.returncode == 0, piped.stderr
    want = set(_numbers(piped.stdout))
    assert want, piped.stdout
    for cols in WIDTHS:
        code, screen, err = on_a_pty(argv, cols)
        assert code == 0 and err == "", (cols, err)
        assert "…" not in screen, (cols, screen)
        # every number whole: the same numbers as in the pipe (a folded table repeats its
        # key column, so each may appear more often), and none cut into a new one
        assert set(_numbers(screen)) == want, (cols, set(_numbers(screen)) ^ want)
        for line in _ESC.sub("", screen).splitlines():
            assert len(line) <= cols or _unbreakable(line), (cols, line)


@pytest.mark.slow
@pytest.mark.skipif(not hasattr(os, "openpty"), reason="needs a pseudo-terminal")
@pytest.mark.parametrize("name", list(PLOTS))
def test_text_plots_fit_the_terminal(name):
    for cols in (40, 80, 200):
        code, screen, err = on_a_pty(PLOTS[name], cols)
        assert code == 0 and err == "", err
        lines = _ESC.sub("", screen).splitlines()
        assert len(lines) > 8
        assert max(map(len, lines)) <= max(cols, 40) + 1, (cols, max(map(len, lines)))


@pytest.mark.slow
@pytest.mark.parametrize("argv", [["plot", "psi"], ["fair"], ["phase", "--cols", "20",
                                                                "--rows", "8"]])
def test_columns_zero_or_garbage_is_ignored(argv):
    for value in ("0", "", "abc", "-5"):
        p = subprocess.run([*COIN, *argv], capture_output=True, text=True,
                           env=_env(COLUMNS=value, LINES=value), timeout=120)
        assert p.returncode == 0 and p.stderr == "" and len(p.stdout.splitlines()) > 3, value


def test_the_layout_folds_wraps_and_never_cuts():
    from coincli.io.table import Column, Result, plain_table

    cols = [Column("model", "model", "text")] + [
        Column(f"c{k}", f"a long header named {'abcdefgh'[k]}") for k in range(8)]
    rows = [("geometric", *(1234.56789 * 10.0**k for k in range(8))),
            ("a model with a long name", *(-0.000123456 for _ in range(8)))]
    res = Result("title words " * 10, cols, rows, note="a note " * 30)
    wide = plain_table(res)
    for width in (20, 30, 40, 60, 80, 100, 200):
        text = plain_table(res, width)
        assert _numbers(text) == _numbers(wide), width
        for line in text.splitlines():
            assert len(line) <= width or _unbreakable(line), (width, line)
        if 40 <= width <= 100:  # folded into blocks, each repeating the key column
            assert text.count("geometric") == text.count("\nmodel") > 1, width
    narrow = plain_table(res, 20)
    assert "1.23457e+10" in narrow and "-0.000123456" in narrow


def test_markdown_is_a_pipe_table_of_the_human_cells(coin):
    out = _ok(coin("table", "--xi", "0.5", "-f", "markdown"))
    lines = out.splitlines()
    assert lines[0] == "| xi = h/D | model | P(heads) | P(sides) | P(tails) |"
    assert lines[1] == "|---:|:---|---:|---:|---:|"
    assert lines[2].startswith("| 0.5 | geometric | 0.276393 | 0.447214 |")
    assert lines[4] == "" and "eq. 11" in lines[5]
    one = _ok(coin("design", "-p", "1/3", "-f", "markdown")).splitlines()
    assert one[0] == "| quantity | value |" and "| xi = h/D | 0.57735 |" in one


def test_markdown_of_a_streamed_batch_has_one_header(coin):
    stdin = "".join(f"{k / 100000!r}\n" for k in range(1, 30001))
    out = _ok(coin("design", "-p", "-", "-f", "markdown", stdin=stdin))
    assert out.count("| P(sides) target |") == 1
    body = [line for line in out.splitlines() if line.startswith("| ")]
    assert len(body) == 30001 and body[-1].startswith("| 0.3 |")


# Every command that takes --format: the arguments it needs.
FORMAT_COMMANDS = {
    "design": ["-p", "0.3,0.4"], "table": ["--xi", "0.5,0.6"], "stack": ["--count", "2,3"],
    "coins": [], "fair": [], "toss": ["--xi", "0.577", "--psi", "90", "--u", "2",
                                      "--omega", "38:39:1"],
    "simulate": ["--xi", "0.577", "--u", "2.4", "--omega", "38", "--psi", "90", "--n", "100",
                 "--seed", "1"],
    "phase": ["--cols", "3", "--rows", "2"],
    "check": ["--xi", "0.5", "--heads", "3", "--sides", "3", "--tails", "3"],
    "fit": [str(TOSSES)],
    "book": ["--size", "235x155x30", "--spin", "0.4,40,0.3", "--times", "0:1:0.5"],
}


def _format_commands():
    import typer

    from coincli.cli import _prepare, app

    root = _prepare(typer.main.get_command(app))
    found = []
    stack = [("", root)]
    while stack:
        path, cmd = stack.pop()
        for name, sub in getattr(cmd, "commands", {}).items():
            stack.append((f"{path} {name}".strip(), sub))
        if any("--format" in getattr(p, "opts", ()) for p in cmd.params):
            found.append(path)
    return sorted(found)


@pytest.mark.slow
def test_every_command_with_format_has_no_headers_and_markdown(coin):
    names = _format_commands()
    assert set(names) <= set(FORMAT_COMMANDS) and len(names) >= 8, names
    for name in names:
        argv = [*name.split(), *FORMAT_COMMANDS[name]]
        full = _ok(coin(*argv, "-f", "csv"))
        assert _ok(coin(*argv, "-f", "csv", "--no-headers")) == full.split("\n", 1)[1], name
        tsv = _ok(coin(*argv, "-f", "tsv"))
        assert _ok(coin(*argv, "-f", "tsv", "--no-headers")) == tsv.split("\n", 1)[1], name
        md = _ok(coin(*argv, "-f", "markdown"))
        assert md.startswith("| ") and "|---" in md or "|:---" in md, name
        _error(coin(*argv, "--no-headers"), 2, "--no-headers", "csv or tsv")
        assert "--no-headers" in _ok(coin(*name.split(), "--help")), name


def test_usage_errors_point_to_the_subcommands_help(coin):
    _error(coin("design", "-p", "1/3", "--bogus"), 2, "(see 'coin design --help')")
    _error(coin("plot", "psi", "--bogus"), 2, "(see 'coin plot psi --help')")
    _error(coin("bogus"), 2, "(see 'coin --help')")


@pytest.mark.slow
def test_help_is_plain_and_fits_80_columns():
    import typer

    from coincli.cli import _prepare, app

    root = _prepare(typer.main.get_command(app))
    paths = [[]] + [[n] for n in root.commands] + [["plot", n] for n in
                                                    root.commands["plot"].commands]
    env = _env(COLUMNS="80")
    for path in paths:
        p = subprocess.run([*COIN, *path, "--help"], capture_output=True, text=True, env=env,
                           timeout=60)
        assert p.returncode == 0 and p.stderr == "", path
        assert "╭" not in p.stdout and "\x1b" not in p.stdout and "\\[" not in p.stdout
        assert max(map(len, p.stdout.splitlines())) <= 80, (path, p.stdout)
        assert "range>" not in p.stdout, path  # no <int range> labels
    design = subprocess.run([*COIN, "design", "--help"], capture_output=True, text=True,
                            env=env).stdout
    assert "  Examples:\n    coin design --p-sides 1/3\n" in design


def test_no_arguments_prints_the_help_on_stdout(coin):
    code, out, err = coin("plot")
    assert code == 2 and out.startswith("Usage: coin plot") and err == ""


# --------------------------------------------------------------------------- files written


def _run(argv, cwd=None, env=None, preexec=None, timeout=180, stdin=subprocess.DEVNULL):
    p = subprocess.run([*COIN, *argv], capture_output=True, text=True, cwd=cwd,
                       env=env if env is not None else _env(), preexec_fn=preexec,
                       timeout=timeout, stdin=stdin)
    return p.returncode, p.stdout, p.stderr


_WROTE = re.compile(r"^coin: wrote .* \(\d+ x \d+ pixels\)\n$")


def _wrote(result) -> bool:
    """Exit 0, nothing on stdout, and on stderr only the line saying which figure was written."""
    code, out, err = result
    return code == 0 and out == "" and bool(_WROTE.match(err)), result


def _one_line(result, code, *words):
    rc, out, err = result
    assert rc == code, (rc, err)
    assert out == "" and err.startswith("coin: error: ") and err.count("\n") == 1, err
    assert "Traceback" not in err
    for w in words:
        assert w in err, (w, err)
    return err


def _small_files():
    resource.setrlimit(resource.RLIMIT_FSIZE, (8192, 8192))


@pytest.mark.slow
@pytest.mark.parametrize("argv", [["plot", "map"], ["plot", "psi"],
                                  ["phase", "--cols", "20", "--rows", "10"]])
def test_a_failed_write_leaves_the_old_file_and_no_temporary(tmp_path, argv):
    pytest.importorskip("matplotlib")
    target = tmp_path / "k.png"
    target.write_bytes(b"KEEP\n")
    os.chmod(target, 0o640)
    result = _run([*argv, "--out", str(target)], preexec=_small_files)
    _one_line(result, 1, "cannot write", "File too large")
    assert target.read_bytes() == b"KEEP\n"
    assert stat.S_IMODE(target.stat().st_mode) == 0o640
    assert sorted(p.name for p in tmp_path.iterdir()) == ["k.png"]


@pytest.mark.slow
def test_a_write_replaces_the_file_whole_and_keeps_its_mode_and_link(tmp_path):
    pytest.importorskip("matplotlib")
    real = tmp_path / "real.png"
    real.write_bytes(b"old")
    os.chmod(real, 0o600)
    link = tmp_path / "link.png"
    link.symlink_to(real.name)
    assert _wrote(_run(["plot", "psi", "--out", str(link)]))[0]
    assert link.is_symlink() and real.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert stat.S_IMODE(real.stat().st_mode) == 0o600
    assert sorted(p.name for p in tmp_path.iterdir()) == ["link.png", "real.png"]


def test_write_atomic_cleans_up_after_any_failure(tmp_path):
    from coincli.io.files import write_atomic

    target = tmp_path / "t.csv"
    target.write_bytes(b"old contents\n")

    def fails(fh):
        fh.write(b"half of the new")
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        write_atomic(target, fails)
    assert target.read_bytes() == b"old contents\n"
    assert [p.name for p in tmp_path.iterdir()] == ["t.csv"]
    assert write_atomic(target, b"new\n") == 4 and target.read_bytes() == b"new\n"
    fresh = tmp_path / "fresh.txt"
    old = os.umask(0o027)
    try:
        write_atomic(fresh, b"x")
    finally:
        os.umask(old)
    assert stat.S_IMODE(fresh.stat().st_mode) == 0o640


@pytest.mark.parametrize("kind", ["fifo", "dir", "device", "socket"])
@pytest.mark.parametrize("argv", [["plot", "psi"], ["phase", "--cols", "5", "--rows", "5"]])
def test_out_must_be_a_regular_file_checked_before_anything_blocks(tmp_path, kind, argv):
    import socket

    pytest.importorskip("matplotlib")
    path = tmp_path / "x.png"
    if kind == "fifo":
        os.mkfifo(path)
    elif kind == "dir":
        path.mkdir()
    elif kind == "socket":
        s = socket.socket(socket.AF_UNIX)
        s.bind(str(path))
    else:
        path.symlink_to("/dev/null")
    words = {"fifo": "a FIFO", "dir": "a directory", "device": "a character device",
             "socket": "a socket"}[kind]
    _one_line(_run([*argv, "--out", str(path)], timeout=60), 2, "--out", words,
              "regular file")


# --------------------------------------------------------------------------- files read


@pytest.mark.parametrize("argv", [
    ["fit", "{}"], ["table", "--xi", "0.5", "--psi-dist", "table:{}"],
    ["plot", "sides", "--data", "{}"], ["design", "-p", "0.3", "--psi-dist", "table:{}"],
])
def test_a_fifo_or_device_is_refused_where_a_file_is_read(tmp_path, argv):
    fifo = tmp_path / "fifo"
    os.mkfifo(fifo)
    for path, words in ((fifo, "a FIFO (named pipe)"), ("/dev/zero", "a character device")):
        _one_line(_run([a.replace("{}", str(path)) for a in argv], timeout=60), 2, words,
                  "not a regular file")


def test_stdin_stays_allowed_where_a_file_is_read():
    data = TOSSES.read_text()
    p = subprocess.run([*COIN, "fit", "-", "-f", "csv"], input=data, capture_output=True,
                       text=True, timeout=120)
    assert p.returncode == 0 and p.stderr == "" and p.stdout.startswith("scope,")


# --------------------------------------------------------------------------- descriptors


def _closed(fd):
    def close():
        os.close(fd)
    return close


@pytest.mark.parametrize("argv", [["design", "-p", "1/3"], ["fair", "-f", "json"],
                                  ["plot", "psi"], ["coins", "-q"], ["--help"]])
def test_a_closed_stdout_is_exit_1_with_one_line(argv):
    p = subprocess.run([*COIN, *argv], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                       preexec_fn=_closed(1), text=True, timeout=120)
    assert p.returncode == 1
    assert p.stderr == "coin: error: standard output is closed; nothing can be written\n"


@pytest.mark.slow
def test_a_closed_stdout_does_not_stop_a_command_that_writes_a_file(tmp_path):
    pytest.importorskip("matplotlib")
    out = tmp_path / "p.png"
    p = subprocess.run([*COIN, "plot", "psi", "--out", str(out)], stderr=subprocess.PIPE,
                       preexec_fn=_closed(1), timeout=120)
    assert p.returncode == 0 and p.stderr.startswith(b"coin: wrote") and out.stat().st_size > 1000


@pytest.mark.parametrize("argv,code", [(["design", "-p", "2"], 2), (["design", "-p", "1/3"], 0),
                                       (["fit", "/nonexistent"], 2), (["bogus"], 2),
                                       (["toss", "--xi", "-1"], 2)])
def test_a_closed_stderr_changes_no_exit_code(argv, code):
    p = subprocess.run([*COIN, *argv], capture_output=False, stdout=subprocess.DEVNULL,
                       preexec_fn=_closed(2), timeout=120)
    assert p.returncode == code


@pytest.mark.parametrize("argv", [["plot", "sides", "--data", "-"], ["design", "-p", "-"],
                                  ["fit", "-"], ["table", "--xi", "-"]])
def test_a_closed_stdin_is_one_usage_line(argv):
    p = subprocess.run([*COIN, *argv], capture_output=True, text=True, preexec_fn=_closed(0),
                       timeout=120)
    _one_line((p.returncode, p.stdout, p.stderr), 2, "standard input")


# --------------------------------------------------------------------------- completion


def _complete(env_extra):
    env = _env(**env_extra)
    return subprocess.run([*COIN], capture_output=True, text=True, env=env, timeout=60)


@pytest.mark.slow
def test_completion_for_bash_zsh_and_fish():
    bash = _complete({"_COIN_COMPLETE": "complete_bash", "COMP_WORDS": "coin des",
                      "COMP_CWORD": "1"})
    assert bash.returncode == 0 and "design" in bash.stdout.split(), bash.stderr
    zsh = _complete({"_COIN_COMPLETE": "complete_zsh", "_TYPER_COMPLETE_ARGS": "coin design --p"})
    assert zsh.returncode == 0 and "--p-sides" in zsh.stdout
    fish = _complete({"_COIN_COMPLETE": "complete_fish", "_TYPER_COMPLETE_FISH_ACTION": "get-args",
                      "_TYPER_COMPLETE_ARGS": "coin design --no-h"})
    assert fish.returncode == 0 and "--no-headers" in fish.stdout
    for shell in ("bash", "zsh", "fish"):
        src = _complete({"_COIN_COMPLETE": f"source_{shell}"})
        assert src.returncode == 0 and "_COIN_COMPLETE" in src.stdout, shell


@pytest.mark.parametrize("value,words", [
    ("complete_bash", ["COMP_WORDS", "source_bash"]),
    ("bogus_shell", ["_COIN_COMPLETE", "bash, zsh, fish", "'bogus_shell'"]),
    ("source_powershellx", ["_COIN_COMPLETE"]), ("nounderscore", ["_COIN_COMPLETE"]),
])
def test_bad_completion_requests_are_one_error_line(value, words):
    p = _complete({"_COIN_COMPLETE": value})
    _one_line((p.returncode, p.stdout, p.stderr), 2, *words)


def test_bash_completion_with_a_bad_word_index_is_one_line():
    p = _complete({"_COIN_COMPLETE": "complete_bash", "COMP_WORDS": "coin", "COMP_CWORD": "x"})
    _one_line((p.returncode, p.stdout, p.stderr), 2, "COMP_CWORD")
    p = _complete({"_COIN_COMPLETE": "complete_bash", "COMP_WORDS": "coin", "COMP_CWORD": "9"})
    assert p.returncode == 0 and p.stderr == ""


# --------------------------------------------------------------------------- environment


def _hostile_envs(tmp_path):
    fifo = tmp_path / "rc-fifo"
    os.mkfifo(fifo)
    bad_rc = tmp_path / "bad.rc"
    bad_rc.write_text("bogus.key: 1\ntext.usetex: True\nfont.size: huge\nsavefig.dpi: x\n")
    locked = tmp_path / "locked"
    locked.mkdir(mode=0o500)
    return {
        "MPLCONFIGDIR=/dev/null": {"MPLCONFIGDIR": "/dev/null"},
        "MPLCONFIGDIR=locked": {"MPLCONFIGDIR": str(locked)},
        "MATPLOTLIBRC=bad keys": {"MATPLOTLIBRC": str(bad_rc)},
        "MATPLOTLIBRC=fifo": {"MATPLOTLIBRC": str(fifo)},
        "MATPLOTLIBRC=/dev/zero": {"MATPLOTLIBRC": "/dev/zero"},
        "MPLBACKEND=bogus": {"MPLBACKEND": "bogus"},
        "HOME unwritable": {"HOME": str(locked), "XDG_CONFIG_HOME": "",
                            "XDG_CACHE_HOME": ""},
        "HOME missing": {"HOME": "/nonexistent/home"},
        "XDG dirs are devices": {"XDG_CONFIG_HOME": "/dev/null",
                                 "XDG_CACHE_HOME": "/dev/null"},
        "PYTHONWARNINGS=error": {"PYTHONWARNINGS": "error"},
        "PYTHONWARNINGS=always": {"PYTHONWARNINGS": "always"},
        "TMPDIR missing": {"TMPDIR": "/nonexistent/tmp"},
        "TERM=dumb": {"TERM": "dumb"}, "TERM unset": {"TERM": ""},
        "NO_COLOR=1": {"NO_COLOR": "1"}, "FORCE_COLOR=1": {"FORCE_COLOR": "1"},
        "COLUMNS, LINES garbage": {"COLUMNS": "x", "LINES": "-1"},
        "COLUMNS huge": {"COLUMNS": "999999999999"},
        "TYPER_USE_RICH=0": {"TYPER_USE_RICH": "0"},
        "OMP/OPENBLAS threads garbage": {"OMP_NUM_THREADS": "abc",
                                         "OPENBLAS_NUM_THREADS": "-3"},
        "LC_ALL=C": {"LC_ALL": "C", "LANG": "C"},
    }


@pytest.mark.slow
def test_hostile_environments_give_clean_output_and_the_same_figure(tmp_path):
    mpl = pytest.importorskip("matplotlib")
    del mpl
    clean = tmp_path / "clean.png"
    assert _wrote(_run(["plot", "psi", "--out", str(clean)]))[0]
    want_table = _run(["table", "--xi", "0.5", "-f", "csv"])
    for name, extra in _hostile_envs(tmp_path).items():
        env = _env(**extra)
        if extra.get("TERM") == "":
            env.pop("TERM")
        fig = tmp_path / "env.png"
        assert _wrote(_run(["plot", "psi", "--out", str(fig)], env=env, cwd=tmp_path))[0], name
        assert fig.read_bytes() == clean.read_bytes(), name
        assert _run(["table", "--xi", "0.5", "-f", "csv"], env=env) == want_table, name
        code, out, err = _run(["simulate", "--xi", "0.5", "--u", "2.4", "--omega", "38",
                               "--psi", "90", "--n", "500", "--seed", "3"], env=env)
        assert code == 0 and err == "", (name, err)


@pytest.mark.slow
def test_a_matplotlibrc_fifo_in_the_working_directory_does_not_block(tmp_path):
    pytest.importorskip("matplotlib")
    os.mkfifo(tmp_path / "matplotlibrc")
    assert _wrote(_run(["plot", "psi", "--out", "x.png"], cwd=tmp_path, timeout=120))[0]


@pytest.mark.slow
def test_a_mathtext_title_is_drawn_as_plain_text(tmp_path):
    pytest.importorskip("matplotlib")
    for title in ("$\\frac{$", "$x^$", "100% of $5", "\\"):
        out = tmp_path / "t.png"
        assert _wrote(_run(["plot", "psi", "--title", title, "--out", str(out)]))[0], title
        assert out.stat().st_size > 1000


def test_python_warnings_never_reach_stderr(coin, monkeypatch):
    import warnings

    from coincli.reports import design

    real = design.values_stream

    def noisy(*a, **k):
        warnings.warn("a library's deprecation", DeprecationWarning, stacklevel=1)
        return real(*a, **k)

    monkeypatch.setattr(design, "values_stream", noisy)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert _ok(coin("design", "-p", "0.3,0.4", "-q")).split() == [
            "0.5095254494944288", "0.7265425280053609"]


# --------------------------------------------------------------------------- streaming


def _peak_kib(argv, stdin_path=None, extra_env=None) -> tuple[int, int]:
    """(exit code, peak resident KiB) of ``coin argv`` run by a fresh wrapper process."""
    probe = ("import resource, subprocess, sys\n"
             "stdin = open(sys.argv[1], 'rb') if sys.argv[1] else subprocess.DEVNULL\n"
             "p = subprocess.run(sys.argv[2:], stdin=stdin, stdout=subprocess.DEVNULL)\n"
             "print(p.returncode, resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)\n")
    env = _env(**(extra_env or {}))
    out = subprocess.run([sys.executable, "-c", probe, str(stdin_path or ""), *COIN, *argv],
                         capture_output=True, text=True, env=env, timeout=900).stdout.split()
    return int(out[0]), int(out[1])


@pytest.mark.slow
def test_batches_stream_in_flat_memory(tmp_path):
    """Memory does not grow with the rows: 600,000 targets (past the spool threshold, 73
    chunks) peak within 10 MiB of 60,000 (8 chunks), and under 100 MiB, in each format."""
    import random

    rng = random.Random(5)
    big, small = tmp_path / "big.txt", tmp_path / "small.txt"
    vals = [repr(rng.random()) for _ in range(600_000)]
    big.write_text("\n".join(vals) + "\n")
    small.write_text("\n".join(vals[:60_000]) + "\n")
    for fmt in ("csv", "json", "table"):
        code_s, base = _peak_kib(["design", "-p", "-", "-f", fmt], small)
        code_b, peak = _peak_kib(["design", "-p", "-", "-f", fmt], big)
        assert code_s == code_b == 0
        assert peak - base < 10 * 1024 and peak < 100 * 1024, (fmt, base, peak)
    code, peak = _peak_kib(["table", "--xi", "0.001:600:0.001", "-f", "json"])
    assert code == 0 and peak < 100 * 1024, peak


@pytest.mark.slow
def test_a_spooled_batch_gives_the_same_bytes(coin, monkeypatch):
    import coincli.io.batches as common

    stdin = "".join(f"{k / 70001!r}\n" for k in range(1, 70001))
    whole = _ok(coin("design", "-p", "-", "-f", "csv", stdin=stdin))
    monkeypatch.setattr(common, "SPOOL_VALUES", 1000)
    assert _ok(coin("design", "-p", "-", "-f", "csv", stdin=stdin)) == whole
    rows = list(csv.DictReader(io.StringIO(whole)))
    assert len(rows) == 70000 and float(rows[-1]["p_sides"]) == 70000 / 70001
    monkeypatch.setattr(common, "_spool_file", lambda: None)  # no temporary directory
    assert _ok(coin("design", "-p", "-", "-f", "csv", stdin=stdin)) == whole


def test_a_bad_line_at_the_end_of_a_long_batch_writes_nothing(coin):
    good = "".join(f"{k / 100001!r}\n" for k in range(1, 100001))
    for bad, *words in (("1.5", "stdin line 100001", "[0, 1]"), ("x", "stdin line 100001"),
                        ("0.5\x00", "stdin line 100001", "NUL")):
        for fmt in ("csv", "json", "table"):
            _error(coin("design", "-p", "-", "-f", fmt, stdin=good + bad + "\n"), 2, *words)


@pytest.mark.slow
def test_streamed_json_and_jsonl_are_the_rows_of_csv(coin):
    stdin = "".join(f"{k / 20001!r}\n" for k in range(1, 20001)) + "1\n0\n"
    rows = list(csv.DictReader(io.StringIO(_ok(coin("design", "-p", "-", "-f", "csv",
                                                    stdin=stdin)))))
    objs = json.loads(_ok(coin("design", "-p", "-", "-f", "json", stdin=stdin)))
    lines = [json.loads(x) for x in _ok(coin("design", "-p", "-", "-f", "jsonl",
                                             stdin=stdin)).splitlines()]
    assert len(rows) == len(objs) == len(lines) == 20002
    for r, o, j in zip(rows[::997] + rows[-2:], objs[::997] + objs[-2:],
                       lines[::997] + lines[-2:], strict=True):
        assert o == j
        for k, v in r.items():
            want = o[k]
            assert (v == "" and want is None) or v == (str(want) if not isinstance(want, float)
                                                       else repr(want)), (k, v, want)


def test_a_range_is_generated_as_the_list_would_be(coin):
    from coincli.io import grammar as parse

    for text in ("0.001:1:0.001", "0.1:0.3:0.1", "0:1e-300:1e-303", "1e300:1.5e300:1e298",
                 "-0:0.5:0.25"):
        want = [x + 0.0 for x in parse.parse_values(text, "--xi", parse.parse_number)]
        rows = list(csv.DictReader(io.StringIO(_ok(coin("table", "--xi", text, "-f", "csv")))))
        assert [float(r["xi"]) for r in rows[::2]] == want, text
        assert [r["model"] for r in rows[:2]] == ["geometric", "dynamic"]


def _naive_rows(cols, sep: str) -> str:
    """The reference for :func:`coincli.io.table.write_rows`: one cell at a time."""
    from coincli.io.table import csv_cell, machine_text

    cols = [c.tolist() if hasattr(c, "tolist") else list(c) for c in cols]
    return "".join(sep.join(csv_cell(machine_text(v), sep) for v in row) + "\n"
                   for row in zip(*cols, strict=True))


def _writer_columns(rng, n: int):
    """Columns of the kinds a batch writes, each as an array and as a list: distinct doubles of
    every magnitude, few distinct values (with and without a missing one), a twin, a constant,
    signed zeros, NaN and infinities, whole numbers and texts with a separator or a quote."""
    import numpy as np

    wide = rng.standard_normal(n) * 10.0 ** rng.integers(-300, 300, n)
    few = rng.choice([0.1, 1 / 3, 2.5e-300, 7e22, -1.0], n)
    with_none = [None if v == -1.0 else v for v in few.tolist()]
    odd = rng.choice([0.0, -0.0, np.nan, np.inf, -np.inf, 0.5], n)
    cols = [wide, few, few.tolist(), with_none, wide.copy(), np.full(n, 24.26), odd,
            odd.tolist(), rng.integers(-5, 5, n), rng.integers(0, 3, n).tolist(),
            rng.choice(["quarter", "a,b", 'say "x"', "100%"], n).tolist(), ["k"] * n,
            np.repeat(rng.standard_normal((n + 1) // 2), 2)[:n]]
    return cols


@pytest.mark.parametrize("n", [0, 1, 3, 64, 1000, pytest.param(20_000, marks=pytest.mark.slow)])
def test_the_batch_writer_writes_what_one_cell_at_a_time_writes(n):
    """Every shortcut of the csv/tsv writer (a constant folded into the separators, a twin's
    text reused, few distinct values formatted once, one %-format a block) gives the bytes of
    formatting each cell on its own: shortest round-trip text, empty for None."""
    import numpy as np

    from coincli.io.table import write_rows

    rng = np.random.default_rng(n)
    cols = _writer_columns(rng, n)
    for sep in (",", "\t"):
        for pick in (cols, cols[:1], cols[1:2], cols[3:4], cols[5:6], cols[6:8], cols[::-1]):
            out = io.StringIO()
            write_rows(out, pick, sep)
            assert out.getvalue() == _naive_rows(pick, sep), (sep, len(pick))
    out = io.StringIO()
    write_rows(out, [cols[0]], "\n", quote=False)  # -q: one value a line
    assert out.getvalue() == "".join(f"{v!r}\n" for v in cols[0].tolist())


_MODULES_PROBE = r"""
import json, sys
from coincli.cli import run
sys.stdout = open("/dev/null", "w")
code = run(json.loads(sys.argv[1]))
loaded = sorted(m for m in sys.modules if m.startswith("coincli.cli.") or m == "decimal")
print(json.dumps([code, loaded]), file=sys.stderr)
"""

COMMAND_RUNS = {  # command module -> one run of each of its commands
    "design": [["design", "-p", "0.33"], ["table", "--xi", "0.577"], ["fair"], ["coins"],
               ["stack", "--coin", "quarter", "--count", "8"]],
    "toss": [["toss", "--xi", "0.577", "--psi", "90", "--u", "2", "--omega", "40"]],
    "check": [["check", "--xi", "0.5", "--heads", "30", "--sides", "30", "--tails", "30"],
              ["fit", str(TOSSES)]],
    "book": [["book", "--size", "235x155x30", "--spin", "0.4,40,0.3", "--times", "0:1:0.5"]],
    "plot": [["plot", "psi"]],
}


@pytest.mark.parametrize("module", sorted(COMMAND_RUNS))
def test_a_run_imports_only_its_own_command_module(module):
    """A command imports its own module (and the shared helpers it uses), not every command's:
    the others cost milliseconds of every start-up.  check and fit never import decimal."""
    from coincli.cli import COMMAND_MODULES

    others = {f"coincli.cli.{m}" for m in COMMAND_MODULES} - {f"coincli.cli.{module}"}
    for argv in COMMAND_RUNS[module]:
        p = subprocess.run([sys.executable, "-c", _MODULES_PROBE, json.dumps(argv)],
                           capture_output=True, text=True, env=_env(), timeout=120)
        code, loaded = json.loads(p.stderr.strip().splitlines()[-1])
        assert code == 0, (argv, p.stderr)
        assert f"coincli.cli.{module}" in loaded, argv
        assert not others & set(loaded), (argv, sorted(others & set(loaded)))
        if module == "check":
            assert "decimal" not in loaded, argv


def test_the_root_help_lists_every_command_in_one_order():
    """The root's help lists every command module's commands, in COMMAND_MODULES' order, however
    the process met them first (a run of one command imports its module alone)."""
    probe = ("import sys\nfrom coincli.cli import run\nsys.stdout = open('/dev/null', 'w')\n"
             "run(['fit', sys.argv[1]])\nrun(['book', '--size', '235x155x30', '--spin', "
             "'0.4,40,0.3', '--times', '0:1'])\nsys.stdout = sys.__stdout__\nrun(['--help'])\n")
    warm = subprocess.run([sys.executable, "-c", probe, str(TOSSES)], capture_output=True,
                          text=True, env=_env(COLUMNS="80"), timeout=120)
    cold = subprocess.run([*COIN, "--help"], capture_output=True, text=True,
                          env=_env(COLUMNS="80"), timeout=60)
    assert warm.returncode == 0 and cold.returncode == 0, warm.stderr
    assert warm.stdout == cold.stdout
    names = [line.split()[0] for line in cold.stdout.split("Commands:")[1].splitlines()
             if line.startswith("  ") and not line.startswith("   ")]
    assert names[:5] == ["design", "table", "stack", "coins", "fair"] and "plot" in names
    assert {"toss", "simulate", "phase", "check", "fit", "book"} <= set(names)


def test_a_command_missing_from_the_module_map_still_runs():
    """COMMAND_MODULE is only a shortcut: a command it does not name (one added later) is found
    by importing every command module, and runs (not the parameterless listing entry)."""
    probe = ("import sys\nfrom coincli import cli\ndel cli.COMMAND_MODULE['fit']\n"
             "sys.exit(cli.run(['fit', sys.argv[1], '-q']))\n")
    p = subprocess.run([sys.executable, "-c", probe, str(TOSSES)], capture_output=True,
                       text=True, env=_env(), timeout=120)
    direct = subprocess.run([*COIN, "fit", str(TOSSES), "-q"], capture_output=True, text=True,
                            env=_env(), timeout=120)
    assert p.returncode == 0 and p.stderr == "", p.stderr
    assert p.stdout == direct.stdout and float(p.stdout) > 0


@pytest.mark.parametrize("group", [[], ["plot"]], ids=["coin", "coin plot"])
def test_command_listings_never_stop_at_an_abbreviation(coin, group):
    """A command's summary is its whole first sentence, wrapped to the width, never cut: never
    'Fig.' or 'eq.' taken for a sentence's end (coin phase read '...(u, omega): Fig.'), never
    '...' at 80 columns."""
    text = _ok(coin(*group, "--help"))
    entries = []  # a command's summary: its first line and the deeper-indented lines after it
    for ln in text.split("Commands:")[1].splitlines():
        if ln.startswith("  ") and not ln.startswith("   "):
            entries.append(ln)
        elif ln.startswith("   ") and entries:
            entries[-1] += " " + ln.strip()
    assert len(entries) >= 4
    for entry in entries:
        last = entry.split()[-1]
        assert not re.fullmatch(r"\(?(Figs?|[Ee]qs?|Sec|e\.g|i\.e|vs)\.", last), entry
        assert "\0" not in entry and not entry.endswith("..."), entry
        assert entry.endswith((".", ")")), entry


@pytest.mark.skipif(not hasattr(os, "openpty"), reason="needs a pseudo-terminal")
def test_a_folded_vs_psi_table_repeats_psi():
    """Each block of `coin table --vs psi` folded at 40 columns names its rows by xi and psi
    (the second block once repeated only xi, the same on every row)."""
    code, screen, err = on_a_pty(["table", "--xi", "0.577", "--vs", "psi", "--psi", "0:180:30"], 40)
    assert code == 0 and err == ""
    blocks = [b for b in _ESC.sub("", screen).split("\n\n") if "P(" in b]
    assert len(blocks) >= 2
    for b in blocks:
        assert "psi" in b.splitlines()[0] or "psi" in b.splitlines()[1], b
