r"""Chances averaged over a distribution of psi (eq. 15, Table II) and the inverses by root finding.

.. math:: P(i) = \int_0^\pi P(i \mid \psi)\, P(\psi)\, d\psi

Method.  ``P(i | psi) = P(i | pi - psi)``, so the integral is taken over ``[0, pi/2]`` against the
folded density ``P(psi) + P(pi - psi)``.  The integrand has kinks at the regime boundaries
``t = theta0/2`` and ``pi/2 - t`` (Table I), where the rarer outcome grows like the square root of
the distance.  The range is split there into

- A: ``[0, t]``, heads only;
- B: ``[t, pi/2 - t]`` with ``psi = t + beta s^2`` (``beta = pi/2 - theta0 = atan xi``);
- C: ``[pi/2 - t, pi/2]`` with ``psi = pi/2 - t + t s^2``;

the substitution ``s^2`` makes the square roots analytic in ``s``.  What remains are branch
points just outside a piece when one piece is much shorter than the other (``sin psi = -sin t``
for a thick coin, ``sin psi = sin t`` seen from C for a thin one); the ``s`` range is split
geometrically toward them (ratio 4), so Gauss-Legendre converges spectrally on every
subinterval.  Narrow normals and table kinks add their own breakpoints.  The integrand is
evaluated from the offsets to the boundaries (``u1``, ``u2`` of
:func:`coincli.models._from_offsets`), so even a chance of 1e-300 keeps its relative accuracy.
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np

from coincli import models
from coincli.densities import Density, Normal
from coincli.models import HALF_PI, Outcome

__all__ = ["marginal", "marginal_inverse", "conditional_inverse", "DEFAULT_ORDER"]

DEFAULT_ORDER = 16  #: Gauss-Legendre nodes per subinterval
_RATIO = 4.0  #: geometric grading ratio toward a nearby branch point
_FEATURE_STEPS = (0.0, 0.5, 1.0, 2.0, 3.0, 4.0, 6.0, 8.0, 12.0, 16.0, 24.0, 40.0)


@lru_cache(maxsize=16)
def _gauss_legendre(n: int):
    x, w = np.polynomial.legendre.leggauss(n)
    return (x + 1) / 2, w / 2  # on [0, 1]


def _graded(s_star: float) -> list[float]:
    """Breakpoints s*, 4 s*, 16 s*, ... below 1: each subinterval is at most 3 times as long as
    its distance from a branch point at distance ``s_star`` from s = 0 (none if s* >= 1)."""
    pts, s = [], max(s_star, 1e-300)
    while s < 1.0:
        pts.append(s)
        s *= _RATIO
    return pts


def _folded_points(density: Density) -> tuple[list[float], list[tuple[float, float]]]:
    """The density's kinks and features folded onto [0, pi/2]."""
    kinks = sorted({min(k, math.pi - k) for k in density.kinks()})
    feats = [(min(c, math.pi - c), s) for c, s in density.features()]
    return kinks, feats


def _psi_breaks(lo: float, hi: float, kinks, feats) -> list[float]:
    pts = [k for k in kinks if lo < k < hi]
    for c, sd in feats:
        for m in _FEATURE_STEPS:
            for p in (c - m * sd, c + m * sd):
                if lo < p < hi:
                    pts.append(p)
    return pts


def _nodes(breaks_s, n):
    """Gauss-Legendre nodes and weights on [0, 1] split at sorted unique ``breaks_s``."""
    x, w = _gauss_legendre(n)
    edges = np.unique(np.concatenate(([0.0], np.clip(breaks_s, 0.0, 1.0), [1.0])))
    a, b = edges[:-1], edges[1:]
    keep = b > a
    a, b = a[keep], b[keep]
    s = (a[:, None] + (b - a)[:, None] * x[None, :]).ravel()
    ws = ((b - a)[:, None] * w[None, :]).ravel()
    return s, ws


def _marginal_one(xi: float, density: Density, n: int) -> tuple[float, float, float]:
    if xi == math.inf:
        return 0.0, 1.0, 0.0  # every precessing toss lands on a side; psi = 0, pi has no mass
    t, s0, c0, c = models._parts(models.M, xi)
    beta = math.atan(xi)  # = pi/2 - theta0, without cancellation
    kinks, feats = _folded_points(density)

    def fold(psi):
        return density.pdf(psi) + density.pdf(math.pi - psi)

    heads = sides = tails = 0.0
    # A: [0, t], heads only
    if t > 0:
        br = [p / t for p in _psi_breaks(0.0, t, kinks, feats)]
        s, w = _nodes(br, n)
        heads += t * float(np.dot(w, fold(t * s)))
    # B: psi = t + beta s^2 on [t, pi/2 - t]
    if beta > 0:
        br = _graded(math.sqrt(2 * t / beta)) + [
            math.sqrt((p - t) / beta) for p in _psi_breaks(t, HALF_PI - t, kinks, feats)]
        s, w = _nodes(br, n)
        u1 = beta * s * s
        psi = t + u1
        h, si, _ = models._from_offsets(np, np.sin(psi), t, s0, c0, c, u1, u1 - beta)
        wt = 2 * beta * s * w * fold(psi)
        heads += float(np.dot(wt, h))
        sides += float(np.dot(wt, si))
    # C: psi = pi/2 - t + t s^2 on [pi/2 - t, pi/2]
    if t > 0:
        br = _graded(math.sqrt(beta / t)) + [
            math.sqrt((p - (HALF_PI - t)) / t) for p in _psi_breaks(HALF_PI - t, HALF_PI, kinks,
                                                                     feats)]
        s, w = _nodes(br, n)
        u2 = t * s * s
        psi = (HALF_PI - t) + u2
        h, si, ta = models._from_offsets(np, np.cos(t - u2), t, s0, c0, c, u2 + beta, u2)
        wt = 2 * t * s * w * fold(psi)
        heads += float(np.dot(wt, h))
        sides += float(np.dot(wt, si))
        tails += float(np.dot(wt, ta))
    return heads, sides, tails


