"""Speed of the probability engine: scalar calls per second, and 10^6-element arrays.

Run from the repository root (about a minute):

    python benchmarks/bench_core.py            # writes its section of docs/performance.md
    python benchmarks/bench_core.py --no-write # print only

Scalar: each public function called on Python floats (the closed forms never touch numpy),
calls per second as the median of several ``timeit`` repeats.  Arrays: each closed form over
the same 10^6 doubles, against bare ``np.arctan`` over that array timed in the same run and
interleaved with it; the aim for the closed forms is within 3x of ``np.arctan``.  The
quadrature model (``marginal``) is timed on 10^5 values and compared with ``np.arctan`` over
those.
"""

from __future__ import annotations

import argparse
import math
import sys
import time
import timeit
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import _report  # noqa: E402

AIM_ARRAY = 3.0


def scalar_rates(repeat: int) -> list[tuple[str, str, float]]:
    from coincli.core import models
    from coincli.core.averages import conditional_inverse, marginal, marginal_inverse
    from coincli.io.grammar import parse_density

    normal = parse_density("normal")
    cases = [
        ("geometric(0.577)", "eq. 11", lambda: models.geometric(0.577)),
        ("dynamic(0.577)", "eq. 12", lambda: models.dynamic(0.577)),
        ("conditional(0.577, 1.2)", "Table I", lambda: models.conditional(0.577, 1.2)),
        ("geometric_inverse(1/3)", "closed form", lambda: models.geometric_inverse(1 / 3)),
        ("dynamic_inverse(1/3)", "closed form", lambda: models.dynamic_inverse(1 / 3)),
        ("theta0(0.577)", "closed form", lambda: models.theta0(0.577)),
        ("psi_boundaries(0.577)", "closed form", lambda: models.psi_boundaries(0.577)),
        ("asymptotic_sides(0.01)", "eq. 13", lambda: models.asymptotic_sides(0.01)),
        ("conditional_inverse(1/3, 1.2)", "root finding", lambda: conditional_inverse(1 / 3, 1.2)),
        ("marginal(0.577, normal)", "quadrature", lambda: marginal(0.577, normal)),
        ("marginal_inverse(1/3, normal)", "quadrature + root finding",
         lambda: marginal_inverse(1 / 3, normal)),
    ]
    out = []
    for name, kind, fn in cases:
        fn()  # warm caches (quadrature nodes, breakpoints)
        timer = timeit.Timer(fn)
        number, _ = timer.autorange()
        number = max(1, number // 4)  # ~50 ms a repeat
        rates = [number / t for t in timer.repeat(repeat=repeat, number=number)]
        out.append((name, kind, _report.median(rates)))
        print(f"  {name:32s} {_report.fmt_rate(out[-1][2])} calls/s", file=sys.stderr)
    return out


def _timed(fn) -> float:
    t = time.perf_counter()
    fn()
    return time.perf_counter() - t


def array_ratios(n: int, repeat: int):
    import numpy as np

    from coincli.core import models
    from coincli.core.averages import marginal
    from coincli.io.grammar import parse_density

    rng = np.random.default_rng(2024)
    xi = rng.uniform(0.0, 3.0, n)  # every regime of a real coin, thin to very thick
    p = rng.uniform(0.0, 1.0, n)
    psi = rng.uniform(0.0, math.pi, n)
    cases = [
        ("geometric(xi)", lambda: models.geometric(xi)),
        ("dynamic(xi)", lambda: models.dynamic(xi)),
        ("geometric_inverse(p)", lambda: models.geometric_inverse(p)),
        ("dynamic_inverse(p)", lambda: models.dynamic_inverse(p)),
        ("theta0(xi)", lambda: models.theta0(xi)),
        ("conditional(xi, 1.2)", lambda: models.conditional(xi, 1.2)),
        ("conditional(xi, psi)", lambda: models.conditional(xi, psi)),
    ]
    primitives = [  # numpy's own ufuncs over the same array: the floor for each formula
        ("np.arctan2(1, xi)", lambda: np.arctan2(1.0, xi)),
        ("np.hypot(1, xi)", lambda: np.hypot(1.0, xi)),
        ("np.sqrt(1 + xi*xi)", lambda: np.sqrt(1.0 + xi * xi)),
        ("np.tan(xi)", lambda: np.tan(xi)),
        ("np.sin(xi)", lambda: np.sin(xi)),
        ("0.5 / xi", lambda: 0.5 / xi),
    ]
    cases = primitives + cases
    rows = []
    for name, fn in cases:
        fn()
        base, mine = [], []
        for _ in range(repeat):  # interleaved with the baseline
            base.append(_timed(lambda: np.arctan(xi)))
            mine.append(_timed(fn))
        b, m = _report.median(base), _report.median(mine)
        rows.append((name, n, m, b, m / b))
        print(f"  {name:24s} {_report.fmt_time(m)} vs np.arctan {_report.fmt_time(b)}: "
              f"{m / b:.1f}x", file=sys.stderr)
    # quadrature on a tenth of the size
    k = n // 10
    small = xi[:k]
    normal = parse_density("normal")
    marginal(small, normal)
    base, mine = [], []
    for _ in range(max(3, repeat // 2)):
        base.append(_timed(lambda: np.arctan(small)))
        mine.append(_timed(lambda: marginal(small, normal)))
    b, m = _report.median(base), _report.median(mine)
    rows.append(("marginal(xi, normal)", k, m, b, m / b))
    print(f"  marginal on {k}: {_report.fmt_time(m)}, {m / b:.0f}x np.arctan", file=sys.stderr)
    return rows


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("-n", type=int, default=10**6, help="array size (default 10^6)")
    ap.add_argument("--repeat", type=int, default=9, help="repeats per figure (default 9)")
    ap.add_argument("--no-write", action="store_true", help="do not touch docs/performance.md")
    args = ap.parse_args(argv)

    where = _report.machine()
    print("scalar calls per second", file=sys.stderr)
    scalars = scalar_rates(max(3, args.repeat // 2))
    print(f"arrays of {args.n}", file=sys.stderr)
    arrays = array_ratios(args.n, args.repeat)

    body = ["## The engine (`benchmarks/bench_core.py`)", "",
            "Command: `python benchmarks/bench_core.py` (about a minute).  " + where + ".", "",
            "### Scalar calls (Python floats; the closed forms use the `math` module only)", "",
            _report.table(["call", "method", "calls/s", "µs/call"],
                          [[f"`{n}`", k, _report.fmt_rate(r), f"{1e6 / r:.2f}"]
                           for n, k, r in scalars]),
            f"### Arrays, against bare `np.arctan` over the same array (aim: within "
            f"{AIM_ARRAY:g}x for the closed forms)", "",
            "xi uniform on [0, 3], p uniform on [0, 1], psi uniform on [0, pi]; medians of "
            f"{args.repeat} runs interleaved with the baseline.", "",
            _report.table(["call", "elements", "time", "np.arctan", "ratio", "ns/element",
                           "aim met"],
                          [[f"`{n}`", f"{k:,}", _report.fmt_time(m), _report.fmt_time(b),
                            f"{r:.1f}x", f"{1e9 * m / k:.1f}",
                            ("yes" if r <= AIM_ARRAY else "**no**")
                            if not n.startswith("marginal") else "(quadrature)"]
                           for n, k, m, b, r in arrays if not n.startswith(("np.", "0.5"))]),
            "numpy's own ufuncs over the same array, for scale (the closed forms are built from "
            "these):", "",
            _report.table(["ufunc", "time", "np.arctan", "ratio"],
                          [[f"`{n}`", _report.fmt_time(m), _report.fmt_time(b), f"{r:.1f}x"]
                           for n, k, m, b, r in arrays if n.startswith(("np.", "0.5"))])]
    missed = [n for n, _, _, _, r in arrays
              if r > AIM_ARRAY and not n.startswith(("marginal", "np.", "0.5"))]
    if missed:
        body += ["Missed: " + ", ".join(f"`{n}`" for n in missed) + " (the code is in "
                 "`coincli/models.py`; where the time goes is in the notes below).", ""]
    text = "\n".join(body)
    print(text)
    if not args.no_write:
        _report.write_section("bench_core", text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
