r"""Goodness of fit of one experiment (or many at once): exact tests, G-tests, verdicts.

A coin designer tosses a prototype a few hundred times and asks whether the counts agree with a
model (issue 6; the paper did the same with 100 tosses a coin, Sec. IV and Fig. 5).  This module
and its neighbours in :mod:`coincli.core.stats` are the pure core of ``coin check`` and
``coin fit``: numbers in, numbers and named tuples out, ``ValueError`` naming the argument and
its allowed range otherwise.  Nothing here prints.  The counts are
:mod:`coincli.core.stats.counts`', the intervals :mod:`coincli.core.stats.intervals`', the fits
across experiments :mod:`coincli.core.stats.fit`'.

Goodness of fit (:func:`exact_pvalue`, :func:`goodness_of_fit`)
    The exact test orders outcomes by their probability under the model (the "probability" or
    "likelihood" ordering of Tate & Hyer 1973, the one :func:`scipy.stats.binomtest` uses for its
    two-sided p-value).  The p-value is

    .. math:: p = \sum_{x:\ P(x) \le (1 + 10^{-7})\, P(x_\mathrm{obs})} P(x),

    the sum over all outcomes ``x`` with ``sum(x) = n`` that are no more likely than the observed
    one.  The relative tolerance ``1e-7`` is scipy's: outcomes tied in exact arithmetic (e.g.
    heads and tails swapped under a model with equal chances) are not split by rounding.  The
    binomial p-value is :func:`scipy.stats.binomtest`'s (its two tails, :func:`_crossings`).  The
    trinomial one (:func:`_trinomial_logp`): the rows of the rarest outcome whose whole mass is
    below the threshold are two binomial tails; in every other row the middle outcome is
    binomial given the rarest, log-concave, so the row's outcomes no more likely than the
    observed one are two tails again.  Tails are incomplete beta functions.  Every outcome is
    accounted for; no sampling, no asymptotics; all tests of a file run together, each distinct
    one once.  It takes 0.02 s at ``n = 10^6`` (:data:`EXACT_MAX_N`); beyond that
    ``method="auto"`` switches to the likelihood-ratio G-test,

    .. math:: G = 2 \sum_i O_i \ln(O_i / E_i) \sim \chi^2_{k-1},

    and says so in the result (``exact=False``, ``method`` names the test).

Log-likelihoods
    The full multinomial (binomial) log-probability of the observed counts, multinomial
    coefficient included (the formula of ``scipy.stats.multinomial.logpmf``), so that values from
    different models of the same data are comparable and AIC differences are meaningful.

Verdicts and checks
    :func:`verdict` words a p-value without claiming more than the test shows; :func:`check`
    and :func:`check_many` test experiments against each model's chances
    (:func:`model_chances`: geometric, dynamic and psi densities).

numpy and scipy.special are imported inside the functions that need them (the CLI's start-up
budget); scipy.stats is not used at all (0.6 s of import).
"""

from __future__ import annotations

import math
from collections import namedtuple
from collections.abc import Mapping, Sequence

from coincli.core._numerics.wilson import CONFIDENCE, check_level, wilson_interval
from coincli.core.models import Outcome
from coincli.core.stats.counts import (
    CountColumns,
    Counts,
    LogFactorial,
    RowSequence,
    binom_cdf,
    binom_logpmf,
    binom_upper,
    check_probs,
    whole_count,
)
from coincli.core.stats.intervals import Interval, Proportion, clopper_pearson_interval

__all__ = [
    "ALPHA",
    "EXACT_MAX_N",
    "TIE_RTOL",
    "exact_pvalue",
    "g_test",
    "log_likelihood",
    "ModelTest",
    "goodness_of_fit",
    "format_p",
    "percent",
    "verdict",
    "model_chances",
    "CheckResult",
    "Checks",
    "check",
    "check_many",
]

ALPHA = 0.05  #: default significance level of the verdicts
EXACT_MAX_N = 1_000_000  #: largest n for which method="auto" runs the exact test
TIE_RTOL = 1e-7  #: relative tolerance for "no more likely than the observed" (scipy's)
P_DISPLAY_FLOOR = 1e-300  #: p-values below this are shown as "p < 1e-300"
_LOG_TINY = math.log(5e-324)  # exp() of anything below is 0.0 in double precision


# --------------------------------------------------------------------------- exact test
# Batched: many tests (rows of a file, models) in a few numpy passes.

_ROWS_PER_PASS = 1 << 18  #: (tests x rows of outcomes) evaluated together in the trinomial test


