"""Fresh tosses against a precomputed table: is an engine setting the same physics?

The tables of ``coincli/core/bounce/tables.json`` hold 2000 hand tosses at each of 39 aspect
ratios per surface preset (:mod:`coincli.core.bounce.tables`).  That makes them a reference
for any change to the engine: simulate fresh tosses (another seed) at some of the tables'
points with the engine as it is now, or at another ``--dt``, and test each point's counts of
heads, sides and tails against the table's, a chi-square test of the 2 x 3 table.  Issue 25
used it to choose the default step (docs/bounce.md, "A coarser step").

    python benchmarks/bounce_vs_tables.py --dt 3e-4                  # against the shipped tables
    python benchmarks/bounce_vs_tables.py --reference 67df6ea        # the tables at a revision
    python benchmarks/bounce_vs_tables.py --surfaces wood --xi 0.3,0.5 -n 2000 --seed 8

Prints a markdown table: per point the table's and the fresh counts, P(sides) both ways with
z (the difference in standard errors of a difference of two proportions) and the chi-square p;
per surface the number of points at p < 0.05 and Fisher's combined p over its points; and the
same over every point.  Each point is :func:`coincli.core.bounce.runs.simulate` with the
table's launch (:func:`coincli.core.bounce.tables.launch_kw`) but ``--dt``, seeded ``--seed`` on
the stream ``(3000, point)`` (the tables use 25 and ``(1000 + preset, point)``), every core.
"""

from __future__ import annotations

import argparse
import json
import math
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

DEFAULT_XI = "0.25,0.3,0.4,0.5,0.6,0.8,1.0,1.3"


def reference(rev):
    """The tables document: the shipped file, or the one at git revision ``rev``."""
    from coincli.core.bounce import tables as TB

    if rev is None:
        return json.loads(Path(TB.TABLES_FILE).read_text())
    rel = Path(TB.TABLES_FILE).relative_to(ROOT).as_posix()
    return json.loads(subprocess.run(["git", "show", f"{rev}:{rel}"], cwd=ROOT, check=True,
                                     capture_output=True, text=True).stdout)


def compare(a, b):
    """(z of P(sides), chi-square p) of two rows of counts (heads, sides, tails): Pearson's
    test without Yates' correction, as tests/core/test_tables.py computes it and docs/bounce.md
    quotes it.  At thousands of tosses a row it is close to ``coin check``'s exact test
    (``coincli.core.stats.homogeneity``): 0.9117 against 0.9120, 3.43e-7 against 3.26e-7 and
    0.0295 against 0.0304 on rows of this benchmark."""
    from scipy.stats import chi2_contingency

    na, nb = sum(a), sum(b)
    pa, pb = a[1] / na, b[1] / nb
    se = math.sqrt(pa * (1 - pa) / na + pb * (1 - pb) / nb)
    z = (pb - pa) / se if se > 0 else 0.0
    cols = [k for k in range(3) if a[k] + b[k] > 0]  # a column of zeros has no expectation
    p = 1.0 if len(cols) < 2 else float(chi2_contingency([[a[k] for k in cols],
                                                         [b[k] for k in cols]],
                                                        correction=False)[1])
    return z, p


def fisher(ps):
    from scipy.stats import combine_pvalues

    return float(combine_pvalues(ps, method="fisher")[1]) if ps else math.nan


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--dt", type=float, default=None, help="the fresh tosses' step (default: "
                    "the engine's)")
    ap.add_argument("--reference", default=None, help="git revision of the reference tables "
                    "(default: the shipped file)")
    ap.add_argument("--surfaces", default=None, help="presets, comma-separated (default: all)")
    ap.add_argument("--xi", default=DEFAULT_XI, help="aspect ratios; each is taken to the "
                    "table's nearest point")
    ap.add_argument("-n", type=int, default=2000, help="fresh tosses a point")
    ap.add_argument("--seed", type=int, default=7)
    args = ap.parse_args(argv)

    from coincli.core.bounce import runs as R
    from coincli.core.bounce import tables as TB
    from coincli.core.bounce.engine import DEFAULT_DT, SURFACES

    doc = reference(args.reference)
    names = args.surfaces.split(",") if args.surfaces else list(doc["surfaces"])
    dt = DEFAULT_DT if args.dt is None else args.dt
    ref_dt = doc["signature"]["engine"]["DEFAULT_DT"]
    want = [float(x) for x in args.xi.split(",")]
    print(f"Fresh tosses at dt = {dt:g} s ({args.n} a point, seed {args.seed}, streams (3000, "
          f"point)) against the tables of {args.reference or 'this checkout'} (dt = "
          f"{ref_dt:g} s, seed {TB.TABLE_SEED}), the hand toss, every core.\n")
    print("| surface | xi | table H / S / T (unsettled) | fresh H / S / T (unsettled) | "
          "P(sides) table | fresh | z | p |")
    print("|---|---|---|---|---|---|---|---|")
    every, summary = [], []
    for name in names:
        pts = {float(p[0]): p for p in doc["surfaces"][name]["points"]}
        xs = sorted({min(pts, key=lambda x, w=w: abs(math.log(x / w))) for w in want})
        kw = dict(TB.launch_kw(SURFACES[name]), dt=dt)
        w0 = time.monotonic()
        sims = R.simulate_many([dict(kw, n=args.n, seed=args.seed, xi=x, stream=(3000, j))
                                for j, x in enumerate(xs)])
        ps = []
        for x, s in zip(xs, sims, strict=True):
            p = pts[x]
            a, b = list(p[2:5]), list(s.counts[:3])
            z, pv = compare(a, b)
            ps.append(pv)
            print(f"| {name} | {x:g} | {' / '.join(map(str, a))} ({p[5]}) | "
                  f"{' / '.join(map(str, b))} ({s.counts[3]}) | {a[1] / sum(a):.4f} | "
                  f"{b[1] / sum(b):.4f} | {z:+.2f} | {pv:.3f} |", flush=True)
        every += ps
        summary.append((name, sum(p < 0.05 for p in ps), len(ps), fisher(ps),
                        time.monotonic() - w0))
    print()
    for name, low, k, f, wall in summary:
        print(f"- {name}: {low} of {k} points at p < 0.05; Fisher's combined p = {f:.3f} "
              f"({wall:.0f} s of wall)")
    print(f"- every point: {sum(p < 0.05 for p in every)} of {len(every)} at p < 0.05 "
          f"(expected by chance: {0.05 * len(every):.1f}); Fisher's combined p = "
          f"{fisher(every):.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
