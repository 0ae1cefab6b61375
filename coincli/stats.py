r"""Statistics for real tosses: intervals, exact goodness-of-fit tests, fits of the spread of psi.

A coin designer tosses a prototype a few hundred times and asks whether the counts agree with a
model (issue 6; the paper did the same with 100 tosses a coin, Sec. IV and Fig. 5).  This module
is the pure core of ``coin check`` and ``coin fit``: numbers in, numbers and dataclasses out,
``ValueError`` naming the argument and its allowed range otherwise.  Nothing here prints.

Counts
    ``(heads, sides, tails)`` when the faces were told apart (a trinomial), or ``sides`` out of
    ``n`` when they were not (a binomial: side or face).  :func:`make_counts` validates them.

Intervals
    Wilson score and Clopper-Pearson ("exact") intervals for each observed frequency, both from
    :meth:`scipy.stats.binomtest(...).proportion_ci <scipy.stats._result_classes.BinomTestResult>`.

Goodness of fit (:func:`exact_pvalue`, :func:`goodness_of_fit`)
    The exact test orders outcomes by their probability under the model (the "probability" or
    "likelihood" ordering of Tate & Hyer 1973, the one :func:`scipy.stats.binomtest` uses for its
    two-sided p-value).  The p-value is

    .. math:: p = \sum_{x:\ P(x) \le (1 + 10^{-7})\, P(x_\mathrm{obs})} P(x),

    the sum over all outcomes ``x`` with ``sum(x) = n`` that are no more likely than the observed
    one.  The relative tolerance ``1e-7`` is scipy's: outcomes tied in exact arithmetic (e.g.
    heads and tails swapped under a model with equal chances) are not split by rounding.  The
    binomial p-value is :func:`scipy.stats.binomtest`'s.  The trinomial one is computed exactly
    as the binomial one row by row (see :func:`_exact_trinomial_logp`): for each number of sides
    ``s`` the heads count is binomial given ``s``; its probability is log-concave in the heads
    count, so the outcomes of that row no more likely than the observed one are two tails, found
    by bisection and summed with ``binom.cdf``/``binom.sf``.  Every outcome is accounted for; no
    sampling, no asymptotics.  It takes well under a second up to ``n = 10^6``
    (:data:`EXACT_MAX_N`); beyond that ``method="auto"`` switches to the likelihood-ratio G-test,

    .. math:: G = 2 \sum_i O_i \ln(O_i / E_i) \sim \chi^2_{k-1},

    and says so in the result (``exact=False``, ``method`` names the test).

Log-likelihoods
    The full multinomial (binomial) log-probability of the observed counts, multinomial
    coefficient included (:func:`scipy.stats.multinomial.logpmf`), so that values from different
    models of the same data are comparable and AIC differences are meaningful.

Spread of psi (:func:`fit_spread`)
    The tossing style enters through the angle psi between the angular momentum and the normal.
    The model: psi is normal about pi/2 with standard deviation ``sigma``, truncated to [0, pi]
    (:class:`coincli.densities.Normal`); the chances are the psi-averages of Table I
    (:func:`coincli.averages.marginal`).  ``sigma = 0`` is the Keller flip, i.e. the dynamic model
    (eq. 12); ``sigma -> inf`` is psi uniform on [0, pi] (Table II, first column).  ``sigma`` is
    estimated by maximum likelihood over ``[0, inf]`` and given a profile-likelihood interval
    ``{sigma: 2 (l_max - l(sigma)) <= chi2_1(0.95) = 3.84}``.

Model comparison
    ``AIC = 2k - 2 log L`` with ``k = 0`` for the geometric and dynamic models (nothing is
    fitted) and ``k = 1`` for the fitted spread; the paper's sum of squared errors of the side
    frequencies (``0.20`` geometric against ``0.01`` dynamic in Sec. IV) is :func:`sse_sides`.

numpy and scipy are imported inside the functions that need them (the CLI's start-up budget).
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

from coincli.models import Outcome

__all__ = [
    "CONFIDENCE",
    "ALPHA",
    "EXACT_MAX_N",
    "TIE_RTOL",
    "Counts",
    "make_counts",
    "Interval",
    "Proportion",
    "proportion",
    "proportions",
    "exact_pvalue",
    "g_test",
    "log_likelihood",
    "ModelTest",
    "goodness_of_fit",
    "format_p",
    "verdict",
    "model_chances",
    "CheckResult",
    "check",
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
]

CONFIDENCE = 0.95  #: default confidence level of the intervals
ALPHA = 0.05  #: default significance level of the verdicts
EXACT_MAX_N = 1_000_000  #: largest n for which method="auto" runs the exact test
TIE_RTOL = 1e-7  #: relative tolerance for "no more likely than the observed" (scipy's)
P_DISPLAY_FLOOR = 1e-300  #: p-values below this are shown as "p < 1e-300"
_LOG_TINY = math.log(5e-324)  # exp() of anything below is 0.0 in double precision

HALF_PI = math.pi / 2


# --------------------------------------------------------------------------- validation


def _check_level(value, name: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise ValueError(f"{name} must be a number in (0, 1), got {value!r}")
    v = float(value)
    if not 0.0 < v < 1.0:
        raise ValueError(f"{name} must be in (0, 1), got {value!r}")
    return v


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


@dataclass(frozen=True)
class Counts:
    """Observed tosses: ``sides`` of ``n``, and ``heads``/``tails`` when faces were told apart."""

    n: int
    sides: int
    heads: int | None = None
    tails: int | None = None

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


# --------------------------------------------------------------------------- intervals


@dataclass(frozen=True)
class Interval:
    """A confidence interval for a proportion."""

    low: float
    high: float
    method: str  # "wilson" or "clopper-pearson"
    confidence: float


@dataclass(frozen=True)
class Proportion:
    """An observed frequency ``count / n`` with its Wilson and Clopper-Pearson intervals."""

    outcome: str
    count: int
    n: int
    estimate: float
    wilson: Interval
    clopper_pearson: Interval


def proportion(count: int, n: int, outcome: str = "sides", confidence: float = CONFIDENCE
               ) -> Proportion:
    """The frequency ``count / n`` with 95% (``confidence``) Wilson and Clopper-Pearson intervals.

    Both come from ``scipy.stats.binomtest(count, n).proportion_ci`` (methods ``"wilson"`` and
    ``"exact"``).  They stay inside [0, 1] and finite for ``count = 0`` and ``count = n``, at
    any ``n``.

    >>> r = proportion(0, 10**6)
    >>> r.clopper_pearson.low, round(r.clopper_pearson.high, 10)
    (0.0, 3.6889e-06)
    """
    from scipy.stats import binomtest

    c = _whole(count, "count")
    m = _whole(n, "n")
    if m == 0:
        raise ValueError("n must be >= 1, got 0")
    if c > m:
        raise ValueError(f"count must be <= n = {m}, got {c}")
    conf = _check_level(confidence, "confidence")
    res = binomtest(c, m)
    out = {}
    for method, label in (("wilson", "wilson"), ("exact", "clopper-pearson")):
        ci = res.proportion_ci(confidence_level=conf, method=method)
        lo = min(max(float(ci.low), 0.0), 1.0)
        hi = min(max(float(ci.high), 0.0), 1.0)
        out[label] = Interval(lo, hi, label, conf)
    return Proportion(outcome, c, m, c / m, out["wilson"], out["clopper-pearson"])


def proportions(counts: Counts, confidence: float = CONFIDENCE) -> tuple[Proportion, ...]:
    """A :class:`Proportion` for each observed outcome (heads, sides, tails; or sides only)."""
    if counts.faces:
        return tuple(proportion(k, counts.n, name, confidence)
                     for name, k in zip(("heads", "sides", "tails"), counts.values, strict=True))
    return (proportion(counts.sides, counts.n, "sides", confidence),)


# --------------------------------------------------------------------------- exact test


def _exact_trinomial_logp(x: tuple[int, int, int], p: tuple[float, float, float]) -> float:
    """Log of the exact p-value for trinomial counts ``x`` (heads, sides, tails), all ``p > 0``.

    Write ``P(h, s, t) = B(s; n, p_s) * B(h; n - s, q)`` with ``q = p_h / (p_h + p_t)`` and ``B``
    the binomial pmf.  (The names are generic: :func:`exact_pvalue` passes the rarest outcome as
    ``s`` and the middle one as ``h``, so that ``p_s <= 1/3`` and ``q <= 1/2`` and no chance is
    lost to ``1 - p`` rounding.)  For each row ``s``:

    - if ``B(s; n, p_s) <= thr`` (the threshold ``P(x_obs) (1 + 1e-7)``) every outcome of the row
      is at most as likely as the observed one: the whole row counts, mass ``B(s; n, p_s)``;
    - otherwise ``h -> log P(h, s, n-s-h)`` is concave (a binomial pmf is log-concave), so the
      outcomes above the threshold form one interval around the mode.  Its ends are found by
      bisection and the row contributes ``B(s) * (cdf(L) + sf(R - 1))`` for the two tails.

    The result is exact up to floating-point rounding of the pmf and cdf (scipy/Boost, relative
    accuracy ~1e-14); it equals the brute-force sum over all ``(n+1)(n+2)/2`` outcomes
    (``tests/test_stats.py`` checks it against ``scipy.stats.multinomial.pmf`` enumeration).
    When ``#outcomes * P(x_obs) < 5e-324`` the p-value underflows and ``-inf`` is returned.
    """
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
    """Exact goodness-of-fit p-value of 2 or 3 category counts under the chances ``probs``.

    The sum of the model probabilities of all outcomes with the same total that are no more
    likely than the observed one (to a relative 1e-7, as in :func:`scipy.stats.binomtest`); see
    the module docstring.  Categories the model gives probability 0 are dropped when their count
    is 0; a positive count in one makes the observation impossible and the p-value 0.  Two
    categories: ``scipy.stats.binomtest(k, n, p).pvalue``.  Three: :func:`_exact_trinomial_logp`.

    The value is exact for any ``n`` but the trinomial case costs O(n) memory and time (about
    0.3 s at ``n = 10^6``); :func:`goodness_of_fit` uses :func:`g_test` above :data:`EXACT_MAX_N`.

    >>> round(exact_pvalue([35, 33, 32], [1/3, 1/3, 1/3]), 4)
    0.9519
    >>> exact_pvalue([50, 50], [0.5, 0.5])
    1.0
    """
    x = [_whole(v, "counts") for v in counts]
    if len(x) not in (2, 3):
        raise ValueError(f"counts must have 2 or 3 categories, got {len(x)}")
    p = _check_probs(probs, len(x))
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
    r"""Likelihood-ratio (G) test: ``(G, df, p)`` with ``G = 2 sum O ln(O/E)`` and ``p`` from chi2.

    ``df`` is the number of categories with positive expected count minus 1; a positive count
    where the model expects none gives ``G = inf`` and ``p = 0``.  Asymptotic: reliable when
    every expected count is large (say >= 5); :func:`exact_pvalue` has no such condition.
    """
    from scipy.special import xlogy
    from scipy.stats import chi2

    x = [_whole(v, "counts") for v in counts]
    p = _check_probs(probs, len(x))
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
    """Log-probability of the observed counts under the model's chances ``probs``.

    ``probs`` is an :class:`Outcome` (or ``(heads, sides, tails)``).  Faces told apart: the
    multinomial log-pmf; sides only: the binomial log-pmf of ``sides`` with ``P(sides)``.  The
    coefficient is included.  ``-inf`` when the model gives the counts probability 0.
    """
    from scipy.stats import binom, multinomial

    ph, ps, pt = _check_probs(probs, 3)
    if counts.faces:
        return float(multinomial.logpmf(list(counts.values), counts.n, [ph, ps, pt]))
    if ps <= 0.5:
        return float(binom.logpmf(counts.sides, counts.n, ps))
    return float(binom.logpmf(counts.n - counts.sides, counts.n, ph + pt))  # no 1 - ps rounding


# --------------------------------------------------------------------------- verdicts


def format_p(p: float) -> str:
    """``p = 0.43``, ``p = 0.0052``, ``p = 3.1e-7``; ``p < 1e-300`` below the display floor."""
    if not p >= P_DISPLAY_FLOOR:
        return "p < 1e-300"
    if p >= 1e-3:
        return f"p = {p:.2g}"
    mant, _, exp = f"{p:.1e}".partition("e")
    return f"p = {mant.rstrip('0').rstrip('.')}e{int(exp)}"


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
        text = f"consistent at the {100 * a:g}% level ({format_p(p)})"
    else:
        text = f"rejected, {format_p(p)}"
    return text if exact else text + " (asymptotic G-test)"


# --------------------------------------------------------------------------- one experiment


@dataclass(frozen=True)
class ModelTest:
    """How one model fares on one experiment."""

    model: str
    chances: Outcome  # (heads, sides, tails) as the model gave them (tests renormalize)
    categories: tuple[str, ...]  # the tested categories: heads/sides/tails or sides/faces
    expected: tuple[float, ...]  # expected counts, in the order of categories
    p_value: float
    exact: bool
    method: str  # "exact multinomial", "exact binomial" or "G-test (asymptotic chi2, df=k)"
    g_statistic: float  # likelihood-ratio statistic against the observed frequencies
    df: int
    log_likelihood: float
    verdict: str


def goodness_of_fit(counts: Counts, chances, model: str = "model", *, alpha: float = ALPHA,
                    method: str = "auto") -> ModelTest:
    """Test ``counts`` against a model's ``chances`` (heads, sides, tails).

    ``method``: ``"auto"`` (exact when ``n <= EXACT_MAX_N``, else the G-test), ``"exact"`` or
    ``"asymptotic"``.  With faces told apart the test is trinomial; otherwise binomial in
    ``sides`` against ``P(sides)``.
    """
    if method not in ("auto", "exact", "asymptotic"):
        raise ValueError(f"method must be 'auto', 'exact' or 'asymptotic', got {method!r}")
    ph, ps, pt = _check_probs(chances, 3, "chances")
    raw = Outcome(*(float(v) for v in chances))  # reported as the model gave them
    probs = (ph, ps, pt) if counts.faces else (ps, ph + pt)
    x = counts.values
    shown = tuple(raw) if counts.faces else (raw.sides, raw.heads + raw.tails)
    expected = tuple(counts.n * v for v in shown)
    g, df, p_asym = g_test(x, probs)
    exact = method == "exact" or (method == "auto" and counts.n <= EXACT_MAX_N)
    if exact:
        p = exact_pvalue(x, probs)
        how = "exact multinomial" if counts.faces else "exact binomial"
    else:
        p = p_asym
        how = f"G-test (asymptotic chi2, df={df})"
    ll = log_likelihood(counts, (ph, ps, pt))
    impossible = ll == -math.inf
    if impossible:
        p = 0.0
    return ModelTest(model, raw, counts.categories, expected, p, exact, how, g, df,
                     ll, verdict(p, alpha, exact=exact, impossible=impossible))


def model_chances(xi: float, densities: Mapping[str, object] | None = None
                  ) -> dict[str, Outcome]:
    """The chances under the geometric and dynamic models, and under each psi density given.

    ``densities`` maps a name to a :class:`coincli.densities.Density`; its chances are the
    psi-average :func:`coincli.averages.marginal`.
    """
    from coincli.models import dynamic, geometric

    out = {"geometric": geometric(xi), "dynamic": dynamic(xi)}
    for name, dens in (densities or {}).items():
        from coincli.averages import marginal

        out[name] = marginal(xi, dens)
    return out


@dataclass(frozen=True)
class CheckResult:
    """One experiment: the frequencies with intervals, and each model's test."""

    xi: float
    counts: Counts
    proportions: tuple[Proportion, ...]
    tests: tuple[ModelTest, ...]
    label: str = ""


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
    tests = tuple(goodness_of_fit(counts, ch, name, alpha=alpha, method=method)
                  for name, ch in chances.items())
    return CheckResult(float(xi), counts, proportions(counts, confidence), tests, label)


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