def marginal(xi, density: Density | None = None, *, order: int = DEFAULT_ORDER) -> Outcome:
    r"""Chances of heads, sides and tails averaged over a density of psi: eq. (15), Table II.

    Parameters
    ----------
    xi : float or array_like
        Aspect ratio, ``0 <= xi <= inf``.
    density : Density
        A :mod:`coincli.densities` density (default: the paper's normal, mean pi/2, sd 1/sqrt 2).
    order : int
        Gauss-Legendre nodes per subinterval (16 reaches about 1e-15 relative on the paper's
        densities; see ``docs/accuracy.md``).

    Returns
    -------
    Outcome
        Floats for a float ``xi``, arrays of its shape otherwise.

    Examples
    --------
    >>> from coincli.densities import Uniform
    >>> [round(v, 3) for v in marginal(3 ** -0.5, Uniform())]  # Table II, uniform column
    [0.63, 0.281, 0.088]
    """
    density = Normal() if density is None else density
    if not isinstance(density, Density):
        raise ValueError(f"density must be a coincli.densities.Density, got {density!r}")
    xi = models.check_xi(xi)
    if isinstance(xi, float):
        return Outcome(*_marginal_one(xi, density, order))
    flat = xi.ravel()
    out = np.empty((3, flat.size))
    cache: dict[float, tuple] = {}
    for k, x in enumerate(flat.tolist()):
        r = cache.get(x)
        if r is None:
            r = cache[x] = _marginal_one(x, density, order)
        out[:, k] = r
    return Outcome(*(o.reshape(xi.shape) for o in out))


# --------------------------------------------------------------------------- inverses

_LOG_LO, _LOG_HI = math.log(5e-324), math.log(1.7e308)


def _invert(sides_of, p: float, guess: float) -> float:
    """Root of sides_of(xi) = p in log xi (relative accuracy in xi), bracketed around guess."""
    from scipy.optimize import brentq

    def g(u):
        return sides_of(math.exp(u)) - p

    c = math.log(guess) if 0 < guess < math.inf else 0.0
    lo, hi, step = c - 1.0, c + 1.0, 2.0
    while g(lo) > 0 and lo > _LOG_LO:
        lo, step = max(lo - step, _LOG_LO), step * 2
    step = 2.0
    while g(hi) < 0 and hi < _LOG_HI:
        hi, step = min(hi + step, _LOG_HI), step * 2
    glo, ghi = g(lo), g(hi)
    if glo > 0 or ghi < 0:
        raise ValueError(f"p_sides = {p!r} is not reachable for any xi in [5e-324, 1.7e308]")
    if glo == 0:
        return math.exp(lo)
    if ghi == 0:
        return math.exp(hi)
    u = brentq(g, lo, hi, xtol=1e-16, rtol=8.9e-16, maxiter=400)
    return math.exp(u)


def _vectorize(fn, p):
    p = models.check_p(p, "p_sides")
    if isinstance(p, float):
        return fn(p)
    return np.vectorize(fn, otypes=[float])(p)


def marginal_inverse(p_sides, density: Density | None = None, *, order: int = DEFAULT_ORDER):
    """The aspect ratio whose psi-averaged chance of a side is ``p_sides``.

    Root finding (Brent) in ``log xi``, so the tolerance is relative in ``xi`` (about 1e-15),
    not scipy's absolute default that would be meaningless for a thin coin.  ``p = 0`` gives 0
    and ``p = 1`` gives ``inf`` (the chance tends to 1 only as ``xi`` grows without bound).
    """
    density = Normal() if density is None else density

    def one(p):
        if p == 0.0:
            return 0.0
        if p == 1.0:
            return math.inf
        return _invert(lambda x: _marginal_one(x, density, order)[1], p,
                       models.dynamic_inverse(p))

    return _vectorize(one, p_sides)


def conditional_inverse(p_sides, psi):
    """The aspect ratio whose chance of a side at the fixed angle ``psi`` (radians) is ``p_sides``.

    At ``psi = 0`` or ``pi`` the coin never precesses and always lands heads: only
    ``p_sides = 0`` is reachable there.  Otherwise every ``p`` in [0, 1] is (``p = 1`` at
    ``xi = inf``).
    """
    psi = models.check_psi(psi)
    if not isinstance(psi, float):
        raise ValueError("psi must be a single angle for conditional_inverse")

    def one(p):
        if p == 0.0:
            return 0.0
        if math.sin(psi) == 0.0:
            raise ValueError(
                "at psi = 0 or 180 degrees the coin never precesses and always lands heads; "
                "only p_sides = 0 is reachable"
            )
        if p == 1.0:
            return math.inf
        return _invert(lambda x: models.conditional(x, psi).sides, p, models.dynamic_inverse(p))

    return _vectorize(one, p_sides)
