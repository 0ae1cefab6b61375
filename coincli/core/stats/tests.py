r"""Statistics for real tosses: intervals, exact goodness-of-fit tests, fits of the spread of psi.

A coin designer tosses a prototype a few hundred times and asks whether the counts agree with a
model (issue 6; the paper did the same with 100 tosses a coin, Sec. IV and Fig. 5).  This module
is the pure core of ``coin check`` and ``coin fit``: numbers in, numbers and named tuples out,
``ValueError`` naming the argument and its allowed range otherwise.  Nothing here prints.

Counts
    ``(heads, sides, tails)`` when the faces were told apart (a trinomial), or ``sides`` out of
    ``n`` when they were not (a binomial: side or face).  :func:`make_counts` validates them.

Intervals
    Wilson score (:func:`wilson_interval`) and Clopper-Pearson ("exact",
    :func:`clopper_pearson_interval`) intervals for each observed frequency: the Wilson ends
    without cancellation, the Clopper-Pearson ends as beta quantiles (closed forms at
    ``k = 0, 1, n - 1, n``; otherwise scipy.special's inverse polished by the secant method), both
    finite for every level in (0, 1) and within 19 ulps of mpmath up to ``n = 2^53``.

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

Spread of psi (:func:`fit_spread`)
    The tossing style enters through the angle psi between the angular momentum and the normal.
    The model: psi is normal about pi/2 with standard deviation ``sigma``, truncated to [0, pi]
    (:class:`coincli.core.densities.Normal`); the chances are the psi-averages of Table I
    (:func:`coincli.core.averages.marginal`).  ``sigma = 0`` is the Keller flip, i.e. the dynamic model
    (eq. 12); ``sigma -> inf`` is psi uniform on [0, pi] (Table II, first column).  ``sigma`` is
    estimated by maximum likelihood over ``[0, inf]`` and given a profile-likelihood interval
    ``{sigma: 2 (l_max - l(sigma)) <= chi2_1(0.95) = 3.84}``.

Model comparison
    ``AIC = 2k - 2 log L`` with ``k = 0`` for the geometric and dynamic models (nothing is
    fitted) and ``k = 1`` for the fitted spread; the paper's sum of squared errors of the side
    frequencies (``0.20`` geometric against ``0.01`` dynamic in Sec. IV) is :func:`sse_sides`.

numpy and scipy.special are imported inside the functions that need them (the CLI's start-up
budget); scipy.stats and scipy.optimize are not used at all (0.6 s and 0.2 s of import).
"""

from __future__ import annotations

import math
import re
from collections import namedtuple
from collections.abc import Mapping, Sequence

from coincli.core._numerics.wilson import CONFIDENCE, _check_level, _z, wilson_interval  # noqa: F401
from coincli.core.models import Outcome

__all__ = [
    "CONFIDENCE",
    "ALPHA",
    "EXACT_MAX_N",
    "TIE_RTOL",
    "Counts",
    "make_counts",
    "Interval",
    "Proportion",
    "wilson_interval",
    "clopper_pearson_interval",
    "proportion",
    "proportions",
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
    "sse_sides",
    "aic",
    "SpreadFit",
    "fit_spread",
    "ModelSummary",
    "FitResult",
    "fit",
    "Experiment",
    "parse_experiments",
    "CSV_COLUMNS",
    "DELIMITERS",
    "delimiter_of",
]

ALPHA = 0.05  #: default significance level of the verdicts
EXACT_MAX_N = 1_000_000  #: largest n for which method="auto" runs the exact test
TIE_RTOL = 1e-7  #: relative tolerance for "no more likely than the observed" (scipy's)
P_DISPLAY_FLOOR = 1e-300  #: p-values below this are shown as "p < 1e-300"
_LOG_TINY = math.log(5e-324)  # exp() of anything below is 0.0 in double precision

HALF_PI = math.pi / 2


# --------------------------------------------------------------------------- validation


#: The largest count of tosses (every count is exact in a double up to here)
MAX_COUNT = 2**53


def _whole(value, name: str) -> int | None:
    """A count: None, or a whole number >= 0 (int, or a float/numpy number with no fraction)."""
    if value is None:
        return None
    if isinstance(value, (bool, str, bytes)):
        raise ValueError(f"{name} must be a whole number >= 0, got {value!r}")
    import operator

    try:
        v = operator.index(value)  # int and numpy integers
    except TypeError:
        v = None
    if v is None:
        try:
            f = float(value)
        except (TypeError, ValueError):
            raise ValueError(f"{name} must be a whole number >= 0, got {value!r}") from None
        if not math.isfinite(f) or f != math.floor(f) or abs(f) > 2.0**53:
            raise ValueError(f"{name} must be a whole number >= 0, got {value!r}")
        v = int(f)
    if v < 0:
        raise ValueError(f"{name} must be a whole number >= 0, got {value!r}")
    if v > MAX_COUNT:
        raise ValueError(f"{name} must be a whole number from 0 to {MAX_COUNT} (2**53), "
                         f"got {value!r}")
    return int(v)


class CountsError(ValueError):
    """A bad count; ``argument`` names the offending one (heads, sides, tails or n)."""

    def __init__(self, message: str, argument: str):
        super().__init__(message)
        self.argument = argument


class Counts(namedtuple("Counts", "n sides heads tails", defaults=(None, None))):
    """Observed tosses: ``sides`` of ``n``, and ``heads``/``tails`` when faces were told apart."""

    # n: int
    # sides: int
    # heads: int | None
    # tails: int | None
    __slots__ = ()

    @property
    def faces(self) -> bool:
        """True when heads and tails were counted separately (a trinomial observation)."""
        return self.heads is not None

    @property
    def categories(self) -> tuple[str, ...]:
        return ("heads", "sides", "tails") if self.faces else ("sides", "faces")

    @property
    def values(self) -> tuple[int, ...]:
        """The counts in the order of :attr:`categories`."""
        if self.faces:
            return (self.heads, self.sides, self.tails)
        return (self.sides, self.n - self.sides)