def _crossings(c, n, q, t, lf):
    """Where ``g(h) = c + log b(h; n, q)`` (``h = 0..n``, a log-concave row) crosses ``t``.

    Arrays in, ``(above, left, right)`` out: ``above`` marks rows whose peak is above ``t``;
    for those, ``left`` is the largest ``h`` below the mode with ``g(h) <= t`` (-1 if none) and
    ``right`` the smallest above it (``n + 1`` if none), so the outcomes above ``t`` are
    ``left < h < right``.  The log-pmf is scipy.stats.binom.logpmf's formula (in its
    association).  Each end is found by bisection, in a bracket of a few outcomes around the
    normal approximation ``n q -+ sqrt(2 v (peak - t))`` when its two sides check out (they
    usually do), else in the whole half-row.
    """
    import numpy as np

    lq, l1q = np.log(q), np.log1p(-q)
    lfn = lf(n)

    def g(h, i=None):
        if i is None:
            return c + (((lfn - (lf(h) + lf(n - h))) + h * lq) + (n - h) * l1q)
        return c[i] + (((lfn[i] - (lf(h) + lf(n[i] - h))) + h * lq[i]) + (n[i] - h) * l1q[i])

    mode = np.clip(np.floor((n + 1) * q), 0, n).astype(np.int64)
    cands = [np.clip(mode + d, 0, n) for d in (-1, 0, 1)]
    vals = np.stack([g(k) for k in cands])
    best = np.argmax(vals, axis=0)
    mstar = np.choose(best, cands)
    peak = np.choose(best, vals)
    above = peak > t
    with np.errstate(invalid="ignore"):
        half = np.sqrt(2.0 * n * q * (1.0 - q) * np.maximum(peak - t, 0.0))

    def bisect(lo, hi, left):
        """lo < hi bracket the crossing (left: g(lo) <= t or lo = -1, g(hi) > t;
        right: g(lo) > t, g(hi) <= t or hi = n + 1); narrow it to neighbours."""
        while True:
            i = np.flatnonzero(hi - lo > 1)
            if i.size == 0:
                return lo, hi
            mid = (lo[i] + hi[i]) // 2
            below = g(mid, i) <= t[i]
            if left:
                lo[i] = np.where(below, mid, lo[i])
                hi[i] = np.where(below, hi[i], mid)
            else:
                hi[i] = np.where(below, mid, hi[i])
                lo[i] = np.where(below, lo[i], mid)

    centre = n * q
    with np.errstate(invalid="ignore"):
        gl = np.nan_to_num(np.floor(centre - half), nan=0.0).astype(np.int64)
        gr = np.nan_to_num(np.ceil(centre + half), nan=0.0).astype(np.int64)
    # left end, in [-1, mstar]: try the bracket [gl - 2, gl + 3] first
    lo = np.clip(gl - 2, -1, np.maximum(mstar - 1, -1))
    hi = np.clip(gl + 3, lo + 1, mstar)
    ok = above & ((lo == -1) | (g(np.maximum(lo, 0)) <= t)) & (g(np.maximum(hi, 0)) > t)
    lo = np.where(ok, lo, -1)
    hi = np.where(ok, hi, np.where(above, mstar, 0))
    left, _ = bisect(lo, hi, True)
    # right end, in [mstar, n + 1]: try [gr - 2, gr + 3]
    lo = np.clip(gr - 2, mstar, n)
    hi = np.clip(gr + 3, lo + 1, n + 1)
    ok = above & (g(lo) > t) & ((hi == n + 1) | (g(np.minimum(hi, n)) <= t))
    lo = np.where(ok, lo, np.where(above, mstar, n))
    hi = np.where(ok, hi, n + 1)
    _, right = bisect(lo, hi, False)
    return above, left, right


def _binomial_pvalues(k, n, p, p1):
    """Exact two-sided binomial p-values (scipy.stats.binomtest's ordering), arrays.

    ``p`` is the chance of the counted category and ``p1`` that of the other one (``p <= p1``
    is best: then ``1 - p`` is never needed).  The outcomes no more likely than the observed one
    are two tails, ``P(X <= L) + P(X >= R)`` (:func:`_crossings`).
    """
    import numpy as np

    k = np.asarray(k, dtype=np.int64)
    n = np.asarray(n, dtype=np.int64)
    p = np.asarray(p, dtype=float)
    p1 = np.asarray(p1, dtype=float)
    lf = LogFactorial(int(np.max(n, initial=0)))
    with np.errstate(divide="ignore", invalid="ignore", under="ignore", over="ignore"):
        obs = (lf(n) - (lf(k) + lf(n - k))) + k * np.log(p) + (n - k) * np.log1p(-p)
        thr = obs + math.log1p(TIE_RTOL)
        above, left, right = _crossings(np.zeros(k.shape), n, p, thr, lf)
        tail = binom_cdf(left, n, p1) + binom_upper(right, n, p)
    return np.where(above, np.minimum(tail, 1.0), 1.0)


def _trinomial_logp(x, p):
    """Log exact p-values of trinomial counts ``x`` (T x 3, int) under chances ``p`` (T x 3, all
    > 0), columns ordered (rarest, middle, commonest) as :func:`exact_pvalue` arranges them.

    Write ``P(r, a, c) = B(r; n, p_r) * B(a; n - r, q)`` with ``q = p_a / (p_a + p_c)`` and ``B``
    the binomial pmf, and let ``thr = P(x_obs) (1 + 1e-7)``.  Both factors are log-concave, so:

    - the rows ``r`` with ``B(r; n, p_r) <= thr`` are the two tails of the binomial in ``r``:
      every outcome in them is at most as likely as the observed one, and their mass is
      ``P(r <= L) + P(r >= R)`` (two incomplete beta functions);
    - in each other row the outcomes above the threshold form one interval around the row's mode
      (:func:`_crossings`), and the row contributes ``B(r) * (P(a <= L_r) + P(a >= R_r))``.

    Every row of every test is one entry of a flat array (in passes of at most
    :data:`_ROWS_PER_PASS` entries), so a file of many experiments costs a few numpy passes.
    The result is exact up to floating-point rounding of the pmf and the incomplete beta
    function; it equals the brute-force sum over all ``(n+1)(n+2)/2`` outcomes
    (``tests/test_stats.py``).  When ``#outcomes * P(x_obs) < 5e-324`` the p-value underflows
    and ``-inf`` is returned.
    """
    import numpy as np

    x = np.asarray(x, dtype=np.int64).reshape(-1, 3)
    p = np.asarray(p, dtype=float).reshape(-1, 3)
    out = np.full(len(x), -np.inf)
    n_all = x.sum(axis=1)
    k = 0
    while k < len(x):  # passes of whole tests
        rows = np.cumsum(n_all[k:] + 1)
        j = k + max(1, int(np.searchsorted(rows, _ROWS_PER_PASS, side="right")))
        out[k:j] = _trinomial_pass(x[k:j], p[k:j])
        k = j
    return out


