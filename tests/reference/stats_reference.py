"""The statistics of ``coin check``/``coin fit`` as they were before they moved to
scipy.special (coincli 0.x, commit ac0d553): scipy.stats' ``binomtest`` for the binomial test
and both intervals, ``binom``/``multinomial`` for the trinomial test and the log-likelihoods,
``chi2`` for the G-test and scipy.optimize for the spread fit, one experiment at a time.

Kept only as a reference for tests/test_stats_batch.py, which checks that the batched engine
gives the same numbers on random files.  (scipy's Clopper-Pearson ends come from a root finder
on binom.sf, good to about 1e-9 relative; the new ends are exact beta quantiles.)
"""
# ruff: noqa

from __future__ import annotations

import math
from collections.abc import Sequence

from coincli.core._numerics.wilson import CONFIDENCE, check_level
from coincli.core.models import Outcome
from coincli.core.stats.counts import Counts, check_probs, whole_count
from coincli.core.stats.fit import SpreadFit, _sigma_of, _spread_chances, aic
from coincli.core.stats.intervals import Interval, Proportion
from coincli.core.stats.tests import TIE_RTOL, _LOG_TINY


def proportion(count: int, n: int, outcome: str = "sides", confidence: float = CONFIDENCE
               ) -> Proportion:
    from scipy.stats import binomtest

    c = whole_count(count, "count")
    m = whole_count(n, "n")
    if m == 0:
        raise ValueError("n must be >= 1, got 0")
    if c > m:
        raise ValueError(f"count must be <= n = {m}, got {c}")
    conf = check_level(confidence, "confidence")
    res = binomtest(c, m)
    out = {}
    for method, label in (("wilson", "wilson"), ("exact", "clopper-pearson")):
        ci = res.proportion_ci(confidence_level=conf, method=method)
        lo = min(max(float(ci.low), 0.0), 1.0)
        hi = min(max(float(ci.high), 0.0), 1.0)
        out[label] = Interval(lo, hi, label, conf)
    return Proportion(outcome, c, m, c / m, out["wilson"], out["clopper-pearson"])




def _exact_trinomial_logp(x: tuple[int, int, int], p: tuple[float, float, float]) -> float:
    import numpy as np
    from scipy.special import logsumexp
    from scipy.stats import binom

    a, r, c = x
    pa, pr, pc = p
    n = a + r + c
    q = pa / (pa + pc)
    f_obs = float(binom.logpmf(r, n, pr) + binom.logpmf(a, n - r, q))
    thr = f_obs + math.log1p(TIE_RTOL)
    n_outcomes = (n + 1) * (n + 2) / 2
    if thr + math.log(n_outcomes) < _LOG_TINY:
        return -math.inf
    with np.errstate(divide="ignore", invalid="ignore", under="ignore"):
        ks = np.arange(n + 1)
        row = binom.logpmf(ks, n, pr)
        full = row <= thr
        parts = [row[full]]
        act = ~full
        rowa, na = row[act], n - ks[act]

        def f(k):
            return rowa + binom.logpmf(k, na, q)

        if rowa.size:
            mode = np.clip(np.floor((na + 1) * q), 0, na).astype(np.int64)
            cands = [np.clip(mode + d, 0, na) for d in (-1, 0, 1)]
            vals = np.stack([f(cc) for cc in cands])
            best = np.argmax(vals, axis=0)
            mstar = np.choose(best, cands)
            fmax = np.choose(best, vals)
            whole = fmax <= thr
            parts.append(rowa[whole])
            keep = ~whole
            rowa, na, mstar = rowa[keep], na[keep], mstar[keep]
        if rowa.size:
            # left end: the largest h < mstar with f(h) <= thr (-1 if none)
            lo, hi = np.full_like(mstar, -1), mstar.copy()
            while True:
                gap = hi - lo > 1
                if not gap.any():
                    break
                mid = (lo + hi) // 2
                below = f(mid) <= thr
                lo = np.where(gap & below, mid, lo)
                hi = np.where(gap & ~below, mid, hi)
            left = lo
            # right end: the smallest h > mstar with f(h) <= thr (n - s + 1 if none)
            lo, hi = mstar.copy(), na + 1
            while True:
                gap = hi - lo > 1
                if not gap.any():
                    break
                mid = (lo + hi) // 2
                below = f(mid) <= thr
                hi = np.where(gap & below, mid, hi)
                lo = np.where(gap & ~below, mid, lo)
            right = hi
            tails = binom.cdf(left, na, q) + binom.sf(right - 1, na, q)
            parts.append(rowa + np.log(tails))
        allparts = np.concatenate(parts)
        if allparts.size == 0:
            return -math.inf
        return min(float(logsumexp(allparts)), 0.0)




