"""Confidence intervals for an observed frequency ``count / n``.

Wilson score (:func:`coincli.core._numerics.wilson.wilson_interval`, its one home) and
Clopper-Pearson ("exact", :func:`clopper_pearson_interval`) intervals for each observed
frequency: the Wilson ends without cancellation, the Clopper-Pearson ends as beta quantiles
(closed forms at ``k = 0, 1, n - 1, n``; otherwise scipy.special's inverse polished by the secant
method on ``betainc``/``betaincc``, :func:`_beta_quantile`), both finite for every level in
(0, 1) and within 19 ulps of mpmath up to ``n = 2^53``.  :func:`proportion` and
:func:`proportions` give an outcome's frequency with both intervals.

numpy and scipy.special are imported inside the functions that need them.
"""

from __future__ import annotations

import math
from collections import namedtuple

from coincli.core._numerics.wilson import CONFIDENCE, check_level, wilson_interval
from coincli.core.stats.counts import Counts, whole_count

__all__ = [
    "Interval",
    "Proportion",
    "clopper_pearson_interval",
    "proportion",
    "proportions",
]


class Interval(namedtuple("Interval", "low high method confidence")):
    """A confidence interval for a proportion."""

    # low: float
    # high: float
    # method: str  "wilson" or "clopper-pearson"
    # confidence: float
    __slots__ = ()
class Proportion(namedtuple("Proportion", "outcome count n estimate wilson clopper_pearson")):
    """An observed frequency ``count / n`` with its Wilson and Clopper-Pearson intervals."""

    # outcome: str
    # count: int
    # n: int
    # estimate: float
    # wilson: Interval
    # clopper_pearson: Interval
    __slots__ = ()
def clopper_pearson_interval(count, n, confidence: float = CONFIDENCE):
    """Clopper-Pearson ("exact") interval(s) ``(low, high)`` for ``count`` of ``n`` (arrays too).

    With ``a = (1 - confidence) / 2``: ``low`` is the ``a`` quantile of Beta(k, n - k + 1) and
    ``high`` the ``1 - a`` quantile of Beta(k + 1, n - k) (the chances at which seeing ``k`` or
    more, ``k`` or fewer, has probability ``a``).  Closed forms where the beta is a power:

    - ``k = 0``: low = 0, high = 1 - a^(1/n);   ``k = n``: low = a^(1/n), high = 1;
    - ``k = 1``: low = 1 - (1 - a)^(1/n);        ``k = n - 1``: high = (1 - a)^(1/n);

    each written with ``expm1``/``log1p`` so that a small end keeps its relative accuracy.
    Otherwise ``betaincinv`` (or ``betainccinv`` on the far side, so that a quantile near 1
    never needs ``1 - a`` rounded), polished by the secant method on ``betainc`` (see
    :func:`_beta_quantile`).  ``a >= 2^-54`` for every accepted confidence, so every end is
    finite.  Accuracy against mpmath: docs/accuracy.md.
    """
    import numpy as np

    conf = check_level(confidence, "confidence")
    k = np.asarray(count, dtype=float)
    m = np.asarray(n, dtype=float)
    a = (1.0 - conf) / 2  # exact for conf >= 1/2; a relative rounding below
    la, l1a = math.log(a), math.log1p(-a)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore", under="ignore"):
        mid_lo = (k >= 2) & (k < m)
        mid_hi = (k > 0) & (k <= m - 2)
        lo = np.where(k == m, np.exp(la / m), -np.expm1(l1a / m))
        lo = np.where(m == 1, np.where(k == 1, a, 0.0), lo)
        lo = np.where(k == 0, 0.0, lo)
        hi = np.where(k == 0, -np.expm1(la / m), np.exp(l1a / m))
        hi = np.where(m == 1, np.where(k == 0, 1.0 - a, 1.0), hi)
        hi = np.where(k == m, 1.0, hi)
        if np.any(mid_lo):
            lo = np.where(mid_lo, _beta_quantile(np.where(mid_lo, k, 1.0),
                                                 np.where(mid_lo, m - k + 1, 1.0), a, False), lo)
        if np.any(mid_hi):
            hi = np.where(mid_hi, _beta_quantile(np.where(mid_hi, k + 1, 1.0),
                                                 np.where(mid_hi, m - k, 1.0), a, True), hi)
        # low < k/n < high in exact arithmetic; at a level near 0 both ends are within an ulp
        # or two of the median, on either side after rounding: keep the estimate inside
        est = k / m
    return np.minimum(lo, est), np.maximum(hi, est)


