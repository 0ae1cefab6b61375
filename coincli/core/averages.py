r"""Chances averaged over a distribution of psi (eq. 15, Table II) and the inverses by root finding.

.. math:: P(i) = \int_0^\pi P(i \mid \psi)\, P(\psi)\, d\psi

Method.  ``P(i | psi) = P(i | pi - psi)``, so the integral is taken over ``[0, pi/2]`` against the
folded density ``P(psi) + P(pi - psi)``.  The integrand has kinks at the regime boundaries
``t = theta0/2`` and ``pi/2 - t`` (Table I), where the rarer outcome grows like the square root of
the distance.  The range is split there into

- A: ``[0, t]``, heads only, ``psi = t s``;
- B: ``[t, pi/2 - t]`` with ``psi = t + beta s^2`` (``beta = pi/2 - theta0 = atan xi``);
- C: ``[pi/2 - t, pi/2]`` with ``psi = pi/2 - t + t s^2``;

the substitution ``s^2`` makes the square roots analytic in ``s``.  What remains are branch
points just outside a piece when one piece is much shorter than the other (at ``s = i s*`` with
``s* = sqrt(2t/beta)`` in B for a thick coin, ``s* = sqrt(beta/t)`` in C for a thin one); the
``s`` range is split geometrically toward them (ratio 4), so Gauss-Legendre converges spectrally
(at least like ``3**(-2n)`` with ``n`` nodes) on every subinterval.  In C the grading stops at
``s* = 1e-18``: closer, the branch point changes the integral by about ``s*`` relative, under a
rounding error.  Narrow normals and table kinks add their own breakpoints, and so does a
narrow normal's far tail beyond a regime boundary (``_tail_points``: a chance of 1e-300 keeps its
relative accuracy).  A table's thousands of short subintervals get the few nodes each needs
(``_orders``), and its points times the xi values per call are capped (``MAX_TABLE_WORK``).

Vectorized.  For an array of ``xi`` the subintervals of every ``xi`` and piece are laid out as one
flat list, the nodes as a 2-D array (subintervals x nodes, in cache-sized blocks), and each
piece's integrand is evaluated in one numpy pass; the sums go back to their ``xi`` by
``bincount``.  The integrands use ``D1 = sin^2 psi - sin^2 t = sin u1 cos u2`` and
``D2 = sin^2 psi - cos^2 t = sin u2 cos u1`` with the offsets ``u1 = psi - t``,
``u2 = psi - pi/2 + t``, each factor the sine of an angle in ``[0, pi/2]`` formed without
cancellation, so that even a chance of 1e-300 keeps its relative accuracy.

Precision.  Where numpy's long double has 64 bits (x86), the nodes, the integrands, the sums and
the normalization below run in it, and each chance is rounded to double once (``_working``):
the chances are then monotone in xi over consecutive doubles, which sums of doubles are not.

Normalization.  The sums are divided by the quadrature's own mass of the density, and the
largest chance is taken as 1 minus the other two: heads + sides + tails = 1 to rounding, every
chance lies in [0, 1], and a narrow density's peak a rounding away from a piece's end costs
nothing.  A normal too narrow for any quadrature (``mean +- sd/2`` rounds to the mean) is Table I
at its mean, the limit; one within 2^-600 of psi = 0 is averaged scaled up (``_planar``), and a
coin thinner than 2^-600 has P(sides) = C xi (``_THIN``).

Inverses.  ``P(sides) = p`` is solved by bracketing and Chandrupatla's method down to adjacent
doubles (:func:`coincli.core._numerics.roots.positive_roots`), on the complement
``P(heads) + P(tails) = 1 - p`` for p > 1/2; Table I's inverse starts from its closed form
(``_table_i_guess``).  docs/accuracy.md has the errors.
"""

from __future__ import annotations

import math
import weakref

import numpy as np

from coincli.core import models
from coincli.core._numerics.backend import long_double_64
from coincli.core._numerics.quadrature import gauss_legendre
from coincli.core._numerics.roots import POSITIVE_MAX, POSITIVE_MIN, positive_roots
from coincli.core.densities import Cosine, Density, Normal, Table, Uniform, check_density
from coincli.core.models import HALF_PI, Outcome

__all__ = [
    "marginal",
    "marginal_inverse",
    "conditional_inverse",
    "DEFAULT_ORDER",
    "MIN_ORDER",
    "MAX_ORDER",
    "order_for_tol",
    "error_bound",
    "check_table_work",
    "MAX_TABLE_WORK",
]

DEFAULT_ORDER = 16  #: Gauss-Legendre nodes per subinterval
MIN_ORDER, MAX_ORDER = 2, 64  #: the range of ``order``
_RATIO = 4.0  #: geometric grading ratio toward a nearby branch point
_LAST = 0.9  #: no graded point above this: a sliver [0.9, 1] would cost a subinterval for little
_S_FLOOR = 1e-18  #: no grading in C toward a branch point closer than this (see module notes)
_FEATURE_STEPS = np.array([0.0, 1.0, 2.0, 3.0, 4.0, 6.0, 8.0, 12.0, 16.0])
#: a regime boundary where a normal is below exp(-_TAIL_SD**2/2) of its peak (and above
#: exp(-_TAIL_FAR**2/2): smaller tails are below 1e-340 of the mass and round to 0) gets
#: breakpoints on its far side, at these multiples of the tail's decay length
_TAIL_SD, _TAIL_FAR = 4.0, 40.0
_TAIL_STEPS = 2.0 ** np.arange(-2, 7)
_CHUNK = 1 << 21  #: (xi values) x (breakpoints + 64) per pass, to bound memory
_CHUNK_BREAKS = 1 << 19  #: ... and (xi values) x (breakpoints) per pass for long tables
# 2/pi as hi + lo: the sums of angles are scaled once, with one rounding
_TWO_OVER_PI_HI = 0.6366197723675814
_TWO_OVER_PI_LO = -3.935735335036497e-17