def _trinomial_pass(x, p):
    import numpy as np

    r, a, c = x[:, 0], x[:, 1], x[:, 2]
    pr, pa, pc = p[:, 0], p[:, 1], p[:, 2]
    n = r + a + c
    lf = LogFactorial(int(n.max()))
    out = np.full(len(x), -np.inf)
    with np.errstate(divide="ignore", invalid="ignore", under="ignore", over="ignore"):
        q, q1 = pa / (pa + pc), pc / (pa + pc)
        lpr, l1pr = np.log(pr), np.log1p(-pr)
        f_obs = ((lf(n) - (lf(r) + lf(n - r))) + r * lpr + (n - r) * l1pr) \
            + ((lf(n - r) - (lf(a) + lf(n - r - a))) + a * np.log(q) + (n - r - a) * np.log1p(-q))
        thr = f_obs + math.log1p(TIE_RTOL)
        n_outcomes = (n + 1.0) * (n + 2.0) / 2
        live = np.flatnonzero(thr + np.log(n_outcomes) >= _LOG_TINY)
        if live.size == 0:
            return out
        n, pr, q, q1, thr = n[live], pr[live], q[live], q1[live], thr[live]
        lpr, l1pr = lpr[live], l1pr[live]
        # rows r at or below the threshold: two binomial tails in r
        above, lo, hi = _crossings(np.zeros(len(n)), n, pr, thr, lf)
        outer = binom_cdf(lo, n, pa[live] + pc[live]) + binom_upper(hi, n, pr)
        # the other rows, lo < r < hi, one flat entry each
        sizes = np.where(above, hi - lo - 1, 0)
        starts = np.concatenate(([0], np.cumsum(sizes)[:-1]))
        tid = np.repeat(np.arange(len(n)), sizes)
        rr = np.arange(int(sizes.sum())) - starts[tid] + lo[tid] + 1
        nt = n[tid]
        base = (lf(nt) - (lf(rr) + lf(nt - rr))) + rr * lpr[tid] + (nt - rr) * l1pr[tid]
        na, qt, tt = nt - rr, q[tid], thr[tid]
        row_above, left, right = _crossings(base, na, qt, tt, lf)
        tails = binom_cdf(left, na, q1[tid]) + binom_upper(right, na, qt)
        contrib = np.where(row_above, base + np.log(tails), base)
        # log(outer + sum over rows of exp(contrib)), per test
        top = np.full(len(n), -np.inf)
        np.maximum.at(top, tid, contrib)
        top = np.maximum(top, np.log(outer))
        safe = np.where(np.isfinite(top), top, 0.0)
        total = np.exp(np.log(outer) - safe)
        total += np.bincount(tid, weights=np.exp(contrib - safe[tid]), minlength=len(n))
        res = np.minimum(safe + np.log(total), 0.0)
        out[live] = np.where(above, res, 0.0)  # no row above: every outcome counts
    return out


def _exact_pvalues(x, p):
    """Exact p-values of T tests at once: counts ``x`` (T x K) under chances ``p`` (T x K),
    K = 2 or 3, each row of ``p`` summing to 1.  See :func:`exact_pvalue`."""
    import numpy as np

    x = np.asarray(x, dtype=np.int64)
    p = np.asarray(p, dtype=float)
    # experiments of one coin and one model often repeat their counts: each distinct test once
    key = np.ascontiguousarray(np.concatenate([x.astype(float), p], axis=1))
    key = key.view(np.dtype((np.void, key.dtype.itemsize * key.shape[1]))).ravel()
    _, first, inverse = np.unique(key, return_index=True, return_inverse=True)
    if len(first) < len(x):
        return _exact_pvalues(x[first], p[first])[inverse.ravel()]
    out = np.ones(len(x))
    impossible = np.any((p == 0) & (x > 0), axis=1)
    out[impossible] = 0.0
    # the rarer categories first: 1 - p loses a chance below 1e-16 (a face of a very thick coin
    # is 2.5e-19 at xi = 1e9, while its sides chance rounds to 1.0)
    order = np.argsort(p, axis=1, kind="stable")
    xs = np.take_along_axis(x, order, axis=1)
    ps = np.take_along_axis(p, order, axis=1)
    live = (ps > 0).sum(axis=1)
    K = x.shape[1]
    two = ~impossible & (live == 2)
    if np.any(two):
        out[two] = _binomial_pvalues(xs[two, K - 2], xs[two, K - 2] + xs[two, K - 1],
                                     ps[two, K - 2], ps[two, K - 1])
    three = ~impossible & (live == 3)
    if np.any(three):
        out[three] = np.exp(_trinomial_logp(xs[three], ps[three]))
    return out


def exact_pvalue(counts: Sequence[int], probs: Sequence[float]) -> float:
    """Exact goodness-of-fit p-value of 2 or 3 category counts under the chances ``probs``.

    The sum of the model probabilities of all outcomes with the same total that are no more
    likely than the observed one (to a relative 1e-7, as in :func:`scipy.stats.binomtest`); see
    the module docstring.  Categories the model gives probability 0 are dropped when their count
    is 0; a positive count in one makes the observation impossible and the p-value 0.  Two
    categories: the binomial test (scipy.stats.binomtest's p-value, from the incomplete beta
    function).  Three: :func:`_trinomial_logp`.

    The value is exact for any ``n`` but the trinomial case costs O(n) memory and time (about
    0.1 s at ``n = 10^6``); :func:`goodness_of_fit` uses :func:`g_test` above :data:`EXACT_MAX_N`.

    >>> round(exact_pvalue([35, 33, 32], [1/3, 1/3, 1/3]), 4)
    0.9519
    >>> exact_pvalue([50, 50], [0.5, 0.5])
    1.0
    """
    x = [whole_count(v, "counts") for v in counts]
    if len(x) not in (2, 3):
        raise ValueError(f"counts must have 2 or 3 categories, got {len(x)}")
    p = check_probs(probs, len(x))
    if sum(x) == 0:
        raise ValueError("counts are all zero: no tosses to test")
    return float(_exact_pvalues([x], [p])[0])


