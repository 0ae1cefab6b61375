"""Speed of ``coin check`` and ``coin fit``: start-up against the imports their answers need,
and files of 10^5 experiments (time and peak memory).

Run from the repository root in the development environment (several minutes):

    python benchmarks/bench_stats.py            # writes its section of docs/performance.md
    python benchmarks/bench_stats.py --quick    # fewer rounds, 10^4-row files; print only

How it runs, as a user gets it: the package is built and installed (``pip install --no-deps
--target``, not editable, bytecode compiled) into a temporary directory put first on
PYTHONPATH, so the children import that copy (checked) with its ``.pyc`` files, and the
dependencies of the current environment.  Each case is run alternately with its floor, so
both see the same machine load; figures are medians of CPU time (user + system of the child,
which a loaded machine stretches less than wall time), wall time beside them.

Floors: ``check`` needs typer, numpy and scipy.special (binomial tails, beta quantiles,
chi-square tails); ``fit`` the same plus a one-dimensional optimizer, written in Python in
coincli.core._numerics.roots (a run of ``import scipy.optimize`` is timed beside it to show what
it would cost).  Aim: each command at most 1.2x its floor.

Files: 10^5 experiments of 100 tosses each (4 rows in 5 with heads, sides and tails, 1 in 5
with sides and n), drawn from psi ~ normal(90, 18) deg, once with 10 distinct coins and once
with every row a different coin (xi uniform on [0.05, 2]); ``coin fit FILE --format csv`` and
``coin plot sides --data FILE``.  Peak memory is the child's maximum resident set size.
"""

from __future__ import annotations

import argparse
import math
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import _report  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
AIM = 1.2


def install(where: Path) -> Path:
    """A non-editable copy of the package in ``where`` (bytecode compiled); its directory."""
    target = where / "site"
    subprocess.run([sys.executable, "-m", "pip", "install", "-q", "--no-deps", "--no-compile",
                    "--target", str(target), str(ROOT)], check=True)
    subprocess.run([sys.executable, "-m", "compileall", "-q", str(target / "coincli")],
                   check=True)
    return target


def environment(target: Path) -> dict:
    env = {k: v for k, v in os.environ.items()
           if k not in ("PYTHONDONTWRITEBYTECODE", "NO_COLOR", "PYTHONPYCACHEPREFIX")}
    env["PYTHONPATH"] = str(target) + os.pathsep + env.get("PYTHONPATH", "")
    env["COIN_BENCH_DIR"] = str(target.parent)
    return env


def run_once(argv, env) -> tuple[float, float, int]:
    """(wall s, CPU s, peak resident KiB) of one run, output discarded.  The children run in
    the temporary directory: ``python -c`` puts its working directory first on sys.path, and
    the repository's own coincli must not be the one imported."""
    t0 = time.perf_counter()
    p = subprocess.Popen(argv, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, env=env,
                         cwd=env["COIN_BENCH_DIR"])
    err = p.stderr.read()
    _, status, usage = os.wait4(p.pid, 0)
    p.returncode = os.waitstatus_to_exitcode(status)
    wall = time.perf_counter() - t0
    if p.returncode != 0:
        raise SystemExit(f"{' '.join(argv)} failed ({p.returncode}): {err.decode()}")
    return wall, usage.ru_utime + usage.ru_stime, usage.ru_maxrss


def interleaved(cases: dict[str, list[str]], env, rounds: int):
    """Every case ``rounds`` times, round-robin, after one warm-up run each:
    {name: (median wall, median CPU, peak KiB)}."""
    out = {k: ([], [], []) for k in cases}
    for argv in cases.values():
        run_once(argv, env)
    for i in range(rounds):
        for k, argv in cases.items():
            for acc, v in zip(out[k], run_once(argv, env), strict=True):
                acc.append(v)
        print(f"  round {i + 1}/{rounds}", file=sys.stderr, end="\r")
    print(file=sys.stderr)
    return {k: (_report.median(w), _report.median(c), max(m)) for k, (w, c, m) in out.items()}