# Absolute error reached by ``order`` nodes per subinterval: the worst over xi from 1e-300 to
# 1e300 and the density stress cases (paper's densities, normals of sd 1e-6 to 1e3 on and off
# the regime boundaries, means at 0 and pi and outside, a table), against order 40 (itself
# checked against mpmath to 40 digits), with a margin of 3 or more.  The rate is the grading's:
# a branch point at the end of a subinterval 3 times longer than its distance gives 3**(-2n).
# Measured worst (docs/work-precision.md): n=4 2.4e-5, 6 6.3e-8, 8 3.3e-10, 10 7.7e-12,
# 11 6.1e-13, 12 2.6e-14; from 13 on, rounding (about 4e-16; 1e-14 for a normal narrower than
# 1e-3 rad, whose peak of height 1/sd magnifies the rounding of psi).
_ORDER_TABLE = ((2, 2e-2), (3, 2e-3), (4, 1e-4), (5, 5e-6), (6, 3e-7), (7, 1e-8), (8, 1e-9),
                (9, 2e-10), (10, 3e-11), (11, 2e-12), (12, 1e-13))
_FLOOR = 2e-15  #: rounding floor of the quadrature
_FLOOR_NARROW = 3e-14  #: ... for a normal narrower than _NARROW_SD
_NARROW_SD = 1e-3


def _working():
    """The type the quadrature sums in: numpy's 64-bit long double where there is one (each
    sum is rounded to double once, in :func:`_finish`), else double.

    Monotone to the last bit: in double, the nodes ``psi`` (which move with xi), the integrands
    and the sums each round, and those errors come and go from one double xi to the next, so
    that P(sides) stepped down (and heads, tails up) by 1 to 6 ulps over runs of consecutive
    doubles.  In long double the sums are the quadrature's value within a few 2**-64 relative;
    the quadrature's own error (about 1e-18 at 16 nodes) changes smoothly with xi, except
    where a graded breakpoint appears, by far less than a chance moves from one double to the
    next.  Rounding once, a monotone step, keeps the order of the sums (see
    :func:`coincli.core.models._extended_finish`).
    """
    return np.longdouble if long_double_64(np) else np.float64


def _floor(density) -> float:
    if isinstance(density, Normal) and density.sd < _NARROW_SD:
        return _FLOOR_NARROW
    return _FLOOR


def order_for_tol(tol: float, density: Density | None = None) -> int:
    """The fewest Gauss-Legendre nodes per subinterval whose absolute error is within ``tol``.

    From the calibration in ``_ORDER_TABLE``; a tolerance below the rounding floor (2e-15, or
    3e-14 for a normal narrower than 1e-3 rad) gets ``DEFAULT_ORDER``, the best there is.
    """
    if isinstance(tol, bool) or not isinstance(tol, (int, float)) or not tol > 0 \
            or math.isnan(tol):
        raise ValueError(f"tol must be a number > 0, got {tol!r}")
    for n, err in _ORDER_TABLE:
        if max(err, _floor(density)) <= tol:
            return n
    if tol >= _floor(density):
        return 13 if tol >= 5e-14 else DEFAULT_ORDER
    return DEFAULT_ORDER


def error_bound(order: int, density: Density | None = None) -> float:
    """The calibrated absolute error of :func:`marginal` with ``order`` nodes per subinterval."""
    order = _check_order(order)
    bound = 1.0
    for n, err in _ORDER_TABLE:
        if n <= order:
            bound = err
    if order >= 13:
        bound = 5e-14 if order < DEFAULT_ORDER else 0.0
    return max(bound, _floor(density))


def _check_order(order) -> int:
    if isinstance(order, bool) or not isinstance(order, (int, np.integer)) \
            or not MIN_ORDER <= order <= MAX_ORDER:
        raise ValueError(f"order must be an integer in [{MIN_ORDER}, {MAX_ORDER}] "
                         f"(Gauss-Legendre nodes per subinterval), got {order!r}")
    return int(order)


# --------------------------------------------------------------------------- the density


def _features(density: Density) -> list[tuple[float, float]]:
    """(centre, scale) pairs on [0, pi] where the density varies quickly."""
    if isinstance(density, Normal):
        mean, sd = density.mean, density.sd
        out = [(mean, sd)] if sd < 0.5 else []
        # a mean outside [0, pi] leaves the tail: exp(-d x / sd^2) from the nearer end
        for end, d in ((0.0, -mean), (math.pi, mean - math.pi)):
            if d > sd and sd * sd / d < 0.5:
                out.append((end, sd * sd / d))
        return out
    return list(density.features())


def _tail_centres(density: Density) -> list[tuple[float, float]]:
    """(centre, sd) of a normal whose far tail a regime boundary can cut (see _tail_points):
    the folded mean ``min(mean, pi - mean)`` (the nearer of the two centres to every point of
    [0, pi/2]), when the density falls below exp(-_TAIL_SD**2/2) of its peak somewhere there."""
    if not isinstance(density, Normal):
        return []
    try:
        return _TAILS[density]
    except KeyError:
        pass
    _TAILS[density] = out = _tail_centres_uncached(density)
    return out


def _tail_centres_uncached(density: Normal) -> list[tuple[float, float]]:
    mu = min(density.mean, math.pi - density.mean)
    if max(_tail_exponent(0.0, mu, density.sd), _tail_exponent(HALF_PI, mu, density.sd)) \
            <= 0.5 * _TAIL_SD**2:
        return []
    return [(mu, density.sd)]


def _tail_exponent(b, mu, sd):
    """-log of the normal (folded centre ``mu``) at ``b`` relative to its peak on [0, pi/2],
    ``max(mu, 0)``: ``z**2/2`` for a centre inside, ``x (x + 2 |mu|/sd)/2`` (x = b/sd) beyond 0."""
    peak, beyond = max(mu, 0.0), min(max(-mu, 0.0) / sd, 1e300)
    with np.errstate(over="ignore", invalid="ignore"):
        x = np.abs(b - peak) / sd
        return 0.5 * (x * (x + 2 * beyond))


_BREAKS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()
_TAILS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def psi_breaks(density: Density) -> np.ndarray:
    """Sorted points of (0, pi/2) where the folded density has a kink or a fast change."""
    try:
        return _BREAKS[density]
    except (KeyError, TypeError):
        pass
    arr = _psi_breaks_uncached(density)
    try:
        _BREAKS[density] = arr
    except TypeError:  # not weak-referenceable: no cache
        pass
    return arr


