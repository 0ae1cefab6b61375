r"""Three ways to average over psi (eq. 15), each with an error estimate, and a chooser.

- :func:`quad`: Gauss-Legendre on the pieces between the integrand's kinks
  (:func:`coincli.core.averages.marginal`) with the fewest nodes whose calibrated error is within the
  tolerance; :func:`scipy_quad` is QUADPACK (``scipy.integrate.quad``) on the same
  breakpoints, as an independent check.
- :func:`monte_carlo`: the paper's Problem 2.  Simulated tosses: psi drawn from the density (by
  its inverse distribution function), the landing phase of the precessing normal uniform on
  ``[0, 2 pi)`` (the vigorous limit of Kemperman and Engel).  The normal then makes the angle
  ``alpha`` with the vertical, ``cos alpha = cos^2 psi + sin^2 psi cos phase``: heads when
  ``cos alpha > cos theta0``, tails when ``cos alpha < -cos theta0``, sides otherwise.  Reports
  the standard error and a 95% (Wilson) interval; with a tolerance it stops as soon as every
  interval's half-width is within it, checked after whole batches of fixed sizes, or at a
  budget of tosses: the stopping point is a function of the inputs and the seed alone (never
  of the clock), so a seed always gives the same numbers.
- :func:`quasi_monte_carlo`: the same tosses from scrambled Sobol points
  (``scipy.stats.qmc``), the error from independent scrambles (a t interval over them).
  ``phase="table1"`` integrates the landing phase exactly instead (Table I), a 1-D rule in psi.

:func:`estimate` picks the cheapest method that meets a tolerance: quadrature with the fewest
nodes (``docs/work-precision.md`` measures it as the fastest at every tolerance, by orders of
magnitude), unless a method is forced.

Tolerances are absolute, on each of P(heads), P(sides), P(tails): the quadrature's calibrated
error bound, or the half-width of the Monte Carlo intervals (95%).

Pure: no printing; a long run reports through an optional ``progress(done, total)`` callback.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from coincli.core import averages as _mg
from coincli.core import models
from coincli.core._numerics.roots import bisect
from coincli.core._numerics.wilson import two_sided_z, wilson_interval
from coincli.core.densities import Cosine, Density, Normal, Table, Uniform, check_density
from coincli.core.models import HALF_PI, Outcome

__all__ = [
    "Estimate",
    "METHODS",
    "estimate",
    "quad",
    "scipy_quad",
    "monte_carlo",
    "quasi_monte_carlo",
    "sample_psi",
    "toss_outcomes",
    "check_tol",
    "chance_spread",
    "mc_tosses_for_tol",
    "mc_smallest_tol",
    "wilson_half_width",
    "MC_MAX_SAMPLES",
]

METHODS = ("auto", "quad", "mc", "qmc")
MC_MAX_SAMPLES = 1 << 28  #: default cap on tosses (or points) for a tolerance (seconds)
_Z95 = two_sided_z(0.95)  # the 97.5% point of the standard normal (coincli.core._numerics.wilson's stored value)
_MIN_TOL, _MAX_TOL = 1e-16, 0.5


class Estimate(NamedTuple):
    """A psi-averaged estimate and how good it is.

    ``value``, ``error``, ``low`` and ``high`` are :class:`~coincli.core.models.Outcome` triples
    (floats for a float ``xi``, arrays of its shape otherwise).  ``error`` is the standard error
    for Monte Carlo and quasi-Monte Carlo, the calibrated absolute error bound for quadrature
    (QUADPACK's own estimate for :func:`scipy_quad`); ``low``/``high`` bound a 95% interval (for
    quadrature, ``value -+ error``, clipped to [0, 1]).  ``met`` tells whether a requested
    tolerance was reached; ``n`` is the nodes per subinterval (quad) or the tosses / points
    (mc, qmc); ``detail`` says it in words.
    """

    value: Outcome
    error: Outcome
    low: Outcome
    high: Outcome
    method: str
    n: int
    tol: float | None
    met: bool
    detail: str

    @property
    def half_width(self):
        """The largest half-width of the three 95% intervals (an array for an array xi)."""
        hw = [np.maximum(np.asarray(h) - np.asarray(v), np.asarray(v) - np.asarray(lo))
              for v, lo, h in zip(self.value, self.low, self.high, strict=True)]
        out = np.maximum(np.maximum(hw[0], hw[1]), hw[2])
        return float(out) if out.ndim == 0 else out


def check_tol(tol, name="tol"):
    """A tolerance: a number in [1e-16, 0.5] (absolute, on a chance); ``None`` passes."""
    if tol is None:
        return None
    if isinstance(tol, bool) or not isinstance(tol, (int, float)) or math.isnan(tol) \
            or not _MIN_TOL <= tol <= _MAX_TOL:
        raise ValueError(f"{name} must be a number in [{_MIN_TOL:g}, {_MAX_TOL:g}] "
                         f"(an absolute error on a chance), got {tol!r}")
    return float(tol)


def _shape(xi, arr):
    """An array of xi's shape from a flat array; a float for a float xi."""
    if isinstance(xi, float):
        return float(arr[0])
    return arr.reshape(np.shape(xi))


