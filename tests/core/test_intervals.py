"""Wilson and Clopper-Pearson intervals against mpmath (tests/interval_reference.py), and finite
for every accepted confidence (issue 13: ``--confidence 0.9999999999999999`` printed ``nan``).

Accuracy stated in docs/accuracy.md: Clopper-Pearson ends within 8e-15 relative (measured
worst 3.2e-15, at k = 2 and confidence 1 - 1e-15), Wilson ends within 1e-15 (measured 4.3e-16),
over n from 1 to 2^53, k at 0, 1, 2, a third, a half, n - 1, n, confidence 0.5 to 1 - 2^-53.
"""

from __future__ import annotations

import math
import warnings

import interval_reference as ref
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from coincli.core._numerics import wilson
from coincli.core.stats import intervals as stats_intervals

CP_TOL = 8e-15
WILSON_TOL = 1e-15

LEVELS = [0.5, 0.95, 1 - 1e-15, 0.9999999999999999]


def _ks(n: int) -> list[int]:
    return sorted({k for k in (0, 1, 2, n // 3, n // 2, n - 1, n) if 0 <= k <= n})


def _check(k: int, n: int, conf: float) -> None:
    lo, hi = (float(v) for v in stats_intervals.clopper_pearson_interval(k, n, conf))
    want_lo, want_hi = ref.clopper_pearson(k, n, conf, (lo, hi))
    assert ref.relative_error(lo, want_lo) <= CP_TOL, ("low", k, n, conf, lo, want_lo)
    assert ref.relative_error(hi, want_hi) <= CP_TOL, ("high", k, n, conf, hi, want_hi)
    wl, wh = (float(v) for v in wilson.wilson_interval(k, n, conf))
    want_wl, want_wh = ref.wilson(k, n, conf)
    assert ref.relative_error(wl, want_wl) <= WILSON_TOL, ("wilson low", k, n, conf, wl)
    assert ref.relative_error(wh, want_wh) <= WILSON_TOL, ("wilson high", k, n, conf, wh)


@pytest.mark.parametrize("k, n, conf", [
    (1, 41, 0.99),  # issue 17: scipy's end was 3.1e-10 off
    (33, 100, 0.95), (0, 10, 0.95), (10, 10, 0.9999999999999999), (2, 10**6, 1 - 1e-15),
    (8, 10, 0.9999999999999999),  # a far tail on the other side of 1/2 from the mean
    (2, 2**53, 0.95),  # Boost's inverse was off by half here
    (2**53 // 3, 2**53, 0.5),  # ... and by 3e-9 here
    (1, 10**9, 0.95),  # betaincc loses 1e-12 for a small k at a huge n: summed instead
])
def test_intervals_against_mpmath(k, n, conf):
    _check(k, n, conf)


@pytest.mark.slow
@pytest.mark.parametrize("n", [1, 2, 3, 10, 41, 1000, 10**6, 10**9, 10**12, 2**53])
def test_interval_grid_against_mpmath(n):
    for k in _ks(n):
        for conf in LEVELS:
            _check(k, n, conf)


@settings(max_examples=120, deadline=None)
@given(n=st.integers(1, 2**53), frac=st.floats(0, 1), conf=st.one_of(
    st.floats(5e-324, 1.0, exclude_max=True),
    st.sampled_from([5e-324, 1e-300, 0.5, 1 - 2**-53, 1 - 1e-15, 0.9999999999999999])))
def test_every_accepted_confidence_gives_a_finite_interval(n, frac, conf):
    k = min(n, int(frac * n))
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no RuntimeWarning from numpy or scipy either
        p = stats_intervals.proportion(k, n, confidence=conf)
    for iv in (p.wilson, p.clopper_pearson):
        assert math.isfinite(iv.low) and math.isfinite(iv.high)
        assert 0.0 <= iv.low <= iv.high <= 1.0
        assert iv.low <= p.estimate <= iv.high


def test_arrays_and_scalars_agree():
    k = np.array([0, 1, 5, 99, 100])
    lo, hi = stats_intervals.clopper_pearson_interval(k, 100, 0.95)
    for i, kk in enumerate(k.tolist()):
        r = stats_intervals.proportion(kk, 100)
        assert (r.clopper_pearson.low, r.clopper_pearson.high) == (lo[i], hi[i])