def _loglik_rows(counts: Sequence[Counts], heads, sides, tails) -> float:
    """Total log-likelihood of several experiments; ``heads`` etc. are arrays, one per row."""
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


def _spread_chances(xi, sigma: float) -> Outcome:
    """Chances for psi ~ Normal(pi/2, sigma) on [0, pi]; sigma = 0: dynamic, inf: uniform psi."""
    from coincli.models import dynamic

    if sigma == 0:
        return dynamic(xi)
    from coincli.densities import Normal, Uniform
    from coincli.averages import marginal

    return marginal(xi, Uniform() if math.isinf(sigma) else Normal(HALF_PI, sigma))


@dataclass(frozen=True)
class SpreadFit:
    """Maximum-likelihood spread of psi (sd of a normal about pi/2 truncated to [0, pi])."""

    sigma: float  #: the estimate, radians; 0 is the Keller flip (dynamic), inf is uniform psi
    low: float  #: lower end of the profile-likelihood interval
    high: float  #: upper end (inf when a uniform psi is not excluded)
    pieces: tuple[tuple[float, float], ...]  #: the confidence set; one piece unless flagged
    confidence: float
    log_likelihood: float
    aic: float
    chances: Outcome  #: arrays, one entry per experiment, at the estimate
    note: str = ""
    profile: tuple[tuple[float, float], ...] = field(default=(), repr=False)  #: (sigma, log L)

    n_params = 1