_FEW = 64  #: up to this many terms, a binomial tail is summed term by term ...
_FEW_FROM = 1e7  #: ... when n is past this (below, betaincc is within a few ulps)


def _binom_head(k, n, t):
    """``P(X <= k)`` for ``X ~ Binomial(n, t)``, ``k <= _FEW``, by its ``k + 1`` terms from
    ``(1 - t)^n`` up (each the last times ``(n - j) t / ((j + 1)(1 - t))``): positive terms, a
    few roundings each, at any ``n`` (``betaincc`` loses up to 1e-11 relative at ``n = 10^9``
    for small ``k``)."""
    import numpy as np

    with np.errstate(all="ignore"):
        log_term = n * np.log1p(-t)
        log_ratio = np.log(t) - np.log1p(-t)
        top = log_term.copy()
        logs = [log_term]
        for j in range(int(np.max(k, initial=0))):
            log_term = log_term + (np.log((n - j) / (j + 1.0)) + log_ratio)
            logs.append(np.where(j + 1 <= k, log_term, -np.inf))
            top = np.maximum(top, logs[-1])
        total = sum(np.exp(v - top) for v in logs)
        return np.exp(top) * total


def _beta_quantile(a, b, y: float, upper: bool):
    """x with ``I_x(a, b) = y`` (``upper``: with ``1 - I_x(a, b) = y``), ``0 < y < 1/2``.

    Solved on the side where the answer is at most about 1/2 (the other end as ``1 - x`` of the
    mirrored beta, ``I_x(a, b) = 1 - I_{1-x}(b, a)``), so no ``1 - x`` rounds away a small
    answer.  Started from ``betaincinv``/``betainccinv`` and polished by the secant method on
    ``betainc``/``betaincc`` inside a bracket (bisection when a step leaves it): Boost's inverse
    is off by up to 1e-8 relative at ``a + b ~ 10^15`` (and by half at ``a = 2``,
    ``b = 2^53``), while the forward function is accurate there, and the quantile is well
    conditioned (its relative error is the forward one times ``y / (x I'(x)) <= 1``).  No
    derivative is needed: ``betaln`` at such parameters is a difference of numbers near 10^17.
    """
    import numpy as np

    a, b = np.broadcast_arrays(np.asarray(a, dtype=float), np.asarray(b, dtype=float))
    shape = a.shape
    a, b = a.reshape(-1), b.reshape(-1)
    small = a <= b  # the mean a / (a + b) is at most 1/2: solve for x itself ...
    x = _beta_quantile_on(a, b, y, upper, small)
    # ... unless the answer lies on the other side of 1/2 (a far tail): solve again there
    again = (small & (x > 0.5)) | (~small & (x < 0.5))
    if np.any(again):
        x = np.where(again, _beta_quantile_on(a, b, y, upper, ~small), x)
    return x.reshape(shape)


