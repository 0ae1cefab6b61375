"""Speed of the ``coin`` command: start-up of the closed-form answers, and a 10^6-line batch.

Run from the repository root, in the environment where ``coin`` is installed (a few minutes):

    python benchmarks/bench_cli.py             # writes its section of docs/performance.md
    python benchmarks/bench_cli.py --quick     # 10^5-line batch, fewer repeats; print only

Start-up: each closed-form command (geometric or dynamic model, one value) against
``python -c "import typer"``, the floor for any typer program, run alternately so both see the
same machine; the aim is a ratio of medians <= 1.15 for ``coin design --p-sides 0.33`` (issue
14).  ``coin fit tests/data/tosses.csv`` against its own floor, ``python -c "import typer,
numpy, scipy.special"``; aim <= 1.2.

Help: ``coin --help`` and ``coin design --help`` against ``import typer``; aim <= 1.5x.

Batch: 10^6 targets on stdin (``coin design --p-sides - --format csv`` and ``-q``) against
numpy alone reading the same file with ``np.loadtxt`` and writing with ``np.savetxt``
(``%.17g``, enough digits to read back): once the same 10^6 numbers (one column, what ``-q``
writes), once as many numbers as coin's csv (14 columns; aim <= 1.0x).  ``coin table --xi
0.001:1000:0.001 -f csv`` (10^6 coins, 2 x 10^6 rows) against ``np.savetxt`` of the same
numbers (aim <= 1.2x).

Memory: the peak resident size of each batch (``os.wait4``'s ``ru_maxrss``) for 10^6 and 10^7
targets in every format; aim <= 100 MiB.

``coin`` is a non-editable install: ``pip install --no-deps --target`` of this checkout into a
temporary directory, run through a copy of the console script (``--installed``, the default
when the ``coin`` beside this interpreter is an editable install).

Times are wall-clock medians; CPU time (user + system of the child) is reported beside them
because a loaded machine stretches wall time more than CPU time.  The children write their
bytecode caches to a temporary PYTHONPYCACHEPREFIX (an installed program has its .pyc files).
"""

from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import _report  # noqa: E402

AIM_STARTUP = 1.15
AIM_FIT = 1.2
AIM_HELP = 1.5
AIM_BATCH = 2.0


_INSTALL: list[str] = []


