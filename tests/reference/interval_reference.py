r"""Reference confidence intervals for a binomial proportion, in mpmath, written from the
definitions (independently of ``coincli.core.stats.intervals``):

- Clopper-Pearson: with ``a = (1 - confidence) / 2``, ``low`` solves ``P(X >= k | low) = a`` and
  ``high`` solves ``P(X <= k | high) = a`` for ``X ~ Binomial(n, p)``; equivalently ``low`` is
  the ``a`` quantile of Beta(k, n - k + 1) and ``high`` the ``1 - a`` quantile of
  Beta(k + 1, n - k).  ``low = 0`` at ``k = 0`` and ``high = 1`` at ``k = n``.
- Wilson: the roots ``p`` of ``(k/n - p)^2 = z^2 p (1 - p) / n`` with ``z`` the two-sided normal
  quantile, ``erfc(z / sqrt 2) = 1 - confidence``.

The beta tails are integrals of the beta density, taken by ``mp.quad`` from the quantile down
to 0 over pieces that grow geometrically (so that a density of width 1e-8, at ``n = 2^53``,
is integrated as accurately as one of width 0.3), with ``log B(a, b)`` from ``mp.loggamma``;
an upper quantile is 1 minus the lower quantile of the mirrored beta.  The quantile is found by
Newton's method in 40-digit arithmetic, started from the double under test and ended when the
step is below 1e-30 relative.  Confidence and counts are taken exactly as the doubles and
integers given.
"""

from __future__ import annotations

import mpmath
from mpmath import mp, mpf

DPS = 40  #: working digits
STOP = 30  #: Newton stops when a step is below 10^-STOP relative


def _lower_tail(a, b, x, lbeta):
    """``I_x(a, b)``: the integral of the beta density from 0 to x, taken from x downward (in
    ``s = x - t``) over pieces that double in length from a first one set by the log-density's
    slope at x, until a piece adds nothing at this precision."""

    def density(s):
        t = x - s
        return mp.exp((a - 1) * mp.log(t) + (b - 1) * mp.log1p(-t) - lbeta)

    slope = abs((a - 1) / x - (b - 1) / (1 - x))
    length = min(x, 1 / slope if slope > 0 else x) / 4
    total, start = mpf(0), mpf(0)
    while start < x:
        stop = min(start + length, x)
        piece = mp.quad(density, [start, stop])
        total += piece
        if piece <= total * mpf(10) ** (-DPS):
            break
        start, length = stop, length * 2
    return total


def lower_quantile(a, b, y, start: float):
    """x with ``I_x(a, b) = y``, by Newton's method from ``start``, kept inside a bracket."""
    with mp.workdps(DPS):
        a, b, y = mpf(a), mpf(b), mpf(y)
        lbeta = mp.loggamma(a) + mp.loggamma(b) - mp.loggamma(a + b)
        x = mpf(start)
        if not 0 < x < 1:
            x = a / (a + b)
        lo, hi = mpf(0), mpf(1)
        for _ in range(100):
            v = _lower_tail(a, b, x, lbeta) - y
            d = mp.exp((a - 1) * mp.log(x) + (b - 1) * mp.log1p(-x) - lbeta)
            if v > 0:
                hi = min(hi, x)
            else:
                lo = max(lo, x)
            new = x - v / d
            if not lo <= new <= hi:
                new = (lo + hi) / 2
            if abs(new - x) <= abs(x) * mpf(10) ** -STOP:
                return new
            x = new
        raise RuntimeError(f"no convergence for {a}, {b}, {y}")


def clopper_pearson(k: int, n: int, confidence: float, start=(0.5, 0.5)):
    """(low, high) as mpf; ``start`` are the doubles to start Newton from.  ``high`` is found
    as ``1 - x`` with ``I_x(n - k, k + 1) = a`` (the mirrored beta)."""
    with mp.workdps(DPS):
        a = (1 - mpf(confidence)) / 2
        low = mpf(0) if k == 0 else lower_quantile(k, n - k + 1, a, start[0])
        high = mpf(1) if k == n else 1 - lower_quantile(n - k, k + 1, a, 1 - mpf(start[1]))
        return low, high


def wilson(k: int, n: int, confidence: float):
    with mp.workdps(DPS):
        c = mpf(confidence)
        z = mp.sqrt(2) * mp.erfinv(c)
        k, n = mpf(k), mpf(n)
        z2 = z * z
        root = z * mp.sqrt(k * (n - k) / n + z2 / 4)
        low = (k + z2 / 2 - root) / (n + z2)
        high = (k + z2 / 2 + root) / (n + z2)
        return (mpf(0) if k == 0 else low), (mpf(1) if k == n else high)


def relative_error(value: float, ref) -> float:
    with mp.workdps(DPS):
        if ref == 0:
            return 0.0 if value == 0 else float("inf")
        return float(abs(mpf(value) / ref - 1))


__all__ = ["DPS", "lower_quantile", "clopper_pearson", "wilson", "relative_error", "mpmath"]