def _outcome(xi, rows):
    return Outcome(*(_shape(xi, np.asarray(r, dtype=float)) for r in rows))


# --------------------------------------------------------------------------- quadrature


def quad(xi, density: Density | None = None, *, tol: float | None = None,
         order: int | None = None) -> Estimate:
    """Gauss-Legendre with the fewest nodes per subinterval whose calibrated error is <= tol.

    ``order`` forces the nodes per subinterval; neither gives the default (double precision).
    The error reported is the calibrated bound of ``order``
    (:func:`coincli.core.averages.error_bound`); ``met`` is whether it is within ``tol``.
    """
    density = check_density(density)
    tol = check_tol(tol)
    if order is None:
        order = _mg.DEFAULT_ORDER if tol is None else _mg.order_for_tol(tol, density)
    xi = models.check_xi(xi)
    val = _mg.marginal(xi, density, order=order)
    bound = _mg.error_bound(order, density)
    if isinstance(xi, float):  # plain floats: this is the path a single --tol answer takes
        err = Outcome(bound, bound, bound)
        low = Outcome(*(max(v - bound, 0.0) for v in val))
        high = Outcome(*(min(v + bound, 1.0) for v in val))
    else:
        err = Outcome(*(np.full(np.shape(xi), bound) for _ in range(3)))
        low = Outcome(*(np.clip(v - bound, 0, 1) for v in val))
        high = Outcome(*(np.clip(v + bound, 0, 1) for v in val))
    met = tol is None or bound <= tol
    return Estimate(val, err, low, high, "quad", order, tol, met,
                    f"Gauss-Legendre, {order} nodes per subinterval (error <= {bound:.0e})")


def scipy_quad(xi, density: Density | None = None, *, tol: float = 1e-10) -> Estimate:
    """QUADPACK's adaptive ``quad`` (QAGP) over psi in [0, pi/2] against the folded density,
    with the regime boundaries and the density's breakpoints as ``points``: a check of
    :func:`quad` that shares none of its machinery but Table I (:func:`models.conditional`)."""
    from scipy.integrate import quad as qp

    density = check_density(density)
    tol = check_tol(tol)
    xi = models.check_xi(xi)
    flat = np.atleast_1d(np.asarray(xi, dtype=float)).ravel()
    breaks = _mg.psi_breaks(density).tolist()
    out = np.zeros((3, flat.size))
    err = np.zeros((3, flat.size))
    evals = 0

    def fold(psi):
        return float(density.pdf(np.array([psi]))[0] + density.pdf(np.array([math.pi - psi]))[0])

    for j, x in enumerate(flat.tolist()):
        if x == math.inf:
            out[:, j] = (0.0, 1.0, 0.0)
            continue
        t = math.atan2(1.0, x) / 2
        pts = sorted({p for p in [t, models.HALF_PI - t, *breaks] if 0 < p < models.HALF_PI})
        for k in range(3):
            def f(psi, k=k, x=x):
                return models.conditional(x, psi)[k] * fold(psi)

            v, e, info = qp(f, 0.0, models.HALF_PI, points=pts or None, epsabs=tol / 4,
                            epsrel=0.0, limit=max(400, 2 * len(pts) + 50),
                            full_output=True)[:3]
            out[k, j], err[k, j] = v, e
            evals += info["neval"]
    val = _outcome(xi, out)
    return Estimate(val, _outcome(xi, err), _outcome(xi, np.clip(out - err, 0, 1)),
                    _outcome(xi, np.clip(out + err, 0, 1)), "scipy", evals, tol,
                    bool((err <= tol).all()), f"scipy.integrate.quad, {evals} evaluations")