def make_counts(heads=None, sides=None, tails=None, n=None) -> Counts:
    """Validate observed counts and return :class:`Counts`.

    Give ``heads``, ``sides`` and ``tails`` (``n`` optional, then it must be their sum), or
    ``sides`` and ``n`` when the faces were not told apart.  One of heads/tails with ``n`` fixes
    the other.  Every count must be a whole number >= 0 and ``n`` must be >= 1.

    Raises
    ------
    CountsError (a ValueError)
        Naming the argument, e.g. ``heads must be a whole number >= 0, got -1``.

    >>> make_counts(35, 33, 32)
    Counts(n=100, sides=33, heads=35, tails=32)
    >>> make_counts(sides=33, n=100)
    Counts(n=100, sides=33, heads=None, tails=None)
    """
    vals = {}
    for name, v in (("heads", heads), ("sides", sides), ("tails", tails), ("n", n)):
        try:
            vals[name] = _whole(v, name)
        except ValueError as exc:
            raise CountsError(str(exc), name) from None
    h, s, t, m = vals["heads"], vals["sides"], vals["tails"], vals["n"]
    if s is None:
        raise CountsError("sides is required (the number of tosses that landed on a side)",
                          "sides")
    if (h is None) != (t is None):
        given, missing = ("heads", "tails") if t is None else ("tails", "heads")
        if m is None:
            raise CountsError(f"{given} was given without {missing}; give both, or n", missing)
        other = m - s - (h if h is not None else t)
        if other < 0:
            raise CountsError(
                f"{given} + sides = {m - other} exceeds n = {m}", "n")
        h, t = (h, other) if t is None else (other, t)
    if h is not None:
        total = h + s + t
        if total > MAX_COUNT:
            raise CountsError(f"heads + sides + tails = {total}; at most {MAX_COUNT} (2**53) "
                              "tosses are allowed", "n")
        if m is not None and m != total:
            raise CountsError(f"heads + sides + tails = {total} but n = {m}", "n")
        m = total
        if m == 0:
            raise CountsError("heads, sides and tails are all zero: no tosses to check", "n")
        return Counts(m, s, h, t)
    if m is None:
        raise CountsError("give n (the number of tosses) with sides, or heads and tails too", "n")
    if m == 0:
        raise CountsError("n must be >= 1 (no tosses to check), got 0", "n")
    if s > m:
        raise CountsError(f"sides = {s} exceeds n = {m}", "sides")
    return Counts(m, s)


def _check_probs(probs, k: int, name: str = "probabilities") -> tuple[float, ...]:
    """k finite probabilities >= 0 summing to 1 within 1e-6; returned renormalized."""
    try:
        p = [float(v) for v in probs]
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be {k} numbers, got {probs!r}") from None
    if len(p) != k:
        raise ValueError(f"{name} must be {k} numbers, got {len(p)}")
    if any(not math.isfinite(v) or v < 0 for v in p):
        raise ValueError(f"{name} must be finite and >= 0, got {p!r}")
    total = math.fsum(p)
    if not abs(total - 1.0) <= 1e-6:
        raise ValueError(f"{name} must sum to 1, got {p!r} (sum {total!r})")
    return tuple(v / total for v in p)


# --------------------------------------------------------------------------- special functions
# Vectorized numpy over scipy.special (Boost and Cephes underneath).  scipy.stats is never
# imported: its import alone costs 0.6 s, twice what the answer needs.  The formulas are the
# ones scipy.stats uses, so the numbers are the same:
#   binomial log-pmf   gammaln(n+1) - (gammaln(k+1) + gammaln(n-k+1)) + k ln p + (n-k) ln(1-p)
#   P(X <= k)          I_{1-p}(n - k, k + 1)    (betainc; 1 - p passed as the complement chance)
#   P(X >= k)          I_p(k, n - k + 1)
#   chi-square tail    chdtrc(df, x)
#   beta quantiles     betaincinv / betainccinv (Clopper-Pearson), polished by the secant
#                      method on betainc / betaincc

_TABLE_MAX = 1 << 21  #: log-factorials are tabulated up to this n (16 MiB); gammaln beyond


class _LogFactorial:
    """``v -> log(v!)`` for whole numbers ``0 <= v <= nmax``: a table of gammaln(k + 1) (the same
    numbers, looked up instead of recomputed) when ``nmax`` is small enough, else gammaln."""

    def __init__(self, nmax: int):
        import numpy as np
        from scipy.special import gammaln

        self._gammaln = gammaln
        self._table = (gammaln(np.arange(int(nmax) + 1, dtype=float) + 1.0)
                       if nmax <= _TABLE_MAX else None)

    def __call__(self, v):
        import numpy as np

        if self._table is not None:
            return self._table[np.asarray(v, dtype=np.int64)]
        return self._gammaln(np.asarray(v, dtype=float) + 1.0)


def _binom_logpmf(k, n, p, lf=None):
    """log P(X = k) for X ~ Binomial(n, p), arrays; scipy.stats.binom.logpmf's formula."""
    import numpy as np
    from scipy.special import xlog1py, xlogy

    k = np.asarray(k)
    n = np.asarray(n)
    if lf is None:
        lf = _LogFactorial(int(np.max(n, initial=0)))
    return (lf(n) - (lf(k) + lf(n - k))) + xlogy(k, p) + xlog1py(n - k, -p)


def _binom_cdf(k, n, p1):
    """P(X <= k) for X ~ Binomial(n, p) with ``p1 = 1 - p`` given (not formed from p)."""
    import numpy as np
    from scipy.special import betainc

    k, n = np.asarray(k, dtype=float), np.asarray(n, dtype=float)
    inside = (k >= 0) & (k < n)
    with np.errstate(invalid="ignore", divide="ignore"):
        v = betainc(np.where(inside, n - k, 1.0), np.where(inside, k + 1, 1.0), p1)
    return np.where(inside, v, np.where(k >= n, 1.0, 0.0))


def _binom_upper(k, n, p):
    """P(X >= k) for X ~ Binomial(n, p)."""
    import numpy as np
    from scipy.special import betainc

    k, n = np.asarray(k, dtype=float), np.asarray(n, dtype=float)
    inside = (k >= 1) & (k <= n)
    with np.errstate(invalid="ignore", divide="ignore"):
        v = betainc(np.where(inside, k, 1.0), np.where(inside, n - k + 1, 1.0), p)
    return np.where(inside, v, np.where(k <= 0, 1.0, 0.0))


# --------------------------------------------------------------------------- intervals


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

    conf = _check_level(confidence, "confidence")
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
    c = _whole(count, "count")
    m = _whole(n, "n")
    if m == 0:
        raise ValueError("n must be >= 1, got 0")
    if c > m:
        raise ValueError(f"count must be <= n = {m}, got {c}")
    conf = _check_level(confidence, "confidence")
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
    lf = _LogFactorial(int(np.max(n, initial=0)))
    with np.errstate(divide="ignore", invalid="ignore", under="ignore", over="ignore"):
        obs = (lf(n) - (lf(k) + lf(n - k))) + k * np.log(p) + (n - k) * np.log1p(-p)
        thr = obs + math.log1p(TIE_RTOL)
        above, left, right = _crossings(np.zeros(k.shape), n, p, thr, lf)
        tail = _binom_cdf(left, n, p1) + _binom_upper(right, n, p)
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
    lf = _LogFactorial(int(n.max()))
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
        outer = _binom_cdf(lo, n, pa[live] + pc[live]) + _binom_upper(hi, n, pr)
        # the other rows, lo < r < hi, one flat entry each
        sizes = np.where(above, hi - lo - 1, 0)
        starts = np.concatenate(([0], np.cumsum(sizes)[:-1]))
        tid = np.repeat(np.arange(len(n)), sizes)
        rr = np.arange(int(sizes.sum())) - starts[tid] + lo[tid] + 1
        nt = n[tid]
        base = (lf(nt) - (lf(rr) + lf(nt - rr))) + rr * lpr[tid] + (nt - rr) * l1pr[tid]
        na, qt, tt = nt - rr, q[tid], thr[tid]
        row_above, left, right = _crossings(base, na, qt, tt, lf)
        tails = _binom_cdf(left, na, q1[tid]) + _binom_upper(right, na, qt)
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
    x = [_whole(v, "counts") for v in counts]
    if len(x) not in (2, 3):
        raise ValueError(f"counts must have 2 or 3 categories, got {len(x)}")
    p = _check_probs(probs, len(x))
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
    x = [_whole(v, "counts") for v in counts]
    p = _check_probs(probs, len(x))
    if sum(x) == 0:
        raise ValueError("counts are all zero: no tosses to test")
    g, df, pv = _g_tests([x], [p])
    return float(g[0]), int(df[0]), float(pv[0])