def exact_pvalue(counts: Sequence[int], probs: Sequence[float]) -> float:
    x = [whole_count(v, "counts") for v in counts]
    if len(x) not in (2, 3):
        raise ValueError(f"counts must have 2 or 3 categories, got {len(x)}")
    p = check_probs(probs, len(x))
    n = sum(x)
    if n == 0:
        raise ValueError("counts are all zero: no tosses to test")
    if any(pi == 0 and xi > 0 for xi, pi in zip(x, p, strict=True)):
        return 0.0
    keep = [i for i, pi in enumerate(p) if pi > 0]
    x = [x[i] for i in keep]
    p = [p[i] for i in keep]
    if len(x) == 1:
        return 1.0  # only one outcome is possible, and it was observed
    # Work with the rarer categories' chances: 1 - p loses a chance below 1e-16 (a face of a
    # very thick coin is 2.5e-19 at xi = 1e9, while its sides chance rounds to 1.0).
    order = sorted(range(len(x)), key=lambda i: p[i])
    if len(x) == 2:
        from scipy.stats import binomtest

        i = order[0]
        return float(min(1.0, binomtest(x[i], n, p[i]).pvalue))
    r, a, c = order  # r: the rarest outcome, binomial in n; a: the middle one, given r
    return math.exp(_exact_trinomial_logp((x[a], x[r], x[c]), (p[a], p[r], p[c])))




def g_test(counts: Sequence[int], probs: Sequence[float]) -> tuple[float, int, float]:
    from scipy.special import xlogy
    from scipy.stats import chi2

    x = [whole_count(v, "counts") for v in counts]
    p = check_probs(probs, len(x))
    n = sum(x)
    if n == 0:
        raise ValueError("counts are all zero: no tosses to test")
    g = 0.0
    for xi, pi in zip(x, p, strict=True):
        if pi == 0:
            if xi > 0:
                return math.inf, sum(1 for v in p if v > 0) - 1, 0.0
            continue
        g += float(xlogy(xi, xi / (n * pi)))
    g = max(2.0 * g, 0.0)
    df = sum(1 for v in p if v > 0) - 1
    if df == 0:
        return g, 0, 1.0
    return g, df, float(chi2.sf(g, df))




def log_likelihood(counts: Counts, probs) -> float:
    from scipy.stats import binom, multinomial

    ph, ps, pt = check_probs(probs, 3)
    if counts.faces:
        return float(multinomial.logpmf(list(counts.values), counts.n, [ph, ps, pt]))
    if ps <= 0.5:
        return float(binom.logpmf(counts.sides, counts.n, ps))
    return float(binom.logpmf(counts.n - counts.sides, counts.n, ph + pt))  # no 1 - ps rounding




def _loglik_rows(counts: Sequence[Counts], heads, sides, tails) -> float:
    import numpy as np
    from scipy.stats import binom, multinomial

    with np.errstate(divide="ignore", invalid="ignore", under="ignore"):
        total = 0.0
        tri = [i for i, c in enumerate(counts) if c.faces]
        bi = [i for i, c in enumerate(counts) if not c.faces]
        if tri:
            x = np.array([counts[i].values for i in tri])
            p = np.stack([heads[tri], sides[tri], tails[tri]], axis=1)
            p = p / p.sum(axis=1, keepdims=True)
            total += float(np.sum(multinomial.logpmf(x, x.sum(axis=1), p)))
        if bi:
            k = np.array([counts[i].sides for i in bi])
            m = np.array([counts[i].n for i in bi])
            ps = np.clip(sides[bi], 0.0, 1.0)
            pf = np.clip(heads[bi] + tails[bi], 0.0, 1.0)  # not 1 - ps: a thick coin's faces
            ll = np.where(ps <= 0.5, binom.logpmf(k, m, ps), binom.logpmf(m - k, m, pf))
            total += float(np.sum(ll))
    return total if not math.isnan(total) else -math.inf