def _sigma_of(u: float) -> float:
    return math.inf if u >= 1.0 else u / (1.0 - u)


def fit_spread(xi: Sequence[float], counts: Sequence[Counts], *, confidence: float = CONFIDENCE,
               grid: int = 41) -> SpreadFit:
    r"""Maximum-likelihood ``sigma`` of psi ~ Normal(pi/2, sigma) truncated to [0, pi].

    All experiments share ``sigma`` (one tossing style); each contributes its multinomial (or
    binomial) log-likelihood with the chances :func:`coincli.averages.marginal` gives at its
    ``xi``.  The parameter runs over ``[0, inf]``, mapped to ``u = sigma / (1 + sigma)`` in
    ``[0, 1]``: ``sigma = 0`` is the dynamic model (Keller flip), ``sigma = inf`` uniform psi.

    Method: the log-likelihood on ``grid`` equally spaced ``u`` (both ends included), the best
    point refined by bounded Brent; the profile-likelihood confidence set
    ``{sigma: 2 (l_max - l(sigma)) <= chi2_1(confidence)}`` from the sign changes on the grid,
    each end refined by ``brentq``.  At the boundary ``sigma = 0`` the chi2_1 calibration is
    conservative (the exact limit is a 50:50 mixture of 0 and chi2_1).

    The set need not be one interval: the chance of a side is not monotone in ``sigma`` (it
    rises from the dynamic value, peaks near ``sigma ~ 0.4`` and falls to the uniform value), so
    side counts alone can fit a narrow and a wide spread equally well.  ``pieces`` lists every
    piece, ``low``/``high`` span them, and ``note`` says so.  Counts of heads and tails separate
    the two: the bias toward heads grows with ``sigma``.

    Raises ValueError when no spread gives the data positive probability.
    """
    import numpy as np
    from scipy.optimize import brentq, minimize_scalar
    from scipy.stats import chi2

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