def _log_likelihoods(x, n, p, faces):
    """Log-probabilities of T observations: ``x`` (T x 3) counts (heads, sides, tails; only the
    sides column is read where ``faces`` is False), ``p`` (T x 3) normalized chances."""
    import numpy as np
    from scipy.special import xlogy

    x = np.asarray(x, dtype=np.int64)
    n = np.asarray(n, dtype=np.int64)
    p = np.asarray(p, dtype=float)
    faces = np.asarray(faces, dtype=bool)
    lf = _LogFactorial(int(np.max(n, initial=0)))
    out = np.empty(len(n))
    with np.errstate(divide="ignore", invalid="ignore"):
        if np.any(faces):
            xf, pf = x[faces], p[faces]
            out[faces] = lf(n[faces]) + np.sum(xlogy(xf, pf) - lf(xf), axis=1)
        side = ~faces
        if np.any(side):
            k, m = x[side, 1], n[side]
            ps, pface = p[side, 1], p[side, 0] + p[side, 2]
            # the rarer category's chance: 1 - ps loses a face chance below 1e-16
            out[side] = np.where(ps <= 0.5, _binom_logpmf(k, m, ps, lf),
                                 _binom_logpmf(m - k, m, pface, lf))
    return np.where(np.isnan(out), -np.inf, out)


def log_likelihood(counts: Counts, probs) -> float:
    """Log-probability of the observed counts under the model's chances ``probs``.

    ``probs`` is an :class:`Outcome` (or ``(heads, sides, tails)``).  Faces told apart: the
    multinomial log-pmf; sides only: the binomial log-pmf of ``sides`` with ``P(sides)``.  The
    coefficient is included (the formulas of scipy.stats' ``multinomial.logpmf`` and
    ``binom.logpmf``).  ``-inf`` when the model gives the counts probability 0.
    """
    p = _check_probs(probs, 3)
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
    a = _check_level(alpha, "alpha")
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
class _CountColumns:
    """Counts of many experiments as arrays: heads, sides, tails (0 where faces were not told
    apart), n, and ``faces``."""

    def __init__(self, counts: Sequence[Counts]):
        import numpy as np

        if not all(isinstance(c, Counts) for c in counts):
            bad = next(c for c in counts if not isinstance(c, Counts))
            raise ValueError(f"counts must be a Counts (see make_counts), got {bad!r}")
        self.counts = counts
        self.faces = np.fromiter((c.heads is not None for c in counts), bool, len(counts))
        self.sides = np.fromiter((c.sides for c in counts), np.int64, len(counts))
        self.n = np.fromiter((c.n for c in counts), np.int64, len(counts))
        self.heads = np.fromiter((c.heads or 0 for c in counts), np.int64, len(counts))
        self.tails = np.fromiter((c.tails or 0 for c in counts), np.int64, len(counts))

    def __len__(self):
        return len(self.n)

    def matrix(self):
        import numpy as np

        return np.stack([self.heads, self.sides, self.tails], axis=1)


def _chance_columns(chances, size: int, name: str = "chances"):
    """(heads, sides, tails) arrays of ``size`` raw chances and the normalized T x 3 matrix;
    ValueError as :func:`_check_probs` words it, for the first bad row."""
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
        _check_probs(raw[:, i].tolist(), 3, name)  # raises, with the scalar wording
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


def _model_tests(cc: _CountColumns, chances, model: str, alpha: float, method: str) -> _Tests:
    """Test every experiment of ``cc`` against a model's ``chances`` (arrays, one per row)."""
    import numpy as np

    a = _check_level(alpha, "alpha")
    raw, p = _chance_columns(chances, len(cc), "chances")
    faces = cc.faces
    T = len(cc)
    # tested categories: faces told apart (heads, sides, tails); else (sides, faces)
    x = np.where(faces[:, None], cc.matrix(),
                 np.stack([cc.sides, cc.n - cc.sides, np.zeros(T, np.int64)], axis=1))
    side, face = p[:, 1], p[:, 0] + p[:, 2]
    total2 = side + face  # side or face: renormalized as a pair, as a two-category test is
    q = np.where(faces[:, None], p, np.stack([side / total2, face / total2, np.zeros(T)], axis=1))
    nf = cc.n.astype(float)
    expected = np.where(faces, nf * raw, np.stack([nf * raw[1], nf * (raw[0] + raw[2]),
                                                   np.zeros(T)]))
    g, df, p_asym = np.empty(T), np.empty(T, np.int64), np.empty(T)
    pv = np.empty(T)
    exact = np.full(T, method == "exact") | ((method == "auto") & (cc.n <= EXACT_MAX_N))
    for sel, k in ((faces, 3), (~faces, 2)):
        if not np.any(sel):
            continue
        g[sel], df[sel], p_asym[sel] = _g_tests(x[sel, :k], q[sel, :k])
        ex = sel & exact
        pv[sel] = p_asym[sel]
        if np.any(ex):
            pv[ex] = _exact_pvalues(x[ex, :k], q[ex, :k])
    ll = _log_likelihoods(cc.matrix(), cc.n, p, faces)
    impossible = ll == -np.inf
    pv = np.where(impossible, 0.0, pv)
    methods = [("exact multinomial" if f else "exact binomial") if e else
               f"G-test (asymptotic chi2, df={d})"
               for f, e, d in zip(faces.tolist(), exact.tolist(), df.tolist(), strict=True)]
    verdicts = _verdicts(pv, a, exact, impossible)
    cats = [_CATS3 if f else _CATS2 for f in faces.tolist()]
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
    _check_method(method)
    return _model_tests(_CountColumns([counts]), chances, model, alpha, method).get(0)


