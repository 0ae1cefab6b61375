"""Speed of the root-found inverses and of the psi averages they call, against another commit.

    python benchmarks/bench_inverses.py                 # this checkout, one run, a table
    python benchmarks/bench_inverses.py --against REV   # REV and this checkout, interleaved

``--against`` extracts ``coincli/`` of REV (``git archive``) to a temporary directory and runs
the same cases there and here in alternation, three times each, in separate processes; the
table gives the medians and their ratio (after / before), which a shared, noisy machine affects
far less than the times themselves.  Each time is the best of 3 repeats of a timeit loop.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import statistics
import subprocess
import sys
import tarfile
import tempfile
import timeit
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def cases():
    import numpy as np

    from coincli.core import averages as A
    from coincli.core.densities import Normal

    d, nn = Normal(), Normal(math.radians(30), math.radians(0.05))
    xs = np.random.default_rng(1).uniform(0, 3, 20000)
    ps = np.random.default_rng(2).uniform(0, 1, 200)
    return {
        "marginal(0.577, normal)": lambda: A.marginal(0.577, d),
        "marginal(0.577, normal:30:0.05)": lambda: A.marginal(0.577, nn),
        "marginal(2e4 xi, normal)": lambda: A.marginal(xs, d),
        "marginal(2e4 xi, normal:30:0.05)": lambda: A.marginal(xs, nn),
        "marginal_inverse(1/3, normal)": lambda: A.marginal_inverse(1 / 3, d),
        "marginal_inverse(0.9, normal)": lambda: A.marginal_inverse(0.9, d),
        "marginal_inverse(200 p, normal)": lambda: A.marginal_inverse(ps, d),
        "conditional_inverse(1/3, 1.2)": lambda: A.conditional_inverse(1 / 3, 1.2),
        "conditional_inverse(0.999, 0.3)": lambda: A.conditional_inverse(0.999, 0.3),
        "conditional_inverse(200 p, 1.2)": lambda: A.conditional_inverse(ps, 1.2),
    }


def measure() -> dict:
    out = {}
    for name, fn in cases().items():
        fn()
        n = max(1, timeit.Timer(fn).autorange()[0] // 4)
        out[name] = min(timeit.Timer(fn).repeat(3, n)) / n
    return out


def _run(pythonpath: str | None) -> dict:
    env = dict(os.environ)
    if pythonpath:
        env["PYTHONPATH"] = pythonpath
    r = subprocess.run([sys.executable, __file__, "--json"], capture_output=True, text=True,
                       env=env, check=True, cwd=pythonpath or ROOT)
    return json.loads(r.stdout)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--against", metavar="REV", help="compare with this git revision")
    ap.add_argument("--json", action="store_true", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.json:
        print(json.dumps(measure()))
        return
    if not args.against:
        for name, t in measure().items():
            print(f"| `{name}` | {t * 1e3:.3g} ms |")
        return
    with tempfile.TemporaryDirectory() as tmp:
        archive = subprocess.run(["git", "archive", args.against, "coincli"], cwd=ROOT,
                                 capture_output=True, check=True).stdout
        tar = Path(tmp) / "old.tar"
        tar.write_bytes(archive)
        with tarfile.open(tar) as tf:
            tf.extractall(tmp, filter="data")
        before, after = [], []
        for _ in range(3):
            before.append(_run(tmp))
            after.append(_run(str(ROOT)))
    print(f"| call | before ({args.against}) | after | ratio |")
    print("|---|---:|---:|---:|")
    for name in before[0]:
        b = statistics.median(r[name] for r in before)
        a = statistics.median(r[name] for r in after)
        print(f"| `{name}` | {b * 1e3:.3g} ms | {a * 1e3:.3g} ms | {a / b:.2f} |")


if __name__ == "__main__":
    main()