@dataclass(frozen=True)
class ModelSummary:
    """One model across all experiments."""

    model: str
    n_params: int
    log_likelihood: float
    aic: float
    delta_aic: float  #: AIC minus the smallest AIC of the models compared
    sse_sides: float  #: the paper's sum of squared errors of the side frequencies


@dataclass(frozen=True)
class FitResult:
    """``coin fit``: each experiment checked, and the models compared across them."""

    rows: tuple[CheckResult, ...]
    spread: SpreadFit | None
    models: tuple[ModelSummary, ...]


SPREAD_MODEL = "psi-spread"  #: the model name of the fitted spread in results


def fit(experiments: Sequence[Experiment], densities: Mapping[str, object] | None = None, *,
        confidence: float = CONFIDENCE, alpha: float = ALPHA, method: str = "auto",
        spread: bool = True) -> FitResult:
    """Check each experiment and compare the models across all of them.

    Models: geometric, dynamic, each named density in ``densities`` (0 free parameters each),
    and, with ``spread=True``, the maximum-likelihood spread of psi (1 free parameter; its
    per-row p-values ignore that the spread was fitted to the same data, so they lean lenient).
    """
    import numpy as np

    if not experiments:
        raise ValueError("experiments is empty: nothing to fit")
    counts = [e.counts for e in experiments]
    xs = [e.xi for e in experiments]
    per_model: dict[str, tuple[list, int]] = {}
    xa = np.asarray(xs, dtype=float)
    from coincli.models import dynamic, geometric

    per_model["geometric"] = (_rows_of(geometric(xa)), 0)
    per_model["dynamic"] = (_rows_of(dynamic(xa)), 0)
    if densities:
        from coincli.averages import marginal

        for name, dens in densities.items():
            per_model[name] = (_rows_of(marginal(xa, dens)), 0)
    sp = None
    if spread:
        sp = fit_spread(xs, counts, confidence=confidence)
        per_model[SPREAD_MODEL] = (_rows_of(sp.chances), 1)
    rows = tuple(
        check(e.counts, e.xi, {name: ch[i] for name, (ch, _) in per_model.items()},
              confidence=confidence, alpha=alpha, method=method, label=e.label)
        for i, e in enumerate(experiments)
    )
    lls = {name: math.fsum(r.tests[k].log_likelihood for r in rows)
           for k, name in enumerate(per_model)}
    if sp is not None:
        lls[SPREAD_MODEL] = sp.log_likelihood  # the same number, without re-summing rounding
    aics = {name: aic(lls[name], k) for name, (_, k) in per_model.items()}
    best = min(aics.values())
    summaries = tuple(
        ModelSummary(name, k, lls[name], aics[name],
                     (aics[name] - best) if math.isfinite(best) else math.nan,
                     sse_sides(counts, [c.sides for c in ch]))
        for name, (ch, k) in per_model.items()
    )
    return FitResult(rows, sp, summaries)