def _check_method(method) -> None:
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
class Checks(Sequence):
    """Many experiments checked at once, as columns; ``checks[i]`` is the :class:`CheckResult`
    of row ``i`` (built on demand: a file of 10^5 rows needs none of them to be written).

    Columns: ``xi``, ``labels``, ``cc`` (the counts), ``intervals[outcome]`` (estimate, Wilson
    low/high, Clopper-Pearson low/high arrays; NaN where an outcome was not counted) and
    ``tests`` (one :class:`_Tests` per model, in order).
    """

    def __init__(self, xi, labels, cc: _CountColumns, intervals, tests, confidence: float):
        self.xi, self.labels, self.cc = xi, labels, cc
        self.intervals, self.tests, self.confidence = intervals, tests, confidence

    def __len__(self):
        return len(self.cc)

    def __getitem__(self, i):
        if isinstance(i, slice):
            return [self[k] for k in range(*i.indices(len(self)))]
        if i < 0:
            i += len(self)
        if not 0 <= i < len(self):
            raise IndexError(i)
        c = self.cc.counts[i]
        props = []
        for name in (_CATS3 if c.faces else ("sides",)):
            est, wl, wh, cl, ch = (float(v[i]) for v in self.intervals[name])
            conf = self.confidence
            props.append(Proportion(name, getattr(c, name), c.n, est,
                                    Interval(wl, wh, "wilson", conf),
                                    Interval(cl, ch, "clopper-pearson", conf)))
        return CheckResult(float(self.xi[i]), c, tuple(props),
                           tuple(t.get(i) for t in self.tests), self.labels[i])


def check_many(counts: Sequence[Counts], xi, chances: Mapping[str, object], *,
               confidence: float = CONFIDENCE, alpha: float = ALPHA, method: str = "auto",
               labels: Sequence[str] | None = None) -> Checks:
    """:func:`check` for many experiments at once: ``xi`` and each model's chances are arrays,
    one entry per experiment.  The exact tests of all rows run together (see
    :func:`_trinomial_logp`); the result is columnar (:class:`Checks`)."""
    import numpy as np

    _check_method(method)
    conf = _check_level(confidence, "confidence")
    _check_level(alpha, "alpha")
    cc = _CountColumns(counts)
    xs = np.broadcast_to(np.asarray(xi, dtype=float), (len(cc),))
    # the intervals depend on (count, n) alone: each distinct pair once
    ks = np.concatenate([cc.heads, cc.sides, cc.tails])
    pairs, inverse = np.unique(np.stack([ks, np.tile(cc.n, 3)], axis=1), axis=0,
                               return_inverse=True)
    inverse = inverse.ravel()
    pk, pn = pairs[:, 0], pairs[:, 1]
    ends = [*wilson_interval(pk, pn, conf), *clopper_pearson_interval(pk, pn, conf)]
    T = len(cc)
    intervals = {}
    for j, (name, k) in enumerate((("heads", cc.heads), ("sides", cc.sides),
                                   ("tails", cc.tails))):
        sel = inverse[j * T:(j + 1) * T]
        cols = [k / cc.n, *(v[sel] for v in ends)]
        if name != "sides":
            cols = [np.where(cc.faces, v, np.nan) for v in cols]
        intervals[name] = cols
    tests = [_model_tests(cc, ch, name, alpha, method) for name, ch in chances.items()]
    return Checks(xs, list(labels) if labels is not None else [""] * len(cc), cc, intervals,
                  tests, conf)


def check(counts: Counts, xi: float, chances: Mapping[str, object] | None = None, *,
          confidence: float = CONFIDENCE, alpha: float = ALPHA, method: str = "auto",
          label: str = "") -> CheckResult:
    """Check tosses of a coin of aspect ratio ``xi`` against models.

    ``chances`` maps a model name to its (heads, sides, tails); the default is
    :func:`model_chances` (geometric and dynamic).
    """
    if not isinstance(counts, Counts):
        raise ValueError(f"counts must be a Counts (see make_counts), got {counts!r}")
    if chances is None:
        chances = model_chances(xi)
    return check_many([counts], xi, chances, confidence=confidence, alpha=alpha, method=method,
                      labels=[label])[0]


# --------------------------------------------------------------------------- across experiments


def sse_sides(counts: Sequence[Counts], p_sides: Sequence[float]) -> float:
    """The paper's sum of squared errors: ``sum_i (sides_i / n_i - P_model(sides)_i)^2``."""
    if len(counts) != len(p_sides):
        raise ValueError(f"counts and p_sides must have one entry each, got {len(counts)} and "
                         f"{len(p_sides)}")
    return math.fsum((c.sides / c.n - float(p)) ** 2 for c, p in zip(counts, p_sides, strict=True))


def aic(log_lik: float, n_params: int) -> float:
    """Akaike's information criterion ``2k - 2 log L`` (``inf`` when ``log L = -inf``)."""
    return 2 * n_params - 2 * log_lik


class _Likelihood:
    """The total log-likelihood of many experiments as a function of their chances.

    The counts' parts (log-factorials) are summed once; each call adds ``sum x ln p`` over the
    rows, so a fit that tries many chances pays one pass of numpy per try.  The formulas are
    :func:`_log_likelihoods`' (multinomial with faces told apart, else binomial in sides with
    the rarer category's chance)."""

    def __init__(self, cc: _CountColumns):
        import numpy as np

        lf = _LogFactorial(int(np.max(cc.n, initial=0)))
        f = cc.faces
        self.faces = f
        self.x = cc.matrix()[f]
        self.k, self.m = cc.sides[~f], cc.n[~f]
        const = np.concatenate([lf(cc.n[f]) - lf(self.x).sum(axis=1),
                                lf(self.m) - (lf(self.k) + lf(self.m - self.k))])
        self.const = math.fsum(const.tolist())

    def __call__(self, heads, sides, tails) -> float:
        import numpy as np
        from scipy.special import xlog1py, xlogy

        f = self.faces
        with np.errstate(divide="ignore", invalid="ignore", under="ignore"):
            total = self.const
            if self.x.size:
                p = np.stack([heads[f], sides[f], tails[f]], axis=1)
                p = p / p.sum(axis=1, keepdims=True)
                total += float(np.sum(xlogy(self.x, p)))
            if self.k.size:
                k, m = self.k, self.m
                ps = np.clip(sides[~f], 0.0, 1.0)
                pf = np.clip(heads[~f] + tails[~f], 0.0, 1.0)  # not 1 - ps: a thick coin's faces
                ll = np.where(ps <= 0.5, xlogy(k, ps) + xlog1py(m - k, -ps),
                              xlogy(m - k, pf) + xlog1py(k, -pf))
                total += float(np.sum(ll))
        return total if not math.isnan(total) else -math.inf


def _spread_chances(xi, sigma: float) -> Outcome:
    """Chances for psi ~ Normal(pi/2, sigma) on [0, pi]; sigma = 0: dynamic, inf: uniform psi."""
    from coincli.core.models import dynamic

    if sigma == 0:
        return dynamic(xi)
    from coincli.core.averages import marginal
    from coincli.core.densities import Normal, Uniform

    return marginal(xi, Uniform() if math.isinf(sigma) else Normal(HALF_PI, sigma))


