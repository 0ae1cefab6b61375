r"""Do two sets of counts come from the same chances?  The test of ``coin check --landing
bounce``, where the model's chances are themselves estimated by simulated tosses.

Comparing the user's counts with a simulated table's frequencies as if those were exact would
ignore the simulation's own sampling error (a few thousand simulated tosses are not much more
precise than a few hundred real ones).  The honest question is whether the two samples (the
experiment and the simulation) share one set of chances: a test of homogeneity of a 2 x k
contingency table, conditional on its margins.

Exact (Freeman & Halton 1951)
    Given the row totals (the experiment's ``n1`` tosses, the simulation's ``n2``) and the
    column totals (each outcome's count in both), the experiment's row is multivariate
    hypergeometric under the hypothesis,

    .. math:: P(a) = \prod_j \binom{c_j}{a_j} \Big/ \binom{N}{n_1},

    and the p-value is the total probability of the tables no more likely than the observed one
    (the probability ordering of :func:`coincli.core.stats.tests.exact_pvalue`, with scipy's
    relative tolerance ``1e-7`` for ties).  For two outcomes this is Fisher's exact test
    (:func:`scipy.stats.fisher_exact`'s two-sided p-value).  Every table with the observed
    margins is enumerated, vectorized over the second outcome: about ``n1^2 / 2`` tables for
    three outcomes.

Asymptotic (G-test)
    Beyond :data:`EXACT_MAX_TABLES` tables, the likelihood-ratio statistic of homogeneity,
    :math:`G = 2 \sum O \ln(O / E)` over the 2 k cells (E from the margins), against
    :math:`\chi^2_{k'-1}`, k' the outcomes seen at all; the result says which test it is.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import NamedTuple

#: the most tables the exact test enumerates (a few tenths of a second); beyond, the G-test
EXACT_MAX_TABLES = 5_000_000
_TIE = 1e-7  #: scipy's relative tolerance for tied probabilities


class Homogeneity(NamedTuple):
    """The test of two samples' chances: the p-value, the statistic (G, also reported for the
    exact test), its degrees of freedom, whether the p-value is exact, and the method's name."""

    p_value: float
    g: float
    df: int
    exact: bool
    method: str


def _check(a: Sequence[int], b: Sequence[int]) -> tuple[list[int], list[int]]:
    if len(a) != len(b) or len(a) < 2:
        raise ValueError("homogeneity: two rows of the same outcomes (2 or more) are needed")
    a, b = [int(v) for v in a], [int(v) for v in b]
    if min(a + b) < 0:
        raise ValueError("homogeneity: counts must be >= 0")
    if sum(a) == 0 or sum(b) == 0:
        raise ValueError("homogeneity: each row needs at least one count")
    return a, b


def g_statistic(a: Sequence[int], b: Sequence[int]) -> tuple[float, int]:
    """The likelihood-ratio statistic of homogeneity of rows ``a`` and ``b``, and its degrees of
    freedom (the outcomes seen in either row, less one)."""
    a, b = _check(a, b)
    n1, n2 = sum(a), sum(b)
    n = n1 + n2
    g = 0.0
    seen = 0
    for x, y in zip(a, b, strict=True):
        c = x + y
        if c == 0:
            continue
        seen += 1
        for o, r in ((x, n1), (y, n2)):
            if o:
                g += o * math.log(o * n / (r * c))
    return max(2.0 * g, 0.0), max(seen - 1, 0)


def tables(a: Sequence[int], b: Sequence[int]) -> int:
    """How many tables the exact test would enumerate (first rows with the observed margins)."""
    a, b = _check(a, b)
    col = [x + y for x, y in zip(a, b, strict=True)]
    n1 = sum(a)
    if len(col) == 2:
        return min(col[0], n1) - max(0, n1 - col[1]) + 1
    # three outcomes: pairs (a0, a1) with a2 = n1 - a0 - a1 in [0, c2]
    count = 0
    for a0 in range(max(0, n1 - col[1] - col[2]), min(col[0], n1) + 1):
        lo, hi = max(0, n1 - a0 - col[2]), min(col[1], n1 - a0)
        count += max(hi - lo + 1, 0)
    return count


def homogeneity(a: Sequence[int], b: Sequence[int], *, method: str = "auto") -> Homogeneity:
    """Test that counts ``a`` (the experiment) and ``b`` (the simulation) of the same outcomes
    (two or three) come from the same chances.  ``method``: ``"exact"`` (Freeman-Halton),
    ``"g"`` (the G-test) or ``"auto"`` (exact up to :data:`EXACT_MAX_TABLES` tables)."""
    a, b = _check(a, b)
    if method not in ("auto", "exact", "g"):
        raise ValueError(f"method must be auto, exact or g, got {method!r}")
    if len(a) > 3:
        raise ValueError("homogeneity: at most three outcomes")
    g, df = g_statistic(a, b)
    if df == 0:  # one outcome seen in all: the rows cannot differ
        return Homogeneity(1.0, 0.0, 0, True, "exact conditional (Freeman-Halton)")
    if method == "g" or (method == "auto" and tables(a, b) > EXACT_MAX_TABLES):
        from scipy.special import chdtrc

        return Homogeneity(float(chdtrc(df, g)), g, df, False,
                           f"G-test of homogeneity (chi-square, {df} df)")
    return Homogeneity(_exact(a, b), g, df, True, "exact conditional (Freeman-Halton)")


def _exact(a: list[int], b: list[int]) -> float:
    import numpy as np
    from scipy.special import gammaln

    col = [x + y for x, y in zip(a, b, strict=True)]
    n1, n = sum(a), sum(col)

    def lchoose(m, k):
        return gammaln(m + 1.0) - gammaln(k + 1.0) - gammaln(m - k + 1.0)

    base = lchoose(n, n1)
    if len(col) == 2:
        k = np.arange(max(0, n1 - col[1]), min(col[0], n1) + 1, dtype=float)
        logp = lchoose(col[0], k) + lchoose(col[1], n1 - k) - base
        obs = float(lchoose(col[0], a[0]) + lchoose(col[1], a[1]) - base)
        return _tail(logp, obs)
    obs = float(sum(lchoose(c, x) for c, x in zip(col, a, strict=True)) - base)
    total, cut = 0.0, obs + math.log1p(_TIE)
    for a0 in range(max(0, n1 - col[1] - col[2]), min(col[0], n1) + 1):
        lo, hi = max(0, n1 - a0 - col[2]), min(col[1], n1 - a0)
        if hi < lo:
            continue
        a1 = np.arange(lo, hi + 1, dtype=float)
        logp = lchoose(col[0], a0) + lchoose(col[1], a1) + lchoose(col[2], n1 - a0 - a1) - base
        keep = logp[logp <= cut]
        if keep.size:
            total += float(np.exp(keep).sum())
    return min(total, 1.0)


def _tail(logp, obs: float) -> float:
    import numpy as np

    keep = logp[logp <= obs + math.log1p(_TIE)]
    return min(float(np.exp(keep).sum()), 1.0)