def _beta_quantile_on(a, b, y: float, upper: bool, small):
    """:func:`_beta_quantile`, solved for x where ``small`` and for 1 - x elsewhere."""
    import numpy as np
    from scipy.special import betainc, betaincc, betainccinv, betaincinv

    aa = np.where(small, a, b)
    bb = np.where(small, b, a)
    # lower quantile: I_x(a, b) = y; mirrored: I_t(b, a) = 1 - y, i.e. 1 - I_t = y.  Upper
    # quantile: 1 - I_x(a, b) = y; mirrored: I_t(b, a) = y.
    lower = np.where(small, not upper, upper)

    # where betaincc loses digits (a small a at a huge b) its value is summed instead
    few = np.flatnonzero(~lower & (aa <= _FEW) & (bb > _FEW_FROM))

    def resid(t):
        """Increasing in t, zero at the answer."""
        with np.errstate(all="ignore"):
            upper_tail = betaincc(aa, bb, t)
            if few.size:  # 1 - I_t(a, b) = P(X <= a - 1), X ~ Binomial(a + b - 1, t): a sum
                upper_tail[few] = _binom_head(aa[few] - 1, aa[few] + bb[few] - 1, t[few])
            return np.where(lower, betainc(aa, bb, t) - y, y - upper_tail)

    with np.errstate(all="ignore"):
        t = np.where(lower, betaincinv(aa, bb, y), betainccinv(aa, bb, y))
    t = np.where((t > 0) & (t < 1), t, 0.5)
    f = resid(t)
    # a bracket [lo, hi] with resid(lo) <= 0 <= resid(hi), widened from the start by relative
    # steps 1e-14, 1.6e-13, ... (one step when the start is already good to 14 digits)
    lo = np.where(f <= 0, t, 0.0)
    hi = np.where(f >= 0, t, 1.0)
    flo = np.where(f <= 0, f, -np.inf)
    fhi = np.where(f >= 0, f, np.inf)
    d = 1e-14
    for _ in range(40):
        down = (f > 0) & (flo == -np.inf)
        up = (f < 0) & (fhi == np.inf)
        if not (down.any() or up.any()):
            break
        probe = np.where(down, t * (1 - min(d, 1.0)), t + (1 - t) * min(d, 1 - 2**-52))
        fp = resid(probe)
        lo_new = (down | up) & (fp <= 0)
        hi_new = (down | up) & (fp >= 0)
        lo, flo = np.where(lo_new, probe, lo), np.where(lo_new, fp, flo)
        hi, fhi = np.where(hi_new, probe, hi), np.where(hi_new, fp, fhi)
        d *= 16
    flo = np.where(np.isfinite(flo), flo, -y)  # resid at 0 (never evaluated: an ideal end)
    fhi = np.where(np.isfinite(fhi), fhi, 1.0)
    # secant from the start toward the far end of the bracket, safeguarded by bisection
    x0, f0 = t, f
    x1 = np.where(f > 0, lo, hi)
    f1 = np.where(f > 0, flo, fhi)
    done = (f == 0)
    best = t.copy()
    for _ in range(100):
        with np.errstate(all="ignore"):
            step = f1 * (x1 - x0) / (f1 - f0)
            x2 = x1 - step
        inside = np.isfinite(x2) & (x2 > lo) & (x2 < hi)
        x2 = np.where(inside, x2, 0.5 * (lo + hi))
        x2 = np.where(done, best, x2)
        f2 = resid(x2)
        lo, flo = np.where(f2 <= 0, x2, lo), np.where(f2 <= 0, f2, flo)
        hi, fhi = np.where(f2 >= 0, x2, hi), np.where(f2 >= 0, f2, fhi)
        best = np.where(done, best, x2)
        done = done | (f2 == 0) | (hi - lo <= 4e-16 * hi) | (x2 == x1)
        if done.all():
            break
        x0, f0, x1, f1 = x1, f1, x2, f2
    # the bracket end with the smaller residual, if it beats the last step
    fb = np.abs(resid(best))
    for end, fe in ((lo, flo), (hi, fhi)):
        better = (np.abs(fe) < fb) & (end > 0) & (end < 1)
        best = np.where(better, end, best)
        fb = np.where(better, np.abs(fe), fb)
    return np.where(small, best, 1.0 - best)


def proportion(count: int, n: int, outcome: str = "sides", confidence: float = CONFIDENCE
               ) -> Proportion:
    """The frequency ``count / n`` with 95% (``confidence``) Wilson and Clopper-Pearson intervals.

    See :func:`wilson_interval` and :func:`clopper_pearson_interval`.  Both stay inside [0, 1]
    and finite for ``count = 0`` and ``count = n``, at any ``n`` and every confidence in (0, 1).

    >>> r = proportion(0, 10**6)
    >>> r.clopper_pearson.low, round(r.clopper_pearson.high, 10)
    (0.0, 3.6889e-06)
    """
    c = whole_count(count, "count")
    m = whole_count(n, "n")
    if m == 0:
        raise ValueError("n must be >= 1, got 0")
    if c > m:
        raise ValueError(f"count must be <= n = {m}, got {c}")
    conf = check_level(confidence, "confidence")
    wl, wh = wilson_interval(c, m, conf)
    cl, ch = clopper_pearson_interval(c, m, conf)
    return Proportion(outcome, c, m, c / m,
                      Interval(float(wl), float(wh), "wilson", conf),
                      Interval(float(cl), float(ch), "clopper-pearson", conf))


def proportions(counts: Counts, confidence: float = CONFIDENCE) -> tuple[Proportion, ...]:
    """A :class:`Proportion` for each observed outcome (heads, sides, tails; or sides only)."""
    if counts.faces:
        return tuple(proportion(k, counts.n, name, confidence)
                     for name, k in zip(("heads", "sides", "tails"), counts.values, strict=True))
    return (proportion(counts.sides, counts.n, "sides", confidence),)