class SpreadFit(namedtuple("SpreadFit", "sigma low high pieces confidence log_likelihood aic "
                                        "chances note profile", defaults=("", ()))):
    """Maximum-likelihood spread of psi (sd of a normal about pi/2 truncated to [0, pi])."""

    # sigma: float  the estimate, radians; 0 is the Keller flip (dynamic), inf is uniform psi
    # low: float  lower end of the profile-likelihood interval
    # high: float  upper end (inf when a uniform psi is not excluded)
    # pieces: tuple[tuple[float, float], ...]  the confidence set; one piece unless flagged
    # confidence: float
    # log_likelihood: float
    # aic: float
    # chances: Outcome  arrays, one entry per experiment, at the estimate
    # note: str
    # profile: tuple[tuple[float, float], ...]  (sigma, log L) on the grid
    __slots__ = ()

    n_params = 1

    def __repr__(self):  # the profile is long: left out, as a dataclass field(repr=False) was
        shown = ", ".join(f"{k}={getattr(self, k)!r}" for k in self._fields if k != "profile")
        return f"SpreadFit({shown})"


def _sigma_of(u: float) -> float:
    return math.inf if u >= 1.0 else u / (1.0 - u)


# One-dimensional search in pure Python: the fit's only optimizer needs.  scipy.optimize would
# cost 0.1-0.2 s of import for two routines of a few dozen lines; these are the same algorithms
# (scipy's bounded Brent minimizer, Brent's bracketed root finder as in scipy's brentq) with the
# same tolerances, so the estimates agree with scipy's to those tolerances.

_SQRT_EPS = math.sqrt(2.2e-16)
_GOLDEN = 0.5 * (3.0 - math.sqrt(5.0))


def _minimize_bounded(func, x1: float, x2: float, xatol: float = 1e-5, maxfun: int = 500,
                      known=()):
    """``(x, f(x))`` minimizing ``func`` on ``[x1, x2]``: Brent's method (golden section with
    parabolic steps), scipy.optimize.minimize_scalar(method="bounded")'s algorithm.

    ``known``: three or more ``(x, f(x))`` inside the bracket already evaluated (a grid around
    the minimum); the search then starts from them with a parabolic step instead of spending
    its first evaluations on golden-section points.
    """

    def sign(v: float) -> float:
        return (v > 0) - (v < 0) + (v == 0)

    a, b = x1, x2
    rat = e = 0.0
    pts = sorted((float(f), float(x)) for x, f in known if a <= x <= b)
    if len(pts) >= 3:
        (fx, xf), (fnfc, nfc), (ffulc, fulc) = pts[:3]
        e = b - a  # allow a parabolic first step
        num = 0
    else:
        fulc = a + _GOLDEN * (b - a)
        nfc, xf = fulc, fulc
        fx = func(xf)
        num = 1
        ffulc = fnfc = fx
    x = xf
    xm = 0.5 * (a + b)
    tol1 = _SQRT_EPS * abs(xf) + xatol / 3.0
    tol2 = 2.0 * tol1
    while abs(xf - xm) > (tol2 - 0.5 * (b - a)):
        golden = True
        if abs(e) > tol1:  # try a parabola through the three best points
            golden = False
            r = (xf - nfc) * (fx - ffulc)
            q = (xf - fulc) * (fx - fnfc)
            p = (xf - fulc) * q - (xf - nfc) * r
            q = 2.0 * (q - r)
            if q > 0.0:
                p = -p
            q = abs(q)
            r = e
            e = rat
            if abs(p) < abs(0.5 * q * r) and q * (a - xf) < p < q * (b - xf):
                rat = (p + 0.0) / q
                x = xf + rat
                if (x - a) < tol2 or (b - x) < tol2:
                    rat = tol1 * sign(xm - xf)
            else:
                golden = True
        if golden:
            e = (a - xf) if xf >= xm else (b - xf)
            rat = _GOLDEN * e
        x = xf + sign(rat) * max(abs(rat), tol1)
        fu = func(x)
        num += 1
        if fu <= fx:
            if x >= xf:
                a = xf
            else:
                b = xf
            fulc, ffulc = nfc, fnfc
            nfc, fnfc = xf, fx
            xf, fx = x, fu
        else:
            if x < xf:
                a = x
            else:
                b = x
            if fu <= fnfc or nfc == xf:
                fulc, ffulc = nfc, fnfc
                nfc, fnfc = x, fu
            elif fu <= ffulc or fulc == xf or fulc == nfc:
                fulc, ffulc = x, fu
        xm = 0.5 * (a + b)
        tol1 = _SQRT_EPS * abs(xf) + xatol / 3.0
        tol2 = 2.0 * tol1
        if num >= maxfun:
            break
    return xf, fx


def _root(func, xa: float, xb: float, xtol: float = 1e-12, rtol: float = 8.9e-16,
          maxiter: int = 100, fa: float | None = None, fb: float | None = None) -> float:
    """A zero of ``func`` in ``[xa, xb]`` (the signs at the ends differ): Brent's method as in
    scipy.optimize.brentq (inverse quadratic interpolation, secant, bisection).  ``fa``, ``fb``:
    the values at the ends, when already known."""
    xpre, xcur = xa, xb
    xblk = fblk = spre = scur = 0.0
    fpre = func(xpre) if fa is None else fa
    fcur = func(xcur) if fb is None else fb
    if fpre == 0:
        return xpre
    if fcur == 0:
        return xcur
    if (fpre > 0) == (fcur > 0):
        raise ValueError("the function has the same sign at both ends of the bracket")
    for _ in range(maxiter):
        if fpre != 0 and fcur != 0 and (fpre < 0) != (fcur < 0):
            xblk, fblk = xpre, fpre
            spre = scur = xcur - xpre
        if abs(fblk) < abs(fcur):
            xpre, xcur, xblk = xcur, xblk, xcur
            fpre, fcur, fblk = fcur, fblk, fcur
        delta = (xtol + rtol * abs(xcur)) / 2
        sbis = (xblk - xcur) / 2
        if fcur == 0 or abs(sbis) < delta:
            return xcur
        if abs(spre) > delta and abs(fcur) < abs(fpre):
            if xpre == xblk:  # interpolate
                stry = -fcur * (xcur - xpre) / (fcur - fpre)
            else:  # extrapolate
                dpre = (fpre - fcur) / (xpre - xcur)
                dblk = (fblk - fcur) / (xblk - xcur)
                stry = -fcur * (fblk * dblk - fpre * dpre) / (dblk * dpre * (fblk - fpre))
            if 2 * abs(stry) < min(abs(spre), 3 * abs(sbis) - delta):
                spre, scur = scur, stry  # a good short step
            else:
                spre = scur = sbis
        else:
            spre = scur = sbis
        xpre, fpre = xcur, fcur
        xcur += scur if abs(scur) > delta else (delta if sbis > 0 else -delta)
        fcur = func(xcur)
    return xcur