def _rows_of(ch) -> list[Outcome]:
    """Outcome of arrays -> one Outcome of floats per row."""
    import numpy as np

    h, s, t = (np.atleast_1d(np.asarray(v, dtype=float)) for v in ch)
    return [Outcome(float(a), float(b), float(c)) for a, b, c in zip(h, s, t, strict=True)]


# --------------------------------------------------------------------------- the experiments CSV

CSV_COLUMNS = ("label", "xi", "coin", "count", "diameter", "thickness", "heads", "sides", "tails",
               "n")
_CSV_ALIASES = {"name": "label", "tosses": "n", "diameter_mm": "diameter",
                "thickness_mm": "thickness"}


@dataclass(frozen=True)
class Experiment:
    """One row of an experiments file: a coin's aspect ratio and its tosses."""

    line: int  #: line number in the file (1-based)
    xi: float
    counts: Counts
    label: str  #: the label column, else a description of the coin ("nickel x3", "xi=0.583")


class CSVError(ValueError):
    """A malformed experiments file; the message names the line and column."""

    def __init__(self, message: str, line: int, column: str | None = None):
        super().__init__(message)
        self.line = line
        self.column = column


def _err(line: int, column: str | None, msg: str) -> CSVError:
    where = f"line {line}" + (f", column {column!r}" if column else "")
    return CSVError(f"{where}: {msg}", line, column)


