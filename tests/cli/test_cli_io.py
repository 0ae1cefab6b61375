"""Input the user does not control the size of: stdin batches, `coin fit FILE`, psi tables.

Every read is bounded (a byte cap, checked while reading in chunks, never by the size a file
claims: /dev/zero and pipes have none), stops at the first NUL byte or over-long line, and ends
in one line on stderr that names the limit, exit 2 and nothing on stdout.  Also: a leading UTF-8
byte-order mark is accepted, counts beyond 2**53 are refused by name, and an error repeats at
most about 60 characters of what the user typed.

Real processes reading /dev/zero or an endless pipe run under a 2 GB address-space limit and a
timeout, so a regression fails the test instead of taking the machine down.
"""

from __future__ import annotations

import io
import os
import resource
import shutil
import subprocess
import sys

import pytest
from cli_helpers import error
from cli_helpers import ok as _ok

from coincli.io import batches
from coincli.io.batches import MAX_LINE_CHARS, MAX_STDIN_BYTES, MAX_STDIN_LINES


def _error(result, code: int, *words: str, longest: int = 300) -> str:
    """:func:`cli_helpers.error`, at most 300 characters unless told otherwise, and no bug."""
    err = error(result, code, *words, longest=longest)
    assert "internal error" not in err
    return err

COIN = [sys.executable, "-m", "coincli"]
MAX_COUNT = 2**53
LIMIT_AS = 2 * 1024**3


def _limited():
    resource.setrlimit(resource.RLIMIT_AS, (LIMIT_AS, LIMIT_AS))


def _process(argv, stdin=subprocess.DEVNULL, shell_input: str | None = None, timeout=60):
    """Run ``coin argv`` (or a shell pipe into it) under the memory limit; (code, out, err)."""
    if shell_input is not None:
        cmd = f"{shell_input} | {' '.join(COIN + argv)}"
        p = subprocess.run(["/bin/sh", "-c", cmd], capture_output=True, timeout=timeout,
                           preexec_fn=_limited)
    else:
        p = subprocess.run([*COIN, *argv], stdin=stdin, capture_output=True, timeout=timeout,
                           preexec_fn=_limited)
    return p.returncode, p.stdout.decode(), p.stderr.decode("utf-8", "replace")