def fit_spread(xi: Sequence[float], counts: Sequence[Counts], *, confidence: float = CONFIDENCE,
               grid: int = 41) -> SpreadFit:
    r"""Maximum-likelihood ``sigma`` of psi ~ Normal(pi/2, sigma) truncated to [0, pi].

    All experiments share ``sigma`` (one tossing style); each contributes its multinomial (or
    binomial) log-likelihood with the chances :func:`coincli.core.averages.marginal` gives at its
    ``xi``.  The parameter runs over ``[0, inf]``, mapped to ``u = sigma / (1 + sigma)`` in
    ``[0, 1]``: ``sigma = 0`` is the dynamic model (Keller flip), ``sigma = inf`` uniform psi.

    Method: the log-likelihood on ``grid`` equally spaced ``u`` (both ends included), the best
    point refined by bounded Brent (to 1e-9 in ``u``); the profile-likelihood confidence set
    ``{sigma: 2 (l_max - l(sigma)) <= chi2_1(confidence)}`` from the sign changes on the grid,
    each end refined by Brent's root finder (to 1e-10 in ``u``).  At the boundary
    ``sigma = 0`` the chi2_1 calibration is conservative (the exact limit is a 50:50 mixture of
    0 and chi2_1).  The chances are computed once per distinct ``xi`` and try of ``sigma``, and
    each try's log-likelihood is one pass over all rows (:class:`_Likelihood`).

    The set need not be one interval: the chance of a side is not monotone in ``sigma`` (it
    rises from the dynamic value, peaks near ``sigma ~ 0.4`` and falls to the uniform value), so
    side counts alone can fit a narrow and a wide spread equally well.  ``pieces`` lists every
    piece, ``low``/``high`` span them, and ``note`` says so.  Counts of heads and tails separate
    the two: the bias toward heads grows with ``sigma``.

    Raises ValueError when no spread gives the data positive probability.
    """
    import numpy as np
    from scipy.special import gammainccinv, gammaincinv

    conf = _check_level(confidence, "confidence")
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
    ux, inv = np.unique(xs, return_inverse=True)  # rows share coins: chances once per coin
    like = _Likelihood(_CountColumns(counts))
    cache: dict[float, float] = {}
    best: list = [-math.inf, None, None]  # log L, u and chances of the best try so far

    def chances(u: float) -> Outcome:
        if u == best[1]:
            return best[2]
        ch = _spread_chances(ux, _sigma_of(u))
        return Outcome(*(np.asarray(v, dtype=float).reshape(-1)[inv] for v in ch))

    def loglik(u: float) -> float:
        u = min(max(float(u), 0.0), 1.0)
        if u not in cache:
            ch = chances(u)
            cache[u] = v = like(*ch)
            if v > best[0] or best[1] is None:
                best[:] = [v, u, ch]
        return cache[u]

    us = np.linspace(0.0, 1.0, int(grid))
    ls = np.array([loglik(u) for u in us])
    if not np.any(np.isfinite(ls)):
        raise ValueError("no spread of psi gives these counts a positive probability")
    j = int(np.argmax(ls))
    a, b = float(us[max(j - 1, 0)]), float(us[min(j + 1, len(us) - 1)])
    known = [(float(us[k]), -float(ls[k])) for k in range(max(j - 1, 0), min(j + 2, len(us)))]
    u_min, f_min = _minimize_bounded(lambda u: -loglik(u), a, b, xatol=1e-9, known=known)
    u_hat, l_hat = (u_min, -f_min) if -f_min > ls[j] else (float(us[j]), float(ls[j]))
    # The log-likelihood is flat at sigma = 0 (the chances move like sigma^2): a gain below
    # 1e-8 over an end of the range is rounding, not evidence; report the end itself.
    if j in (0, len(us) - 1) and l_hat - ls[j] < 1e-8:
        u_hat, l_hat = float(us[j]), float(ls[j])
    # chi2_1(conf) / 2 = gammaincinv(1/2, conf) (scipy.stats.chi2.ppf's formula), from the
    # upper tail when conf is near 1 (1 - conf is exact there; conf itself rounds to 1)
    half = gammainccinv(0.5, 1.0 - conf) if conf >= 0.5 else gammaincinv(0.5, conf)
    cut = l_hat - float(half)

    # The ends are where log L crosses the cut.  They are found on the equivalent
    # sqrt(l_hat - cut) - sqrt(l_hat - log L), which has the same sign and zeros but is nearly
    # linear in u near the maximum (log L is nearly quadratic there), so the root finder's
    # interpolation steps land at once instead of bisecting a steep parabola.
    depth = math.sqrt(max(l_hat - cut, 0.0))

    def g(u):
        v = loglik(u)
        if not math.isfinite(v):
            return -1e150
        return depth - math.sqrt(max(l_hat - v, 0.0))

    pts = sorted(set(us.tolist()) | {u_hat})
    gv = [g(u) for u in pts]
    pieces, start = [], (0.0 if gv[0] >= 0 else None)
    for k in range(1, len(pts)):
        if (gv[k - 1] >= 0) == (gv[k] >= 0):
            continue
        root = _root(g, pts[k - 1], pts[k], xtol=1e-10, fa=gv[k - 1], fb=gv[k])
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
    return SpreadFit(
        sigma=sigma,
        low=spans[0][0],
        high=spans[-1][1],
        pieces=spans,
        confidence=conf,
        log_likelihood=l_hat,
        aic=aic(l_hat, 1),
        chances=chances(u_hat),
        note="; ".join(notes),
        profile=tuple((_sigma_of(u), cache[u]) for u in us.tolist()),
    )


class ModelSummary(namedtuple("ModelSummary",
                               "model n_params log_likelihood aic delta_aic sse_sides")):
    """One model across all experiments."""

    # model: str
    # n_params: int
    # log_likelihood: float
    # aic: float
    # delta_aic: float  AIC minus the smallest AIC of the models compared
    # sse_sides: float  the paper's sum of squared errors of the side frequencies
    __slots__ = ()


class FitResult(namedtuple("FitResult", "rows spread models")):
    """``coin fit``: each experiment checked, and the models compared across them."""

    # rows: Checks  a sequence of CheckResult (columns underneath)
    # spread: SpreadFit | None
    # models: tuple[ModelSummary, ...]
    __slots__ = ()
SPREAD_MODEL = "psi-spread"  #: the model name of the fitted spread in results