def _g_tests(x, p):
    """``(G, df, p)`` arrays of the likelihood-ratio test for T tests (see :func:`g_test`)."""
    import numpy as np
    from scipy.special import chdtrc, xlogy

    x = np.asarray(x, dtype=float)
    p = np.asarray(p, dtype=float)
    n = x.sum(axis=1, keepdims=True)
    pos = p > 0
    impossible = np.any(~pos & (x > 0), axis=1)
    df = pos.sum(axis=1) - 1
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        terms = np.where(pos, xlogy(x, x / (n * p)), 0.0)
        g = np.maximum(2.0 * terms.sum(axis=1), 0.0)
        pv = np.where(df > 0, chdtrc(np.maximum(df, 1), g), 1.0)
    g = np.where(impossible, np.inf, g)
    pv = np.where(impossible, 0.0, pv)
    return g, df, pv


def g_test(counts: Sequence[int], probs: Sequence[float]) -> tuple[float, int, float]:
    r"""Likelihood-ratio (G) test: ``(G, df, p)`` with ``G = 2 sum O ln(O/E)`` and ``p`` from chi2.

    ``df`` is the number of categories with positive expected count minus 1; a positive count
    where the model expects none gives ``G = inf`` and ``p = 0``.  Asymptotic: reliable when
    every expected count is large (say >= 5); :func:`exact_pvalue` has no such condition.
    The chi-square tail is ``scipy.special.chdtrc``.
    """
    x = [whole_count(v, "counts") for v in counts]
    p = check_probs(probs, len(x))
    if sum(x) == 0:
        raise ValueError("counts are all zero: no tosses to test")
    g, df, pv = _g_tests([x], [p])
    return float(g[0]), int(df[0]), float(pv[0])


def _log_likelihoods(x, n, p, faces, caught=None, same=None):
    """Log-probabilities of T observations: ``x`` (T x 3) counts (heads, sides, tails; only the
    sides column is read where ``faces`` is False), ``p`` (T x 3) normalized chances.  Rows
    marked ``caught`` are ``same`` of ``n`` caught flips, binomial with the chance
    ``P(H) / (P(H) + P(T))`` (:mod:`coincli.core.stats.caught`)."""
    import numpy as np
    from scipy.special import xlogy

    x = np.asarray(x, dtype=np.int64)
    n = np.asarray(n, dtype=np.int64)
    p = np.asarray(p, dtype=float)
    faces = np.asarray(faces, dtype=bool)
    lf = LogFactorial(int(np.max(n, initial=0)))
    out = np.empty(len(n))
    caught = np.zeros(len(n), bool) if caught is None else np.asarray(caught, dtype=bool)
    with np.errstate(divide="ignore", invalid="ignore"):
        if np.any(faces):
            xf, pf = x[faces], p[faces]
            out[faces] = lf(n[faces]) + np.sum(xlogy(xf, pf) - lf(xf), axis=1)
        if np.any(caught):
            s, m = np.asarray(same, dtype=np.int64)[caught], n[caught]
            ph, pt = p[caught, 0], p[caught, 2]
            out[caught] = ((lf(m) - (lf(s) + lf(m - s))) + xlogy(s, ph / (ph + pt))
                           + xlogy(m - s, pt / (ph + pt)))
        side = ~faces & ~caught
        if np.any(side):
            k, m = x[side, 1], n[side]
            ps, pface = p[side, 1], p[side, 0] + p[side, 2]
            # the rarer category's chance: 1 - ps loses a face chance below 1e-16
            out[side] = np.where(ps <= 0.5, binom_logpmf(k, m, ps, lf),
                                 binom_logpmf(m - k, m, pface, lf))
    return np.where(np.isnan(out), -np.inf, out)


def log_likelihood(counts: Counts, probs) -> float:
    """Log-probability of the observed counts under the model's chances ``probs``.

    ``probs`` is an :class:`Outcome` (or ``(heads, sides, tails)``).  Faces told apart: the
    multinomial log-pmf; sides only: the binomial log-pmf of ``sides`` with ``P(sides)``.  The
    coefficient is included (the formulas of scipy.stats' ``multinomial.logpmf`` and
    ``binom.logpmf``).  ``-inf`` when the model gives the counts probability 0.
    """
    p = check_probs(probs, 3)
    x = (counts.heads, counts.sides, counts.tails) if counts.faces else (0, counts.sides, 0)
    return float(_log_likelihoods([x], [counts.n], [p], [counts.faces])[0])



# --------------------------------------------------------------------------- verdicts


def format_p(p: float) -> str:
    """``p = 0.43``, ``p = 0.0052``, ``p = 3.1e-7``; ``p < 1e-300`` below the display floor."""
    if not p >= P_DISPLAY_FLOOR:
        return "p < 1e-300"
    if p >= 1e-3:
        return f"p = {p:.2g}"
    mant, _, exp = f"{p:.1e}".partition("e")
    return f"p = {mant.rstrip('0').rstrip('.')}e{int(exp)}"