class _Endless(io.RawIOBase):
    """A stdin that never ends (``unit`` over and over) and counts what was read from it."""

    def __init__(self, unit: bytes):
        self.unit, self.taken = unit, 0

    def readable(self):
        return True

    def readinto(self, b):
        n = len(b)
        reps = -(-n // len(self.unit))
        b[:] = (self.unit * reps)[:n]
        self.taken += n
        return n


def _endless_stdin(unit: bytes):
    raw = _Endless(unit)
    return raw, io.TextIOWrapper(io.BufferedReader(raw))


# --------------------------------------------------------------------------- /dev/zero


needs_dev_zero = pytest.mark.skipif(not os.path.exists("/dev/zero"), reason="no /dev/zero")


@needs_dev_zero
@pytest.mark.parametrize("argv", [["design", "-p", "-"], ["table", "--xi", "-"],
                                  ["design", "-p", "-", "-q"]])
def test_dev_zero_on_a_stdin_batch_stops_at_the_first_nul(argv):
    with open("/dev/zero", "rb") as zero:
        result = _process(argv, stdin=zero)
    _error(result, 2, "stdin line 1 contains a NUL byte")


@needs_dev_zero
@pytest.mark.parametrize("argv, words", [
    (["fit", "-"], ["stdin: contains a NUL byte", "CSV text file"]),
    (["fit", "/dev/zero"], ["/dev/zero: it is a character device, not a regular file"]),
])
def test_fit_of_dev_zero_is_refused_or_stops_at_the_first_nul(argv, words):
    with open("/dev/zero", "rb") as zero:
        result = _process(argv, stdin=zero if argv[-1] == "-" else subprocess.DEVNULL)
    _error(result, 2, *words)


@needs_dev_zero
@pytest.mark.parametrize("argv", [
    ["table", "--xi", "0.5"],
    ["check", "--xi", "0.5", "--heads", "1", "--sides", "1", "--tails", "1"],
    ["simulate", "--xi", "0.5", "--u", "2.4", "--omega", "38", "-n", "10", "--seed", "1"],
    ["design", "-p", "0.3"],
])
def test_a_psi_table_of_dev_zero_is_refused_as_a_device(argv):
    result = _process([*argv, "--psi-dist", "table:/dev/zero"])
    _error(result, 2, "--psi-dist", "psi table '/dev/zero' is a character device, not a regular")


@pytest.mark.slow
@pytest.mark.skipif(shutil.which("yes") is None, reason="no `yes` command")
def test_an_endless_pipe_of_values_stops_at_the_byte_cap():
    # an endless pipe of long lines: coin reads MAX_STDIN_BYTES + 1 bytes, no more, and names
    # the limit (10^7 of these lines would be 400 MB)
    result = _process(["design", "-p", "-", "-q"], shell_input="yes 0." + "1" * 37, timeout=120)
    _error(result, 2, "--p-sides: stdin is larger than 300 MB", f"{MAX_STDIN_LINES} values",
           f"{MAX_STDIN_BYTES} bytes")
    # `yes 0.5` never ends either: it reaches the value limit first (40 MB), and stops there
    result = _process(["design", "-p", "-", "-q"], shell_input="yes 0.5", timeout=120)
    _error(result, 2, f"--p-sides: stdin has more than {MAX_STDIN_LINES} values")


@pytest.mark.slow
def test_too_many_values_are_refused_before_the_lines_are_split():
    # 25 million lines (100 MB, within the byte cap) once took 3.1 GB and 8 s; the line count
    # comes first now, so the refusal fits well inside the 2 GB address-space limit
    data = b"0.5\n" * 25_000_000
    p = subprocess.run([*COIN, "design", "-p", "-", "-q"], input=data, capture_output=True,
                       timeout=120, preexec_fn=_limited)
    _error((p.returncode, p.stdout.decode(), p.stderr.decode()), 2,
           f"--p-sides: stdin has more than {MAX_STDIN_LINES} values")


# --------------------------------------------------------------------------- the caps, in-process


def test_an_endless_stdin_is_read_up_to_the_cap_and_no_further(coin, monkeypatch):
    monkeypatch.setattr(batches, "MAX_STDIN_BYTES", 50_000)
    raw, stdin = _endless_stdin(b"0.5\n")
    _error(coin("table", "--xi", "-", stdin=stdin), 2, "--xi: stdin is larger than 0.05 MB",
           "at most 50000 bytes")
    assert 50_000 < raw.taken <= 50_000 + 2 * batches.READ_CHUNK


@pytest.mark.parametrize("unit, words", [
    (b"\0", ["stdin line 1 contains a NUL byte"]),
    (b"5", [f"stdin line 1 is longer than {MAX_LINE_CHARS} characters"]),
])
def test_an_endless_stdin_stops_at_a_nul_or_an_overlong_line(coin, unit, words):
    raw, stdin = _endless_stdin(unit)
    _error(coin("design", "-p", "-", stdin=stdin), 2, *words)
    assert raw.taken <= 2 * batches.READ_CHUNK + 8192  # a chunk or two, not the whole cap


def test_the_first_bad_line_is_named_even_when_reading_stops_early(coin):
    data = b"0.1\n" + b"9" * 2000 + b"\n0.2\n\0"
    _error(coin("design", "-p", "-", stdin=data), 2,
           f"stdin line 2 is longer than {MAX_LINE_CHARS} characters")
    _error(coin("design", "-p", "-", stdin=b"0.1\n0.2\n\xff\n0.3\0" + b"0" * 3_000_000), 2,
           "stdin line 3 is not UTF-8 text")


def test_the_value_limit_holds_on_both_paths(coin, monkeypatch):
    monkeypatch.setattr(batches, "MAX_STDIN_LINES", 1000)
    plain = "".join(f"{k / 7001!r}\n" for k in range(7000))  # the fast path's size
    assert len(plain) >= batches.FAST_MIN_BYTES
    for data in (plain, "# a comment sends it line by line\n" + plain,
                 " 0.5\n" * 1001, "0.5\n\n# c\n" * 1001):
        _error(coin("design", "-p", "-", "-q", stdin=data), 2,
               "--p-sides: stdin has more than 1000 values")
    # blank and comment lines are not values
    out = _ok(coin("design", "-p", "-", "-q", stdin="\n# c\n \n" * 5000 + "0.5\n" * 1000))
    assert out.count("\n") == 1000


def test_fit_file_cap_names_the_limit(coin, tmp_path, monkeypatch):
    from coincli.io import experiments

    monkeypatch.setattr(experiments, "MAX_FILE_BYTES", 1000)
    path = tmp_path / "big.csv"
    path.write_text("xi,heads,sides,tails\n" + "0.5,1,2,3\n" * 200)
    _error(coin("fit", str(path)), 2, f"{path}: larger than", "at most 1000 bytes")
    _error(coin("fit", "-", stdin=path.read_bytes()), 2, "stdin: larger than",
           "at most 1000 bytes")


def test_psi_table_cap_names_the_limit(coin, tmp_path, monkeypatch):
    from coincli.io import grammar

    monkeypatch.setattr(grammar, "MAX_TABLE_BYTES", 1000)
    path = tmp_path / "psi.csv"
    path.write_text("psi,weight\n" + "".join(f"{k},1.000\n" for k in range(181)))
    _error(coin("table", "--xi", "0.5", "--psi-dist", f"table:{path}"), 2,
           "--psi-dist: psi table", "is larger than 1000 bytes")


# --------------------------------------------------------------------------- over-long lines


def _batch(n: int) -> str:
    return "0.5\n" * n


@pytest.mark.parametrize("long_line", ["5" * 5000, "0." + "5" * 5000, " " * 5000, "#" * 5000])
@pytest.mark.parametrize("lead", ["", pytest.param("# force the per-line path\n",
                                                   marks=pytest.mark.slow)])
def test_a_long_line_is_refused_by_number_on_both_paths(coin, long_line, lead):
    # the fast path (a plain batch of 300000 lines) once echoed the whole line in the error, and
    # accepted '0.555...' (5000 digits), which the per-line path refused
    data = lead + _batch(300_000) + long_line + "\n0.5\n"
    n = 300_001 + (1 if lead else 0)
    _error(coin("design", "-p", "-", "-q", stdin=data), 2,
           f"--p-sides: stdin line {n} is longer than {MAX_LINE_CHARS} characters", longest=120)


def test_a_line_of_exactly_the_limit_is_fine(coin):
    value = "0." + "5" * (MAX_LINE_CHARS - 3)  # plus the newline: 1000 bytes
    out = _ok(coin("design", "-p", "-", "-q", stdin=_batch(10_000) + value + "\n"))
    assert out.count("\n") == 10_001


# --------------------------------------------------------------------------- long user text


@pytest.mark.parametrize("argv", [
    ["design", "-p", "5" * 10_000],
    ["design", "-p", "0.5", "--coin", "q" * 10_000],
    ["table", "--xi", "x" * 10_000],
    ["check", "--xi", "x" * 10_000, "--heads", "1", "--sides", "1", "--tails", "1"],
    ["table", "--xi", "0.5", "--psi-dist", "normal:" + "9" * 10_000 + ":1x"],
])
def test_errors_repeat_at_most_about_60_characters_of_user_text(coin, argv):
    err = _error(coin(*argv), 2, "...", longest=500)
    assert "x" * 61 not in err and "5" * 61 not in err and "q" * 61 not in err
    assert "9" * 61 not in err


def test_a_bad_stdin_value_is_shown_cut_short(coin):
    data = _batch(10_000) + "7" * 900 + "\n"  # on the fast path, out of [0, 1]
    err = _error(coin("design", "-p", "-", stdin=data), 2, "stdin line 10001", "...'",
                 longest=200)
    assert "7" * 61 not in err
    _error(coin("design", "-p", "-", stdin="0.5\n" + "x" * 900 + "\n"), 2, "stdin line 2",
           "...'", longest=200)


def test_clip_message_keeps_short_values_and_escapes():
    from coincli.errors import clip_message as clip

    short = "--coin: unknown coin 'quater'; did you mean 'quarter' or 'paper-quarter'?"
    assert clip(short) == short
    long_nul = "got " + repr("\0" * 500) + ", expected a number"
    clipped = clip(long_nul)
    assert clipped.startswith("got '\\x00") and clipped.endswith("...', expected a number")
    assert len(clipped) < 100
    assert "\\x0'" not in clipped and "\\x...'" not in clipped  # never cut inside an escape
    assert clip("the paper's own " + "word " * 30) == "the paper's own " + "word " * 30


# --------------------------------------------------------------------------- byte-order mark


def test_a_byte_order_mark_on_stdin_is_ignored(coin):
    plain = _ok(coin("design", "-p", "-", "-f", "csv", stdin=b"0.1\n1/3\n"))
    assert _ok(coin("design", "-p", "-", "-f", "csv", stdin=b"\xef\xbb\xbf0.1\n1/3\n")) == plain
    long = _batch(10_000).encode()
    assert _ok(coin("table", "--xi", "-", "-q", stdin=b"\xef\xbb\xbf" + long)) == \
        _ok(coin("table", "--xi", "-", "-q", stdin=long))
    # only at the very start: elsewhere it is text, and an error names its line
    _error(coin("design", "-p", "-", stdin=b"0.1\n\xef\xbb\xbf0.2\n"), 2, "stdin line 2")


def test_a_byte_order_mark_in_fit_input_and_psi_tables_is_ignored(coin, tmp_path):
    csv_text = b"xi,heads,sides,tails\n0.5,10,5,10\n"
    plain = _ok(coin("fit", "-", "-f", "csv", stdin=csv_text))
    assert _ok(coin("fit", "-", "-f", "csv", stdin=b"\xef\xbb\xbf" + csv_text)) == plain
    table = b"psi,weight\n0,1\n90,2\n180,1\n"
    (tmp_path / "a.csv").write_bytes(table)
    (tmp_path / "b.csv").write_bytes(b"\xef\xbb\xbf" + table)
    outs = [_ok(coin("table", "--xi", "0.5", "--psi-dist", f"table:{tmp_path / n}", "-q"))
            for n in ("a.csv", "b.csv")]
    assert outs[0] == outs[1]


# --------------------------------------------------------------------------- counts


CHECK = ["check", "--xi", "0.583"]


_COUNT_RANGE = f"must be a whole number from 0 to {MAX_COUNT} (2**53)"


@pytest.mark.parametrize("argv, words", [
    (["--heads", "99999999999999999999", "--sides", "33", "--tails", "32"],
     ["--heads", _COUNT_RANGE]),
    (["--heads", "35", "--sides", "9" * 5000, "--tails", "32"], ["--sides", _COUNT_RANGE]),
    # -n is the number of tosses, as every command words it (issue 28 item 11)
    (["--sides", "33", "-n", "9" * 5000], [f"-n must be a whole number from 1 to {MAX_COUNT}"]),
    (["--heads", "1", "--sides", "1", "--tails", str(MAX_COUNT + 1)], ["--tails", _COUNT_RANGE]),
])
def test_check_refuses_counts_beyond_2_53_by_name(coin, argv, words):
    err = _error(coin(*CHECK, *argv), 2, *words, longest=200)
    assert "Python" not in err and "C long" not in err and "4300" not in err


def test_check_refuses_a_total_beyond_2_53(coin):
    _error(coin(*CHECK, "--heads", "3", "--sides", str(MAX_COUNT), "--tails", str(MAX_COUNT)),
           2, f"heads + sides + tails = {2 * MAX_COUNT + 3}", f"at most {MAX_COUNT} (2**53)")


def test_check_takes_counts_up_to_2_53(coin):
    out = _ok(coin(*CHECK, "--sides", "3", "-n", str(MAX_COUNT), "-q"))
    assert len(out.split()) == 2


@pytest.mark.parametrize("row, words", [
    ("0.5,99999999999999999999,5,10",
     ["line 2, column 'heads'", "from 0 to 9007199254740992", "got '99999999999999999999'"]),
    ("0.5," + "9" * 5000 + ",5,10",
     ["line 2, column 'heads'", "from 0 to 9007199254740992", "got '999", "...'"]),
    ("0.5,1,2,3\n0.5,9007199254740992,9007199254740992,1",
     ["line 3", f"heads + sides + tails = {2 * MAX_COUNT + 1}", "at most 9007199254740992"]),
])
def test_fit_refuses_counts_beyond_2_53_by_line_and_column(coin, row, words):
    err = _error(coin("fit", "-", stdin=f"xi,heads,sides,tails\n{row}\n"), 2, "stdin ", *words,
                 longest=200)
    assert "Python" not in err and "C long" not in err and "int_max_str_digits" not in err
    if "99999" in row:
        assert f"from 0 to {MAX_COUNT} (2**53)" in err


def test_fit_refuses_n_beyond_2_53(coin):
    _error(coin("fit", "-", stdin="xi,sides,n\n0.5,5," + "9" * 30 + "\n"), 2,
           "stdin line 2, column 'n'", f"from 0 to {MAX_COUNT} (2**53)")


# --------------------------------------------------------------------------- check --xi


@pytest.mark.parametrize("xi", ["inf", "+inf", "nan", "-1", "abc", "-", ""])
def test_check_xi_says_what_is_allowed(coin, xi):
    _error(coin("check", "--xi", xi, "--heads", "1", "--sides", "2", "--tails", "3"), 2,
           "--xi must be a finite number >= 0", f"got {xi!r}")


def test_table_mc_quiet_reports_the_drawn_seed_on_stderr(coin):
    """-q has no room for the note that names the seed: a drawn seed goes to stderr, and it
    repeats the run byte for byte; a seed given is not repeated back."""
    import re

    argv = ["table", "--xi", "0.5", "--psi-dist", "uniform", "--method", "mc", "--tol", "0.01",
            "-q"]
    rc, out, err = coin(*argv)
    assert rc == 0
    m = re.fullmatch(r"coin: seed (\d+) \(--seed \1 repeats this run\)\n", err)
    assert m, err
    assert coin(*argv, "--seed", m.group(1)) == (0, out, "")
