"""Coverage of the bouncing design's intervals (issue 37): how often the 95% interval of
``coin design --landing bounce`` holds the engine's own answer.

The engine is replaced by a stand-in whose true P(sides) curves are the engine's: for each
preset, probit P(sides) a natural cubic spline in ln xi (7 knots at quantiles of the tosses),
fitted by maximum likelihood to the shipped table's 78,800 tosses
(``coincli/core/bounce/tables.json``, 43 aspect ratios), and checked to be increasing.  So the
curvature, and the floor at thin coins that a straight probit misses, are the engine's.  A
simulated point is a binomial draw from that curve, seeded as the design seeds its simulations
(``(seed, round, point)``), so each design is a pure function of its seed.  Two arms:

- ``table``: the design starts from a table, as on a preset: a synthetic table drawn from the
  curve at the shipped grid and counts (stream 10**6 + design), then the design's rounds;
- ``fresh``: ``--no-table``: the first sweep, then the rounds.

For each preset, arm, ``--tol`` (0.05, 0.02, 0.01) and target (0.1, 1/3, 0.6), ``N`` designs
(seeds 1..N) are run and the share whose interval holds the true xi is reported with its 95%
Wilson interval, with the median half-width and how many stopped before meeting ``--tol``.

    python benchmarks/design_coverage.py [N] [preset,...] [arm,...] [tol,...] > coverage.md

Prints a Markdown table.  CPU: about 10 ms a design (more at tol 0.01).
"""

from __future__ import annotations

import json
import math
import multiprocessing as mp
import sys
import time

import numpy as np
from scipy.optimize import brentq
from scipy.special import ndtr

from coincli.core.bounce import design as D
from coincli.core.bounce import tables as TB

TOLS = (0.05, 0.02, 0.01)
TARGETS = (0.1, 1 / 3, 0.6)


KNOTS = 7  #: the natural cubic spline of the truth: knots at quantiles of the tosses' ln xi


def _basis(lx, knots):
    """A natural cubic spline basis in ``lx`` (the truncated-power form, linear beyond the end
    knots: Hastie, Tibshirani & Friedman, eq. 5.4-5.5)."""
    lx = np.atleast_1d(np.asarray(lx, float))
    k = np.asarray(knots)

    def d(j):
        return (np.maximum(lx - k[j], 0) ** 3 - np.maximum(lx - k[-1], 0) ** 3) / (k[-1] - k[j])

    cols = [np.ones_like(lx), lx] + [d(j) - d(len(k) - 2) for j in range(len(k) - 2)]
    return np.column_stack(cols)


def truth(preset: str):
    """``(knots, coefficients)`` of ``preset``'s smooth curve: probit P(sides) a natural cubic
    spline in ln xi (:data:`KNOTS` knots), fitted by maximum likelihood to the shipped table;
    checked to be increasing from xi 0.1 to 2.4."""
    from scipy.optimize import minimize

    doc = json.loads(TB.TABLES_FILE.read_text())
    pts = [p for p in doc["surfaces"][preset]["points"] if p[1] - p[5] > 0]
    lx = np.log([p[0] for p in pts])
    n = np.array([p[1] - p[5] for p in pts], float)
    k = np.array([p[3] for p in pts], float)
    knots = tuple(float(v) for v in np.quantile(np.repeat(lx, n.astype(int)),
                                                np.linspace(0, 1, KNOTS)))
    X = _basis(lx, knots)

    def nll(c):
        mu = np.clip(ndtr(X @ c), 1e-12, 1 - 1e-12)
        return -np.sum(k * np.log(mu) + (n - k) * np.log1p(-mu))

    c0 = np.linalg.lstsq(X, np.clip((k + 0.5) / (n + 1), 1e-3, 1 - 1e-3), rcond=None)[0]
    res = minimize(nll, c0 * 0 + np.r_[1.0, 2.0, [0.0] * (KNOTS - 2)], method="BFGS",
                   options={"gtol": 1e-8, "maxiter": 10000})
    coef = (knots, tuple(float(v) for v in res.x))
    grid = np.linspace(math.log(0.1), math.log(2.4), 2000)
    eta = _basis(grid, knots) @ res.x
    if not np.all(np.diff(eta) > 0):
        raise ValueError(f"{preset}: the fitted curve is not increasing")
    return coef