def percent(level: float) -> str:
    """A level as a percentage that names the double exactly, never rounded to a neighbour:
    ``0.95 -> '95%'``, ``0.9999999999999999 -> '99.99999999999999%'`` (not '100%'),
    ``1e-300 -> '1e-298%'``."""
    level = float(level)
    if not math.isfinite(level) or level < 0:  # not a level; say it as Decimal does
        from decimal import Decimal

        d = (Decimal(repr(level)) * 100).normalize()
        return (format(d, "f") if d.adjusted() >= -6 else format(d, "e")) + "%"
    # The repr's digits times 10^2, shifted as text: the decimal module's exact product and
    # format, without its import (a few ms of every check and fit).
    mant, _, exp = repr(level).partition("e")
    whole, _, frac = mant.partition(".")
    digits = (whole + frac).lstrip("0")
    power = int(exp or 0) - len(frac) + 2  # level * 100 = int(digits) * 10^power
    if not digits:
        return "0%"
    stripped = digits.rstrip("0")
    power += len(digits) - len(stripped)
    digits = stripped
    if power + len(digits) - 1 < -6:  # Decimal's 'e' format
        tail = f".{digits[1:]}" if len(digits) > 1 else ""
        return f"{digits[0]}{tail}e{power + len(digits) - 1}%"
    if power >= 0:
        return digits + "0" * power + "%"
    point = len(digits) + power
    if point > 0:
        return f"{digits[:point]}.{digits[point:]}%"
    return f"0.{'0' * -point}{digits}%"


def verdict(p: float, alpha: float = ALPHA, *, exact: bool = True, impossible: bool = False
            ) -> str:
    """A verdict in words that claims no more than the test shows.

    ``"consistent at the 5% level (p = 0.43)"`` (the data do not contradict the model; they do
    not prove it), ``"rejected, p = 3.1e-7"``, and ``"rejected: impossible under the model"``
    when the model gives the counts probability 0.  A non-exact test adds its name.
    """
    a = check_level(alpha, "alpha")
    if impossible:
        return "rejected: these counts are impossible under the model (probability 0)"
    if p >= a:
        text = f"consistent at the {percent(a)} level ({format_p(p)})"
    else:
        text = f"rejected, {format_p(p)}"
    return text if exact else text + " (asymptotic G-test)"



# --------------------------------------------------------------------------- one experiment


class ModelTest(namedtuple("ModelTest", "model chances categories expected p_value exact "
                                        "method g_statistic df log_likelihood verdict")):
    """How one model fares on one experiment."""

    # model: str
    # chances: Outcome  (heads, sides, tails) as the model gave them (tests renormalize)
    # categories: tuple[str, ...]  the tested categories: heads/sides/tails or sides/faces
    # expected: tuple[float, ...]  expected counts, in the order of categories
    # p_value: float
    # exact: bool
    # method: str  "exact multinomial", "exact binomial" or "G-test (asymptotic chi2, df=k)"
    # g_statistic: float  likelihood-ratio statistic against the observed frequencies
    # df: int
    # log_likelihood: float
    # verdict: str
    __slots__ = ()


def _chance_columns(chances, size: int, name: str = "chances"):
    """(heads, sides, tails) arrays of ``size`` raw chances and the normalized T x 3 matrix;
    ValueError as :func:`check_probs` words it, for the first bad row."""
    import numpy as np

    try:
        raw = np.stack([np.broadcast_to(np.asarray(v, dtype=float), (size,)) for v in chances])
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be 3 numbers (or arrays of one length), got "
                         f"{chances!r}") from None
    if raw.shape[0] != 3:
        raise ValueError(f"{name} must be 3 numbers, got {raw.shape[0]}")
    with np.errstate(invalid="ignore", over="ignore"):
        total = raw.sum(axis=0)
        bad = ~(np.all(np.isfinite(raw) & (raw >= 0), axis=0) & (np.abs(total - 1.0) <= 1e-6))
    if np.any(bad):
        i = int(np.argmax(bad))
        check_probs(raw[:, i].tolist(), 3, name)  # raises, with the scalar wording
    return raw, (raw / total).T


class _Tests:
    """One model's tests of many experiments, as columns; :meth:`get` gives one ModelTest."""

    def __init__(self, model, raw, categories, expected, p_value, exact, method, g, df, ll,
                 verdicts):
        self.model, self.raw, self.categories, self.expected = model, raw, categories, expected
        self.p_value, self.exact, self.method, self.g, self.df = p_value, exact, method, g, df
        self.log_likelihood, self.verdict = ll, verdicts

    def get(self, i: int) -> ModelTest:
        faces = len(self.categories[i]) == 3
        return ModelTest(self.model, Outcome(*(float(v) for v in self.raw[:, i])),
                         self.categories[i],
                         tuple(float(v) for v in (self.expected[:, i] if faces
                                                  else self.expected[:2, i])),
                         float(self.p_value[i]), bool(self.exact[i]), self.method[i],
                         float(self.g[i]), int(self.df[i]), float(self.log_likelihood[i]),
                         self.verdict[i])


_CATS3 = ("heads", "sides", "tails")
_CATS2 = ("sides", "faces")
_CATS_CAUGHT = ("same", "different")
#: the test of a caught row, named: conditioned on a face
CAUGHT_TEST = " of same side, given a face"


def _tested(cc: CountColumns, p):
    """The tested counts ``x``, their chances ``q`` (T x 3; the third column 0 where two
    categories are tested) and the expected counts (3 x T, of the raw chances ``p`` as given)
    of the rows of ``cc`` under the normalized chances ``p`` (T x 3): faces told apart (heads,
    sides, tails); else (sides, faces); caught flips (same, different)."""
    import numpy as np

    faces = cc.faces
    T = len(cc)
    x = np.where(faces[:, None], cc.matrix(),
                 np.stack([cc.sides, cc.n - cc.sides, np.zeros(T, np.int64)], axis=1))
    side, face = p[:, 1], p[:, 0] + p[:, 2]
    total2 = side + face  # side or face: renormalized as a pair, as a two-category test is
    q = np.where(faces[:, None], p, np.stack([side / total2, face / total2, np.zeros(T)], axis=1))
    caught = cc.caught
    if np.any(caught):  # conditioned on a face: same ~ Binomial(n, P(H) / (P(H) + P(T)))
        with np.errstate(divide="ignore", invalid="ignore"):
            qs, qd = p[:, 0] / face, p[:, 2] / face
        x = np.where(caught[:, None], np.stack([cc.same, cc.n - cc.same,
                                                np.zeros(T, np.int64)], axis=1), x)
        q = np.where(caught[:, None], np.stack([qs, qd, np.zeros(T)], axis=1), q)
    return x, q, (qs, qd) if np.any(caught) else None


