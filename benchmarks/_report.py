"""Shared by the benchmarks: statistics, the machine they ran on, and docs/performance.md.

Each benchmark owns one section of ``docs/performance.md`` between two HTML comments
(``<!-- bench_core -->`` ... ``<!-- /bench_core -->``) and rewrites only that section.
"""

from __future__ import annotations

import os
import platform
import statistics
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
DOC = ROOT / "docs" / "performance.md"

HEADER = """# Performance

Measured by the two benchmarks in `benchmarks/`, each against baselines timed in the same run
(interleaved with the measured commands, so both see the same machine load).  Every figure is
a median; ratios are ratios of medians.  Rerun them with the commands given in each section;
they rewrite only their own section of this file.

"""


def median(xs):
    return statistics.median(xs)


def machine() -> str:
    """One line: Python, numpy, CPU count, load average, git commit."""
    try:
        import numpy

        np_version = numpy.__version__
    except ImportError:  # pragma: no cover
        np_version = "absent"
    try:
        commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT,
                                capture_output=True, text=True).stdout.strip()
        dirty = subprocess.run(["git", "status", "--porcelain", "--untracked-files=no"],
                               cwd=ROOT, capture_output=True, text=True).stdout.strip()
        commit = f"{commit}{' + uncommitted changes' if dirty else ''}"
    except OSError:  # pragma: no cover
        commit = "unknown"
    load = ", ".join(f"{v:.2f}" for v in os.getloadavg()) if hasattr(os, "getloadavg") else "?"
    return (f"Python {platform.python_version()}, numpy {np_version}, {platform.machine()}, "
            f"{os.cpu_count()} CPUs, load average {load} at the start, commit {commit}")


def table(header: list[str], rows: list[list[str]]) -> str:
    lines = ["| " + " | ".join(header) + " |", "|" + "|".join("---" for _ in header) + "|"]
    lines += ["| " + " | ".join(r) + " |" for r in rows]
    return "\n".join(lines) + "\n"


def write_section(name: str, body: str, path: Path = DOC) -> None:
    """Replace (or append) the section ``name`` of docs/performance.md with ``body``."""
    start, end = f"<!-- {name} -->", f"<!-- /{name} -->"
    text = path.read_text() if path.exists() else HEADER
    block = f"{start}\n{body.rstrip()}\n{end}"
    if start in text and end in text:
        before, rest = text.split(start, 1)
        _, after = rest.split(end, 1)
        text = before + block + after
    else:
        text = text.rstrip() + "\n\n" + block + "\n"
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text)
    print(f"wrote the {name} section of {path.relative_to(ROOT)}", file=sys.stderr)


def fmt_time(seconds: float) -> str:
    if seconds >= 1:
        return f"{seconds:.2f} s"
    if seconds >= 1e-3:
        return f"{seconds * 1e3:.1f} ms"
    return f"{seconds * 1e6:.1f} µs"


def fmt_rate(per_second: float) -> str:
    if per_second >= 1e6:
        return f"{per_second / 1e6:.2f} M"
    if per_second >= 1e3:
        return f"{per_second / 1e3:.0f} k"
    return f"{per_second:.0f}"