# --------------------------------------------------------------------------- sampling psi


def sample_psi(density: Density, u):
    """psi = F^-1(u) for u in [0, 1): the density's inverse distribution function (numpy).

    Exact for every density of :mod:`coincli.core.densities` (a Kepler-type equation solved by
    Newton for the cosine one, the normal's through ``ndtri``/``ndtri_exp`` in the tail where it
    does not cancel, a table's piecewise-quadratic distribution inverted segment by segment);
    other densities by a tabulated distribution function.
    """
    u = np.asarray(u, dtype=float)
    if type(density) is Uniform:
        return math.pi * u
    if type(density) is Cosine:
        return _cosine_ppf(u)
    if type(density) is Normal:
        return _normal_ppf(density, u)
    if type(density) is Table:
        return _table_ppf(density.psi, density.w, u)
    grid = np.linspace(0.0, math.pi, 1 << 14)
    return _table_ppf(grid, density.pdf(grid), u)


def _x_minus_sin(e):
    """e - sin e without cancellation for 0 <= e <= pi (a series below 1)."""
    out = e - np.sin(e)
    small = e < 1.0
    if small.any():
        es = e[small]
        e2 = es * es
        series = np.zeros_like(es)
        term = es * e2 / 6.0
        for k in range(10):  # e^3/3! - e^5/5! + ...: the 11th term is below 1e-19 relative
            series = series + term
            term = -term * e2 / ((2 * k + 4) * (2 * k + 5))
        out[small] = series
    return out


def _cosine_ppf(u):
    """F(psi) = (2 psi - sin 2 psi)/(2 pi) = u.  Folded to u <= 1/2 (F(pi - psi) = 1 - F(psi));
    a start interpolated on a uniform grid in cbrt(u) (F ~ 2 psi^3/(3 pi) near 0, so psi is
    smooth in it; the start is within 1e-8 relative), then one Newton step with
    F' = 2 sin^2 psi / pi, ``2 psi - sin 2 psi`` formed without cancellation."""
    upper = u > 0.5
    uf = np.where(upper, 1.0 - u, u)
    vmax, table = _cosine_table()
    n = table.size - 1
    x = np.cbrt(uf) * (n / vmax)
    k = np.minimum(x.astype(np.intp), n - 1)
    f = x - k
    psi = table[k] + f * (table[k + 1] - table[k])
    s = np.sin(psi)
    d = 2 * s * s / math.pi
    r = _x_minus_sin(2 * psi) / (2 * math.pi) - uf
    psi = psi - np.where(d > 0, r / np.where(d > 0, d, 1.0), 0.0)
    psi = np.clip(psi, 0.0, HALF_PI)
    return np.where(upper, math.pi - psi, psi)


_COSINE_TABLE = None


def _cosine_table():
    """(cbrt(1/2), psi at 8192 equal steps of cbrt(u) up to it)."""
    global _COSINE_TABLE
    if _COSINE_TABLE is None:
        psi = np.concatenate([np.linspace(0.0, 0.05, 20001)[:-1],
                              np.linspace(0.05, HALF_PI, 200001)])
        v = np.cbrt(_x_minus_sin(2 * psi) / (2 * math.pi))
        vmax = float(v[-1])
        _COSINE_TABLE = (vmax, np.interp(np.linspace(0.0, vmax, 8193), v, psi))
    return _COSINE_TABLE


def normal_is_exponential(d: Normal) -> bool:
    """True when the normal truncated to [0, pi] is an exponential from the end nearest its
    mean, to 1e-8 relative or better (a mean more than 1e4 sd beyond an end), or flat to within
    one (the window [0, pi] narrower than 1e-8 sd).  There ``mean + sd Phi^-1(...)`` cancels
    (to 1e-16 |mean| absolute, as much as the whole spread past 1e8 sd) or fails, and
    :func:`_normal_ppf` inverts the exponential instead."""
    return max(-d.mean, d.mean - math.pi) > 1e4 * d.sd or math.pi < 1e-8 * d.sd