_WHOLE = re.compile(r"^\+?\d+(\.0*)?$")


def _csv_count(text: str, name: str) -> int:
    s = text.strip()
    digits = s.split(".")[0].lstrip("+").lstrip("0")
    if not _WHOLE.match(s) or len(digits) > 16 or int(digits or "0") > MAX_COUNT:
        shown = text if len(text) <= 40 else text[:37] + "..."
        raise ValueError(f"{name} must be a whole number from 0 to {MAX_COUNT} (2**53), "
                         f"got {shown!r}")
    return int(digits or "0")


def parse_experiments(text: str, *, max_rows: int = 100_000) -> list[Experiment]:
    """Parse an experiments CSV; raise :class:`CSVError` naming the line and column.

    The first non-blank, non-``#`` line is the header (case-insensitive, any order).  Columns:

    - the coin, one of: ``xi``; ``coin`` (a catalog name, :func:`coincli.coins.get_coin`) with
      an optional ``count`` of stacked coins (default 1); ``diameter`` and ``thickness`` (mm, or
      with a unit: ``24.26mm``, ``2.4cm``, ``0.955in``) with an optional ``count``;
    - the tosses: ``heads``, ``sides``, ``tails`` (``n`` optional, must match), or ``sides``
      and ``n`` when the faces were not told apart;
    - optionally ``label``.

    Rows may use different kinds (an empty cell is absent).  Aliases: ``name`` for ``label``,
    ``tosses`` for ``n``.  Blank lines and lines starting with ``#`` are skipped.
    """
    import csv
    import io

    from coincli.parse import parse_length_mm, parse_number

    if text.startswith("\ufeff"):
        text = text[1:]
    reader = csv.reader(io.StringIO(text), skipinitialspace=True, strict=True)
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
                for k, raw in enumerate(cells, start=1):
                    name = raw.strip().lower()
                    name = _CSV_ALIASES.get(name, name)
                    if name not in CSV_COLUMNS:
                        raise _err(line, raw.strip() or f"#{k}",
                                   f"unknown column; expected some of {', '.join(CSV_COLUMNS)}")
                    if name in header:
                        raise _err(line, raw.strip(), "appears twice in the header")
                    header.append(name)
                if "sides" not in header:
                    raise _err(line, None, "the header has no 'sides' column")
                if not ({"xi", "coin", "diameter"} & set(header)):
                    raise _err(line, None,
                               "the header needs xi, coin (and count), or diameter and thickness")
                continue
            if len(cells) > len(header):
                extra = cells[len(header):]
                if any(c.strip() for c in extra):
                    raise _err(line, f"#{len(header) + 1}",
                               f"{len(cells)} fields but the header (line {header_line}) has "
                               f"{len(header)} columns")
                cells = cells[:len(header)]
            row = {name: cells[k].strip() if k < len(cells) else ""
                   for k, name in enumerate(header)}
            out.append(_experiment(line, row, parse_number, parse_length_mm))
            if len(out) > max_rows:
                raise _err(line, None, f"more than {max_rows} experiments")
    except csv.Error as exc:
        raise _err(reader.line_num, None, f"not valid CSV: {exc}") from None
    if header is None:
        raise _err(1, None, "the file is empty (expected a header such as xi,heads,sides,tails)")
    if not out:
        raise _err(header_line, None, "no experiments after the header")
    return out