def write_files(where: Path, rows: int) -> dict[str, Path]:
    """The two experiment files (seeded: the same bytes on every run)."""
    import numpy as np

    from coincli.core.averages import marginal
    from coincli.core.densities import Normal

    out = {}
    dens = Normal(math.pi / 2, math.radians(18))
    for kind in ("10 coins", "every row a different coin"):
        rng = np.random.default_rng(2024)
        if kind == "10 coins":
            xi = np.repeat(np.linspace(0.1, 1.5, 10), rows // 10 + 1)[:rows]
        else:
            xi = rng.uniform(0.05, 2.0, rows)
        ux, inv = np.unique(xi, return_inverse=True)
        p = np.stack(marginal(ux, dens), axis=1)[inv.ravel()]
        p /= p.sum(axis=1, keepdims=True)
        c = np.array([rng.multinomial(100, pp) for pp in p])
        lines = ["label,xi,heads,sides,tails,n"]
        for i in range(rows):
            x = float(xi[i])
            lines.append(f"r{i},{x!r},,{c[i, 1]},,100" if i % 5 == 4 else
                         f"r{i},{x!r},{c[i, 0]},{c[i, 1]},{c[i, 2]},")
        path = where / f"{kind.split()[0]}.csv"
        path.write_text("\n".join(lines) + "\n")
        out[kind] = path
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--rounds", type=int, default=15, help="start-up runs per case (15)")
    ap.add_argument("--file-rounds", type=int, default=3, help="runs of each file case (3)")
    ap.add_argument("--rows", type=int, default=100_000, help="experiments a file (10^5)")
    ap.add_argument("--quick", action="store_true", help="5 and 1 rounds, 10^4 rows, print only")
    ap.add_argument("--no-write", action="store_true", help="do not touch docs/performance.md")
    args = ap.parse_args(argv)
    if args.quick:
        args.rounds, args.file_rounds, args.rows, args.no_write = 5, 1, 10_000, True
    where = _report.machine()
    tmp = Path(tempfile.mkdtemp(prefix="coin-bench-stats-"))
    try:
        target = install(tmp)
        env = environment(target)
        got = subprocess.run([sys.executable, "-c", "import coincli; print(coincli.__file__)"],
                             env=env, capture_output=True, text=True, check=True,
                             cwd=tmp).stdout.strip()
        if not got.startswith(str(target)):
            raise SystemExit(f"the children import {got}, not the installed copy")
        coin = [str(Path(sys.executable).with_name("coin"))]
        if not Path(coin[0]).exists():
            coin = [sys.executable, "-m", "coincli"]
        py = sys.executable
        tosses = str(ROOT / "tests" / "data" / "tosses.csv")
        floor = "import typer, numpy, scipy.special"
        cases = {
            'python -c "import typer"': [py, "-c", "import typer"],
            f'python -c "{floor}"': [py, "-c", floor],
            f'python -c "{floor}, scipy.optimize"': [py, "-c", floor + ", scipy.optimize"],
            "coin check --xi 0.5 --heads 30 --sides 30 --tails 30":
                [*coin, "check", "--xi", "0.5", "--heads", "30", "--sides", "30", "--tails",
                 "30"],
            "coin check --xi 0.583 --sides 33 -n 100 --format csv":
                [*coin, "check", "--xi", "0.583", "--sides", "33", "-n", "100", "--format",
                 "csv"],
            "coin fit tests/data/tosses.csv": [*coin, "fit", tosses],
            "coin fit tests/data/tosses.csv --format csv": [*coin, "fit", tosses, "--format",
                                                           "csv"],
        }
        print(f"start-up, {args.rounds} rounds", file=sys.stderr)
        st = interleaved(cases, env, args.rounds)
        files = write_files(tmp, args.rows)
        fcases = {}
        for kind, path in files.items():
            fcases[f"coin fit FILE --format csv ({kind})"] = [*coin, "fit", str(path),
                                                              "--format", "csv"]
        for kind, path in files.items():
            fcases[f"coin fit FILE --no-spread --format csv ({kind})"] = [
                *coin, "fit", str(path), "--no-spread", "--format", "csv"]
        fcases["coin plot sides --data FILE --terminal (every row a different coin)"] = [
            *coin, "plot", "sides", "--data", str(files["every row a different coin"]),
            "--terminal"]
        fcases["coin plot sides --data FILE --out sides.png (every row a different coin)"] = [
            *coin, "plot", "sides", "--data", str(files["every row a different coin"]),
            "--out", str(tmp / "sides.png")]
        print(f"files of {args.rows} experiments, {args.file_rounds} rounds", file=sys.stderr)
        ft = interleaved(fcases, env, args.file_rounds)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)

    f_w, f_c, _ = st[f'python -c "{floor}"']
    rows = []
    for name, (w, c, m) in st.items():
        rows.append([f"`{name}`", _report.fmt_time(c), _report.fmt_time(w), f"{c / f_c:.2f}",
                     f"{w / f_w:.2f}", f"{m / 1024:.0f} MiB"])
    chk = st["coin check --xi 0.5 --heads 30 --sides 30 --tails 30"]
    fit = st["coin fit tests/data/tosses.csv"]
    opt = st[f'python -c "{floor}, scipy.optimize"']

    def verdict(r):
        return "met" if r <= AIM else "**missed**"

    n_text = f"10^{len(str(args.rows)) - 1}" if str(args.rows).strip("0") == "1" else \
        f"{args.rows:,}"
    frows = [[f"`{name.split(' (')[0]}`", name.split(" (")[1].rstrip(")"),
              _report.fmt_time(c), _report.fmt_time(w), f"{m / 1024:.0f} MiB"]
             for name, (w, c, m) in ft.items()]
    body = [
        "## `coin check` and `coin fit` (`benchmarks/bench_stats.py`)", "",
        "Command: `python benchmarks/bench_stats.py` (several minutes).  " + where + ".  "
        "The package is installed non-editable (`pip install --no-deps --target`, bytecode "
        "compiled) in a temporary directory that the children import first; CPU time is "
        "user + system of the child.", "",
        f"### Start-up ({args.rounds} runs each, interleaved)", "",
        f"`coin check --xi 0.5 --heads 30 --sides 30 --tails 30` takes **{chk[1] / f_c:.2f}x** "
        f"the CPU time of `python -c \"{floor}\"` ({chk[0] / f_w:.2f}x its wall time); aim "
        f"<= {AIM}: {verdict(chk[1] / f_c)}.  `coin fit tests/data/tosses.csv` takes "
        f"**{fit[1] / f_c:.2f}x** the same floor ({fit[0] / f_w:.2f}x wall): "
        f"{verdict(fit[1] / f_c)}; its optimizer (bounded Brent and Brent's root finder, a "
        f"few dozen lines of Python in `coincli.core._numerics.roots`) imports nothing, where "
        "`import "
        f"scipy.optimize` would add {_report.fmt_time(opt[1] - f_c)} of CPU "
        f"({opt[1] / f_c:.2f}x the floor before any work).  Neither command imports "
        "scipy.stats, scipy.optimize, rich or matplotlib (`tests/test_stats_imports.py`).", "",
        _report.table(["run", "CPU", "wall", "CPU / floor", "wall / floor", "peak memory"],
                      rows),
        f"### Files of {n_text} experiments ({args.file_rounds} runs each, interleaved)", "",
        "100 tosses an experiment; the csv output is about 45 columns by 3 rows an experiment "
        "(geometric, dynamic, psi-spread) plus one row a model.  The exact tests run once per "
        "distinct (counts, chances), the intervals once per distinct (count, n), each model's "
        "chances once per distinct coin; the psi-spread fit costs a few dozen evaluations of "
        "the psi-averaged chances at every distinct coin, which is what a file of distinct "
        "coins pays for.", "",
        _report.table(["run", "file", "CPU", "wall", "peak memory"], frows),
    ]
    text = "\n".join(body)
    print(text)
    if not args.no_write:
        _report.write_section("bench_stats", text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