def fit(experiments: Sequence[Experiment], densities: Mapping[str, object] | None = None, *,
        confidence: float = CONFIDENCE, alpha: float = ALPHA, method: str = "auto",
        spread: bool = True) -> FitResult:
    """Check each experiment and compare the models across all of them.

    Models: geometric, dynamic, each named density in ``densities`` (0 free parameters each),
    and, with ``spread=True``, the maximum-likelihood spread of psi (1 free parameter; its
    per-row p-values ignore that the spread was fitted to the same data, so they lean lenient).
    Every model's chances are computed once per distinct coin, and every row's tests run
    together (:func:`check_many`).
    """
    import numpy as np

    from coincli.core.models import dynamic, geometric

    if not experiments:
        raise ValueError("experiments is empty: nothing to fit")
    _check_method(method)
    counts = [e.counts for e in experiments]
    xa = np.fromiter((e.xi for e in experiments), float, len(experiments))
    ux, inv = np.unique(xa, return_inverse=True)

    def per_row(ch) -> Outcome:
        return Outcome(*(np.asarray(v, dtype=float).reshape(-1)[inv] for v in ch))

    per_model: dict[str, tuple[Outcome, int]] = {
        "geometric": (per_row(geometric(ux)), 0),
        "dynamic": (per_row(dynamic(ux)), 0),
    }
    if densities:
        from coincli.core.averages import marginal

        for name, dens in densities.items():
            per_model[name] = (per_row(marginal(ux, dens)), 0)
    sp = None
    if spread:
        sp = fit_spread(xa, counts, confidence=confidence)
        per_model[SPREAD_MODEL] = (sp.chances, 1)
    rows = check_many(counts, xa, {name: ch for name, (ch, _) in per_model.items()},
                      confidence=confidence, alpha=alpha, method=method,
                      labels=[e.label for e in experiments])
    lls = {t.model: math.fsum(t.log_likelihood.tolist()) for t in rows.tests}
    if sp is not None:
        lls[SPREAD_MODEL] = sp.log_likelihood  # the same number, without re-summing rounding
    aics = {name: aic(lls[name], k) for name, (_, k) in per_model.items()}
    best = min(aics.values())
    freq = rows.cc.sides / rows.cc.n
    summaries = tuple(
        ModelSummary(name, k, lls[name], aics[name],
                     (aics[name] - best) if math.isfinite(best) else math.nan,
                     math.fsum(((freq - ch.sides) ** 2).tolist()))
        for name, (ch, k) in per_model.items()
    )
    return FitResult(rows, sp, summaries)


# --------------------------------------------------------------------------- the experiments CSV

CSV_COLUMNS = ("label", "xi", "coin", "count", "diameter", "thickness", "heads", "sides", "tails",
               "n")
_CSV_ALIASES = {"name": "label", "tosses": "n", "diameter_mm": "diameter",
                "thickness_mm": "thickness"}
#: A number written with a decimal comma (``0,5``, ``2,4cm``): read so in semicolon files
_DECIMAL_COMMA = re.compile(r"^[+-]?\d+,\d+([eE][+-]?\d+)?[a-zA-Z\"]*$", re.ASCII)


class Experiment(namedtuple("Experiment", "line xi counts label")):
    """One row of an experiments file: a coin's aspect ratio and its tosses."""

    # line: int  line number in the file (1-based)
    # xi: float
    # counts: Counts
    # label: str  the label column, else a description of the coin ("nickel x3", "xi=0.583")
    __slots__ = ()
class CSVError(ValueError):
    """A malformed experiments file; the message names the line and column."""

    def __init__(self, message: str, line: int, column: str | None = None):
        super().__init__(message)
        self.line = line
        self.column = column


def _err(line: int, column: str | None, msg: str) -> CSVError:
    where = f"line {line}" + (f", column {column!r}" if column else "")
    return CSVError(f"{where}: {msg}", line, column)


_WHOLE = re.compile(r"^\+?\d+(\.0*)?$", re.ASCII)


def _csv_count(text: str, name: str) -> int:
    s = text.strip()
    digits = s.split(".")[0].lstrip("+").lstrip("0")
    if not _WHOLE.match(s) or len(digits) > 16 or int(digits or "0") > MAX_COUNT:
        shown = text if len(text) <= 40 else text[:37] + "..."
        raise ValueError(f"{name} must be a whole number from 0 to {MAX_COUNT} (2**53), "
                         f"got {shown!r}")
    return int(digits or "0")


#: the separators a file may use, by what a user may call them
DELIMITERS = {",": ",", "comma": ",", ";": ";", "semicolon": ";", "\t": "\t", "tab": "\t",
              "\\t": "\t"}
_DELIMITER_NAMES = {",": "comma", ";": "semicolon", "\t": "tab"}


def delimiter_of(name: str) -> str:
    """The separator ``name`` means (``,``/``comma``, ``;``/``semicolon``, tab/``\t``/``tab``)."""
    try:
        return DELIMITERS[name if name == "\t" else name.strip().lower()]
    except (KeyError, AttributeError):
        raise ValueError(f"delimiter must be comma (,), semicolon (;) or tab, got {name!r}") \
            from None


def _sniff(header_line: str) -> str:
    """The separator of a header line: the most frequent of comma, semicolon and tab (comma
    when there is none, or on a tie)."""
    counts = {d: header_line.count(d) for d in (",", ";", "\t")}
    best = max(counts.values())
    return next(d for d in (",", ";", "\t") if counts[d] == best) if best else ","