def curve(coef, xi):
    """P(sides) at ``xi`` of the curve ``coef`` (:func:`truth`)."""
    knots, c = coef
    return float(ndtr(_basis(math.log(xi), knots)[0] @ np.asarray(c)))


class StandIn:
    """``simulate`` of :mod:`coincli.core.bounce.design` for the curve ``coef``."""

    def __init__(self, coef):
        self.coef = coef

    def __call__(self, n, seed, *, xi, stream=(), **kw):
        k = int(np.random.default_rng([seed, *stream]).binomial(n, curve(self.coef, xi)))
        return _R(n, k)


class _R:
    __slots__ = ("settled", "counts", "n", "catch_counts")

    def __init__(self, n, k):
        self.settled, self.counts, self.n, self.catch_counts = n, (0, k, n - k, 0), n, (n, 0, 0)


def synthetic_table(coef, seed: int):
    rng = np.random.default_rng([10**6 + seed])
    pts = []
    for xi, n in TB.GRID:
        k = int(rng.binomial(n, curve(coef, xi)))
        pts.append((xi, n, 0, k, n - k, 0, 0))
    return TB.Table("stand-in", seed, 0, tuple(pts), {})


def _cell(args):
    preset, coef, arm, tol, target, seeds = args
    D.simulate = StandIn(coef)
    true_xi = brentq(lambda x: curve(coef, x) - target, 0.1, 2.4, xtol=1e-12)
    hits = met = 0
    widths, tosses = [], []
    t0 = time.process_time()
    for s in seeds:
        table = synthetic_table(coef, s) if arm == "table" else None
        r = D.design([target], seed=s, tol=tol, table=table, max_tosses=200_000)
        lo, hi = r.low[0], r.high[0]
        hits += lo <= true_xi <= hi
        met += r.met
        widths.append((hi - lo) / 2)
        tosses.append(r.tosses)
    return (preset, arm, tol, target, true_xi, len(seeds), hits, met,
            float(np.median(widths)), float(np.median(tosses)), time.process_time() - t0)


def wilson(k, n, z=1.959963984540054):
    p = k / n
    c = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / (1 + z * z / n)
    m = (p + z * z / (2 * n)) / (1 + z * z / n)
    return m - c, m + c


def main(argv):
    n = int(argv[1]) if len(argv) > 1 else 1000
    presets = argv[2].split(",") if len(argv) > 2 else list(TB.signature()["surfaces"])
    arms = argv[3].split(",") if len(argv) > 3 else ["table", "fresh"]
    tols = [float(t) for t in argv[4].split(",")] if len(argv) > 4 else list(TOLS)
    coefs = {p: truth(p) for p in presets}
    jobs = [(p, coefs[p], a, t, g, range(1, n + 1))
            for p in presets for a in arms for t in tols for g in TARGETS]
    with mp.Pool(2) as pool:
        rows = pool.map(_cell, jobs)
    print(f"Coverage of the 95% interval of `coin design --landing bounce` ({n} designs a cell, "
          "a stand-in engine whose P(sides) is a spline probit fitted to each preset's "
          "shipped table):\n")
    print("| preset | arm | --tol | target | true xi | covered | 95% Wilson | met --tol | "
          "median half-width | median tosses | CPU s |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for (p, a, t, g, x, m, hits, met, w, ts, cpu) in rows:
        lo, hi = wilson(hits, m)
        print(f"| {p} | {a} | {t:g} | {g:.4g} | {x:.4f} | {hits / m:.3f} | [{lo:.3f}, "
              f"{hi:.3f}] | {met}/{m} | {w:.4f} | {ts:.0f} | {cpu:.0f} |")
    for p in presets:
        print(f"\n{p}: the spline's knots (ln xi) {', '.join(f'{v:.4f}' for v in coefs[p][0])}, "
              f"coefficients {', '.join(f'{v:.5g}' for v in coefs[p][1])}")


if __name__ == "__main__":
    main(sys.argv)
