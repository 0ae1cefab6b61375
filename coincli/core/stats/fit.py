r"""Across experiments: the spread of psi fitted to all of them, and the models compared.

Spread of psi (:func:`fit_spread`)
    The tossing style enters through the angle psi between the angular momentum and the normal.
    The model: psi is normal about pi/2 with standard deviation ``sigma``, truncated to [0, pi]
    (:class:`coincli.core.densities.Normal`); the chances are the psi-averages of Table I
    (:func:`coincli.core.averages.marginal`).  ``sigma = 0`` is the Keller flip, i.e. the
    dynamic model (eq. 12); ``sigma -> inf`` is psi uniform on [0, pi] (Table II, first
    column).  ``sigma`` is estimated by maximum likelihood over ``[0, inf]`` and given a
    profile-likelihood interval ``{sigma: 2 (l_max - l(sigma)) <= chi2_1(0.95) = 3.84}``, with
    the pure-Python Brent minimizer and root finder of :mod:`coincli.core._numerics.roots`.

Model comparison (:func:`fit`)
    Each experiment checked (:func:`coincli.core.stats.tests.check_many`), then
    ``AIC = 2k - 2 log L`` with ``k = 0`` for the geometric and dynamic models (nothing is
    fitted) and ``k = 1`` for the fitted spread; the paper's sum of squared errors of the side
    frequencies (``0.20`` geometric against ``0.01`` dynamic in Sec. IV) is :func:`sse_sides`.

numpy and scipy.special are imported inside the functions that need them (the CLI's start-up
budget); scipy.optimize is not used at all (0.1-0.2 s of import).
"""

from __future__ import annotations

import math
from collections import namedtuple
from collections.abc import Mapping, Sequence

from coincli.core._numerics.roots import brent_minimize, brent_root
from coincli.core._numerics.wilson import CONFIDENCE, check_level
from coincli.core.models import HALF_PI, Outcome
from coincli.core.stats.counts import (
    Caught,
    CountColumns,
    Counts,
    Experiment,
    ExperimentColumns,
    LogFactorial,
)
from coincli.core.stats.tests import ALPHA, check_many, check_method

__all__ = [
    "sse_sides",
    "aic",
    "SpreadFit",
    "fit_spread",
    "ModelSummary",
    "FitResult",
    "CaughtFit",
    "SPREAD_MODEL",
    "fit",
]


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
    :func:`coincli.core.stats.tests._log_likelihoods`' (multinomial with faces told apart, else
    binomial in sides with the rarer category's chance)."""

    def __init__(self, cc: CountColumns):
        import numpy as np

        lf = LogFactorial(int(np.max(cc.n, initial=0)))
        f = cc.faces
        self.faces = f
        self.so = so = cc.sides_only
        self.caught = c = cc.caught
        self.x = cc.matrix()[f]
        self.k, self.m = cc.sides[so], cc.n[so]
        self.s, self.d = cc.same[c], cc.n[c] - cc.same[c]
        const = np.concatenate([lf(cc.n[f]) - lf(self.x).sum(axis=1),
                                lf(self.m) - (lf(self.k) + lf(self.m - self.k)),
                                lf(cc.n[c]) - (lf(self.s) + lf(self.d))])
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
                so = self.so
                ps = np.clip(sides[so], 0.0, 1.0)
                pf = np.clip(heads[so] + tails[so], 0.0, 1.0)  # not 1 - ps: a thick coin's faces
                ll = np.where(ps <= 0.5, xlogy(k, ps) + xlog1py(m - k, -ps),
                              xlogy(m - k, pf) + xlog1py(k, -pf))
                total += float(np.sum(ll))
            if self.s.size:  # caught: the same side given a face
                ph, pt = heads[self.caught], tails[self.caught]
                total += float(np.sum(xlogy(self.s, ph / (ph + pt))
                                      + xlogy(self.d, pt / (ph + pt))))
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

    conf = check_level(confidence, "confidence")
    xs = np.asarray([float(v) for v in xi], dtype=float)
    if xs.ndim != 1 or len(xs) != len(counts) or len(xs) == 0:
        raise ValueError(f"xi and counts must be non-empty and of one length, got {len(xs)} and "
                         f"{len(counts)}")
    columns = isinstance(counts, CountColumns)
    if not columns and not all(isinstance(c, (Counts, Caught)) for c in counts):
        raise ValueError("counts must be Counts (see make_counts)")
    if not np.all(np.isfinite(xs) & (xs > 0)):
        raise ValueError("xi must be finite and > 0 for every experiment")
    if int(grid) < 5:
        raise ValueError(f"grid must be >= 5, got {grid!r}")
    ux, inv = np.unique(xs, return_inverse=True)  # rows share coins: chances once per coin
    like = _Likelihood(counts if columns else CountColumns(counts))
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
    u_min, f_min = brent_minimize(lambda u: -loglik(u), a, b, xatol=1e-9, known=known)
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
        root = brent_root(g, pts[k - 1], pts[k], xtol=1e-10, fa=gv[k - 1], fb=gv[k])
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


class FitResult(namedtuple("FitResult", "rows spread models caught", defaults=(None,))):
    """``coin fit``: each experiment checked, and the models compared across them."""

    # rows: Checks  a sequence of CheckResult (columns underneath)
    # spread: SpreadFit | None
    # models: tuple[ModelSummary, ...]
    # caught: CaughtFit | None  the caught rows' own spreads, when the file has any
    __slots__ = ()