def fit_spread(xi: Sequence[float], counts: Sequence[Counts], *, confidence: float = CONFIDENCE,
               grid: int = 41) -> SpreadFit:
    import numpy as np
    from scipy.optimize import brentq, minimize_scalar
    from scipy.stats import chi2

    conf = check_level(confidence, "confidence")
    xs = np.asarray([float(v) for v in xi], dtype=float)
    if xs.ndim != 1 or len(xs) != len(counts) or len(xs) == 0:
        raise ValueError(f"xi and counts must be non-empty and of one length, got {len(xs)} and "
                         f"{len(counts)}")
    if not all(isinstance(c, Counts) for c in counts):
        raise ValueError("counts must be Counts (see make_counts)")
    if not np.all(np.isfinite(xs) & (xs > 0)):
        raise ValueError("xi must be finite and > 0 for every experiment")
    if int(grid) < 5:
        raise ValueError(f"grid must be >= 5, got {grid!r}")
    cache: dict[float, float] = {}

    def loglik(u: float) -> float:
        u = min(max(float(u), 0.0), 1.0)
        if u not in cache:
            ch = _spread_chances(xs, _sigma_of(u))
            cache[u] = _loglik_rows(counts, *(np.asarray(v, dtype=float) for v in ch))
        return cache[u]

    us = np.linspace(0.0, 1.0, int(grid))
    ls = np.array([loglik(u) for u in us])
    if not np.any(np.isfinite(ls)):
        raise ValueError("no spread of psi gives these counts a positive probability")
    j = int(np.argmax(ls))
    a, b = us[max(j - 1, 0)], us[min(j + 1, len(us) - 1)]
    res = minimize_scalar(lambda u: -loglik(u), bounds=(a, b), method="bounded",
                          options={"xatol": 1e-9})
    u_hat, l_hat = (float(res.x), -float(res.fun)) if -res.fun > ls[j] else (float(us[j]),
                                                                              float(ls[j]))
    # The log-likelihood is flat at sigma = 0 (the chances move like sigma^2): a gain below
    # 1e-8 over an end of the range is rounding, not evidence; report the end itself.
    if j in (0, len(us) - 1) and l_hat - ls[j] < 1e-8:
        u_hat, l_hat = float(us[j]), float(ls[j])
    cut = l_hat - float(chi2.ppf(conf, 1)) / 2

    def g(u):
        v = loglik(u)
        return (v - cut) if math.isfinite(v) else -1e300

    pts = sorted(set(us.tolist()) | {u_hat})
    gv = [g(u) for u in pts]
    pieces, start = [], (0.0 if gv[0] >= 0 else None)
    for k in range(1, len(pts)):
        if (gv[k - 1] >= 0) == (gv[k] >= 0):
            continue
        root = brentq(g, pts[k - 1], pts[k], xtol=1e-10)
        if gv[k] >= 0:
            start = root
        else:
            pieces.append((start, root))
            start = None
    if start is not None:
        pieces.append((start, 1.0))
    spans = tuple((_sigma_of(lo), _sigma_of(hi)) for lo, hi in pieces)
    sigma = _sigma_of(u_hat)
    notes = []
    if sigma == 0:
        notes.append("the estimate is at sigma = 0: the Keller flip (dynamic model) fits best")
    elif math.isinf(sigma):
        notes.append("the estimate is sigma = inf: psi uniform on [0, pi] fits best")
    if len(spans) > 1:
        notes.append(
            "the confidence set is not one interval (the chance of a side is not monotone in "
            "sigma); low-high spans its pieces"
        )
    ch = _spread_chances(xs, sigma)
    return SpreadFit(
        sigma=sigma,
        low=spans[0][0],
        high=spans[-1][1],
        pieces=spans,
        confidence=conf,
        log_likelihood=l_hat,
        aic=aic(l_hat, 1),
        chances=Outcome(*(np.asarray(v, dtype=float) for v in ch)),
        note="; ".join(notes),
        profile=tuple((_sigma_of(u), cache[u]) for u in us.tolist()),
    )


