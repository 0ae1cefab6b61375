"""Start-up of ``coin`` commands at this checkout against another revision, in one run.

    python benchmarks/startup_compare.py --against 622b5d1 [--repeats 31]

Both revisions are installed non-editable (``pip install --no-deps --target``) into temporary
directories, with their bytecode cached (a first untimed run of each command writes it), as a
user gets them.  Each command is run alternately at the two revisions and against the floor
``python -c "import typer"``, so that all three see the same machine; the table gives the median
wall and CPU (user + system of the child) time and the ratios new/floor, old/floor and new/old.
"""

from __future__ import annotations

import argparse
import os
import resource
import statistics
import subprocess
import sys
import tarfile
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
COMMANDS = {
    "design --p-sides 0.33": ["design", "--p-sides", "0.33"],
    "table --xi 0.577": ["table", "--xi", "0.577"],
    "--help": ["--help"],
    "design --help": ["design", "--help"],
    "simulate --xi 0.577 -n 1000 --seed 1": ["simulate", "--xi", "0.577", "-n", "1000",
                                            "--seed", "1"],
    "check --xi 0.577 --heads 45 --sides 38 --tails 37": [
        "check", "--xi", "0.577", "--heads", "45", "--sides", "38", "--tails", "37"],
}


def install(source: Path, target: Path) -> list[str]:
    subprocess.run([sys.executable, "-m", "pip", "install", "--quiet", "--no-deps",
                    "--target", str(target), str(source)], check=True,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return [sys.executable, "-c", "import sys; from coincli._entry import main; sys.exit(main())"]


def timed(argv, env) -> tuple[float, float]:
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    subprocess.run(argv, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                   check=False)
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--against", required=True, help="the other revision (a commit)")
    ap.add_argument("--repeats", type=int, default=31)
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        old_src = tmp / "old-src"
        old_src.mkdir()
        archive = subprocess.run(["git", "-C", str(ROOT), "archive", args.against],
                                 check=True, capture_output=True).stdout
        (tmp / "old.tar").write_bytes(archive)
        with tarfile.open(tmp / "old.tar") as tar:
            tar.extractall(old_src, filter="data")
        runs = {}
        for name, src in (("new", ROOT), ("old", old_src)):
            site = tmp / f"{name}-site"
            runs[name] = (install(src, site), {**os.environ, "PYTHONPATH": str(site),
                                               "PYTHONPYCACHEPREFIX": str(tmp / f"{name}-pyc"),
                                               "COLUMNS": "80", "NO_COLOR": "1"})
        floor = ([sys.executable, "-c", "import typer"], {**os.environ})
        print(f"# start-up, median of {args.repeats} interleaved runs (seconds; ratios of "
              "medians)\n")
        print("| command | new wall | old wall | floor wall | new/floor | old/floor | new/old "
              "(wall) | new/old (CPU) |")
        print("|---|---|---|---|---|---|---|---|")
        for label, argv in COMMANDS.items():
            for cmd, env in runs.values():  # bytecode written, caches warm
                timed(cmd + argv, env)
            t = {"new": [], "old": [], "floor": []}
            for _ in range(args.repeats):
                for key in ("new", "old", "floor"):
                    cmd, env = (floor if key == "floor" else
                                (runs[key][0] + argv, runs[key][1]))
                    t[key].append(timed(cmd, env))
            wall = {k: statistics.median(w for w, _ in v) for k, v in t.items()}
            cpu = {k: statistics.median(c for _, c in v) for k, v in t.items()}
            print(f"| `coin {label}` | {wall['new']:.4f} | {wall['old']:.4f} | "
                  f"{wall['floor']:.4f} | {wall['new'] / wall['floor']:.3f} | "
                  f"{wall['old'] / wall['floor']:.3f} | {wall['new'] / wall['old']:.3f} | "
                  f"{cpu['new'] / cpu['old']:.3f} |", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