def _psi_breaks_uncached(density: Density) -> np.ndarray:
    pts = [min(k, math.pi - k) for k in density.kinks()]
    for c, sd in _features(density):
        for centre in {min(c, math.pi - c), c}:
            pts.extend((centre - _FEATURE_STEPS * sd).tolist())
            pts.extend((centre + _FEATURE_STEPS * sd).tolist())
    # sorted(set()), not np.unique: numpy 2's unique imports numpy.ma (some 30 ms of start-up
    # for `coin simulate`, which needs one marginal).
    arr = np.asarray(sorted(set(pts)), dtype=float)
    return arr[(arr > 0) & (arr < HALF_PI)]


def _folded_pdf(density: Density):
    """psi -> P(psi) + P(pi - psi) on [0, pi/2] (numpy in and out)."""
    if type(density) is Uniform:
        return lambda psi: 2 / math.pi
    if type(density) is Cosine:
        def cosine(psi):
            s = np.sin(psi)
            return (4 / math.pi) * (s * s)
        return cosine
    if type(density) is Normal:
        # P(psi) + P(pi - psi) = E (1 + exp(-k (pi - 2 psi)(pi - 2 mu))) with E the normal at
        # mu = min(mean, pi - mean) (the fold is symmetric in mu -> pi - mu): the second term
        # never exceeds the first, so nothing overflows where E underflows.
        # In units of sd (never sd**2, which underflows for sd below 1e-154): the exponent of
        # the mirror term is (pi - 2 mu)(psi - pi/2)/sd**2 = ((pi - 2 mu)/sd) ((psi - pi/2)/sd).
        # E relative to its value at the peak max(mu, 0) (Normal.log_shape): a mean far beyond
        # psi = 0 would overflow z**2 - z0**2 term by term.
        mu = min(density.mean, math.pi - density.mean)
        sd = density.sd
        ln = density._log_peak
        gap = (math.pi - 2 * mu) / sd
        peak, beyond = max(mu, 0.0), min(max(-mu, 0.0) / sd, 1e300)

        if mu == HALF_PI:
            ln2 = ln + math.log(2.0)

            def keller(psi):
                with np.errstate(over="ignore"):
                    z = (psi - mu) / sd
                    return np.exp(ln2 - 0.5 * (z * z))
            return keller

        def normal(psi):
            with np.errstate(over="ignore"):  # z**2 -> inf, exp(-inf) = 0: the right limit
                z = (psi - peak) / sd
                mirror = np.exp(np.fmax(gap * ((psi - HALF_PI) / sd), -1e300))  # fmax: inf*0
                return np.exp(ln - 0.5 * (z * (z + 2 * beyond))) * (1.0 + mirror)
        return normal
    if type(density) is Table:
        xs, ws = density.psi, density.w

        def table(psi):  # joined linearly in psi's own precision (np.interp is double only)
            return _interp(psi, xs, ws) + _interp(math.pi - psi, xs, ws)
        return table
    return lambda psi: density.pdf(psi) + density.pdf(math.pi - psi)


def _interp(x, xs, ws):
    """The points ``(xs, ws)`` joined linearly at ``x`` (zero outside them) as ``w0 + f (w1 -
    w0)``, ``f = (x - x0)/(x1 - x0)`` in [0, 1], in the precision of ``x``
    (:meth:`coincli.core.densities.Table.pdf`'s form for steep tables)."""
    k = np.clip(np.searchsorted(xs, x, side="right") - 1, 0, xs.size - 2)
    x0, x1 = xs[k], xs[k + 1]
    f = np.clip((x - x0) / (x1 - x0), 0.0, 1.0)
    w0 = ws[k]
    out = w0 + f * (ws[k + 1] - w0)
    return np.where((x < xs[0]) | (x > xs[-1]), 0.0, out)


# --------------------------------------------------------------------------- layout
# Each piece of each xi is cut into subintervals of s in [0, 1]: at the graded points toward a
# branch point and at the density's breakpoints mapped to s.  One xi: Python lists.  Many:
# one row of breakpoints per xi, sorted, then the nonempty subintervals as a flat list.


def _graded_one(s_star: float) -> list[float]:
    pts, s = [], s_star
    if 0 < s_star < 1:
        while s < _LAST:
            pts.append(s)
            s *= _RATIO
    return pts


def _edges_one(pts) -> tuple[np.ndarray, np.ndarray]:
    e = sorted({0.0, 1.0, *(min(max(p, 0.0), 1.0) for p in pts if p == p)})  # no NaN
    e = np.array(e)
    return e[:-1], e[1:]


def _graded(s_star: np.ndarray) -> np.ndarray:
    """Breakpoints s*, 4 s*, 16 s*, ... below 1 for each s* (rows; 1.0 where there are none).

    Each subinterval is then at most 3 times as long as its distance from a branch point at
    ``s = i s*``."""
    live = (s_star < 1.0) & (s_star > 0)
    if not live.any():
        return np.ones((s_star.size, 0))
    smin = float(s_star[live].min())
    g = int(math.ceil(-math.log(smin) / math.log(_RATIO))) + 1
    pts = s_star[:, None] * _RATIO ** np.arange(g)[None, :]
    return np.where(live[:, None] & (pts < _LAST), pts, 1.0)


def _intervals(parts: list[np.ndarray], m: int):
    """Rows of breakpoints (each in [0, 1]) -> flat (row, a, b) of the nonempty subintervals."""
    parts = [p for p in parts if p.shape[1]]
    edges = np.concatenate([np.zeros((m, 1)), *parts, np.ones((m, 1))], axis=1)
    if len(parts) > 1:
        edges.sort(axis=1)
    a, b = edges[:, :-1], edges[:, 1:]
    keep = b > a
    rows = np.nonzero(keep)[0]
    return rows, a[keep], b[keep]


def _layout_one(x: float, breaks: list[float], tails=()):
    """(params, [(a, b) of pieces A, B, C]) for one finite xi."""
    t = math.atan2(1.0, x) / 2
    beta = math.atan(x)
    par = _params(np.array([x]))[:, 0]
    lo = HALF_PI - t
    pa = [p / t for p in breaks if p < t]
    pb = _graded_one(math.sqrt(2 * t / beta)) if beta > 0 else []
    if beta > 0:
        pb += [math.sqrt((p - t) / beta) for p in breaks if t < p < lo]
    sstar = math.sqrt(beta / t)
    pc = _graded_one(sstar) if sstar >= _S_FLOOR else []
    pc += [math.sqrt((p - lo) / t) for p in breaks if p > lo]
    for mu, sd in tails:
        if any(0.5 * _TAIL_SD**2 < _tail_exponent(b, mu, sd) < 0.5 * _TAIL_FAR**2
               for b in (t, lo)):
            for into, v in zip((pa, pb, pb, pc), _tail_points(np.array([t]), np.array([beta]),
                                                              mu, sd), strict=True):
                into.extend(v[0].tolist())
    return par, [_edges_one(pa), _edges_one(pb), _edges_one(pc)]