def _exact_rows(cc: CountColumns, method: str):
    """Which rows get the exact test (``auto``: n at most :data:`EXACT_MAX_N`)."""
    import numpy as np

    return np.full(len(cc), method == "exact") | ((method == "auto") & (cc.n <= EXACT_MAX_N))


_METHOD_NAMES: dict = {}


def _method_name(faces: bool, exact: bool, df: int, caught: bool) -> str:
    """The name of a row's test (each distinct one built once: a file of 10^5 rows holds
    references, not 10^5 texts)."""
    key = (faces, exact, df, caught)
    m = _METHOD_NAMES.get(key)
    if m is None:
        m = (("exact multinomial" if faces else "exact binomial") if exact else
             f"G-test (asymptotic chi2, df={df})")
        m = _METHOD_NAMES[key] = m + CAUGHT_TEST if caught else m
    return m


def _model_tests(cc: CountColumns, chances, model: str, alpha: float, method: str) -> _Tests:
    """Test every experiment of ``cc`` against a model's ``chances`` (arrays, one per row)."""
    import numpy as np

    a = check_level(alpha, "alpha")
    raw, p = _chance_columns(chances, len(cc), "chances")
    faces = cc.faces
    T = len(cc)
    x, q, same = _tested(cc, p)
    nf = cc.n.astype(float)
    expected = np.where(faces, nf * raw, np.stack([nf * raw[1], nf * (raw[0] + raw[2]),
                                                   np.zeros(T)]))
    caught = cc.caught
    if same is not None:
        qs, qd = same
        expected = np.where(caught, np.stack([nf * qs, nf * qd, np.zeros(T)]), expected)
    g, df, p_asym = np.empty(T), np.empty(T, np.int64), np.empty(T)
    pv = np.empty(T)
    exact = _exact_rows(cc, method)
    for sel, k in ((faces, 3), (~faces, 2)):
        if not np.any(sel):
            continue
        g[sel], df[sel], p_asym[sel] = _g_tests(x[sel, :k], q[sel, :k])
        ex = sel & exact
        pv[sel] = p_asym[sel]
        if np.any(ex):
            pv[ex] = _exact_pvalues(x[ex, :k], q[ex, :k])
    ll = _log_likelihoods(cc.matrix(), cc.n, p, faces, caught, cc.same)
    impossible = ll == -np.inf
    pv = np.where(impossible, 0.0, pv)
    methods = [_method_name(*key) for key in zip(faces.tolist(), exact.tolist(), df.tolist(),
                                                 caught.tolist(), strict=True)]
    verdicts = _verdicts(pv, a, exact, impossible)
    cats = [_CATS3 if f else _CATS2 for f in faces.tolist()]
    if np.any(caught):
        cats = [_CATS_CAUGHT if c else k for k, c in zip(cats, caught.tolist(), strict=True)]
    return _Tests(model, raw, cats, expected, pv, exact, methods, g, df, ll, verdicts)


def _verdicts(p, alpha: float, exact, impossible) -> list[str]:
    """:func:`verdict` of each test; each distinct (p, exact, impossible) worded once."""
    memo: dict = {}
    out = []
    for key in zip(p.tolist(), exact.tolist(), impossible.tolist(), strict=True):
        text = memo.get(key)
        if text is None:
            text = memo[key] = verdict(key[0], alpha, exact=key[1], impossible=key[2])
        out.append(text)
    return out


def goodness_of_fit(counts: Counts, chances, model: str = "model", *, alpha: float = ALPHA,
                    method: str = "auto") -> ModelTest:
    """Test ``counts`` against a model's ``chances`` (heads, sides, tails).

    ``method``: ``"auto"`` (exact when ``n <= EXACT_MAX_N``, else the G-test), ``"exact"`` or
    ``"asymptotic"``.  With faces told apart the test is trinomial; otherwise binomial in
    ``sides`` against ``P(sides)``.
    """
    check_method(method)
    return _model_tests(CountColumns([counts]), chances, model, alpha, method).get(0)


def check_method(method) -> None:
    if method not in ("auto", "exact", "asymptotic"):
        raise ValueError(f"method must be 'auto', 'exact' or 'asymptotic', got {method!r}")


def model_chances(xi, densities: Mapping[str, object] | None = None) -> dict[str, Outcome]:
    """The chances under the geometric and dynamic models, and under each psi density given.

    ``densities`` maps a name to a :class:`coincli.core.densities.Density`; its chances are the
    psi-average :func:`coincli.core.averages.marginal`.  ``xi`` may be an array (then so are the
    chances).
    """
    from coincli.core.models import dynamic, geometric

    out = {"geometric": geometric(xi), "dynamic": dynamic(xi)}
    for name, dens in (densities or {}).items():
        from coincli.core.averages import marginal

        out[name] = marginal(xi, dens)
    return out


class CheckResult(namedtuple("CheckResult", "xi counts proportions tests label", defaults=("",))):
    """One experiment: the frequencies with intervals, and each model's test."""

    # xi: float
    # counts: Counts
    # proportions: tuple[Proportion, ...]
    # tests: tuple[ModelTest, ...]
    # label: str
    __slots__ = ()
#: rows whose tests and intervals are computed together when a :class:`Checks` is read a part
#: at a time (a file of 10^5 rows never holds more than this many rows' tests)
CHECK_BLOCK = 8192