def _normal_ppf(d: Normal, u):
    """Truncated normal on [0, pi]: mean + sd * Phi^-1(Phi(a) + u (Phi(b) - Phi(a))), in the
    tail where it does not cancel (log-space when the whole window is in one tail).  Where
    :func:`normal_is_exponential`, the density is ``exp(-r y - y^2/2)`` in ``y`` (sd units from
    the end nearest the mean, ``r`` the mean's distance beyond it) with ``y^2/2`` below 1e-8
    relative (``1/(2 r^2)``, or ``L^2/2``): ``y = -log1p(u expm1(-r L))/r`` over the window
    ``L = pi/sd``."""
    if normal_is_exponential(d):
        r = min(max(-d.mean, d.mean - math.pi, 0.0) / d.sd, 1.7976931348623157e308)
        span = min(math.pi / d.sd, 1.7976931348623157e308)
        with np.errstate(over="ignore", under="ignore"):
            if r * span < 1e-300 or r == 0:
                y = u * span
            else:
                y = -np.log1p(u * math.expm1(-r * span)) / r
            off = np.minimum(d.sd * y, math.pi)
        return np.clip(off if d.mean < HALF_PI else math.pi - off, 0.0, math.pi)
    from scipy.special import log_ndtr, ndtr, ndtri_exp

    a, b = -d.mean / d.sd, (math.pi - d.mean) / d.sd
    flip = a > 0  # the window is right of the mean: reflect, x -> -x
    if flip:
        a, b, u = -b, -a, 1.0 - u
    if b <= 0:  # the window is in the lower tail: work with log Phi
        la, lb = float(log_ndtr(a)), float(log_ndtr(b))
        r = math.exp(la - lb)
        x = ndtri_exp(lb + np.log(r + u * (1 - r)))
    else:  # a < 0 < b: Phi(a) + u Z below 1/2, 1 - that from the upper tail otherwise, each
        # formed as a log-sum so that u Z keeps its digits next to Phi(a) (u = 1e-12, say)
        pa, qb = float(ndtr(a)), float(ndtr(-b))
        lz = math.log(1.0 - pa - qb)
        u = np.asarray(u, dtype=float)
        with np.errstate(divide="ignore"):
            lp = np.logaddexp(float(log_ndtr(a)), np.log(u) + lz)
        low = lp < -math.log(2.0)
        x = np.empty(np.shape(lp))
        x[low] = ndtri_exp(lp[low])
        high = ~low  # each point through one of the two tails (the work of one ndtri_exp)
        with np.errstate(divide="ignore"):
            lq = np.logaddexp(float(log_ndtr(-b)), np.log1p(-u[high]) + lz)
        x[high] = -ndtri_exp(np.minimum(lq, -math.log(2.0)))
    x = np.clip(x, a, b)
    if flip:
        x = -x
    return np.clip(d.mean + d.sd * x, 0.0, math.pi)


def _table_ppf(xs, ws, u):
    """Inverse of the distribution of a piecewise-linear density through (xs, ws)."""
    xs, ws = np.asarray(xs, dtype=float), np.asarray(ws, dtype=float)
    dx = np.diff(xs)
    cdf = np.concatenate(([0.0], np.cumsum(dx * (ws[1:] + ws[:-1]) / 2)))
    target = u * cdf[-1]
    k = np.clip(np.searchsorted(cdf, target, side="right") - 1, 0, len(xs) - 2)
    r = target - cdf[k]
    w0 = ws[k]
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):  # points 1e-300 apart
        slope = (ws[k + 1] - w0) / dx[k]
        disc = np.sqrt(np.fmax(w0 * w0 + 2 * slope * r, 0.0))  # fmax: a NaN (inf - inf) is 0
        den = w0 + disc
        step = np.where(den > 0, 2 * r / np.where(den > 0, den, 1.0), 0.0)  # stable root
    return np.clip(xs[k] + np.clip(step, 0.0, dx[k]), 0.0, math.pi)


# --------------------------------------------------------------------------- tosses


def toss_outcomes(xi, psi, phase):
    """0 (heads), 1 (sides) or 2 (tails) for tosses at angle psi landing at precession phase
    ``phase`` (radians), for one xi: the normal makes ``alpha`` with the vertical,
    ``cos alpha = cos^2 psi + sin^2 psi cos phase``."""
    c = float(models.geometric(float(xi)).sides)  # cos theta0
    ca = _cos_alpha(np.asarray(psi, dtype=float), np.asarray(phase, dtype=float))
    return np.where(ca > c, 0, np.where(ca < -c, 2, 1))


def _cos_alpha(psi, phase):
    s = np.sin(psi)
    b = s * s
    return (1.0 - b) + b * np.cos(phase)


