"""The Gauss-Legendre rule on [0, 1]: one home for the averages over psi
(:mod:`coincli.core.averages`) and the normal's mass on [0, pi] (:mod:`coincli.core.densities`).

numpy loads when a rule is first built, not with this module: a closed-form run that imports
the densities never builds one.
"""

from __future__ import annotations

import math
from functools import lru_cache

__all__ = ["gauss_legendre"]


@lru_cache(maxsize=64)
def gauss_legendre(n: int):
    """The ``n``-point Gauss-Legendre rule on [0, 1] (nodes ascending, weights).

    Newton's method on ``P_n`` (the three-term recurrence) from Tricomi's estimates
    ``cos(pi (k - 1/4) / (n + 1/2))``, run until no step exceeds 4e-16 and then once more;
    weights ``2 / ((1 - x^2) P_n'(x)^2)``; both made exactly symmetric.  Against 40-digit
    mpmath, n = 2 to 64, on [0, 1]: nodes within 0.95 * 2^-53, weights within 1.4e-13
    relative (numpy's ``leggauss``: 0.90 * 2^-53 and 1.8e-12), without importing
    ``numpy.polynomial`` (2 ms of a simulate's start-up).  tests/core/test_marginal.py checks it.
    """
    import numpy as np

    k = np.arange(1, n + 1)
    x = np.cos(math.pi * (k - 0.25) / (n + 0.5))
    converged = False
    for _ in range(50):
        p_prev, p = np.ones(n), x
        for j in range(2, n + 1):
            p_prev, p = p, ((2 * j - 1) * x * p - (j - 1) * p_prev) / j
        dp = n * (x * p - p_prev) / (x * x - 1)
        step = p / dp
        x = x - step
        if converged:
            break
        converged = bool(np.max(np.abs(step)) <= 4e-16)
    w = 2 / ((1 - x * x) * dp * dp)  # dp of the last step: the change in x is below 1e-31
    x, w = x[::-1], w[::-1]  # ascending
    x, w = (x - x[::-1]) / 2, (w + w[::-1]) / 2
    return (x + 1) / 2, w / 2  # on [0, 1]