class _Part:
    """The tests and intervals of rows ``start`` to ``stop`` of a :class:`Checks` (arrays over
    those rows alone)."""

    __slots__ = ("start", "stop", "tests", "intervals")

    def __init__(self, start, stop, tests, intervals):
        self.start, self.stop, self.tests, self.intervals = start, stop, tests, intervals

    def sliced(self, a: int, b: int) -> _Part:
        """Rows ``a`` to ``b`` (indices of the whole) of this part."""
        if (a, b) == (self.start, self.stop):
            return self
        i, j = a - self.start, b - self.start
        tests = None if self.tests is None else [
            _Tests(t.model, t.raw[:, i:j], t.categories[i:j], t.expected[:, i:j],
                   t.p_value[i:j], t.exact[i:j], t.method[i:j], t.g[i:j], t.df[i:j],
                   t.log_likelihood[i:j], t.verdict[i:j]) for t in self.tests]
        return _Part(a, b, tests, None if self.intervals is None else {
            k: [v[i:j] for v in cols] for k, cols in self.intervals.items()})


class Checks(RowSequence):
    """Many experiments checked, as columns; ``checks[i]`` is the :class:`CheckResult` of row
    ``i`` (built on demand).

    The tests and intervals are computed when read, a block of :data:`CHECK_BLOCK` rows at a
    time (:meth:`part`; the last block is kept), so that a file of 10^5 rows is written without
    ever holding every row's tests: what is held is the counts and each model's chances (per
    coin, with ``index`` the coin of each row).  :attr:`tests` and :attr:`intervals` compute
    every row at once (and keep it): ``tests`` one :class:`_Tests` per model, in order;
    ``intervals[outcome]`` the estimate, Wilson low/high and Clopper-Pearson low/high arrays
    (NaN where an outcome was not counted).  Columns: ``xi``, ``labels``, ``cc`` (the counts).
    """

    def __init__(self, xi, labels, cc: CountColumns, chances, confidence: float,
                 alpha: float = ALPHA, method: str = "auto", index=None):
        self.xi, self.labels, self.cc = xi, labels, cc
        self.confidence, self.alpha, self.method = confidence, alpha, method
        self._chances, self._index = chances, index
        self.models = list(chances)
        self._full: _Part | None = None
        self._blocks: dict = {}  #: the last block read, of each kind (tests, intervals)

    def __len__(self):
        return len(self.cc)

    def _chances_of(self, a: int, b: int) -> dict:
        """Each model's chances of rows ``a`` to ``b`` (arrays of ``b - a``)."""
        import numpy as np

        T = len(self.cc)
        idx = None if self._index is None else self._index[a:b]
        out = {}
        for name, ch in self._chances.items():
            cols = []
            for v in ch:
                v = np.asarray(v, dtype=float)
                if idx is not None and v.ndim:
                    cols.append(v[idx])
                else:
                    cols.append(np.broadcast_to(v, (T,))[a:b])
            out[name] = cols
        return out

    def _compute(self, a: int, b: int, tests: bool = True, intervals: bool = True) -> _Part:
        cc = self.cc if (a, b) == (0, len(self.cc)) else self.cc.rows(a, b)
        return _Part(a, b, [_model_tests(cc, ch, name, self.alpha, self.method)
                            for name, ch in self._chances_of(a, b).items()] if tests else None,
                     _intervals(cc, self.confidence) if intervals else None)

    def part(self, a: int, b: int, *, tests: bool = True, intervals: bool = True) -> _Part:
        """The tests and intervals of rows ``a`` to ``b`` (only those asked for): from the
        whole when computed, else from the block of :data:`CHECK_BLOCK` rows that holds them,
        computed from row ``a`` on when first read and kept until a row outside it is read
        (rows read in order are each computed once)."""
        a, b = max(a, 0), min(b, len(self))
        if self._full is not None:
            return self._full.sliced(a, b)
        key = (tests, intervals)
        blk = self._blocks.get(key)
        if blk is None or not blk.start <= a <= b <= blk.stop:
            if b - a > CHECK_BLOCK:
                return self._compute(a, b, tests, intervals)
            blk = self._blocks[key] = self._compute(a, min(a + CHECK_BLOCK, len(self)), tests,
                                                    intervals)
        return blk.sliced(a, b)

    def _whole(self) -> _Part:
        if self._full is None:
            self._full = self._compute(0, len(self))
            self._blocks.clear()
        return self._full

    @property
    def tests(self) -> list:
        """Every row's tests, one :class:`_Tests` per model (computed at once, and kept)."""
        return self._whole().tests

    @property
    def intervals(self) -> dict:
        return self._whole().intervals

    def methods(self) -> set[str]:
        """The names of the tests run on any row by any model (without running them)."""
        import numpy as np

        if self._full is not None:
            return {m for t in self._full.tests for m in set(t.method)}
        names = set()
        for a in range(0, len(self), CHECK_BLOCK):
            b = min(a + CHECK_BLOCK, len(self))
            cc = self.cc.rows(a, b)
            for ch in self._chances_of(a, b).values():
                _, p = _chance_columns(ch, b - a, "chances")
                _, q, _ = _tested(cc, p)
                df = np.where(cc.faces, (q > 0).sum(axis=1), (q[:, :2] > 0).sum(axis=1)) - 1
                exact = _exact_rows(cc, self.method)
                keys = np.unique(np.stack([cc.faces, exact, df, cc.caught], axis=1), axis=0)
                names |= {_method_name(bool(f), bool(e), int(d), bool(c))
                          for f, e, d, c in keys.tolist()}
        return names

    def log_likelihoods(self):
        """Each model's log-likelihood of every row, a block at a time: ``{model: iterator of
        arrays}`` in row order (to be summed without holding them all)."""
        def blocks(name):
            for a in range(0, len(self), CHECK_BLOCK):
                b = min(a + CHECK_BLOCK, len(self))
                cc = self.cc.rows(a, b)
                _, p = _chance_columns(self._chances_of(a, b)[name], b - a, "chances")
                yield _log_likelihoods(cc.matrix(), cc.n, p, cc.faces, cc.caught, cc.same)

        if self._full is not None:
            return {t.model: iter([t.log_likelihood]) for t in self._full.tests}
        return {name: blocks(name) for name in self.models}

    def chances_of(self, name: str, a: int, b: int):
        """Model ``name``'s (heads, sides, tails) arrays for rows ``a`` to ``b``."""
        return self._chances_of(a, b)[name]

    def _row(self, i):
        c = self.cc.count(i)
        part = self.part(i, i + 1)
        props = []
        for name in (_CATS3 if c.faces else ("same",) if c.categories == _CATS_CAUGHT
                     else ("sides",)):
            est, wl, wh, cl, ch = (float(v[0]) for v in part.intervals[name])
            conf = self.confidence
            props.append(Proportion(name, getattr(c, name), c.n, est,
                                    Interval(wl, wh, "wilson", conf),
                                    Interval(cl, ch, "clopper-pearson", conf)))
        return CheckResult(float(self.xi[i]), c, tuple(props),
                           tuple(t.get(0) for t in part.tests), self.labels[i])