def _counts(ca, cs):
    """(heads, tails) counts of cos(alpha) samples against each cos(theta0) in cs."""
    if cs.size <= 8:
        heads = np.array([np.count_nonzero(ca > c) for c in cs.tolist()], dtype=np.int64)
        tails = np.array([np.count_nonzero(ca < -c) for c in cs.tolist()], dtype=np.int64)
        return heads, tails
    srt = np.sort(ca)
    heads = srt.size - np.searchsorted(srt, cs, side="right")
    tails = np.searchsorted(srt, -cs, side="left")
    return heads.astype(np.int64), tails.astype(np.int64)


def _wilson(k, n):
    """95% Wilson score interval for k successes in n trials (arrays): the one implementation,
    :func:`coincli.core._numerics.wilson.wilson_interval`."""
    return wilson_interval(k, n, 0.95)


def _prepare(xi, density):
    density = check_density(density)
    xi = models.check_xi(xi)
    flat = np.atleast_1d(np.asarray(xi, dtype=float)).ravel()
    cs = np.asarray(models.geometric(flat).sides, dtype=float)  # cos theta0, 1 at xi = inf
    return density, xi, flat, cs


def _seed_arg(seed):
    if seed is None:
        return None
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise ValueError(f"seed must be a whole number >= 0 or None, got {seed!r}")
    return int(seed)


def _n_arg(n, name="n"):
    if n is None:
        return None
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or not 1 <= n <= 1 << 40:
        raise ValueError(f"{name} must be an integer in [1, 2^40], got {n!r}")
    return int(n)


def monte_carlo(xi, density: Density | None = None, *, tol: float | None = None,
                n: int | None = None, seed=None, max_samples: int = MC_MAX_SAMPLES,
                batch: int = 1 << 20, progress=None) -> Estimate:
    """Simulated tosses (Problem 2 of the paper): chances with standard errors and 95% intervals.

    Parameters
    ----------
    xi : float or array_like
        Aspect ratio(s); an array shares the same tosses (common random numbers).
    density : Density
        The distribution of psi (default: the paper's normal).
    tol : float, optional
        Stop once every 95% interval's half-width is <= tol, checked after batches of 4096,
        8192, ... up to ``batch`` tosses; or at ``max_samples`` tosses, with ``met`` False.
    n : int, optional
        Exactly this many tosses (no early stop).  Default without ``tol``: 2^20.
    seed : int or None
        Seed of the ``numpy.random.Generator`` (PCG64); the same seed gives the same tosses.
    progress : callable, optional
        ``progress(done, total)`` after each batch (total is an estimate while stopping early).
    """
    density, xi, flat, cs = _prepare(xi, density)
    tol = check_tol(tol)
    n = _n_arg(n)
    max_samples = _n_arg(max_samples, "max_samples")
    seed = _seed_arg(seed)
    target = n if n is not None else (max_samples if tol is not None else 1 << 20)
    rng = np.random.default_rng(seed)
    heads = np.zeros(flat.size, dtype=np.int64)
    tails = np.zeros(flat.size, dtype=np.int64)
    done = 0
    size = min(batch, 1 << 12) if tol is not None and n is None else batch
    met = tol is None
    while done < target:
        m = min(size, target - done)
        psi = sample_psi(density, rng.random(m))
        ca = _cos_alpha(psi, (2 * math.pi) * rng.random(m))
        h, t = _counts(ca, cs)
        heads += h
        tails += t
        done += m
        total = target
        if tol is not None and n is None:
            kk = np.stack([heads, done - heads - tails, tails])
            lo, hi = _wilson(kk, done)
            half = float(np.max(np.maximum(hi - kk / done, kk / done - lo)))
            met = half <= tol
            if met:
                break
            total = int(min(target, max(done * 2, done * (half / tol) ** 2)))
        if progress is not None:
            progress(done, total)
        size = min(size * 2, batch)
    k = np.stack([heads, done - heads - tails, tails]).astype(float)
    p = k / done
    se = np.sqrt(p * (1 - p) / done)
    lo, hi = _wilson(k, done)
    if tol is not None:
        met = float(np.max(np.maximum(hi - p, p - lo))) <= tol
    if progress is not None:
        progress(done, done)
    return Estimate(_outcome(xi, p), _outcome(xi, se), _outcome(xi, lo), _outcome(xi, hi),
                    "mc", done, tol, met, f"Monte Carlo, {done} tosses (seed {seed})")


