"""The Wilson score interval and the confidence level it takes: the one implementation, which
:mod:`coincli.core.stats.intervals` and the Monte Carlo estimates import.

It lives in this small module so that ``coin simulate``, which prints a 95% Wilson interval for
each outcome, imports neither scipy nor the statistics of :mod:`coincli.core.stats` (about 2 ms
of its start-up; docs/performance.md).
"""

from __future__ import annotations

import math

CONFIDENCE = 0.95  #: default confidence level of the intervals


def check_level(value, name: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise ValueError(f"{name} must be a number in (0, 1), got {value!r}")
    v = float(value)
    if not 0.0 < v < 1.0:
        raise ValueError(f"{name} must be in (0, 1), got {value!r}")
    return v


#: ``-ndtri((1 - c) / 2)`` of the common levels, bit for bit (tests/test_toss.py): a Wilson
#: interval at these levels needs no scipy (``coin simulate`` draws its 95% ones at start-up).
_Z_COMMON = {0.9: 1.6448536269514729, 0.95: 1.959963984540054, 0.99: 2.5758293035489004}


def two_sided_z(confidence: float) -> float:
    """The two-sided normal quantile: ``P(|Z| <= z) = confidence``, finite for every level in
    (0, 1) (``1 - confidence`` is exact for a level of 1/2 or more; erfinv below)."""
    z = _Z_COMMON.get(confidence)
    if z is not None:
        return z
    from scipy.special import erfinv, ndtri

    if confidence >= 0.5:
        return -float(ndtri((1.0 - confidence) / 2))
    return math.sqrt(2.0) * float(erfinv(confidence))


def wilson_interval(count, n, confidence: float = CONFIDENCE):
    """Wilson score interval(s) ``(low, high)`` for ``count`` successes in ``n`` (arrays too).

    The ends are the roots of ``(k/n - p)^2 = z^2 p (1 - p) / n``.  The upper one is the sum
    ``(k + z^2/2 + z sqrt(k (n-k)/n + z^2/4)) / (n + z^2)`` of positive terms, and the lower one
    comes from the product of the roots, ``k^2 / (n (n + z^2) high)``: no difference of nearly
    equal numbers, so both keep their relative accuracy at ``k = 0``, ``1``, ``n`` and any ``n``
    (scipy's ``center - delta`` loses digits to cancellation at small ``k``).  ``low = 0`` at
    ``k = 0`` and ``high = 1`` at ``k = n`` exactly.
    """
    import numpy as np

    conf = check_level(confidence, "confidence")
    k = np.asarray(count, dtype=float)
    m = np.asarray(n, dtype=float)
    z = two_sided_z(conf)
    z2 = z * z
    with np.errstate(divide="ignore", invalid="ignore"):
        denom = m + z2
        hi = (k + z2 / 2 + z * np.sqrt(k * ((m - k) / m) + z2 / 4)) / denom
        lo = np.where(k > 0, (k * (k / m)) / (denom * hi), 0.0)
    hi = np.where(k >= m, 1.0, np.minimum(hi, 1.0))
    # both ends tend to k/n as the level tends to 0: keep the estimate inside after rounding
    est = k / m
    return np.minimum(lo, est), np.maximum(hi, est)