def _params(xi: np.ndarray):
    """(t, beta, sin t, cos t, cos theta0, sin beta/2, cos beta/2), rows of the working
    precision (:func:`_working`), for a 1-D array of finite xi.  The breakpoints are laid out
    from double t and beta; the nodes and integrands take these."""
    x = xi.astype(_working())
    one = x.dtype.type(1)
    t = np.arctan2(one, x) / 2
    beta = np.arctan(x)
    xc = np.minimum(x, 2.0**600)  # beyond, x/hypot(1, x) is 1.0 (and inf/inf is kept away)
    return np.stack([t, beta, np.sin(t), np.cos(t), xc / np.hypot(one, xc), np.sin(beta / 2),
                     np.cos(beta / 2)])


def _tail_points(t, beta, mu, sd):
    """Breakpoints in s for the far tail of a normal (centre ``mu``, ``sd``) beyond a regime
    boundary: rows (one per xi) for pieces A, B (two sets) and C; 1.0 where there are none.

    Where a boundary ``b`` (``t`` or ``pi/2 - t``) lies more than ``_TAIL_SD`` sd from the
    centre (or as far down a mean's tail beyond psi = 0), the density on its far side decays like ``exp(-(psi - b)/w)`` with
    ``w = sd^2/|b - mu|``, and the chance of the outcome that starts there is a tail of the
    density (1e-60, 1e-300) that breakpoints placed about the mean do not resolve.  Points at
    ``b -+ w 2^k`` (k = -2 .. 6, formed from the offsets, never from ``b`` itself) resolve it to
    the same relative accuracy as the bulk.  Past ``_TAIL_FAR`` sd the tail underflows.
    ``w`` is the exact decay length of the normal at ``b`` for a centre beyond 0 too.
    """
    out = []
    steps = _TAIL_STEPS[None, :]
    with np.errstate(divide="ignore", invalid="ignore", over="ignore", under="ignore"):
        for b, piece_lo, piece_hi in ((t, "A", "B"), (HALF_PI - t, "B", "C")):
            d = b - mu
            far = _tail_exponent(b, mu, sd)
            far = (far > 0.5 * _TAIL_SD**2) & (far < 0.5 * _TAIL_FAR**2)
            w = sd * (sd / np.where(far, np.abs(d), 1.0))[:, None] * steps  # offsets from b
            if piece_lo == "A":  # below t: piece A, s = (t - w)/t; above: piece B, s^2 = w/beta
                below = 1.0 - w / t[:, None]
                above = np.sqrt(np.minimum(w / np.where(beta > 0, beta, np.inf)[:, None], 1.0))
            else:  # below pi/2 - t: piece B, s^2 = 1 - w/beta; above: piece C, s^2 = w/t
                # an offset beyond the piece's far end is its end (sqrt of a negative: NaN)
                below = np.sqrt(np.maximum(1.0 - w / np.where(beta > 0, beta, np.inf)[:, None],
                                           0.0))
                above = np.sqrt(np.minimum(w / t[:, None], 1.0))
            side = (d < 0)[:, None]  # the centre lies above b: the far side is below it
            out.append(np.where(far[:, None] & side, np.clip(below, 0.0, 1.0), 1.0))
            out.append(np.where(far[:, None] & ~side, np.clip(above, 0.0, 1.0), 1.0))
    return out  # A (below t), B (above t), B (below pi/2 - t), C (above pi/2 - t)


def _layout_many(xi: np.ndarray, breaks: np.ndarray, tails=()):
    """(params (7, m), [(rows, a, b) of pieces A, B, C]) for a 1-D array of finite xi."""
    m = xi.size
    t = np.arctan2(1.0, xi) / 2
    beta = np.arctan(xi)
    par = _params(xi)
    nb = breaks.size
    lo = HALF_PI - t
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        pa = [np.clip(breaks[None, :] / t[:, None], 0.0, 1.0)] if nb else []
        bpos = np.where(beta > 0, beta, np.inf)
        pb = [_graded(np.where(beta > 0, np.sqrt(2 * t / bpos), 1.0))]
        if nb:
            pb.append(np.sqrt(np.clip((breaks[None, :] - t[:, None]) / bpos[:, None], 0, 1)))
        sstar = np.sqrt(beta / t)
        pc = [_graded(np.where(sstar >= _S_FLOOR, sstar, 1.0))]
        if nb:
            pc.append(np.sqrt(np.clip((breaks[None, :] - lo[:, None]) / t[:, None], 0, 1)))
    for mu, sd in tails:
        ta, tb1, tb2, tc = _tail_points(t, beta, mu, sd)
        pa.append(ta)
        pb += [tb1, tb2]
        pc.append(tc)
    return par, [_intervals(pa, m), _intervals(pb, m), _intervals(pc, m)]


# --------------------------------------------------------------------------- the integrands
# Each returns per-subinterval sums: heads (as a chance) for A; angles (theta/2) for B and C,
# scaled by 2/pi once at the end.  ``p`` holds (t, beta, s0, c0, c, sin beta/2, cos beta/2),
# floats for one xi or (k, 1) columns, one per subinterval.


def _nodes(a, b, n, scale):
    """Nodes and weights on the subintervals [a, b] (doubles: consecutive subintervals share
    their end exactly) in the working precision of ``scale``."""
    x, w = gauss_legendre(n)
    dt = np.result_type(scale, np.float64)
    a, b = a.astype(dt), b.astype(dt)
    h = (b - a)[:, None]
    return a[:, None] + h * x, (h * scale) * w


def _piece_a(a, b, n, p, fold):
    """psi = t s on [0, t]: heads only; the sum is the mass."""
    t = p[0]
    s, w = _nodes(a, b, n, t)
    return (w * fold(t * s)).sum(axis=1)[None, :]