def wilson_half_width(spread: float, n: int) -> float:
    """An upper bound on the half-width :func:`monte_carlo` checks (the larger distance from
    the estimate to an end of its 95% Wilson interval) after ``n`` tosses, for a chance ``p``
    with ``p (1 - p) = spread``: ``(z sqrt(v/n + z^2/(4 n^2)) + z^2/(2 n)) / (1 + z^2/n)``,
    the centre's offset ``z^2 |1/2 - p| / n`` taken at its largest."""
    z, z2 = _Z95, _Z95 * _Z95
    return (z * math.sqrt(spread / n + z2 / (4.0 * n * n)) + z2 / (2.0 * n)) / (1.0 + z2 / n)


def chance_spread(value: Outcome) -> float:
    """The largest ``p (1 - p)`` over the three chances (each a float or an array): what sets
    the Monte Carlo half-width."""
    return max(float(np.max(np.asarray(p, dtype=float) * (1.0 - np.asarray(p, dtype=float))))
               for p in value)


def mc_tosses_for_tol(spread: float, tol: float) -> int:
    """The tosses :func:`monte_carlo` needs for a half-width <= ``tol`` on chances whose
    largest ``p (1 - p)`` is ``spread`` (:func:`chance_spread` of the chances, e.g. by
    :func:`quad`): the smallest ``n`` with ``wilson_half_width(v, n) <= tol``, where ``v`` is
    ``spread`` moved up by what the estimate's own scatter after ``n`` tosses can add to it,
    four standard errors (``4 sqrt(spread/n) + 16/n``; under 1% once n is in the millions)."""
    tol = check_tol(tol)
    spread = min(max(float(spread), 0.0), 0.25)
    lo, hi = 1, 1 << 62
    while lo < hi:  # the bound decreases with n
        mid = (lo + hi) // 2
        v = min(spread + 4.0 * math.sqrt(spread / mid) + 16.0 / mid, 0.25)
        if wilson_half_width(v, mid) <= tol:
            hi = mid
        else:
            lo = mid + 1
    return lo


def mc_smallest_tol(spreads, budget: int) -> float:
    """The smallest tolerance (two significant digits, rounded up) whose planned tosses
    (:func:`mc_tosses_for_tol`), summed over densities with these spreads, fit in ``budget``;
    0.5 when even that does not fit."""
    spreads = [float(s) for s in spreads]

    def fits(t):
        return sum(mc_tosses_for_tol(s, t) for s in spreads) <= budget

    if not fits(_MAX_TOL):
        return _MAX_TOL
    # in log tol: fits(exp(hi)) holds throughout
    _, hi = bisect(lambda v: not fits(math.exp(v)), math.log(_MIN_TOL), math.log(_MAX_TOL),
                   maxiter=60)
    t = math.exp(hi)
    unit = 10.0 ** (math.floor(math.log10(t)) - 1)
    shown = float(f"{math.ceil(t / unit) * unit:.2g}")
    while not fits(shown):  # the rounding of the shown digits
        shown = float(f"{shown + unit:.2g}")
    return min(shown, _MAX_TOL)