def coin_command() -> list[str]:
    """``coin`` as a user runs it: a non-editable copy of this checkout (see the docstring)."""
    if _INSTALL:
        return _INSTALL
    root = Path(__file__).resolve().parents[1]
    target = os.path.join(_PYCACHE, "site")
    subprocess.run([sys.executable, "-m", "pip", "install", "--quiet", "--no-deps",
                    "--no-compile", "--target", target, str(root)], check=True,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    script = os.path.join(_PYCACHE, "coin")
    with open(script, "w") as f:
        f.write("import sys\nfrom coincli._entry import main\nsys.exit(main())\n")
    ENV["PYTHONPATH"] = target
    _INSTALL[:] = [sys.executable, script]
    return _INSTALL


# Children cache their bytecode as an installed program does (pip compiles on install), in a
# directory of their own: PYTHONDONTWRITEBYTECODE in the caller's environment would otherwise
# make coin recompile its modules on every run while typer's come from site-packages' .pyc.
_PYCACHE = tempfile.mkdtemp(prefix="coin-bench-pycache-")
ENV = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
ENV["PYTHONPYCACHEPREFIX"] = _PYCACHE
ENV.pop("NO_COLOR", None)


PEAK: dict[str, int] = {}  #: the largest resident size seen per argv (KiB)


# The child is started by a small probe process: a child inherits its parent's peak resident
# size at fork (exec does not reset it), and this script holds numpy and arrays.  The probe
# measures the child's wall time, CPU time and peak memory (os.wait4) and prints them.
_PROBE = (
    "import os, subprocess, sys, time\n"
    "stdin = open(sys.argv[1], 'rb') if sys.argv[1] else subprocess.DEVNULL\n"
    "t0 = time.perf_counter()\n"
    "p = subprocess.Popen(sys.argv[2:], stdin=stdin, stdout=subprocess.DEVNULL,\n"
    "                     stderr=subprocess.PIPE)\n"
    "err = p.stderr.read()\n"
    "_, status, ru = os.wait4(p.pid, 0)\n"
    "wall = time.perf_counter() - t0\n"
    "sys.stderr.buffer.write(err)\n"
    "print(os.waitstatus_to_exitcode(status), wall, ru.ru_utime + ru.ru_stime, ru.ru_maxrss)\n"
)


def run_once(argv, stdin_path=None, check=True) -> tuple[float, float]:
    """(wall seconds, CPU seconds) of one run, output discarded; its peak memory goes to PEAK."""
    p = subprocess.run([sys.executable, "-S", "-c", _PROBE, str(stdin_path or ""), *argv],
                       capture_output=True, text=True, env=ENV)
    code, wall, cpu, peak = p.stdout.split()
    key = " ".join(argv)
    PEAK[key] = max(PEAK.get(key, 0), int(peak))
    if check and int(code) != 0:
        raise SystemExit(f"{key} failed ({code}): {p.stderr}")
    return float(wall), float(cpu)


def interleaved(cases: dict[str, list[str]], repeat: int, stdin_paths=None):
    """Run every case ``repeat`` times, round-robin; {name: (wall list, cpu list)}."""
    stdin_paths = stdin_paths or {}
    res = {k: ([], []) for k in cases}
    for k, argv in cases.items():  # warm the disk cache and .pyc files
        run_once(argv, stdin_paths.get(k))
    for i in range(repeat):
        for k, argv in cases.items():
            w, c = run_once(argv, stdin_paths.get(k))
            res[k][0].append(w)
            res[k][1].append(c)
        print(f"  round {i + 1}/{repeat}", file=sys.stderr, end="\r")
    print(file=sys.stderr)
    return {k: (_report.median(w), _report.median(c)) for k, (w, c) in res.items()}


STARTUP = [
    "--help",
    "design --help",
    "design --p-sides 0.33",
    "design --p-sides 1/3 -q",
    "design --p-sides 0.33 --model geometric --format csv",
    "table --xi 0.577",
    "stack --coin quarter --count 8",
    "stack --coin quarter --p-sides 1/3",
    "fair",
    "coins",
]


def startup(repeat: int):
    coin = coin_command()
    py = sys.executable
    cases = {"python -c pass": [py, "-c", "pass"],
             'python -c "import typer"': [py, "-c", "import typer"]}
    cases.update({f"coin {c}": [*coin, *c.split()] for c in STARTUP})
    cases[FIT_FLOOR] = [py, "-c", "import typer, numpy, scipy.special"]
    cases[FIT] = [*coin, "fit", str(Path(__file__).resolve().parents[1] / "tests" / "data" /
                                    "tosses.csv")]
    return interleaved(cases, repeat)


FIT_FLOOR = 'python -c "import typer, numpy, scipy.special"'
FIT = "coin fit tests/data/tosses.csv"


NUMPY_ONE = ("import sys, numpy as np; a = np.loadtxt(sys.stdin.buffer); "
             "np.savetxt(sys.stdout.buffer, a, fmt='%.17g')")
NUMPY_WIDE = ("import sys, numpy as np; a = np.loadtxt(sys.stdin.buffer); "
              "np.savetxt(sys.stdout.buffer, np.column_stack([a] * 14), fmt='%.17g', "
              "delimiter=',')")


NUMPY_TABLE = (
    "import sys, numpy as np\n"
    "from coincli.core import models\n"
    "x = 0.001 + np.arange(10**6) * 0.001\n"
    "g, d = models.geometric(x), models.dynamic(x)\n"
    "cols = [np.repeat(x, 2)] + [np.stack([getattr(g, f), getattr(d, f)], axis=1).ravel()\n"
    "                            for f in ('heads', 'sides', 'tails')]\n"
    "np.savetxt(sys.stdout.buffer, np.column_stack(cols), fmt='%.17g', delimiter=',')\n")


def table_range(repeat: int):
    coin = coin_command()
    cases = {
        "coin table --xi 0.001:1000:0.001 -f csv": [*coin, "table", "--xi", "0.001:1000:0.001",
                                                    "-f", "csv"],
        "numpy: np.savetxt of the same numbers (2 x 10^6 rows, 4 columns)":
            [sys.executable, "-c", NUMPY_TABLE],
    }
    return interleaved(cases, repeat)


MEMORY_FORMATS = ("csv", "tsv", "json", "jsonl", "markdown", "table", "-q")


def memory(sizes):
    """Peak resident size of design -p - and table --xi - over each size, every format."""
    import numpy as np

    coin = coin_command()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for n in sizes:
            path = os.path.join(tmp, f"targets-{n}.txt")
            p = np.random.default_rng(11).uniform(0.0, 1.0, n)
            with open(path, "w") as f:
                for k in range(0, n, 10**6):
                    f.write("\n".join(map(repr, p[k:k + 10**6].tolist())) + "\n")
            # every format of design at 10^6, its csv and json at 10^7 (minutes each on a
            # 2-CPU machine); table's batch (two rows a value) in csv
            cases = [(["design", "--p-sides", "-"], f) for f in
                     (MEMORY_FORMATS if n <= 10**6 else ("csv", "json"))]
            cases.append((["table", "--xi", "-"], "csv" if n > 10**6 else "json"))
            for cmd, fmt in cases:
                if True:
                    argv = [*coin, *cmd, *(["-q"] if fmt == "-q" else ["-f", fmt])]
                    wall, cpu = run_once(argv, path)
                    rows.append([f"{n:.0e}".replace("e+0", "e"), f"`coin {' '.join(cmd)} "
                                 f"{'-q' if fmt == '-q' else '-f ' + fmt}`",
                                 _report.fmt_time(wall), _report.fmt_time(cpu),
                                 f"{PEAK[' '.join(argv)] / 1024:.0f} MiB"])
                    print(f"  memory {n} {cmd[0]} {fmt}: {PEAK[' '.join(argv)] / 1024:.0f} MiB",
                          file=sys.stderr)
    return rows


def batch(n: int, repeat: int):
    import numpy as np

    coin = coin_command()
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "targets.txt")
        p = np.random.default_rng(7).uniform(0.0, 1.0, n)
        with open(path, "w") as f:
            f.write("\n".join(map(repr, p.tolist())) + "\n")
        cases = {
            "coin design --p-sides - --format csv": [*coin, "design", "--p-sides", "-",
                                                     "--format", "csv"],
            "coin design --p-sides - -q": [*coin, "design", "--p-sides", "-", "-q"],
            "numpy: read, write the same numbers (1 column)": [sys.executable, "-c", NUMPY_ONE],
            "numpy: read, write as many numbers as coin's csv (14 columns)":
                [sys.executable, "-c", NUMPY_WIDE],
        }
        with open(path, "rb") as f:
            out = subprocess.run([*coin, "design", "--p-sides", "-", "--format", "csv"],
                                 stdin=f, capture_output=True, check=True, env=ENV).stdout
        sizes = {"input": os.path.getsize(path), "csv": len(out),
                 "rows": out.count(b"\n") - 1}
        del out
        res = interleaved(cases, repeat, dict.fromkeys(cases, path))
    return res, sizes


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--repeat", type=int, default=21, help="start-up runs per command (21)")
    ap.add_argument("--batch-repeat", type=int, default=5, help="runs of each batch case (5)")
    ap.add_argument("-n", type=int, default=10**6, help="batch size (10^6)")
    ap.add_argument("--quick", action="store_true", help="10^5 batch, 7 and 3 repeats, print only")
    ap.add_argument("--no-write", action="store_true", help="do not touch docs/performance.md")
    ap.add_argument("--memory-sizes", default="1000000,10000000",
                    help="batch sizes for the memory table (default 10^6 and 10^7)")
    args = ap.parse_args(argv)
    if args.quick:
        args.repeat, args.batch_repeat, args.n, args.no_write = 7, 3, 10**5, True

    where = _report.machine()
    print(f"start-up, {args.repeat} rounds", file=sys.stderr)
    st = startup(args.repeat)
    print(f"batch of {args.n}, {args.batch_repeat} rounds", file=sys.stderr)
    bt, sizes = batch(args.n, args.batch_repeat)
    print(f"table over 10^6 coins, {args.batch_repeat} rounds", file=sys.stderr)
    tr = table_range(args.batch_repeat)
    print("memory", file=sys.stderr)
    mem = memory([int(v) for v in args.memory_sizes.split(",") if v]) if not args.quick \
        else memory([10**5])

    typer_w, typer_c = st['python -c "import typer"']
    floor_w, floor_c = st.pop(FIT_FLOOR)
    fit_w, fit_c = st.pop(FIT)
    rows = []
    for name, (w, c) in st.items():
        rows.append([f"`{name}`", _report.fmt_time(w), _report.fmt_time(c),
                     f"{w / typer_w:.2f}", f"{c / typer_c:.2f}"])
    frows = [[f"`{name}`", _report.fmt_time(w), _report.fmt_time(c), f"{w / floor_w:.2f}",
              f"{c / floor_c:.2f}"] for name, (w, c) in ((FIT_FLOOR, (floor_w, floor_c)),
                                                         (FIT, (fit_w, fit_c)))]
    head_w = st["coin design --p-sides 0.33"][0] / typer_w
    head_c = st["coin design --p-sides 0.33"][1] / typer_c
    help_w = max(st["coin --help"][0], st["coin design --help"][0]) / typer_w
    help_c = max(st["coin --help"][1], st["coin design --help"][1]) / typer_c
    tab_w, tab_c = tr["coin table --xi 0.001:1000:0.001 -f csv"]
    sav_w, sav_c = tr["numpy: np.savetxt of the same numbers (2 x 10^6 rows, 4 columns)"]
    trows = [[f"`{k}`" if k.startswith("coin") else k, _report.fmt_time(w), _report.fmt_time(c),
              f"{w / sav_w:.2f}", f"{c / sav_c:.2f}"] for k, (w, c) in tr.items()]
    worst = max(float(r[-1].split()[0]) for r in mem)

    one_w, one_c = bt["numpy: read, write the same numbers (1 column)"]
    wide_w, wide_c = bt["numpy: read, write as many numbers as coin's csv (14 columns)"]
    brows = []
    for name, (w, c) in bt.items():
        brows.append([f"`{name}`" if name.startswith("coin") else name,
                      _report.fmt_time(w), _report.fmt_time(c),
                      f"{w / one_w:.2f}", f"{w / wide_w:.2f}"])
    csv_w, csv_c = bt["coin design --p-sides - --format csv"]
    q_w, q_c = bt["coin design --p-sides - -q"]

    def verdict(r, aim):
        return "met" if r <= aim else "**missed**"

    n_text = f"10^{len(str(args.n)) - 1}" if str(args.n).strip("0") == "1" else f"{args.n:,}"
    body = [
        "## The command (`benchmarks/bench_cli.py`)", "",
        "Command: `python benchmarks/bench_cli.py` (a few minutes).  " + where + ".  "
        f"`coin` is `{' '.join(coin_command())}`.", "",
        f"### Start-up of the closed-form answers ({args.repeat} runs each, interleaved)", "",
        f"`coin design --p-sides 0.33` takes **{head_w:.2f}x** the wall time of "
        f"`python -c \"import typer\"` ({head_c:.2f}x its CPU time); aim <= {AIM_STARTUP}: "
        f"{verdict(head_w, AIM_STARTUP)} in wall time, {verdict(head_c, AIM_STARTUP)} in CPU "
        "time.  None of these runs imports numpy, scipy or rich "
        "(checked by `tests/test_cli_subprocess.py`), and each imports only its own command "
        "module (`tests/test_cli_out.py`).", "",
        _report.table(["command", "wall", "CPU", "wall / import typer", "CPU / import typer"],
                      rows),
        f"`coin fit tests/data/tosses.csv` against the imports its answer needs: "
        f"**{fit_c / floor_c:.2f}x** the CPU time of `{FIT_FLOOR}` ({fit_w / floor_w:.2f}x its "
        f"wall time); aim <= {AIM_FIT}: {verdict(fit_c / floor_c, AIM_FIT)} in CPU time, "
        f"{verdict(fit_w / floor_w, AIM_FIT)} in wall time.  Most of the rest is the spread "
        "fit: 57 psi averages (`coincli.core.averages.marginal`, about 0.5 ms each whatever the "
        "number of coins).", "",
        _report.table(["command", "wall", "CPU", "wall / floor", "CPU / floor"], frows),
        f"### A batch of {n_text} targets on stdin ({args.batch_repeat} runs each, interleaved)",
        "",
        f"Input {sizes['input'] / 1e6:.1f} MB ({n_text} random doubles, 17 significant digits); "
        f"coin's csv is {sizes['rows']:,} rows, {sizes['csv'] / 1e6:.0f} MB "
        "(14 columns, every float the shortest text that reads back).", "",
        _report.table(["run", "wall", "CPU", "/ numpy 1 column", "/ numpy 14 columns"], brows),
        f"- `-q` (reads {n_text} numbers, writes {n_text}) against numpy reading and writing the "
        f"same numbers: **{q_w / one_w:.2f}x** wall ({q_c / one_c:.2f}x CPU); aim <= "
        f"{AIM_BATCH:g}: {verdict(q_w / one_w, AIM_BATCH)}.",
        f"- `--format csv` against numpy writing as many numbers (14 columns): "
        f"**{csv_w / wide_w:.2f}x** wall ({csv_c / wide_c:.2f}x CPU); aim <= 1.0: "
        f"{verdict(csv_w / wide_w, 1.0)} in wall time, {verdict(csv_c / wide_c, 1.0)} in CPU "
        f"time.  (Against numpy reading and writing only the {n_text} targets it is "
        f"{csv_w / one_w:.1f}x: the csv holds 14 numbers a row.)  Writing a double as its "
        "shortest round-trip text (`repr`, about 0.45 µs each) is most of the time, so coin "
        "does it as seldom as the columns allow: a constant column is part of the row's "
        "format, a column equal to another (P(tails) = P(heads)) reuses its text, a column of "
        "few values (the nearest stack's chances) formats each value once; then one "
        "`%`-format, repeated for 8192 rows, is applied once to the block's cells laid out row "
        "by row: no Python work per row or per cell.", "",
        f"### Help ({args.repeat} runs each, interleaved, in the start-up table)", "",
        f"`coin --help` and `coin design --help`: at most **{help_w:.2f}x** `import typer` in "
        f"wall time, {help_c:.2f}x in CPU time (aim <= {AIM_HELP}: {verdict(help_w, AIM_HELP)} "
        f"in wall time, {verdict(help_c, AIM_HELP)} in CPU time); plain click help, no rich.  "
        "The root's help lists the commands from their names and help alone, without turning "
        "every command's parameters into click options.", "",
        f"### A table over 10^6 coins ({args.batch_repeat} runs each, interleaved)", "",
        _report.table(["run", "wall", "CPU", "wall / np.savetxt", "CPU / np.savetxt"], trows),
        f"- `coin table --xi 0.001:1000:0.001 -f csv` against `np.savetxt` of the same numbers: "
        f"**{tab_w / sav_w:.2f}x** wall ({tab_c / sav_c:.2f}x CPU); aim <= 1.2: "
        f"{verdict(tab_w / sav_w, 1.2)}.  The range is generated a chunk at a time from arrays "
        "(no value is parsed back from its text), the models run on arrays, and xi, repeated "
        "on each model's row, is formatted once.", "",
        "### Peak memory of the batches (one run each)", "",
        f"Largest peak: **{worst:.0f} MiB** (aim <= 100 MiB: {verdict(worst, 100)}).  Input is "
        "read and checked a piece at a time (past 2^19 values it waits in an anonymous "
        "temporary file, as doubles), then computed and written 8192 rows at a time; json is "
        "written as an array a chunk at a time.", "",
        _report.table(["values", "run", "wall", "CPU", "peak memory"], mem),
    ]
    text = "\n".join(body)
    print(text)
    if not args.no_write:
        _report.write_section("bench_cli", text)
    shutil.rmtree(_PYCACHE, ignore_errors=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
