"""Peak memory, CPU time and file size of ``coin book --times ... --out FIGURE`` (issue 28,
item 14), at this checkout against another revision, in one run.

    python benchmarks/bench_book_figure.py [--against af0b52d] [--write]

Each figure (``coin book --moments 1,2,3 --spin 1,2,3 --times 0:N-1:1 --out x.EXT``) is drawn
by a child process of its own, alternately at the two revisions, and measured by ``os.wait4``
(peak resident memory, user + system CPU) and the size of the file written.  The other revision
is taken from git (``git archive``) into a temporary directory; it is run at 10^4 and 10^5
times only unless ``--full`` (10^6 times there peaked at 2.4 GB and failed in Agg).  ``--write``
puts the table into the ``bench_book_figure`` section of docs/performance.md.
"""

from __future__ import annotations

import argparse
import io
import os
import subprocess
import sys
import tarfile
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _report import ROOT, machine, table, write_section  # noqa: E402

ARGV = ["book", "--moments", "1,2,3", "--spin", "1,2,3"]


def measure(pythonpath: str, n: int, ext: str, workdir: Path):
    """(peak MiB, CPU s, file bytes or None, exit code, last stderr line) of one figure."""
    out = workdir / f"x.{ext}"
    if out.exists():
        out.unlink()
    env = {**os.environ, "PYTHONPATH": pythonpath}
    with open(workdir / "err.txt", "w+b") as err:
        p = subprocess.Popen([sys.executable, "-m", "coincli", *ARGV, "--times",
                              f"0:{n - 1}:1", "--out", str(out)], cwd=workdir, env=env,
                             stdout=subprocess.DEVNULL, stderr=err)
        _, status, ru = os.wait4(p.pid, 0)
        p.returncode = os.waitstatus_to_exitcode(status)
        err.seek(0)
        lines = err.read().decode(errors="replace").splitlines()
    size = out.stat().st_size if out.exists() else None
    return ru.ru_maxrss / 1024, ru.ru_utime + ru.ru_stime, size, p.returncode, \
        (lines[-1] if lines else "")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--against", default="af0b52d", help="the revision to compare with")
    ap.add_argument("--full", action="store_true", help="also 10^6 times at that revision")
    ap.add_argument("--write", action="store_true", help="write docs/performance.md's section")
    args = ap.parse_args()
    sizes = [10_000, 100_000, 1_000_000]
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        data = subprocess.run(["git", "-C", str(ROOT), "archive", args.against, "coincli"],
                              capture_output=True, check=True).stdout
        with tarfile.open(fileobj=io.BytesIO(data)) as tar:
            tar.extractall(tmp / "old", filter="data")
        rows = []
        for n in sizes:
            for ext in ("png", "svg"):
                new = measure(str(ROOT), n, ext, tmp)
                old = measure(str(tmp / "old"), n, ext, tmp) if n < 1_000_000 or args.full \
                    else None

                def cells(m):
                    if m is None:
                        return ["not run", "", ""]
                    mib, cpu, size, code, last = m
                    if code != 0:
                        return [f"{mib:.0f} MiB", f"{cpu:.1f} s", f"exit {code}: {last[:60]}"]
                    return [f"{mib:.0f} MiB", f"{cpu:.1f} s", f"{size / 1e6:.2f} MB"]

                rows.append([f"{n:,}", ext, *cells(old), *cells(new)])
                print(" | ".join(rows[-1]), flush=True)
    body = (
        "### `coin book --times ... --out FIGURE`: thinned to the pixel columns\n\n"
        "`python benchmarks/bench_book_figure.py --write` (each figure a child process; peak "
        "resident memory and user + system CPU by `os.wait4`).  "
        f"{machine()}; against {args.against}.\n\n"
        + table(["times", "file", f"peak ({args.against})", "CPU", "file size",
                 "peak (now)", "CPU", "file size"], rows)
        + "\nBefore, every sample was a vertex of the figure: 10^6 times peaked at 2.4 GB and "
        "failed in Agg (\"Exceeded cell block limit\"), and their SVG was 120 MB (issue 28).  "
        "Now a series of more than 8,192 times is reduced, a chunk at a time, to the first, "
        "smallest, largest and last value of each curve in each of 2,048 pixel columns (the "
        "envelope the line covers): memory and file size no longer grow with the times, only "
        "the CPU of computing them does.\n")
    print(body)
    if args.write:
        write_section("bench_book_figure", body)


if __name__ == "__main__":
    main()