def quasi_monte_carlo(xi, density: Density | None = None, *, tol: float | None = None,
                      n: int | None = None, seed=None, scrambles: int = 16,
                      phase: str = "toss", max_samples: int = MC_MAX_SAMPLES,
                      progress=None) -> Estimate:
    """Scrambled Sobol points; the error from ``scrambles`` independent scramblings.

    ``phase="toss"``: 2-D points (psi, landing phase), the tosses of :func:`monte_carlo`.
    ``phase="table1"``: 1-D points in psi, the landing phase integrated exactly (Table I).
    ``n`` (total points, over all scrambles) is rounded up to ``scrambles`` times a power of
    two; with ``tol`` the points double (from 64 per scramble) until the 95% t interval over
    the scrambles has a half-width <= tol, or up to ``scrambles`` times the largest power of
    two within ``max_samples``.  Default: 2^20 points.
    """
    from scipy.stats import qmc
    from scipy.stats import t as student_t

    density, xi, flat, cs = _prepare(xi, density)
    tol = check_tol(tol)
    n = _n_arg(n)
    max_samples = _n_arg(max_samples, "max_samples")
    seed = _seed_arg(seed)
    if isinstance(scrambles, bool) or not isinstance(scrambles, int) or not 2 <= scrambles <= 1024:
        raise ValueError(f"scrambles must be an integer in [2, 1024], got {scrambles!r}")
    if phase not in ("toss", "table1"):
        raise ValueError(f"phase must be 'toss' or 'table1', got {phase!r}")
    r = scrambles
    dim = 2 if phase == "toss" else 1
    seeds = np.random.SeedSequence(seed).spawn(r)
    engines = [qmc.Sobol(d=dim, scramble=True, seed=np.random.default_rng(s)) for s in seeds]
    sums = np.zeros((r, 3, flat.size))
    per = 0  # points per scramble so far
    if n is not None:
        cap = 1 << max(0, math.ceil(math.log2(max(n / r, 1))))
    elif tol is not None:  # a budget: never more than max_samples points
        cap = 1 << max(0, (max_samples // r).bit_length() - 1)
    else:
        cap = 1 << max(0, math.ceil(math.log2(max((1 << 20) / r, 1))))
    step = cap if tol is None or n is not None else min(cap, 1 << 6)
    tq = float(student_t.ppf(0.975, r - 1))
    met = tol is None
    while per < cap:
        m = min(step, cap - per)
        for j, eng in enumerate(engines):
            pts = eng.random(m)
            psi = sample_psi(density, pts[:, 0])
            if phase == "toss":
                ca = _cos_alpha(psi, (2 * math.pi) * pts[:, 1])
                h, t = _counts(ca, cs)
                sums[j, 0] += h
                sums[j, 2] += t
                sums[j, 1] += m - h - t
            else:
                sums[j] += _table1_sums(flat, psi)
        per += m
        if tol is not None and n is None:
            est = sums / per
            half = tq * est.std(axis=0, ddof=1) / math.sqrt(r)
            met = float(half.max()) <= tol
            if met:
                break
        if progress is not None:
            progress(per * r, cap * r)
        step = per  # double the points: the first 2^k of a scrambled Sobol sequence are a net
    est = sums / per
    mean = est.mean(axis=0)
    se = est.std(axis=0, ddof=1) / math.sqrt(r)
    lo, hi = np.clip(mean - tq * se, 0, 1), np.clip(mean + tq * se, 0, 1)
    if tol is not None:
        met = float((tq * se).max()) <= tol
    total = per * r
    if progress is not None:
        progress(total, total)
    what = "tosses" if phase == "toss" else "psi points, phase exact"
    return Estimate(_outcome(xi, mean), _outcome(xi, se), _outcome(xi, lo), _outcome(xi, hi),
                    "qmc", total, tol, met,
                    f"quasi-Monte Carlo, {r} scrambles x {per} Sobol {what} (seed {seed})")


def _table1_sums(flat, psi):
    """Sums over psi samples of Table I's chances, for each xi: (3, len(flat))."""
    out = np.zeros((3, flat.size))
    for j, x in enumerate(flat.tolist()):
        o = models.conditional(np.full(psi.shape, x), psi)
        out[:, j] = [float(np.sum(v)) for v in o]
    return out


# --------------------------------------------------------------------------- the chooser


def estimate(xi, density: Density | None = None, *, tol: float | None = None,
             method: str = "auto", seed=None, n: int | None = None,
             max_samples: int = MC_MAX_SAMPLES, progress=None) -> Estimate:
    """The psi-averaged chances by ``method`` (auto, quad, mc, qmc) to within ``tol``.

    ``auto`` is the cheapest method that meets ``tol``: quadrature with the fewest nodes (the
    work-precision benchmark finds it faster than Monte Carlo and quasi-Monte Carlo at every
    tolerance from 1e-1 down, by orders of magnitude; simulated tosses cannot reach 1e-6 in a
    minute).  Without ``tol``, ``auto`` and ``quad`` give full double precision and the
    sampling methods 2^20 tosses (``n`` to change it).
    """
    m = str(method).strip().lower()
    if m not in METHODS:
        raise ValueError(f"method must be one of {', '.join(METHODS)}, got {method!r}")
    if m in ("auto", "quad"):
        if n is not None:
            raise ValueError("n (samples) applies to method mc or qmc, not quad")
        return quad(xi, density, tol=tol)
    if m == "mc":
        return monte_carlo(xi, density, tol=tol, n=n, seed=seed, max_samples=max_samples,
                           progress=progress)
    return quasi_monte_carlo(xi, density, tol=tol, n=n, seed=seed, max_samples=max_samples,
                             progress=progress)