def _experiment(line: int, row: dict, parse_number, parse_length_mm) -> Experiment:
    from coincli import coins

    has = {k for k, v in row.items() if v}
    geo = has & {"xi", "coin", "diameter", "thickness"}
    count = None
    if "count" in has:
        if geo == {"xi"}:
            raise _err(line, "count", "count goes with coin or diameter/thickness, not with xi")
        try:
            from coincli.parse import parse_count

            count = parse_count(row["count"], "count")
        except ValueError as exc:
            raise _err(line, "count", str(exc)) from None
    if "xi" in geo:
        if len(geo) > 1:
            other = sorted(geo - {"xi"})[0]
            raise _err(line, other, "give xi, or coin, or diameter and thickness; not several")
        try:
            xi = parse_number(row["xi"], "xi")
        except ValueError as exc:
            raise _err(line, "xi", str(exc)) from None
        if not (math.isfinite(xi) and xi > 0):
            raise _err(line, "xi", f"xi must be a finite number > 0, got {row['xi']!r}")
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
                vals[name] = _csv_count(row[name], name)
            except ValueError as exc:
                raise _err(line, name, str(exc)) from None
    try:
        counts = make_counts(vals.get("heads"), vals.get("sides"), vals.get("tails"),
                             vals.get("n"))
    except CountsError as exc:
        raise _err(line, exc.argument, str(exc)) from None
    return Experiment(line, float(xi), counts, row.get("label") or desc)