def _piece_b(a, b, n, p, fold):
    """psi = t + beta s^2 on [t, pi/2 - t]: heads or sides."""
    t, beta, s0 = p[0], p[1], p[2]
    s, w = _nodes(a, b, n, 2 * beta)
    u1 = beta * (s * s)  # psi - t
    # D1 = sin^2 psi - sin^2 t = sin u1 sin(2t + u1): both angles in [0, pi/2], no cancellation
    q1 = np.sqrt(np.sin(u1)) * np.sqrt(np.sin(2 * t + u1))
    out = np.empty((3, *q1.shape), dtype=q1.dtype)  # theta1/2, its complement, 1 (the mass)
    np.arctan2(s0, q1, out=out[0])
    np.arctan2(q1, s0, out=out[1])
    out[2] = 1.0
    out *= w * s * fold(t + u1)
    return out.sum(axis=2)


def _piece_c(a, b, n, p, fold):
    """psi = pi/2 - t + t s^2 on [pi/2 - t, pi/2]: all three outcomes."""
    t, beta, s0, c0, c = p[0], p[1], p[2], p[3], p[4]
    s, w = _nodes(a, b, n, 2 * t)
    u2 = t * (s * s)  # psi - (pi/2 - t), in [0, t]; u1 = psi - t = beta + u2
    # D1 = sin u1 cos u2 and D2 = sin u2 cos u1 = sin u2 sin(2t - u2): every angle in [0, pi/2]
    # and 2t - u2 >= t, so each factor keeps its relative accuracy
    q1 = np.sqrt(np.sin(beta + u2)) * np.sqrt(np.cos(u2))
    q2 = np.sqrt(np.sin(u2)) * np.sqrt(np.sin(2 * t - u2))
    out = np.empty((4, *q1.shape), dtype=q1.dtype)  # theta1/2, (theta2 - theta1)/2, (pi - theta2)/2, 1
    np.arctan2(s0, q1, out=out[0])
    # (theta2 - theta1)/2 = atan2(c sin^2 psi, (sqrt(D1 D2) + c0 s0)(c0 sqrt D1 + s0 sqrt D2))
    # with sin^2 psi = D1 + s0^2
    np.arctan2((q1 * q1 + s0 * s0) * c, (q1 * q2 + c0 * s0) * (c0 * q1 + s0 * q2), out=out[1])
    np.arctan2(q2, c0, out=out[2])
    out[3] = 1.0
    out *= w * s * fold((HALF_PI - t) + u2)
    return out.sum(axis=2)


_PIECES = (_piece_a, _piece_b, _piece_c)
# where each piece's rows of sums go: 0 heads in A (= its mass), 1-3 heads, sides, tails as
# angles, 4 the mass of B and C
_SLOTS = ((0,), (1, 2, 4), (1, 2, 3, 4))
_BLOCK = 1 << 15  #: nodes per numpy pass: the temporaries stay in cache


def _integrate_one(x: float, density: Density, n: int, breaks: list[float]):
    p, pieces = _layout_one(x, breaks, _tail_centres(density))
    fold = _folded_pdf(density)
    acc = np.zeros(5, dtype=p.dtype)
    for fn, slots, (a, b) in zip(_PIECES, _SLOTS, pieces, strict=True):
        acc[list(slots)] += fn(a, b, n, p, fold).sum(axis=1)
    return acc