def parse_experiments(text: str, *, max_rows: int = 100_000, delimiter: str | None = None
                      ) -> list[Experiment]:
    """Parse an experiments file; raise :class:`CSVError` naming the line and column.

    Comma-, semicolon- or tab-separated: ``delimiter`` (``,``, ``;`` or a tab), or, when None,
    the most frequent of the three in the header line.  The first non-blank, non-``#`` line is
    the header (case-insensitive, any order).  Columns:

    - the coin, one of: ``xi``; ``coin`` (a catalog name, :func:`coincli.core.coins.get_coin`) with
      an optional ``count`` of stacked coins (default 1); ``diameter`` and ``thickness`` (mm, or
      with a unit: ``24.26mm``, ``2.4cm``, ``0.955in``) with an optional ``count``;
    - the tosses: ``heads``, ``sides``, ``tails`` (``n`` optional, must match), or ``sides``
      and ``n`` when the faces were not told apart;
    - optionally ``label``.

    Rows may use different kinds (an empty cell is absent).  Aliases: ``name`` for ``label``,
    ``tosses`` for ``n``.  Blank lines and lines starting with ``#`` are skipped.  A header
    that does not parse says which separator it was read with.
    """
    import csv
    import io

    from coincli.core import coins
    from coincli.io.grammar import parse_length_mm, parse_number

    if text.startswith("\ufeff"):
        text = text[1:]
    sep = delimiter_of(delimiter) if delimiter is not None else None
    if sep is None:
        for raw_line in text.splitlines():
            if raw_line.strip() and not raw_line.lstrip().startswith("#"):
                sep = _sniff(raw_line)
                break
        else:
            sep = ","
    read_as = (f"read as {_DELIMITER_NAMES[sep]}-separated"
               + ("" if delimiter is not None else ", the separator sniffed from the header"))
    reader = csv.reader(io.StringIO(text), delimiter=sep, skipinitialspace=True, strict=True)
    header: list[str] | None = None
    header_line = 0
    out: list[Experiment] = []
    try:
        for cells in reader:
            line = reader.line_num
            if not cells or all(not c.strip() for c in cells) or cells[0].lstrip().startswith("#"):
                continue
            if header is None:
                header, header_line = [], line
                while cells and not cells[-1].strip():  # a spreadsheet's trailing separators
                    cells = cells[:-1]
                for k, raw in enumerate(cells, start=1):
                    name = raw.strip().lower()
                    name = _CSV_ALIASES.get(name, name)
                    if not name:
                        raise _err(line, f"#{k}", f"the header's column {k} has no name; expected "
                                   f"some of {', '.join(CSV_COLUMNS)} ({read_as})")
                    if name not in CSV_COLUMNS:
                        raise _err(line, raw.strip() or f"#{k}",
                                   f"unknown column; expected some of {', '.join(CSV_COLUMNS)} "
                                   f"({read_as})")
                    if name in header:
                        raise _err(line, raw.strip(), "appears twice in the header")
                    header.append(name)
                if "sides" not in header:
                    raise _err(line, None, f"the header has no 'sides' column ({read_as})")
                if not ({"xi", "coin", "diameter"} & set(header)):
                    raise _err(line, None,
                               "the header needs xi, coin (and count), or diameter and thickness "
                               f"({read_as})")
                width = len(header)
                continue
            if len(cells) > width:
                extra = cells[width:]
                if any(c.strip() for c in extra):
                    raise _err(line, f"#{width + 1}",
                               f"{len(cells)} fields but the header (line {header_line}) has "
                               f"{width} columns ({read_as})")
                cells = cells[:width]
            elif len(cells) < width:
                cells = cells + [""] * (width - len(cells))
            row = dict(zip(header, (c.strip() for c in cells), strict=True))
            if sep == ";":  # a decimal comma, as such spreadsheets write it: 0,5 is 0.5
                for key in ("xi", "diameter", "thickness"):
                    v = row.get(key)
                    if v and _DECIMAL_COMMA.match(v):
                        row[key] = v.replace(",", ".")
            out.append(_experiment(line, row, parse_number, parse_length_mm, coins))
            if len(out) > max_rows:
                raise _err(line, None, f"more than {max_rows} experiments")
    except csv.Error as exc:
        raise _err(reader.line_num, None, f"not valid CSV: {exc}") from None
    if header is None:
        raise _err(1, None, "the file is empty (expected a header such as xi,heads,sides,tails)")
    if not out:
        raise _err(header_line, None, "no experiments after the header")
    return out


def _fast_count(text: str, name: str) -> int:
    """A count cell: plain ASCII digits take the fast path; anything else :func:`_csv_count`."""
    if text.isdigit() and text.isascii() and len(text) <= 15:
        return int(text)
    return _csv_count(text, name)


def _counts_of(h, s, t, m) -> Counts:
    """:func:`make_counts` for whole numbers already read: the two usual shapes directly."""
    if s is not None and h is not None and t is not None and m is None:
        total = h + s + t
        if 0 < total <= MAX_COUNT:
            return Counts(total, s, h, t)
    elif s is not None and h is None and t is None and m is not None and 0 < m and s <= m:
        return Counts(m, s)
    return make_counts(h, s, t, m)


def _experiment(line: int, row: dict, parse_number, parse_length_mm, coins) -> Experiment:
    has = {k for k, v in row.items() if v}
    geo = has & {"xi", "coin", "diameter", "thickness"}
    count = None
    if "count" in has:
        if geo == {"xi"}:
            raise _err(line, "count", "count goes with coin or diameter/thickness, not with xi")
        try:
            from coincli.io.grammar import parse_count

            count = parse_count(row["count"], "count")
        except ValueError as exc:
            raise _err(line, "count", str(exc)) from None
    if "xi" in geo:
        if len(geo) > 1:
            other = sorted(geo - {"xi"})[0]
            raise _err(line, other, "give xi, or coin, or diameter and thickness; not several")
        try:
            from coincli.io.grammar import parse_ratio

            xi = parse_ratio(row["xi"], "xi")  # as --xi takes it: 0.5, 1/2, 17/30
        except ValueError as exc:
            raise _err(line, "xi", str(exc)) from None
        if not (math.isfinite(xi) and xi > 0):
            raise _err(line, "xi", f"xi must be a finite number > 0 in a file of tosses (at "
                       f"xi = 0 no model lands on a side: coin check --xi 0 tests such a coin), "
                       f"got {row['xi']!r}")
        desc = f"xi={row['xi']}"
    elif "coin" in geo:
        if len(geo) > 1:
            other = sorted(geo - {"coin"})[0]
            raise _err(line, other, "give coin, or diameter and thickness; not both")
        try:
            coin = coins.get_coin(row["coin"])
        except ValueError as exc:
            raise _err(line, "coin", str(exc)) from None
        k = count or 1
        xi = coins.stack_xi(coin, k)
        desc = coin.name if k == 1 else f"{coin.name} x{k}"
    elif geo:
        for name in ("diameter", "thickness"):
            if name not in has:
                raise _err(line, name, "diameter and thickness must be given together")
        try:
            d = parse_length_mm(row["diameter"], "diameter")
        except ValueError as exc:
            raise _err(line, "diameter", str(exc)) from None
        try:
            h = parse_length_mm(row["thickness"], "thickness")
        except ValueError as exc:
            raise _err(line, "thickness", str(exc)) from None
        k = count or 1
        try:
            xi = coins.stack_xi(coins.custom_coin(d, h), k)
        except ValueError as exc:
            raise _err(line, "thickness", str(exc)) from None
        if not (math.isfinite(xi) and xi > 0):
            raise _err(line, "thickness", f"thickness / diameter = {xi!r} is not a usable ratio")
        desc = f"{row['diameter']}x{row['thickness']}" + (f" x{k}" if k > 1 else "")
    else:
        raise _err(line, "xi", "no coin on this row: give xi, coin, or diameter and thickness")
    vals = {}
    for name in ("heads", "sides", "tails", "n"):
        if name in has:
            try:
                vals[name] = _fast_count(row[name], name)
            except ValueError as exc:
                raise _err(line, name, str(exc)) from None
    try:
        counts = _counts_of(vals.get("heads"), vals.get("sides"), vals.get("tails"),
                            vals.get("n"))
    except CountsError as exc:
        raise _err(line, exc.argument, str(exc)) from None
    return Experiment(line, float(xi), counts, row.get("label") or desc)