def _intervals(cc: CountColumns, conf: float) -> dict:
    """The estimate, Wilson and Clopper-Pearson intervals of each counted outcome of the rows
    of ``cc`` (NaN where not counted); each distinct (count, n) pair once."""
    import numpy as np

    T = len(cc)
    ks = np.concatenate([cc.heads, cc.sides, cc.tails])
    pairs, inverse = np.unique(np.stack([ks, np.tile(cc.n, 3)], axis=1), axis=0,
                               return_inverse=True)
    inverse = inverse.ravel()
    pk, pn = pairs[:, 0], pairs[:, 1]
    ends = [*wilson_interval(pk, pn, conf), *clopper_pearson_interval(pk, pn, conf)]
    intervals = {}
    for j, (name, k) in enumerate((("heads", cc.heads), ("sides", cc.sides),
                                   ("tails", cc.tails))):
        sel = inverse[j * T:(j + 1) * T]
        cols = [k / cc.n, *(v[sel] for v in ends)]
        if name != "sides":
            cols = [np.where(cc.faces, v, np.nan) for v in cols]
        elif np.any(cc.caught):
            cols = [np.where(cc.caught, np.nan, v) for v in cols]
        # an outcome no row counted (heads of a file of caught flips): one read-only NaN
        # broadcast, not T of them
        intervals[name] = [np.broadcast_to(np.nan, (T,)) if np.isnan(v).all() else v
                           for v in cols]
    if np.any(cc.caught):  # the chance of the same side, caught rows only; each pair once
        c = np.flatnonzero(cc.caught)
        sp, sinv = np.unique(np.stack([cc.same[c], cc.n[c]], axis=1), axis=0,
                             return_inverse=True)
        sinv = sinv.ravel()
        ends = [*wilson_interval(sp[:, 0], sp[:, 1], conf),
                *clopper_pearson_interval(sp[:, 0], sp[:, 1], conf)]
        cols = []
        for v in [sp[:, 0] / sp[:, 1], *ends]:
            col = np.full(T, np.nan)
            col[c] = v[sinv]
            cols.append(col)
        intervals["same"] = cols
    else:
        intervals["same"] = [np.broadcast_to(np.nan, (T,))] * 5
    return intervals


def check_many(counts: Sequence[Counts], xi, chances: Mapping[str, object], *,
               confidence: float = CONFIDENCE, alpha: float = ALPHA, method: str = "auto",
               labels: Sequence[str] | None = None, index=None) -> Checks:
    """:func:`check` for many experiments at once: ``xi`` and each model's chances are arrays,
    one entry per experiment (or, with ``index``, one per coin, ``index`` giving each row's
    coin).  The result is columnar and lazy (:class:`Checks`): the exact tests of a block of
    rows run together (see :func:`_trinomial_logp`) when the block is read.  The chances are
    checked here: a bad one raises ValueError now, not when a row is read."""
    import numpy as np

    check_method(method)
    conf = check_level(confidence, "confidence")
    check_level(alpha, "alpha")
    cc = counts if isinstance(counts, CountColumns) else CountColumns(counts)
    T = len(cc)
    xs = np.broadcast_to(np.asarray(xi, dtype=float), (T,))
    if index is not None:
        index = np.asarray(index, dtype=np.int64).reshape(-1)
        if len(index) != T:
            raise ValueError(f"index must have one entry per experiment, got {len(index)} for "
                             f"{T}")
    for ch in chances.values():  # every model's chances valid (per coin when indexed)
        size = T
        if index is not None:
            arrs = [np.asarray(v, dtype=float) for v in ch]
            size = max((v.size for v in arrs if v.ndim), default=1)
        _chance_columns(ch, size, "chances")
    return Checks(xs, labels if labels is not None else [""] * T, cc, dict(chances), conf,
                  alpha, method, index)


def check(counts: Counts, xi: float, chances: Mapping[str, object] | None = None, *,
          confidence: float = CONFIDENCE, alpha: float = ALPHA, method: str = "auto",
          label: str = "") -> CheckResult:
    """Check tosses of a coin of aspect ratio ``xi`` against models.

    ``chances`` maps a model name to its (heads, sides, tails); the default is
    :func:`model_chances` (geometric and dynamic).
    """
    from coincli.core.stats.counts import Caught

    if not isinstance(counts, (Counts, Caught)):
        raise ValueError(f"counts must be a Counts (see make_counts), got {counts!r}")
    if chances is None:
        chances = model_chances(xi)
    return check_many([counts], xi, chances, confidence=confidence, alpha=alpha, method=method,
                      labels=[label])[0]