class CaughtFit(namedtuple("CaughtFit", "rows fits heterogeneity fair_xi")):
    """The caught (faces-only) rows of a fit: their indices ``rows`` among all rows, each row's
    own :class:`coincli.core.stats.caught.RowFits`, the :class:`~.caught.Heterogeneity` of the
    tossers (None for one row), and each row's fair three-sided ``fair_xi`` (None unless a
    design was asked)."""

    __slots__ = ()


SPREAD_MODEL = "psi-spread"  #: the model name of the fitted spread in results
_SSE_BLOCK = 65536  #: rows of the sum of squared errors at a time


def fit(experiments: Sequence[Experiment], densities: Mapping[str, object] | None = None, *,
        confidence: float = CONFIDENCE, alpha: float = ALPHA, method: str = "auto",
        spread: bool = True, design: float | None = None) -> FitResult:
    """Check each experiment and compare the models across all of them.

    Models: geometric, dynamic, each named density in ``densities`` (0 free parameters each),
    and, with ``spread=True``, the maximum-likelihood spread of psi (1 free parameter; its
    per-row p-values ignore that the spread was fitted to the same data, so they lean lenient).
    Every model's chances are computed once per distinct coin, and every row's tests run
    together (:func:`check_many`).

    Caught rows (:class:`~coincli.core.stats.counts.Caught`, faces only) enter every
    likelihood with the chance of the same side given a face, and are also fitted one by one
    (:class:`CaughtFit`: each tosser's spread, the heterogeneity of the tossers and, with
    ``design`` a chance of a side such as 1/3, each tosser's fair coin).
    """
    import numpy as np

    from coincli.core.models import dynamic, geometric

    if not experiments:
        raise ValueError("experiments is empty: nothing to fit")
    check_method(method)
    if isinstance(experiments, ExperimentColumns):  # a file's rows as columns: no row objects
        counts, xa, labels = experiments.cc, experiments.xi, experiments.labels
    else:
        counts = [e.counts for e in experiments]
        xa = np.fromiter((e.xi for e in experiments), float, len(experiments))
        labels = [e.label for e in experiments]
    ux, inv = np.unique(xa, return_inverse=True)
    inv = inv.ravel()

    def per_coin(ch) -> Outcome:
        return Outcome(*(np.asarray(v, dtype=float).reshape(-1) for v in ch))

    # each model's chances per coin; the rows are checked a block at a time when read
    per_model: dict[str, tuple[Outcome, int]] = {
        "geometric": (per_coin(geometric(ux)), 0),
        "dynamic": (per_coin(dynamic(ux)), 0),
    }
    if densities:
        from coincli.core.averages import marginal

        for name, dens in densities.items():
            per_model[name] = (per_coin(marginal(ux, dens)), 0)
    sp = None
    if spread:
        sp = fit_spread(xa, counts, confidence=confidence)
        per_model[SPREAD_MODEL] = (per_coin(_spread_chances(ux, sp.sigma)), 1)
    rows = check_many(counts, xa, {name: ch for name, (ch, _) in per_model.items()},
                      confidence=confidence, alpha=alpha, method=method,
                      labels=labels, index=inv)
    # summed a block at a time (math.fsum of every row's value: the same number as at once)
    lls = {name: math.fsum(v for block in blocks for v in block.tolist())
           for name, blocks in rows.log_likelihoods().items()}
    if sp is not None:
        lls[SPREAD_MODEL] = sp.log_likelihood  # the same number, without re-summing rounding
    aics = {name: aic(lls[name], k) for name, (_, k) in per_model.items()}
    best = min(aics.values())
    cc = rows.cc

    def sse(ch) -> float:
        """The paper's SSE of one model, over the rows whose sides were seen (not caught)."""
        def terms():
            for a in range(0, len(cc), _SSE_BLOCK):
                b = a + _SSE_BLOCK
                freq = cc.sides[a:b] / cc.n[a:b]
                yield from ((freq - ch.sides[inv[a:b]])[~cc.caught[a:b]] ** 2).tolist()
        return math.fsum(terms())

    summaries = tuple(
        ModelSummary(name, k, lls[name], aics[name],
                     (aics[name] - best) if math.isfinite(best) else math.nan, sse(ch))
        for name, (ch, k) in per_model.items()
    )
    cf = None
    if rows.cc.caught.any():
        cf = _fit_caught(xa, rows.cc, confidence, design)
    return FitResult(rows, sp, summaries, cf)


def _fit_caught(xa, cc, confidence: float, design: float | None) -> CaughtFit:
    """Each caught row's own spread, the tossers' heterogeneity, and their fair coins."""
    import numpy as np

    from coincli.core.stats import caught as cs

    idx = np.flatnonzero(cc.caught)
    xi, same, n = xa[idx], cc.same[idx], cc.n[idx]
    chance = cs.SameChance(np.unique(xi))
    fits = cs.fit_rows(xi, same, n, confidence=confidence, chance=chance)
    het = cs.heterogeneity(xi, same, n, fits, chance=chance) if len(idx) > 1 else None
    fair = cs.fair_xi(fits.sigma, design) if design is not None else None
    return CaughtFit(idx, fits, het, fair)

