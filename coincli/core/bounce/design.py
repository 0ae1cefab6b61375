"""The design for a bouncing coin: the aspect ratio that lands on a side with a given chance.

:func:`design` simulates tosses onto a surface (:func:`coincli.core.bounce.runs.simulate`)
at a sweep of aspect ratios, fits ``P(sides) = Phi(alpha + beta ln xi)`` to the counts
(:func:`fit_sides`, a :class:`SidesFit`), and adds tosses near each target's answer until its
confidence interval is narrow enough (:class:`Design`).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

from coincli.core.bounce import runs as _runs
from coincli.core.bounce.engine import smallest_xi
from coincli.core.bounce.runs import Workers, simulate, simulate_many
from coincli.core.toss.flight import DEFAULT_DIAMETER, SIDES
from coincli.limits import BOUNCE_XI_MAX

__all__ = ["SidesFit", "fit_sides", "Design", "design", "TooFewSettled", "BeyondTheEngine",
           "Undetermined"]


class Undetermined(ValueError):
    """The simulated tosses do not determine a curve of P(sides) in xi (a threshold in xi
    separates the tosses on a side from the rest, the fit diverges, or P(sides) does not grow
    with xi): the input was valid, the answer cannot be computed from these tosses."""


class TooFewSettled(ValueError):
    """Too few tosses settled for a fit: fewer than two aspect ratios with a settled toss.
    ``tosses``, ``unsettled``: the counts of the run so far; ``never_landed``: those of the
    unsettled that never reached the surface within ``t_max``."""

    def __init__(self, tosses: int, unsettled: int, never_landed: int):
        super().__init__(f"{unsettled} of {tosses} simulated tosses did not settle: too few "
                         "settled to fit P(sides)")
        self.tosses, self.unsettled, self.never_landed = tosses, unsettled, never_landed


class BeyondTheEngine(ValueError):
    """A target's answer, ``xi``, lies outside ``(lo, hi)``, the aspect ratios the engine can
    simulate for this coin: no simulated toss could check it (issue 28)."""

    def __init__(self, target: float, xi: float, lo: float, hi: float):
        super().__init__(f"P(sides) = {target:g} needs xi = {xi:.3g}, outside the aspect "
                         f"ratios MuJoCo can simulate for this coin ({lo:.3g} to {hi:g})")
        self.target, self.xi, self.lo, self.hi = target, xi, lo, hi


@dataclass
class SidesFit:
    """``P(sides) = Phi(alpha + beta ln xi)``, a probit in log xi fitted to simulated counts by
    maximum likelihood (monotone increasing when ``beta > 0``), with the covariance of
    ``(alpha, beta)`` (inverse Fisher information, times the dispersion ``deviance / df`` when
    that is above 1: quasi-likelihood, so that a curve that misses its points has wider
    intervals) and a goodness-of-fit test against the points (deviance, chi-square with
    points - 2 degrees of freedom)."""

    alpha: float
    beta: float
    cov: tuple  #: ((var alpha, cov), (cov, var beta))
    points: list  #: (xi, tosses, sides) of the settled tosses at each simulated xi
    deviance: float
    df: int
    p_value: float  #: of the goodness-of-fit test (nan when df = 0)

    def p_sides(self, xi):
        import numpy as np
        from scipy.special import ndtr

        with np.errstate(divide="ignore"):  # xi = 0 (a plot's axis): ln 0 = -inf, P = 0
            return ndtr(self.alpha + self.beta * np.log(xi))

    def inverse(self, p):
        """The xi at which the fitted P(sides) is ``p`` (0 < p < 1)."""
        from scipy.special import ndtri

        return math.exp((float(ndtri(p)) - self.alpha) / self.beta)

    def interval(self, p, level=0.95):
        """A ``level`` confidence interval of :meth:`inverse`: Fieller's, the set of ln xi at
        which the fitted curve's value is within its own error of ``ndtri(p)``,
        ``(alpha + beta l - q)^2 <= z^2 var(alpha + beta l)``.  Unlike the delta method it
        carries the error of the slope (the interval is wider, and longer on the flatter side,
        when the slope is uncertain); it is unbounded, ``(0, inf)``, when the slope itself is
        not distinguishable from 0 at that level."""
        from statistics import NormalDist

        from scipy.special import ndtri

        q = float(ndtri(p))
        (vaa, vab), (_, vbb) = self.cov
        z2 = NormalDist().inv_cdf(0.5 + level / 2) ** 2
        d = self.alpha - q
        a = self.beta**2 - z2 * vbb
        b = self.beta * d - z2 * vab  # half the linear coefficient
        c = d * d - z2 * vaa
        disc = b * b - a * c
        if a <= 0 or disc < 0:
            return 0.0, math.inf
        r = math.sqrt(disc)
        lo, hi = sorted(((-b - r) / a, (-b + r) / a))
        return (math.exp(lo) if lo < 709 else math.inf), (math.exp(hi) if hi < 709 else math.inf)


def _norm_pdf(x):
    """The standard normal density, as ``scipy.stats.norm.pdf`` computes it (the same bits),
    without importing scipy.stats (a second of start-up; its ``ppf`` and ``chi2.sf`` are
    ``scipy.special.ndtri`` and ``chdtrc``, used directly)."""
    import numpy as np

    return np.exp(-x**2 / 2.0) / math.sqrt(2 * math.pi)


def _probit_irls(design, n, k, *, steps: int, tol: float):
    """The maximum-likelihood coefficients of ``P = Phi(design @ coef)`` for ``k`` of ``n``,
    by iteratively reweighted least squares (Fisher scoring) from the least-squares fit of the
    probits of the smoothed frequencies: at most ``steps`` steps, until no coefficient moves by
    ``tol``; None when a step diverges."""
    import numpy as np
    from scipy.special import ndtr, ndtri

    f = np.clip((k + 0.5) / (n + 1), 1e-6, 1 - 1e-6)
    coef = np.linalg.lstsq(design, ndtri(f), rcond=None)[0]
    for _ in range(steps):
        eta = design @ coef
        mu = np.clip(ndtr(eta), 1e-12, 1 - 1e-12)
        phi = np.maximum(_norm_pdf(eta), 1e-300)
        w = n * phi * phi / (mu * (1 - mu))
        z = eta + (k / n - mu) / phi
        try:
            new = np.linalg.solve(design.T @ (w[:, None] * design), design.T @ (w * z))
        except np.linalg.LinAlgError:
            return None
        if not np.all(np.isfinite(new)):
            return None
        done = np.max(np.abs(new - coef)) < tol
        coef = new
        if done:
            break
    return coef


def fit_sides(points) -> SidesFit:
    """Fit :class:`SidesFit` to ``points``, ``(xi, n, sides)`` rows (at least two distinct xi
    with some tosses), by iteratively reweighted least squares (Fisher scoring)."""
    import numpy as np
    from scipy.special import chdtrc, ndtr

    pts = [(float(x), int(n), int(k)) for x, n, k in points if n > 0]
    if len({x for x, _, _ in pts}) < 2:
        raise Undetermined("fitting P(sides) needs simulated tosses at two aspect ratios or "
                           "more")
    x = np.log([p[0] for p in pts])
    n = np.array([p[1] for p in pts], dtype=float)
    k = np.array([p[2] for p in pts], dtype=float)
    # A probit has a finite fit only when no threshold in xi separates the tosses that landed on
    # a side from those that did not, even with one aspect ratio holding both (its slope then
    # runs off to infinity): a side must lie below a face, and a face below a side.
    xs, xf = x[k > 0], x[k < n]
    if not (xs.size and xf.size and xs.min() < xf.max() and xf.min() < xs.max()):
        raise Undetermined("the simulated points do not determine a curve of P(sides) in xi (a "
                           "threshold in xi separates the tosses on a side from the rest); "
                           "simulate more tosses, or a range of xi where P(sides) is between "
                           "0 and 1")
    design = np.column_stack([np.ones_like(x), x])
    coef = _probit_irls(design, n, k, steps=100, tol=1e-12)
    if coef is None:
        raise Undetermined("the simulated points do not determine a curve of P(sides) in xi "
                           "(the fit diverges); simulate more tosses")
    eta = design @ coef
    mu = np.clip(ndtr(eta), 1e-12, 1 - 1e-12)
    phi = _norm_pdf(eta)
    w = n * phi * phi / (mu * (1 - mu))
    cov = np.linalg.inv(design.T @ (w[:, None] * design))
    with np.errstate(divide="ignore", invalid="ignore"):
        dev = 2 * np.sum(np.where(k > 0, k * np.log(k / (n * mu)), 0.0)
                         + np.where(n - k > 0, (n - k) * np.log((n - k) / (n * (1 - mu))), 0.0))
    df = len(pts) - 2
    if df > 0:  # points scattered beyond binomial noise (or a curve of the wrong shape):
        cov = cov * max(1.0, float(dev) / df)  # quasi-likelihood, the dispersion widens it
    return SidesFit(float(coef[0]), float(coef[1]), ((float(cov[0, 0]), float(cov[0, 1])),
                    (float(cov[1, 0]), float(cov[1, 1]))), pts, float(dev), df,
                    float(chdtrc(df, max(float(dev), 0.0))) if df > 0 else math.nan)


@dataclass
class Design:
    """Result of :func:`design`: the fitted curve and, per target, the aspect ratio with its
    confidence interval."""

    targets: list
    xi: list
    low: list
    high: list
    fit: SidesFit  #: the curve over every simulated point
    tosses: int
    rounds: int
    met: bool  #: every interval within tol
    stopped_by: str  #: 'tol', 'max_tosses' or 'time_limit'
    seed: int
    unsettled: int
    fits: list = field(default_factory=list)  #: per target, the local fit its answer is from
    first: int = 200  #: tosses at each xi of the first sweep (below DESIGN_FIRST: max_tosses cut it)
    #: the smallest and largest aspect ratios with a settled toss: an answer outside is an
    #: extrapolation of the fitted curve (the run stopped before simulating near it)
    span: tuple = (math.nan, math.nan)
    never_landed: int = 0  #: unsettled tosses that never reached the surface within t_max
    #: the precomputed table the design started from (:mod:`coincli.core.bounce.tables`), whose
    #: points replaced the first sweep, or None; ``tosses``, ``unsettled`` and ``never_landed``
    #: count this run's tosses only
    table: object = None


#: A target's answer comes from the probit fitted to the points within this factor of its
#: estimate (the narrowest of these windows holding three aspect ratios): over the whole sweep
#: (0.1 to 2.4) a probit in log xi can miss the points by far more than their noise.
DESIGN_WINDOWS = (1.12, 1.3, 1.6, 2.2, 3.3)


def _local_fit(points: dict, target, est):
    """The probit fitted near ``est`` (see :data:`DESIGN_WINDOWS`), re-centred on its own answer
    until that stays within its window; falls back to every point.  A window whose points do
    not determine a rising probit (separated: P(sides) jumps from 0 to 1 inside it; or flat
    there, its fitted slope not above 0, or its answer more than a factor 1.5 past its points)
    gives way to the next wider one: never straight to the whole sweep, whose curve can miss a
    floor by far more than its noise."""
    every = [(x, n, k) for x, (n, k) in sorted(points.items())]
    fit = None
    for _ in range(5):
        local = None
        for w in DESIGN_WINDOWS:
            near = [(x, n, k) for x, n, k in every if est / w <= x <= est * w]
            if len(near) >= 3:
                try:
                    candidate = fit_sides(near)
                except ValueError:
                    continue
                # a rising curve whose answer is near its points (not read off far past them)
                if candidate.beta > 0 and near[0][0] / 1.5 <= candidate.inverse(target) \
                        <= near[-1][0] * 1.5:
                    local = candidate
                    break
        if local is None:
            return fit_sides(every)
        fit = local
        new = fit.inverse(target)
        if abs(math.log(new / est)) < 1e-3:
            break
        est = new
    return fit


DESIGN_GRID = (0.1, 0.15, 0.22, 0.33, 0.5, 0.75, 1.1, 1.6, 2.4)  #: first sweep of xi
DESIGN_FIRST = 200  #: tosses at each xi of the first sweep (fewer when max_tosses is smaller)
DESIGN_FIRST_MIN = 20  #: the fewest tosses at each xi of a first sweep cut by max_tosses
#: the smallest max_tosses a design takes: the first sweep cut to DESIGN_FIRST_MIN per xi
DESIGN_LEAST = DESIGN_FIRST_MIN * len(DESIGN_GRID)
DESIGN_ROUND = 400  #: tosses at each of the three xi added near each target per round


def _curvature_shift(points: dict, target: float, est: float, factor: float = 1.3) -> float:
    """How far the answer moves when the local curve may bend: the xi at which a probit
    quadratic in ln xi, fitted to the points within ``factor`` of ``est`` (five aspect ratios at
    least, else 0), reaches ``target``, minus ``est``.  A straight probit over a window misses a
    curved P(sides) by about this much; the interval is widened by it (lack of fit)."""
    import numpy as np
    from scipy.special import ndtri

    near = [(x, n, k) for x, (n, k) in sorted(points.items())
            if n > 0 and est / factor <= x <= est * factor]
    if len(near) < 5:
        return 0.0
    lx = np.log([p[0] for p in near]) - math.log(est)
    n = np.array([p[1] for p in near], float)
    k = np.array([p[2] for p in near], float)
    if not (k.sum() > 0 and (n - k).sum() > 0):
        return 0.0
    coef = _probit_irls(np.column_stack([np.ones_like(lx), lx, lx * lx]), n, k, steps=50,
                        tol=1e-10)
    if coef is None:
        return 0.0
    c0, c1, c2 = (float(v) for v in coef)
    q = float(ndtri(target))
    # the root of c0 - q + c1 l + c2 l^2 nearest l = 0 (est), within the window
    if abs(c2) < 1e-12 * max(abs(c1), 1.0):
        roots = [-(c0 - q) / c1] if c1 else []
    else:
        disc = c1 * c1 - 4 * c2 * (c0 - q)
        roots = [] if disc < 0 else [(-c1 + r) / (2 * c2) for r in (math.sqrt(disc),
                                                                    -math.sqrt(disc))]
    roots = [r for r in roots if abs(r) <= math.log(factor)]
    if not roots:
        return 0.0
    return est * math.exp(min(roots, key=abs)) - est


def _bracketed(points: dict, x: float, factor: float) -> bool:
    """Whether simulated points within ``factor`` of ``x`` lie on both sides of it (three at
    least): an answer from them is read between points, not past them."""
    near = [p for p, (n, _) in points.items() if n > 0 and x / factor <= p <= x * factor]
    return len(near) >= 3 and min(near) <= x <= max(near)


def design(targets, *, seed, tol=0.01, max_tosses=200_000, time_limit=None, level=0.95,
           progress: Callable[[int, int], None] | None = None, clock=None, table=None,
           **kw) -> Design:
    """The aspect ratios at which tosses onto a surface land on a side with the chances
    ``targets`` (each in (0, 1)), with ``level`` confidence intervals.

    Simulates a first sweep of xi (:data:`DESIGN_GRID`, :data:`DESIGN_FIRST` tosses each), fits
    :class:`SidesFit` to every point, then for each target again to the points near its answer
    (:func:`_local_fit`; the answer and its interval come from that fit), then adds rounds of
    :data:`DESIGN_ROUND` tosses at 0.93, 1 and 1.07 times each target's estimate until every
    interval is within ``tol`` of its estimate (both ends), or ``max_tosses`` would be passed
    (never: a ``max_tosses`` below the first sweep's cuts its tosses per xi, to at least
    :data:`DESIGN_FIRST_MIN`, and stops there),
    or ``time_limit`` seconds (of ``clock``, default
    ``time.monotonic``) have gone by at the end of a round.  ``table``: a precomputed table
    (:class:`coincli.core.bounce.tables.Table`) whose points replace the first sweep (its
    tosses are not counted against ``max_tosses``); the rounds are the same.  Every
    simulation is seeded
    ``(seed, round, point)``: the result is a function of the seed and the number of rounds, so a
    run stopped by the time limit is reproduced by ``max_tosses`` equal to its tosses.
    ``kw`` is passed to :func:`coincli.core.bounce.runs.simulate` (xi excluded).
    """
    import time

    targets = [float(t) for t in targets]
    for t in targets:
        if not 0.0 < t < 1.0:
            raise ValueError(f"a target P(sides) must be strictly between 0 and 1, got {t:g}")
    clock = clock or time.monotonic
    start = clock()
    points: dict = {}
    tosses = unsettled = 0
    planned = len(DESIGN_GRID) * DESIGN_FIRST

    never_landed = 0
    lo_xi = smallest_xi(kw.get("diameter", DEFAULT_DIAMETER))  # what the engine can simulate

    run_kw = {k: v for k, v in kw.items() if k not in ("jobs", "executor")}

    def run(xs, n, rnd):
        # the round's points at once, on the design's workers (one pool for the design)
        nonlocal tosses, unsettled, never_landed
        before = tosses

        def tick(done):
            if progress is not None:
                progress(before + done, planned)

        specs = [dict(n=n, seed=seed, xi=x, stream=(rnd, j), **run_kw)
                 for j, x in enumerate(xs)]
        if simulate is _runs.simulate:  # the engine: the round's points in one queue
            sims = simulate_many(specs, workers=workers, executor=kw.get("executor"),
                                 progress=tick)
        else:  # a stand-in for the engine (the tests' counts without MuJoCo): point by point
            sims = [simulate(**spec, **{k: v for k, v in kw.items() if k not in run_kw})
                    for spec in specs]
        for x, r in zip(xs, sims, strict=True):
            old = points.get(x, (0, 0))
            points[x] = (old[0] + r.settled, old[1] + r.counts[SIDES])
            tosses += n
            unsettled += r.counts[3]
            never_landed += r.n - sum(r.catch_counts)  # no first contact: no catch outcome

    first = min(DESIGN_FIRST, int(max_tosses) // len(DESIGN_GRID))
    if first < DESIGN_FIRST_MIN:
        raise ValueError(f"--max-tosses must be at least {DESIGN_LEAST} "
                         f"with --landing bounce ({DESIGN_FIRST_MIN} tosses at each of the "
                         f"{len(DESIGN_GRID)} aspect ratios of the first sweep), got "
                         f"{max_tosses}")
    planned = 0 if table is not None else len(DESIGN_GRID) * first
    workers = Workers(kw.get("jobs"))
    with workers:
        if table is not None:  # the table's points are the first sweep
            points.update(table.design_points())
            first = DESIGN_FIRST
        else:
            run(DESIGN_GRID, first, 0)
        rnd = 0
        stopped = "tol"
        while True:
            if sum(1 for n, _ in points.values() if n > 0) < 2:
                raise TooFewSettled(tosses, unsettled, never_landed)
            fit = fit_sides([(x, n, k) for x, (n, k) in sorted(points.items())])
            if fit.beta <= 0:
                raise Undetermined("the simulated P(sides) does not grow with xi; no design "
                                   "found")
            fits = [_local_fit(points, t, fit.inverse(t)) for t in targets]
            est = [f.inverse(t) for f, t in zip(fits, targets, strict=True)]
            for t, x in zip(targets, est, strict=True):
                if not lo_xi <= x <= BOUNCE_XI_MAX:  # no toss could check it: never an answer
                    raise BeyondTheEngine(t, x, lo_xi, BOUNCE_XI_MAX)
            ivs = []
            for f, t, x in zip(fits, targets, est, strict=True):
                lo, hi = f.interval(t, level)
                shift = abs(_curvature_shift(points, t, x))
                ivs.append((max(lo - shift, 0.0), hi + shift))
            met = all(hi - x <= tol and x - lo <= tol and _bracketed(points, x, DESIGN_WINDOWS[0])
                      for x, (lo, hi) in zip(est, ivs, strict=True))
            if met:
                break
            nxt = sorted({round(x * f, 6) for x in est for f in (0.93, 1.0, 1.07)})
            nxt = [x for x in nxt if lo_xi <= x <= BOUNCE_XI_MAX]
            if first < DESIGN_FIRST or tosses + len(nxt) * DESIGN_ROUND > max_tosses:
                stopped = "max_tosses"  # a cut first sweep: the cap stopped it, whatever is left
                break
            if time_limit is not None and clock() - start > time_limit:
                stopped = "time_limit"
                break
            rnd += 1
            planned = tosses + len(nxt) * DESIGN_ROUND
            run(nxt, DESIGN_ROUND, rnd)
    settled = [x for x, (n, _) in points.items() if n > 0]
    return Design(targets, est, [lo for lo, _ in ivs], [hi for _, hi in ivs], fit, tosses,
                  rnd, met, stopped, seed, unsettled, fits, first, (min(settled), max(settled)),
                  never_landed, table)