def _integrate_many(xi: np.ndarray, density: Density, n: int, breaks: np.ndarray):
    m = xi.size
    par, pieces = _layout_many(xi, breaks, _tail_centres(density))
    fold = _folded_pdf(density)
    acc = np.zeros((5, m), dtype=par.dtype)
    linear = isinstance(density, Table) and breaks.size > _MANY_KINKS
    for k, (fn, slots, (rows, a, b)) in enumerate(zip(_PIECES, _SLOTS, pieces, strict=True)):
        if not rows.size:
            continue
        if linear:  # the fewest nodes each subinterval needs (a table: thousands of short ones)
            orders = _orders(k, a, b, par[:, rows], n)
            groups = [(nk, np.flatnonzero(orders == nk)) for nk in np.unique(orders)]
        else:
            groups = [(n, slice(None))]
        for nk, idx in groups:
            r, ga, gb = rows[idx], a[idx], b[idx]
            step = max(1, _BLOCK // nk)
            sums = [fn(ga[j:j + step], gb[j:j + step], nk, par[:, r[j:j + step]][:, :, None],
                       fold) for j in range(0, r.size, step)]
            # rows come sorted (row-major layout): sum each xi's subintervals with reduceat,
            # which adds pairwise like sum() (a thick coin has hundreds of graded subintervals)
            starts = np.flatnonzero(np.concatenate(([True], r[1:] != r[:-1])))
            acc[np.array(slots)[:, None], r[starts]] += np.add.reduceat(
                np.concatenate(sums, axis=1), starts, axis=1)
    return acc


_DIGITS = 19.6  #: ln(10^17)/2: rho^(-2n) below 1e-17 with n = _DIGITS/ln(rho) nodes
_MANY_KINKS = 64  #: a table with more breakpoints than this gets node counts per subinterval


def _orders(piece: int, a, b, p, n: int):
    """Gauss-Legendre nodes for each subinterval [a, b] (in s) of a piece, for a density that
    is linear in psi between its breakpoints (a table).

    Piece A integrates the density alone (heads is 1 there): linear in s, exact with one node
    (two are used: the rounding of a steep table's arguments then averages a little).
    In B and C the integrand is analytic in s on each subinterval; Gauss-Legendre with k nodes
    errs by about ``rho**(-2k)``, ``rho`` the Bernstein ellipse through the nearest singularity
    (``sin psi = 0`` at ``s = i sqrt(t/beta)`` and ``D1 D2 = 0`` at ``i sqrt(2t/beta)`` in B;
    ``D1 = 0`` at ``i sqrt(beta/t)``, ``psi = 0`` at ``i sqrt(pi/(2t) - 1)`` and ``D2 = 0`` at
    ``s = sqrt 2`` in C).  A subinterval short beside its distance to them (a table's points,
    1e-5 apart) needs 2 or 3 nodes for 1e-17, not ``n``: one more than that estimate is used,
    never more than ``n``.
    """
    if piece == 0:
        return np.full(a.size, 2, dtype=np.intp)
    t, beta = p[0], p[1]
    c, h = (a + b) / 2, (b - a) / 2
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        if piece == 1:  # i y on the imaginary axis: distance sqrt(c^2 + y^2); sqrt(t/beta) is
            near = c * c + t / beta  # the nearer of the two
        else:
            near = np.minimum(c * c + np.minimum(beta / t, np.maximum(HALF_PI / t - 1, 0.0)),
                              (math.sqrt(2.0) - c) ** 2)
        # rho >= 2 d/h - 1 for a singularity at distance d from the centre (d > h)
        rho = 2 * np.sqrt(near) / h - 1
        need = np.where(rho > 2, np.ceil(_DIGITS / np.log(np.where(rho > 2, rho, 3.0))) + 1, n)
    return np.clip(np.nan_to_num(need, nan=n), 2, n).astype(np.intp)


def _scale(angle_sum):
    """An integral of angles -> chances: times 2/pi with one rounding."""
    return angle_sum * _TWO_OVER_PI_HI + angle_sum * _TWO_OVER_PI_LO


def _finish(acc):
    """Sums -> (heads, sides, tails): divided by the quadrature's own mass of the density, and
    the largest as 1 - the other two.

    Dividing by the mass the same nodes see cancels what they miss of a narrow density (a peak
    of height 1/sd a rounding away from a piece's end) and the density's own normalization
    error; the complement keeps the sum at 1 and a chance near 1 at or below 1.  The largest
    is at least 1/3, so the complement costs it no relative accuracy.
    """
    mass = acc[0] + acc[4]
    h = (acc[0] + _scale(acc[1])) / mass
    s, t = _scale(acc[2]) / mass, _scale(acc[3]) / mass
    if acc.ndim == 1:  # one xi: three floats
        if h >= s and h >= t:
            h = 1.0 - (s + t)
        elif s >= t:
            s = 1.0 - (h + t)
        else:
            t = 1.0 - (h + s)
        return tuple(float(min(max(v, 0.0), 1.0)) for v in (h, s, t))
    v = np.stack([h, s, t])
    k = np.argmax(v, axis=0)
    cols = np.arange(v.shape[1])
    v[k, cols] = 0.0
    v[k, cols] = 1.0 - v.sum(axis=0)
    return np.clip(v, 0.0, 1.0).astype(np.float64)  # the one rounding of the long double sums


def _delta(density: Density) -> float | None:
    """The angle of a normal too narrow for any quadrature (mean +- sd/2 round to the mean):
    the mean itself (Table I folds it exactly), except that the ends and the double nearest pi
    stand for 0 (the coin never precesses), as the quadrature's fold ``pi - mean`` has them,
    and ``HALF_PI`` for pi/2 exactly, the Keller flip (:func:`_table_i`); a mean given in
    degrees past 90 is its mirror ``180 - mean`` taken in degrees (``Normal.mirror``), the
    angle ``--psi MEAN`` takes."""
    if isinstance(density, Normal) and density.mean + 0.5 * density.sd == density.mean \
            and density.mean - 0.5 * density.sd == density.mean:
        if density.mirror is not None:  # a mean given in degrees past 90: --psi's angle
            return density.mirror
        return density.mean if 0.0 <= density.mean < math.pi else 0.0
    return None


def _table_i(xi, psi: float):
    """Table I at the folded angle of :func:`_delta`: eq. (12) itself at ``HALF_PI``."""
    return models.dynamic(xi) if psi == HALF_PI else models.conditional(xi, psi)


# A normal whose mass lies within _PLANAR_REACH of psi = 0 (folded; a subnormal sd, a mean of
# 1e-300) is below what the quadrature's nodes resolve.  Every coin with theta0/2 beyond its
# reach lands heads (exactly: no mass reaches a boundary); for the others (xi above 1e180) all
# angles are so small that sin x = x and cos x = 1 in double, Table I depends on psi/theta0
# alone, and the average is the one of the density scaled up by 2**k with xi scaled down by 2**k.
_PLANAR_REACH = 2.0**-600
_PLANAR_EXP = -30  #: the scaled reach lies in [2**-31, 2**-30)
_REACH_SD = 40.0  #: a normal's mass beyond this many sd from its peak underflows


def _planar(density: Density):
    """(reach, k, the scaled density) for such a normal, else None."""
    if not isinstance(density, Normal):
        return None
    mu = min(density.mean, math.pi - density.mean)
    reach = max(mu, 0.0) + _REACH_SD * density.sd
    if not reach < _PLANAR_REACH:
        return None
    k = _PLANAR_EXP - math.frexp(reach)[1]
    return reach, k, Normal(math.ldexp(mu, k), math.ldexp(density.sd, k))


# Thinner than this, a coin's P(sides) is C xi (C its slope at 0) to 1e-180 relative, and heads
# and tails differ from their values at xi = 0 by less than that: the averages there are those
# two numbers, which keeps P(sides) accurate where the quadrature's products of angles of xi's
# size would underflow (a subnormal xi gave P(sides) = 0).  Every density has structure no
# finer than 1e-16 rad near the boundaries at 45 deg (where thin coins precess to a side), or
# is a delta (Table I itself), so the linear term is the whole story.
_THIN = 2.0**-600


def _marginal_flat(xi: np.ndarray, density: Density, n: int) -> np.ndarray:
    """(3, len(xi)) chances for a 1-D array of xi in [0, inf]; chunked to bound memory."""
    psi = _delta(density)
    if psi is not None:  # the limit sd -> 0: Table I at the mean
        return np.array(_table_i(xi, psi), dtype=float).reshape(3, xi.size)
    out = np.empty((3, xi.size))
    inf = np.isinf(xi)
    out[:, inf] = np.array([[0.0], [1.0], [0.0]])  # every precessing toss lands on a side
    planar = _planar(density)
    if planar is not None:
        reach, k, scaled = planar
        heads = ~inf & (np.arctan2(1.0, xi) / 2 >= reach)
        out[:, heads] = np.array([[1.0], [0.0], [0.0]])
        rest = np.flatnonzero(~inf & ~heads)
        if rest.size:
            out[:, rest] = _marginal_flat(np.ldexp(xi[rest], -k), scaled, n)
        return out
    thin = (xi > 0) & (xi < _THIN)
    if thin.any():  # P(sides) = C xi to 1e-180 relative; heads and tails are their xi = 0 values
        base = _marginal_flat(np.array([0.0, _THIN]), density, n)
        out[:, thin] = np.array([[base[0, 0]], [0.0], [base[2, 0]]])
        out[1, thin] = xi[thin] * (base[1, 1] / _THIN)
    fin = np.nonzero(~inf & ~thin)[0]
    if fin.size:
        breaks = psi_breaks(density)
        step = max(1, min(_CHUNK // (breaks.size + 64), _CHUNK_BREAKS // max(breaks.size, 1)))
        for k in range(0, fin.size, step):
            idx = fin[k:k + step]
            out[:, idx] = _finish(_integrate_many(xi[idx], density, n, breaks))
    return out


def _marginal_scalar(x: float, density: Density, n: int, breaks=None):
    psi = _delta(density)
    if psi is not None:  # the limit sd -> 0: Table I at the mean
        return tuple(_table_i(x, psi))
    if x == math.inf:
        return 0.0, 1.0, 0.0  # every precessing toss lands on a side; psi = 0, pi has no mass
    planar = _planar(density)
    if planar is not None:
        reach, k, scaled = planar
        if math.atan2(1.0, x) / 2 >= reach:
            return 1.0, 0.0, 0.0
        return _marginal_scalar(math.ldexp(x, -k), scaled, n)
    if 0 < x < _THIN:  # P(sides) = C xi (see _THIN)
        h0, _, t0 = _marginal_scalar(0.0, density, n, breaks)
        return h0, x * (_marginal_scalar(_THIN, density, n, breaks)[1] / _THIN), t0
    if breaks is None:
        breaks = psi_breaks(density).tolist()
    return _finish(_integrate_one(x, density, n, breaks))


def marginal(xi, density: Density | None = None, *, order: int = DEFAULT_ORDER) -> Outcome:
    r"""Chances of heads, sides and tails averaged over a density of psi: eq. (15), Table II.

    Parameters
    ----------
    xi : float or array_like
        Aspect ratio, ``0 <= xi <= inf``.
    density : Density
        A :mod:`coincli.core.densities` density (default: the paper's normal, mean pi/2, sd 1/sqrt 2).
    order : int
        Gauss-Legendre nodes per subinterval, 2 to 64.  16 (the default) is within a few ulps
        of the exact value; :func:`order_for_tol` gives the fewest nodes for a tolerance.

    Returns
    -------
    Outcome
        Floats for a float ``xi``, arrays of its shape otherwise.  An array is computed in one
        vectorized pass.

    Examples
    --------
    >>> from coincli.core.densities import Uniform
    >>> [round(v, 3) for v in marginal(3 ** -0.5, Uniform())]  # Table II, uniform column
    [0.63, 0.281, 0.088]
    """
    density = check_density(density)
    n = _check_order(order)
    xi = models.check_xi(xi)
    if isinstance(xi, float):
        return Outcome(*_marginal_scalar(xi, density, n))
    flat = xi.ravel()
    if flat.size > 1:
        uniq, inv = np.unique(flat, return_inverse=True)
        check_table_work(density, uniq.size)
        if uniq.size < flat.size:
            out = _marginal_flat(uniq, density, n)[:, inv.ravel()]
        else:
            out = _marginal_flat(flat, density, n)
    else:
        out = _marginal_flat(flat, density, n)
    return Outcome(*(o.reshape(xi.shape) for o in out))


#: A table's points times the xi values averaged over it in one call: every point is a
#: breakpoint of the quadrature (the average is exact between them), so the work grows with
#: both; 10^7 is a few seconds (benchmarks/bench_core.py, docs/performance.md).
MAX_TABLE_WORK = 10**7
_SOLVE_EVALS = 12  #: forward evaluations per target the root finder typically needs


def check_table_work(density: Density, count: int, per: int = 1, what: str = "xi values"):
    """ValueError when a table's breakpoints times ``count`` values (each evaluated ``per``
    times) exceed :data:`MAX_TABLE_WORK`, naming how many values or points would fit."""
    if not isinstance(density, Table):
        return
    k = max(int(psi_breaks(density).size), 1)
    if k * count * per <= MAX_TABLE_WORK:
        return
    most = max(MAX_TABLE_WORK // (k * per), 1)
    raise ValueError(
        f"--psi-dist {density.spec}: its {len(density.psi)} points over {count} {what} are "
        f"{k * count * per:.3g} point evaluations, more than the {MAX_TABLE_WORK:.0e} one run "
        f"makes; give at most {most} {what}, or a table of at most "
        f"{max(MAX_TABLE_WORK // (count * per), 2)} points")


# --------------------------------------------------------------------------- inverses
# P(sides) = p is solved for xi by bracketing, then Chandrupatla's method (inverse quadratic
# interpolation safeguarded by bisection) down to two adjacent doubles: the tolerance is the
# answer's own rounding, whatever its size.  For p > 1/2 the equation solved is the complement,
# P(heads) + P(tails) = 1 - p: 1 - p is exact there, and the forward functions give heads and
# tails to full relative accuracy, while a double P(sides) near 1 moves in steps of 1.1e-16.
# The solver is coincli.core._numerics.roots.positive_roots.


def _sides_equation(forward, p):
    """resid(xi, idx) for P(sides) = p: ``P(sides) - p``, or ``(1 - p) - (P(heads) + P(tails))``
    for p > 1/2 (both increase with xi).  ``forward(xi) -> (heads, sides, tails)`` arrays."""
    up = p > 0.5
    q = 1.0 - p  # exact for p > 1/2 (Sterbenz)

    def resid(x, idx):
        h, s, t = forward(x)
        return np.where(up[idx], q[idx] - (h + t), s - p[idx])

    return resid


def _solve_p(p_sides, solve):
    """Validate ``p_sides`` (float or array) and map 0 -> 0, 1 -> inf, the rest through
    ``solve(p)`` (a 1-D array of distinct p in (0, 1)); a float back for a float."""
    p = models.check_p(p_sides, "p_sides")
    arr = np.atleast_1d(np.asarray(p, dtype=float))
    out = np.where(arr == 1.0, math.inf, 0.0)
    mid = (arr > 0) & (arr < 1)
    if mid.any():
        uniq, inv = np.unique(arr[mid], return_inverse=True)
        try:
            out[mid] = solve(uniq)[inv.ravel()]
        except ValueError as exc:
            if not isinstance(exc.args[0], int):
                raise
            bad = float(uniq[exc.args[0]])
            raise ValueError(f"p_sides = {bad!r} is not reachable for any xi in "
                             f"[5e-324, 1.8e308]") from None
    return float(out[0]) if isinstance(p, float) else out.reshape(np.shape(p))


def _rows(scalar_fn, array_fn):
    """forward(xi array) -> (heads, sides, tails) arrays: ``array_fn`` on many xi, the cheaper
    ``scalar_fn`` on Python floats for one (a root finder's usual case)."""
    def forward(x):
        if x.size == 1:
            return tuple(np.array([v]) for v in scalar_fn(float(x[0])))
        return tuple(array_fn(x))
    return forward


def marginal_inverse(p_sides, density: Density | None = None, *, order: int = DEFAULT_ORDER):
    """The aspect ratio whose psi-averaged chance of a side is ``p_sides`` (a float or an array).

    Root finding (:func:`positive_roots`) down to adjacent doubles, on ``P(sides) = p`` for
    p <= 1/2 and on ``P(heads) + P(tails) = 1 - p`` above; an array is solved in one vectorized
    pass.  ``p = 0`` gives 0 and ``p = 1`` gives ``inf`` (the chance tends to 1 only as ``xi`` grows
    without bound).  A normal too narrow for any quadrature is Table I at its mean, and so is
    its inverse (:func:`conditional_inverse`, or :func:`coincli.core.models.dynamic_inverse` at a mean
    of exactly ``HALF_PI``).  Accuracy: docs/accuracy.md.
    """
    density = check_density(density)
    n = _check_order(order)
    psi = _delta(density)
    if psi is not None:
        if psi == HALF_PI:
            return models.dynamic_inverse(p_sides)
        return conditional_inverse(p_sides, psi)
    breaks = psi_breaks(density).tolist()
    forward = _rows(lambda x: _marginal_scalar(x, density, n, breaks),
                    lambda x: _marginal_flat(x, density, n))

    def solve(p):
        check_table_work(density, p.size, _SOLVE_EVALS, "targets")
        guess, step = models.dynamic_inverse(p), 0.25
        if isinstance(density, Normal) and density.sd < 0.1 and 0 < density.mean < math.pi:
            guess, step = _table_i_guess(p, min(density.mean, math.pi - density.mean)), 0.01
        return positive_roots(_sides_equation(forward, p), guess, step)

    return _solve_p(p_sides, solve)


def conditional_inverse(p_sides, psi):
    """The aspect ratio whose chance of a side at the fixed angle ``psi`` (radians) is ``p_sides``
    (a float or an array).

    At ``psi = 0`` or ``pi`` the coin never precesses and always lands heads: only
    ``p_sides = 0`` is reachable there.  Otherwise every ``p`` in [0, 1] is (``p = 1`` at
    ``xi = inf``).  Table I inverted in closed form (:func:`_table_i_guess`) gives the start;
    root finding on the forward function (:func:`positive_roots`, on the complement for
    p > 1/2) then takes the answer to adjacent doubles.  Accuracy: docs/accuracy.md.
    """
    psi = models.check_psi(psi)
    if not isinstance(psi, float):
        raise ValueError("psi must be a single angle for conditional_inverse")
    forward = _rows(lambda x: models.conditional(x, psi), lambda x: models.conditional(x, psi))

    def solve(p):
        if math.sin(psi) == 0.0:
            raise ValueError(
                "at psi = 0 or 180 degrees the coin never precesses and always lands heads; "
                "only p_sides = 0 is reachable"
            )
        return positive_roots(_sides_equation(forward, p), _table_i_guess(p, psi), 2.0**-40)

    return _solve_p(p_sides, solve)


def _table_i_guess(p, psi):
    r"""Table I inverted in closed form: the xi with ``P(sides | psi) = p`` (numpy, 0 < p < 1).

    With ``phi = pi p/2``, ``e = pi/2 - psi`` (psi folded onto [0, pi/2]) and ``c = cos theta0``:

    - heads or sides (``psi < pi/2 - theta0/2``): ``cos(pi P(heads)) = (c - cos^2 psi)/sin^2 psi``
      gives ``1 - c = 2 sin^2 psi cos^2 phi``;
    - all three (``cos phi > tan e``, which needs psi > pi/4): ``cos(theta2 - theta1) = cos 2 phi``
      squared out gives ``c = cos^2 e sin phi sqrt(1 - r^2)`` with ``r = tan^2 e/cos phi``, and
      ``1 - c = (1 - sin phi) + sin phi (sin^2 e + cos^2 e r^2/(1 + sqrt(1 - r^2)))``, a sum
      of positive terms;

    then ``xi = c/sqrt((1 - c)(1 + c))``.  Good to about 1e-13 where nothing cancels, and the start
    of the root finding everywhere (it is not returned as the answer).
    """
    psi_m, e = models.fold_psi(models.M, psi)
    q = 1.0 - p
    up = p > 0.5
    with np.errstate(all="ignore"):
        sphi = np.where(up, np.cos(HALF_PI * q), np.sin(HALF_PI * p))
        cphi = np.where(up, np.sin(HALF_PI * q), np.cos(HALF_PI * p))
        se, ce = math.sin(e), math.cos(e)
        te = se / ce
        # region C
        r = te * te / cphi
        root = np.sqrt((1 - r) * (1 + r))
        c_c = ce * ce * sphi * root
        omc_c = 2 * np.sin(0.5 * HALF_PI * q) ** 2 + sphi * (se * se + ce * ce * r * r / (1 + root))
        # region B: sqrt(1 - c) = sqrt 2 sin psi cos phi, never squared (sin psi may be 1e-300)
        rt_b = math.sqrt(2.0) * math.sin(psi_m) * cphi
        omc_b = rt_b * rt_b
        c_b = np.where(omc_b < 0.5, 1 - omc_b, -math.cos(2 * e) + 2 * ce * ce * sphi * sphi)
        three = (psi_m > math.pi / 4) & (cphi > te)
        c = np.where(three, c_c, c_b)
        omc = np.where(three, omc_c, omc_b)
        rt = np.where(three, np.sqrt(omc_c), rt_b)
        xi = c / (rt * np.sqrt(2 - omc))
    return np.clip(np.where(np.isnan(xi), 1.0, xi), POSITIVE_MIN, POSITIVE_MAX)
