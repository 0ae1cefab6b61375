r"""One real toss: its limits, geometry, ``F`` and ``F'``, the certified first root (Sec. II).

The closed forms of :mod:`coincli.core.models` hold for a vigorous toss, ``u omega / g >> 1``.  This
module is the deterministic model they are the limit of.  A coin of diameter ``D = 2a`` and
thickness ``h = xi D`` starts heads up with its centre at height ``z0``, is thrown upward at
``u`` and precesses at ``omega = omega_N = M / I_1`` about its angular momentum, which makes the
angle ``psi`` with the normal (eq. 2).  Everything is SI: metres, seconds, radians.

Model
    ``z(t) = z0 + u t - g t^2 / 2`` with the paper's ``z0 = (sqrt 3 / 2) a`` (eq. 5), and
    ``cos alpha(t) = A + B cos(omega t)``, ``A = cos^2 psi``, ``B = sin^2 psi`` (eq. 3).  The coin
    is caught at ``z = 0``; the time of flight ``t_f`` is the smallest positive root of
    ``F(t) = z(t) - L(alpha(t))`` (eq. 6), where ``L`` is the depth of the coin's lowest point
    below its centre:

    - ``contact="rim"`` (the paper's): ``L = a sin alpha``, the rim of the mid-plane disc;
    - ``contact="thick"``: ``L = a sin alpha + (h/2) |cos alpha|``, the lowest corner of the
      cylinder.  Its default launch height is raised by ``h/2`` to ``z0 = (sqrt 3/2) a + h/2``, so
      that the lowest point starts ``(sqrt 3/2) a`` above the catch plane as the paper's rim does
      (with the paper's ``z0`` a coin with ``xi >= sqrt 3 / 2`` would start below the plane).

    The outcome is eq. (7) applied to ``alpha_f = alpha(t_f)``: heads for
    ``0 <= alpha_f <= theta0``, sides for ``theta0 < alpha_f <= pi - theta0``, tails for
    ``pi - theta0 < alpha_f <= pi`` (so ``alpha_f = theta0`` is heads, ``alpha_f = pi - theta0``
    is sides).  ``alpha`` is computed from the half-angle identity
    ``sin(alpha/2) = sin psi |sin(omega t / 2)|``, ``cos(alpha/2) = hypot(cos(omega t/2),
    cos psi sin(omega t/2))``, which keeps full accuracy at ``alpha`` near 0 and pi (the textbook
    ``arccos(A + B cos theta)`` loses half the digits there).

Root finding (never skipping an earlier crossing)
    1. *Window.*  ``L`` never exceeds ``Lmax`` (``a``, or ``hypot(a, h/2)`` for a thick coin, or
       less when ``psi`` keeps the coin from tilting that far), so no contact is possible while
       ``z(t) > Lmax``.  The flight ``[0, t_end]`` (``z(t_end) = 0``, where ``F <= 0``) is cut to
       the one or two intervals where ``z <= Lmax``.
    2. *Scan.*  Each window is marched in cells of at most a sixteenth of a precession period.
       ``F`` is semi-concave: ``F'' <= K2 = omega^2 sin psi (a + (h/2) sin psi) - g`` (the
       horizontal projection of the normal, ``sin alpha``, has second derivative at least
       ``-|N''| = -omega^2 sin psi``; the corners of ``|.|`` only bend it upward).  Hence on a
       cell of width ``d``, ``F >= min(F(t1), F(t2)) - max(K2, 0) d^2 / 8``, and ``F' <= F'(t1+)
       + max(K2, 0) d``: a cell where the first bound is positive, or where ``F`` is certified
       decreasing with ``F(t2) > 0``, holds no root, *certainly*, however thin a dip could be.
       A cell that is neither free nor certified shrinks by 8 (and grows back after free ones).
    3. *Refine.*  A cell with ``F(t1) > 0 >= F(t2)`` certified decreasing holds exactly one
       root.  It starts at the root of the cubic Hermite interpolant of ``F, F'`` at the ends,
       then a bracketed Newton iteration (bisecting whenever a step would leave the bracket)
       stops when ``F`` is zero, a step is below two ulps of ``t`` or so small that the point it
       reaches is exact (Newton's error ``F'' s^2 / 2F'``, with ``F''`` measured between the
       last two points), or the bracket is four ulps wide.  A tangency (a double root, measure
       zero) is resolved to the last bit of ``t`` and counted as contact only if ``F`` goes
       non-positive at a sampled point.  A dip shallower than the rounding band of ``F``
       (``16 eps`` of the height scale, plus ``16 eps`` of the phase ``omega t`` times
       ``Lmax``) cannot be told from noise and is not a contact.

    Contact happens within about one precession period after ``z`` drops below ``Lmax`` (``L``
    reaches ``Lmax`` once a period), so the cost does not grow with the number of turns in the
    air; tosses of millions of turns cost the same as one.  The phase ``omega t`` must stay below
    ``1e12`` rad, beyond which a double no longer holds it to ``1e-4`` rad, and the curvature
    bound ``K2 ~ omega^2 a`` must be a finite double (an infinite one would exclude no cell, and
    the scan would never end); :func:`flight_limits` says whether a toss can be followed.

One vectorized path
    :func:`toss_many` (:mod:`coincli.core.toss.batch`) runs the three steps on numpy arrays, one
    evaluation of ``F`` and ``F'`` a toss a round, dropping tosses as they finish; certified
    cells are refined together.  :func:`toss` and :func:`flight_time` are a batch of one: the
    same code, the same bits, no scipy.  ``sin`` and ``cos`` of the half phase are fdlibm's
    polynomials after a Cody-Waite reduction (``omega t / 2 < 1.5e6``; numpy's beyond), within
    two ulps.  Against an independent 40-digit reference (tests/test_toss_mpmath.py) ``t_f`` is
    within 4 ulps plus the time ``F`` takes to cross its rounding band; ordinary tosses run at
    several million a second (``benchmarks/toss_bench.py``, docs/performance.md).

The toss package
    This module holds the model, the checks of its inputs and what the scan can follow
    (:func:`check_toss`, :func:`flight_limits`), ``F`` and ``F'`` and the certified first root,
    and :func:`toss`.  Many tosses and the outcome engine of ``coin simulate`` are
    :mod:`coincli.core.toss.batch`, phase-space maps :mod:`coincli.core.toss.phase`, launch
    distributions :mod:`coincli.core.toss.launch` and seeded runs :mod:`coincli.core.toss.simulate`.

Nothing here prints or exits; bad input raises :class:`ValueError` naming the argument and its
allowed range.
"""

from __future__ import annotations

import math

from coincli.core._numerics.records import record
from coincli.core._numerics.trig import abs_sin_rough, half_sincos
from coincli.limits import (  # noqa: F401 (re-read by the toss modules' users as T.NAME)
    CONTACTS,
    DEFAULT_DIAMETER,
    G_MAX,
    G_MIN,
    MAX_PHASE,
    MAX_TOSSES,
    STANDARD_G,
    U_MAX,
)

__all__ = [
    "DEFAULT_DIAMETER",
    "STANDARD_G",
    "CONTACTS",
    "HEADS",
    "SIDES",
    "TAILS",
    "NAMES",
    "LETTERS",
    "MAX_PHASE",
    "MAX_TOSSES",
    "U_MAX",
    "default_z0",
    "lowest_point",
    "alpha_at",
    "classify",
    "flight_limits",
    "check_toss",
    "scalar_setup",
]

HEADS, SIDES, TAILS = 0, 1, 2  #: outcome codes
NAMES = ("heads", "sides", "tails")
LETTERS = ("H", "S", "T")

_TWO_PI = 2.0 * math.pi
EPS = 2.220446049250313e-16
SQRT3_2 = math.sqrt(3.0) / 2.0
_CELLS_PER_TURN = 16  # scan step: a sixteenth of a precession period
_ZOOM = 8  # refinement factor of the vectorized scan


# --------------------------------------------------------------------------- validation


def _range_text(lo, hi, lo_open, hi_open, unit, allow_inf=False):
    u = f" {unit}" if unit else ""
    if hi == math.inf:
        return f"{'>' if lo_open else '>='} {lo:g}{u}" + ("" if allow_inf else " (finite)")
    hi_s = "pi" if hi == math.pi else f"{hi:g}"
    return f"in {'(' if lo_open else '['}{lo:g}, {hi_s}{')' if hi_open else ']'}{u}"


def check_number(name, value, lo, hi=math.inf, *, lo_open=False, hi_open=False, unit="",
                 allow_inf=False):
    """Validate a scalar or array_like; return a float or a float ndarray."""
    msg = f"{name} must be {_range_text(lo, hi, lo_open, hi_open, unit, allow_inf)}"
    if isinstance(value, bool):
        raise ValueError(f"{msg}, got {value!r}")
    if isinstance(value, (int, float)):
        v = float(value)
        bad = (math.isnan(v) or v < lo or v > hi or (lo_open and v == lo)
               or (hi_open and v == hi) or (math.isinf(v) and not allow_inf))
        if bad:
            raise ValueError(f"{msg}, got {v!r}")
        return v
    import numpy as np

    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a number or an array of numbers, got {value!r}") from None
    if arr.size:  # two passes (NaN propagates to both) when all is well, as it mostly is
        a, b = float(arr.min()), float(arr.max())
        if ((a > lo or (a == lo and not lo_open)) and (b < hi or (b == hi and not hi_open))
                and (allow_inf or math.isfinite(a) and math.isfinite(b))):
            return arr
    with np.errstate(invalid="ignore"):
        bad = np.isnan(arr) | (arr < lo) | (arr > hi)
        if lo_open:
            bad |= arr == lo
        if hi_open:
            bad |= arr == hi
        if not allow_inf:
            bad |= np.isinf(arr)
    if bad.any():
        raise ValueError(f"{msg}, got {float(arr[bad].flat[0])!r}")
    return arr


def check_contact(contact):
    if contact not in CONTACTS:
        raise ValueError(f"contact must be 'rim' or 'thick', got {contact!r}")
    return contact == "thick"


def check_all(xi, psi, u, omega, diameter, g, contact):
    thick = check_contact(contact)
    xi = check_number("xi", xi, 0.0, 1e100, allow_inf=not thick) if thick else check_number(
        "xi", xi, 0.0, allow_inf=True)
    psi = check_number("psi", psi, 0.0, math.pi, unit="rad")
    u = check_number("u", u, 0.0, U_MAX, unit="m/s")
    omega = check_number("omega", omega, 0.0, unit="rad/s")
    diameter = check_number("diameter", diameter, 0.0, 1e100, lo_open=True, unit="m")
    g = check_number("g", g, G_MIN, G_MAX, unit="m/s^2")
    return xi, psi, u, omega, diameter, g, thick


def check_count(n):
    if isinstance(n, bool) or not isinstance(n, (int,)) and not (
            isinstance(n, float) and n.is_integer()):
        raise ValueError(f"n must be a whole number >= 1, got {n!r}")
    n = int(n)
    if not 1 <= n <= MAX_TOSSES:
        raise ValueError(f"n must be a whole number from 1 to {MAX_TOSSES} (1e8), got {n}; for "
                         "more tosses, run again with another seed and add the counts")
    return n


# --------------------------------------------------------------------------- geometry


def default_z0(xi, diameter=DEFAULT_DIAMETER, contact="rim"):
    """Launch height of the centre: ``(sqrt 3 / 2) a`` (eq. 5), plus ``h / 2`` for thick contact."""
    thick = check_contact(contact)
    a = diameter / 2
    return SQRT3_2 * a + (xi * diameter / 2 if thick else 0.0)


def alpha_at(psi, theta):
    r"""The tilt ``alpha`` of the normal from the vertical after precessing by ``theta`` (eq. 3).

    ``sin(alpha/2) = sin psi |sin(theta/2)|`` (from ``1 - cos alpha = B (1 - cos theta)``), with
    ``cos(alpha/2) = hypot(cos(theta/2), cos psi sin(theta/2))``; ``alpha = 2 atan2(.,.)``.
    Scalars or arrays (numpy only for arrays).
    """
    if isinstance(psi, (int, float)) and isinstance(theta, (int, float)):
        sh = abs(math.sin(0.5 * theta))
        return 2.0 * math.atan2(math.sin(psi) * sh, math.hypot(math.cos(0.5 * theta),
                                                                 math.cos(psi) * sh))
    import numpy as np

    psi = np.asarray(psi, dtype=float)
    theta = np.asarray(theta, dtype=float)
    sh = np.abs(np.sin(0.5 * theta))
    return 2.0 * np.arctan2(np.sin(psi) * sh, np.hypot(np.cos(0.5 * theta), np.cos(psi) * sh))


def lowest_point(alpha, diameter=DEFAULT_DIAMETER, xi=0.0, contact="rim"):
    """Depth of the coin's lowest point below its centre at tilt ``alpha``: ``a sin alpha``
    (rim) or ``a sin alpha + (h/2)|cos alpha|`` (thick)."""
    thick = check_contact(contact)
    a = diameter / 2
    if isinstance(alpha, (int, float)):
        return a * math.sin(alpha) + (xi * diameter / 2 * abs(math.cos(alpha)) if thick else 0.0)
    import numpy as np

    alpha = np.asarray(alpha, dtype=float)
    return a * np.sin(alpha) + (xi * diameter / 2 * np.abs(np.cos(alpha)) if thick else 0.0)


def classify(alpha_f, xi):
    """Outcome codes of eq. (7): 0 heads (``alpha_f <= theta0``), 1 sides
    (``theta0 < alpha_f <= pi - theta0``), 2 tails (``alpha_f > pi - theta0``).

    ``theta0 = atan2(1, xi)`` and ``pi - theta0 = atan2(1, -xi)`` (no rounding of a subtraction).
    Scalars give an int, arrays an int8 array.
    """
    xi = check_number("xi", xi, 0.0, allow_inf=True)
    if isinstance(alpha_f, (int, float)) and isinstance(xi, float):
        t0, t1 = math.atan2(1.0, xi), math.atan2(1.0, -xi)
        return HEADS if alpha_f <= t0 else (SIDES if alpha_f <= t1 else TAILS)
    import numpy as np

    a = np.asarray(alpha_f, dtype=float)
    t0, t1 = np.arctan2(1.0, xi), np.arctan2(1.0, -np.asarray(xi))
    return np.where(a <= t0, HEADS, np.where(a <= t1, SIDES, TAILS)).astype(np.int8)


@record()
class _Setup:
    """Everything the root finder needs about one toss (floats) or many (arrays)."""

    om: object
    sp: object  # sin psi
    cp: object  # cos psi
    a: object
    hh: object  # half thickness entering the contact (0 for rim)
    z0: object
    u: object
    g: object
    t_end: object  # z(t_end) = 0
    lmax: object
    w1: object  # first window [0, w1] (w1 = -1: none)
    w2s: object  # second window [w2s, t_end]
    k2: object  # upper bound of F''
    tol0: object  # absolute accuracy of a computed F at time t: tol0 + tol1 t
    tol1: object
    stol: object  # absolute accuracy of a computed F'
    step: object  # base scan step


#: 2 g z0 below this is computed another way by :func:`fall_time` (it may have underflowed)
FALL_TINY = 1e-280


def fall_time(xp, u, g, z0):
    """``(u + sqrt(u^2 + 2 g z0)) / g``: when the centre, launched up at ``u`` from ``z0``,
    falls back to the plane (the latest contact of a toss).  Where ``2 g z0`` is so small that
    it may have underflowed (a subnormal ``g``, a tiny ``z0``: the time would come out 0, and
    the toss 'land' at once), it is ``u/g + hypot(u/g, sqrt(2 z0) / sqrt(g))``, the same
    number with no product of small numbers (issue 28); ``inf`` when the time overflows."""
    t = (u + xp.sqrt(u * u + 2.0 * g * z0)) / g
    tiny = 2.0 * g * z0 < FALL_TINY
    if isinstance(tiny, bool) and not tiny:
        return t
    rise = u / g
    return xp.where(tiny, rise + xp.hypot(rise, xp.sqrt(2.0 * z0) / xp.sqrt(g)), t)


def setup(xp, xi, psi, u, om, diameter, g, thick, z0):
    """Per-toss constants; xp is ``math`` (via coincli.core._numerics.backend.M) or numpy."""
    a = diameter / 2
    hh = xi * diameter / 2 if thick else 0.0 * a
    if z0 is None:
        z0 = SQRT3_2 * a + hh
    sp, cp = _sin_cos_psi(xp, psi)
    # The largest tilt reached is alpha(pi) = 2 min(psi, pi - psi); none without precession.
    # Its sine and cosine are sin 2 psi and cos 2 psi up to sign: 2 sin psi |cos psi| and
    # (cos psi - sin psi)(cos psi + sin psi), no further trigonometry.
    spin = om > 0
    amax = xp.where(spin, 2.0 * xp.minimum(psi, math.pi - psi), 0.0)
    s2 = xp.where(spin, 2.0 * sp * xp.abs(cp), 0.0)
    if thick:
        c2 = xp.where(spin, xp.abs((cp - sp) * (cp + sp)), 1.0)
        lmax = xp.where(amax >= xp.atan2(a, hh), xp.hypot(a, hh), a * s2 + hh * c2)
    else:
        lmax = xp.where(amax >= 0.5 * math.pi, a, a * s2)
    lmax = lmax * (1.0 + 8 * EPS)  # a rounded-down bound must not shrink the window
    t_end = fall_time(xp, u, g, z0)
    d = lmax - z0  # > 0: the launch height is inside the window
    disc = u * u - 2.0 * g * d
    root = xp.sqrt(xp.maximum(disc, 0.0))
    inside = (d > 0) & (disc <= 0)
    w1 = xp.where(d > 0, 2.0 * d / xp.maximum(u + root, 1e-300), -1.0)
    w1 = xp.where(inside, -1.0, w1)
    w2s = xp.where(inside, 0.0, xp.minimum((u + root) / g, t_end))
    # psi = 0 (sp = 0) has no curvature term even when omega^2 overflows (inf * 0 would be NaN).
    k2 = xp.where(sp > 0, om * om * sp * (a + hh * sp), 0.0) - g
    # The launch window [0, w1] often needs no look: z >= z0 there (the centre is rising) and
    # alpha <= ab = omega t sin psi (|d alpha / d theta| <= sin psi), so L <= a sin(min(ab,
    # pi/2)) + h/2 <= a min(ab, 1) + h/2 (and never more than Lmax).
    ab = xp.minimum(om * xp.maximum(w1, 0.0) * sp, amax)
    lw1 = xp.minimum(a * xp.minimum(ab, 1.0) + hh, lmax)
    zscale = z0 + u * u / (2.0 * g)
    # Rounding: a few ulps of the height scale, plus the phase omega t carried to eps omega t.
    tol0 = 16 * EPS * (zscale + 2.0 * lmax)
    tol1 = 16 * EPS * lmax * om
    stol = 16 * EPS * (u + g * t_end + om * (a + hh) * (1.0 + om * t_end))
    step = xp.where(om > 0, _TWO_PI / (_CELLS_PER_TURN * xp.maximum(om, 1e-300)), xp.inf)
    clear = z0 - lw1 * (1.0 + 8 * EPS) > 2.0 * (tol0 + tol1 * xp.maximum(w1, 0.0))
    w1 = xp.where(clear, -1.0, w1)
    return _Setup(om, sp, cp, a, hh, z0, u, g, t_end, lmax, w1, w2s, k2, tol0, tol1, stol, step)


def _sin_cos_psi(xp, psi):
    """``sin psi, cos psi`` for ``psi`` in ``[0, pi]``: by :func:`half_sincos` for numpy (an
    array or one number alike, so that a toss gives the same bits alone or in a batch), by the
    math module for the scalar checks."""
    if xp is _M():
        return math.sin(psi), math.cos(psi)
    arr = xp.asarray(psi, dtype=float)
    sp, cp = half_sincos(xp, xp.atleast_1d(arr))
    if arr.ndim == 0:
        return float(sp[0]), float(cp[0])
    return sp.reshape(arr.shape), cp.reshape(arr.shape)


def _M():
    from coincli.core._numerics.backend import M

    return M


# --------------------------------------------------------------------------- F and F'


class Batch:
    """The root finder's per-toss constants: each a float (shared by the whole batch) or a 1-D
    float array with one value a toss.  Built from a :class:`_Setup` by :func:`_batch`.

    ``hom = omega/2``; F reads ``z0, u, hg = g/2, c2a = 2 a sin psi, cp2 = cos^2 psi,
    c2psi = cos 2 psi, hh``; F' also ``g, c1 = omega a sin psi, c3 = 2 omega (h/2) sin^2 psi``.
    """

    __slots__ = ("hom", "z0", "u", "g", "hg", "c2a", "cp2", "c2psi", "hh", "c1", "c3", "k2p",
                 "tol0", "tol1", "stol")
    FIELDS = ("hom", "z0", "u", "g", "hg", "c2a", "cp2", "c2psi", "hh", "c1", "c3")  # what _ff reads

    def take(self, sel, names=None):
        """The constants ``names`` (default: all that are set) of the tosses ``sel`` (an index
        array or a boolean mask)."""
        out = Batch.__new__(Batch)
        for k in names or [k for k in Batch.__slots__ if hasattr(self, k)]:
            v = getattr(self, k)
            setattr(out, k, v if isinstance(v, float) else v[sel])
        return out


def _flat(np, v, n):
    """A float for a value shared by the batch, else a 1-D float array of length n."""
    arr = np.asarray(v, dtype=float)
    if arr.ndim == 0:
        return float(arr)
    return np.ascontiguousarray(np.broadcast_to(arr, (n,)))


def _batch(np, s: _Setup, n):
    q = Batch.__new__(Batch)
    for k in ("z0", "u", "g", "hh", "tol0", "tol1", "stol"):
        setattr(q, k, _flat(np, getattr(s, k), n))
    om, sp, cp = (np.asarray(v, dtype=float) for v in (s.om, s.sp, s.cp))
    q.hom = _flat(np, 0.5 * om, n)  # half the phase rate (exact)
    q.hg = _flat(np, 0.5 * np.asarray(s.g, dtype=float), n)
    q.c2a = _flat(np, 2.0 * s.a * sp, n)
    q.cp2 = _flat(np, cp * cp, n)
    q.c2psi = _flat(np, (cp - sp) * (cp + sp), n)
    with np.errstate(over="ignore", invalid="ignore"):  # omega * a overflows only when refused
        q.c1 = _flat(np, np.where(sp > 0, om * s.a * sp, 0.0), n)
        q.c3 = _flat(np, np.where(sp > 0, 2.0 * om * np.asarray(s.hh) * sp * sp, 0.0), n)
    q.k2p = _flat(np, np.maximum(s.k2, 0.0), n)
    return q


def _ff(np, t, q: Batch, thick):
    """``F(t)``, an upper bound of its right derivative ``F'(t+)`` (exact except at a corner),
    and ``|sin x|``, ``cos x'`` (arrays over the tosses of ``q``; ``x = omega t / 2``, ``x'`` its
    representative modulo pi in ``[0, pi)``).

    ``sin(alpha/2) = sin psi |sin x|``, ``cos(alpha/2) = sqrt(cos^2 x + cos^2 psi sin^2 x)``,
    ``cos alpha = cos^2 x + cos 2psi sin^2 x``; ``L = a sin alpha (+ (h/2)|cos alpha|)``;
    ``d alpha / d theta = sin psi cos x' / cos(alpha/2)``.  At the corners (``cos(alpha/2) = 0``,
    the coin upside down; ``cos alpha = 0`` for a thick coin) the corner's term is taken as 0,
    above the right derivative: the monotonicity certificate stays sound.
    """
    sh, ch = half_sincos(np, q.hom * t)
    # The same operations in the same order as the formulas say, in place where one of the
    # operands is a temporary (a + b = b + a, a b = b a exactly).
    sh2 = sh * sh
    ch2 = ch * ch
    ca = np.multiply(q.cp2, sh2)
    ca += ch2
    np.sqrt(ca, out=ca)  # cos(alpha/2) = sqrt(ch2 + cp2 sh2)
    cos_a = np.multiply(q.c2psi, sh2, out=sh2)
    cos_a += ch2  # ch2 + c2psi sh2
    low = np.multiply(q.c2a, sh)
    low *= ca  # a sin alpha = (c2a sh) ca
    dlow = np.multiply(q.c1, cos_a, out=ch2)
    dlow *= ch
    ca += 1e-300
    dlow /= ca  # omega dL/dtheta (rim) = c1 cos_a ch / (ca + 1e-300)
    if thick:
        low += q.hh * np.abs(cos_a)
        dlow -= q.c3 * np.sign(cos_a) * sh * ch
    f = np.multiply(q.hg, t)
    np.subtract(q.u, f, out=f)
    f *= t
    f += q.z0
    f -= low  # z0 + t (u - hg t) - low
    fp = np.multiply(q.g, t)
    np.subtract(q.u, fp, out=fp)
    fp -= dlow  # u - g t - dlow
    return f, fp, sh, ch


def alpha_from(np, sp, cp, sh, ch):
    """The tilt ``alpha`` from ``|sin x|``, ``cos x`` (``x`` half the precession phase), as
    :func:`alpha_at`: ``2 atan2(sin psi |sin x|, hypot(cos x, cos psi sin x))``."""
    cs = cp * sh
    return 2.0 * np.arctan2(sp * sh, np.sqrt(ch * ch + cs * cs))  # (no overflow: both <= 1)


# --------------------------------------------------------------------------- one toss: the checks


def check_toss(xi, psi, u, omega, *, diameter=DEFAULT_DIAMETER, g=STANDARD_G, contact="rim",
               z0=None):
    """Raise the ValueError :func:`toss` would raise for these numbers (out of range, or a toss
    the scan cannot follow), without tossing; return None when the toss can be made."""
    scalar_setup(xi, psi, u, omega, diameter, g, contact, z0)


def scalar_setup(xi, psi, u, omega, diameter, g, contact, z0):
    """The checked :class:`_Setup` of one toss (numbers only), or the ValueError that
    :func:`coincli.core.toss.batch.toss` raises for it."""
    for name, v in (("xi", xi), ("psi", psi), ("u", u), ("omega", omega),
                    ("diameter", diameter), ("g", g)):
        if not isinstance(v, (int, float)) or isinstance(v, bool):
            raise ValueError(f"{name} must be a number, got {v!r} (use toss_many for arrays)")
    xi, psi, u, omega, diameter, g, thick = check_all(xi, psi, u, omega, diameter, g, contact)
    z0 = _check_z0(z0, xi, diameter, thick)
    s = setup(_M(), xi, psi, u, omega, diameter, g, thick, z0)
    problem = problem_code(_M(), s)
    if problem:
        raise ValueError(problem_message(problem, omega, u, g, s.z0, omega * s.t_end))
    return s


def problem_code(xp, s: _Setup):
    """0 when the scan can follow the toss, else why not: 1 ``t_end`` overflows a double,
    2 ``omega t_end > MAX_PHASE``, 3 the curvature bound ``K2`` (``omega^2 a``) or the slope
    tolerance overflows.  Per toss for arrays (int8)."""
    phase = s.om * s.t_end
    curv = xp.isfinite(s.k2) & xp.isfinite(s.stol)
    if xp is not _M():
        import numpy as np

        with np.errstate(invalid="ignore"):
            return np.select([~np.isfinite(s.t_end), phase > MAX_PHASE, ~curv], [1, 2, 3],
                             0).astype(np.int8)
    if not math.isfinite(s.t_end):
        return 1
    return 2 if phase > MAX_PHASE else (0 if curv else 3)


def problem_message(problem, omega, u, g, z0, phase):
    if problem == 1:
        return (f"the flight is too long to represent (g = {g:g} m/s^2, u = {u:g} m/s, z0 = "
                f"{z0:g} m); raise g or lower u or z0")
    if problem == 2:
        return (f"omega * t_end = {phase:.3g} rad exceeds {MAX_PHASE:g} rad, where a double no "
                f"longer holds the phase; lower omega (got {omega:g} rad/s) or u (got {u:g} m/s)")
    return (f"omega = {omega:g} rad/s is too fast to follow: omega^2 * a overflows a double; "
            "lower omega")


def flight_limits(xi, psi, u, omega, *, diameter=DEFAULT_DIAMETER, g=STANDARD_G, contact="rim",
                  z0=None):
    """Whether :func:`toss` / :func:`toss_many` can follow these tosses, as they check it.

    Returns ``(t_end, phase, problem)``: ``t_end`` (s) is the latest possible contact (the
    centre reaches the catch plane), ``phase = omega * t_end`` (rad), and ``problem`` 0 when
    the toss can be followed, else 1 (``t_end`` overflows a double), 2 (``phase > MAX_PHASE``)
    or 3 (``omega^2 a`` overflows: the scan's curvature bound is not finite).  Scalars give
    floats and an int, arrays (broadcast) arrays.  The arguments must already be in range.
    """
    thick = check_contact(contact)
    M = _M()
    if all(isinstance(v, (int, float)) for v in (xi, psi, u, omega, diameter, g)) and (
            z0 is None or isinstance(z0, (int, float))):
        s = setup(M, float(xi), float(psi), float(u), float(omega), float(diameter), float(g),
                   thick, None if z0 is None else float(z0))
        return s.t_end, omega * s.t_end, problem_code(M, s)
    import numpy as np

    arrs = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (
        xi, psi, u, omega, diameter, g, 0.0 if z0 is None else z0)))
    with np.errstate(over="ignore", invalid="ignore"):
        s = setup(np, *arrs[:6], thick, None if z0 is None else arrs[6])
        return s.t_end, arrs[3] * s.t_end, problem_code(np, s)


def _check_z0(z0, xi, diameter, thick):
    if z0 is None:
        return None
    z0 = check_number("z0", z0, 0.0, lo_open=True, unit="m")
    floor = xi * diameter / 2 if thick else 0.0
    if z0 <= floor:
        raise ValueError(f"z0 must be > h/2 = {floor:g} m for thick contact (the coin would start "
                         f"below the catch plane), got {z0!r}")
    return z0


_MAX_ROUNDS = 100_000
_AGE_MULTI = 3  #: rounds after which a toss lays several cells a round
_MULTI = 8  #: cells a round then


def first_root(np, s: _Setup, n, thick, bands=None):
    """The first root of F for each of the ``n`` tosses of a batch (scalars or 1-D arrays in s).

    Returns ``(t_f, |sin x|, cos x')`` at the roots (``x = omega t_f / 2``, as :func:`_ff`).

    With ``bands = (sin(theta0/2), cos(theta0/2))`` (the outcome boundaries of eq. 7 in
    ``sin(alpha/2) = sin psi |sin x|``) only outcomes are wanted: a fourth array is returned,
    the outcome code of each toss decided without refining its root (-1 where the three arrays
    hold the root as above, -2 where a certified cell is left to :func:`newton`; elsewhere
    they are not set), and a fifth, those cells ``(tosses, lo, hi, F(lo), F'(lo), F(hi),
    F'(hi), constants)`` or None.  A cell ``[t1, t2]`` with
    ``F > 0`` certified before ``t1`` and ``F(t2)`` below zero beyond rounding (or certified
    decreasing through zero) holds the first root, as the refinement would find it; when
    ``sin(alpha/2)`` over the whole cell lies inside one outcome's band (by its values at the
    ends, and 0 or ``sin psi`` where the cell crosses a multiple of ``pi/2`` in ``x``), with a
    margin of ``1e-9``, far beyond the rounding of ``alpha_f``, that is the outcome.

    Each toss carries a front ``t`` (``F > 0`` certified on ``[0, t]``, ``F(t)`` and ``F'(t+)``
    known), a cell width ``d`` and its window's end.  A round evaluates F once a toss, at the
    end of the next cell ``[t, t + d]``, and then, toss by toss:

    - the cell holds no root (the semi-concave lower bound ``min(F1, F2) - K2 d^2/8`` is
      positive beyond rounding, or ``F`` is certified decreasing and ``F2 > 0``): the front
      moves to its end and the width grows back (times ``_ZOOM``, up to the base step);
    - ``F2 <= 0`` and ``F`` is certified decreasing (``F'(t+) + K2 d < 0``): exactly one root,
      queued for :func:`newton`;
    - otherwise the cell shrinks (``d / _ZOOM``), down to the last bits of ``t``, where a
      non-positive ``F2`` is the contact (a tangency or a corner).

    A front that reaches its window's end moves to the second window, or is the contact at
    ``t_end`` (where ``z = 0``).  One toss or ten million take the same path.
    """
    q0 = _batch(np, s, n)
    out = np.empty(n)
    osh = np.empty(n)
    och = np.empty(n)
    w1 = _flat(np, s.w1, n)
    w2s = _flat(np, s.w2s, n)
    t_end = _flat(np, s.t_end, n)
    step = _flat(np, s.step, n)
    has1 = np.broadcast_to(np.asarray(w1) >= 0, (n,))
    t = np.where(has1, 0.0, w2s)
    wend = np.where(has1, w1, t_end)
    win2 = ~has1
    base = np.minimum(step, np.maximum(wend - t, 0.0))
    d = base.copy()
    idx = np.arange(n)
    q = q0
    f, fp, sh, ch = _ff(np, t, q, thick)
    hit = f <= 0  # at a window's start (everything before it is certified): contact there
    age = np.zeros(n, dtype=np.int32)
    sh0 = sh  # |sin x| at the front
    if bands is not None:
        code = np.full(n, -1, dtype=np.int8)
        spb = _flat(np, s.sp, n)
        # |sin x| at t_end, the latest contact (a bound: the quadrant is read off the same x).
        she = abs_sin_rough(np, np.broadcast_to(q0.hom * t_end, (n,)))
    st = (t, f, fp, sh0, d, base, wend, win2, idx, age)
    if hit.any():
        out[hit], osh[hit], och[hit] = t[hit], sh[hit], ch[hit]
        keep = ~hit
        st = tuple(v[keep] for v in st)
        q = q.take(keep)
    cells = []  # certified cells: (idx, lo, hi, F(lo), F'(lo), F(hi), F'(hi))
    ends = []  # contacts at t_end (F(t_end) <= 0 by construction): indices
    for _round in range(_MAX_ROUNDS):
        t, f, fp, sh0, d, base, wend, win2, idx, age = st
        if idx.size == 0:
            break
        if bands is not None and _round and win2.any():
            # The contact lies in [t, t_end] (F > 0 is certified before the front): decided
            # when sin(alpha/2) stays in one band over all of it.
            full = idx.size == n
            k = _band_code(np, t, t_end if isinstance(t_end, float) or full else t_end[idx], sh0,
                           she if full else she[idx], q.hom,
                           spb if isinstance(spb, float) or full else spb[idx], bands)
            k[~win2] = -1
            known = k >= 0
            if known.any():
                code[idx[known]] = k[known]
                keep = np.flatnonzero(~known)
                st = tuple(v[keep] for v in st)
                q = q.take(keep)
                t, f, fp, sh0, d, base, wend, win2, idx, age = st
                if idx.size == 0:
                    break
        # The cell each toss decides on this round: [t, t + d] for a toss in its first rounds;
        # for an older one (a dip or a long window: it needs many cells) the first of _MULTI
        # cells laid from t that is not certainly free, or the last of them.  Per toss, not
        # per batch: a toss takes the same steps alone or among millions.
        old = age >= _AGE_MULTI
        if old.any():
            t1, t2, f1, fp1, f2, fp2, sh, ch, sh1, free = _multi_cells(np, t, f, fp, sh0, d,
                                                                        wend, old, q, thick)
        else:
            t1, f1, fp1, sh1 = t, f, fp, sh0
            t2 = np.minimum(t + d, wend)
            f2, fp2, sh, ch = _ff(np, t2, q, thick)
            free = None
        dd = t2 - t1
        k2d = q.k2p * dd
        mono = fp1 + k2d < -q.stol  # F' <= F'(t+) + K2 (s - t) < 0 on the cell
        pos2 = f2 > 0
        cert = mono & ~pos2
        if free is None:
            m = np.minimum(f1, f2)
            curv = k2d * dd * 0.125
            tol = q.tol0 + q.tol1 * t2
            free = (mono & pos2) | ((m > 0) & ((m - curv > tol) | (curv <= tol)))
        decided = None
        if bands is not None:
            # Outcomes certain without refinement: the cell holds the first root, and
            # sin(alpha/2) stays inside one band over it.
            cand = ~pos2 & (cert | (f2 < -4.0 * (q.tol0 + q.tol1 * t2)))
            if cand.any():
                ci = np.flatnonzero(cand)
                k = _band_code(np, t1[ci], t2[ci], sh1[ci], sh[ci],
                               q.hom if isinstance(q.hom, float) else q.hom[ci],
                               spb if isinstance(spb, float) else spb[idx[ci]], bands)
                known = k >= 0
                if known.any():
                    dec = ci[known]
                    code[idx[dec]] = k[known]
                    cert = cert.copy()
                    cert[dec] = False
                    decided = np.zeros(cert.shape, dtype=bool)
                    decided[dec] = True
                    if (cert | decided).all():
                        if cert.any():
                            ci = np.flatnonzero(cert)
                            cells.append((idx[ci], t1[ci], t2[ci], f1[ci], fp1[ci], f2[ci],
                                          fp2[ci]))
                        break
        done = cert if decided is None else cert | decided
        if cert.all():
            cells.append((idx, t1, t2, f1, fp1, f2, fp2))
            break
        if cert.any():
            ci = np.flatnonzero(cert)
            cells.append((idx[ci], t1[ci], t2[ci], f1[ci], fp1[ci], f2[ci], fp2[ci]))
        rest = ~(cert | free) if decided is None else ~(cert | free | decided)
        move = free
        if rest.any():
            tiny = rest & (dd <= 4 * EPS * t2)
            hit = tiny & ~pos2  # a root at the last bit of t: a tangency or a corner
            if hit.any():
                g = idx[hit]
                out[g], osh[g], och[g] = t2[hit], sh[hit], ch[hit]
                done = done | hit
            move = free | (tiny & pos2)  # (a positive tiny cell: noise; cannot happen, be safe)
            zoom = rest & ~tiny  # the front moves to the cell's start, the cell shrinks
            t = np.where(zoom, t1, t)
            f = np.where(zoom, f1, f)
            fp = np.where(zoom, fp1, fp)
            sh0 = np.where(zoom, sh1, sh0)
            d = np.where(zoom, dd / _ZOOM, d)
        t = np.where(move, t2, t)
        f = np.where(move, f2, f)
        fp = np.where(move, fp2, fp)
        sh0 = np.where(move, sh, sh0)
        d = np.where(move, np.minimum(dd * _ZOOM, base), d)
        age = age + 1
        ended = move & (t >= wend)
        if ended.any():
            # F(t_end) = -L <= 0 up to rounding: contact at t_end at the latest.
            last = ended & win2
            ends.append(idx[last])
            done = done | last
            nxt = np.flatnonzero(ended & ~win2)  # on to the second window
            if nxt.size:
                g = idx[nxt]
                t0 = np.broadcast_to(w2s if isinstance(w2s, float) else w2s[g], nxt.shape)
                te = t_end if isinstance(t_end, float) else t_end[g]
                t[nxt] = t0
                wend[nxt] = te
                win2[nxt] = True
                base[nxt] = np.minimum(step if isinstance(step, float) else step[g],
                                       np.maximum(te - t0, 0.0))
                d[nxt] = base[nxt]
                age[nxt] = 0
                fn, fpn, shn, chn = _ff(np, t[nxt], q.take(nxt, Batch.FIELDS), thick)
                f[nxt], fp[nxt], sh0[nxt] = fn, fpn, shn
                at = fn <= 0
                ga = g[at]
                out[ga], osh[ga], och[ga] = t0[at], shn[at], chn[at]
                done[nxt[at]] = True
        st = (t, f, fp, sh0, d, base, wend, win2, idx, age)
        if done.any():
            keep = np.flatnonzero(~done)  # gathers then cost what is kept
            st = tuple(v[keep] for v in st)
            q = q.take(keep)
    else:
        # A toss whose F dips within its rounding band (tol0 + tol1 t, the phase omega t known
        # to eps omega t) for more cells than the scan can lay: a thick coin of xi 1e4 spun at
        # 1e10 rad/s first touches, a turn after another, a hair from where the rounding allows
        # any first contact.  Its outcome is not determined in double precision.
        k = int(st[8][0])
        om_k = float(np.broadcast_to(s.om, (n,))[k])
        raise ValueError(f"this toss cannot be followed in double precision: at omega = "
                         f"{om_k:g} rad/s its first contact hides within the rounding of the "
                         f"phase omega * t through {_MAX_ROUNDS} rounds of the scan; "
                         "lower omega (or xi, for a thick coin)")
    if ends:
        g = np.concatenate(ends)
        te = np.broadcast_to(t_end, (n,))[g]
        out[g] = te
        _, _, osh[g], och[g] = _ff(np, te, q0.take(g, Batch.FIELDS), thick)
    if cells:
        if len(cells) == 1:
            gi, lo, hi, flo, fplo, fhi, fphi = cells[0]
        else:
            gi, lo, hi, flo, fplo, fhi, fphi = (np.concatenate([c[i] for c in cells])
                                                for i in range(7))
        if bands is not None:
            # Outcomes only: the single root of each certified cell is bracketed around the
            # Hermite estimate by two evaluations, and decided where that narrow bracket lies in
            # one band; the rest are refined.
            k, ok = _bracket_code(np, gi, lo, hi, flo, fplo, fhi, fphi, q0, spb, bands, thick)
            code[gi[ok]] = k[ok]
            rest = np.flatnonzero(~ok)
            gi, lo, hi, flo, fplo, fhi, fphi = (v[rest] for v in (gi, lo, hi, flo, fplo, fhi,
                                                                  fphi))
    if cells and gi.size:
        in_order = gi.size == n and bool((gi[1:] > gi[:-1]).all())  # all, as in q0
        qn = q0 if in_order else q0.take(gi, Batch.FIELDS)
        if bands is not None:  # refined by the caller, with those of other batches
            code[gi] = -2
            return out, osh, och, code, (gi, lo, hi, flo, fplo, fhi, fphi, qn)
        out[gi], osh[gi], och[gi] = newton(np, lo, hi, flo, fplo, fhi, fphi, qn, thick)
    if bands is not None:
        return out, osh, och, code, None
    return out, osh, och


def _bracket_code(np, gi, lo, hi, flo, fplo, fhi, fphi, q0, sp, bands, thick):
    """For certified cells ``[lo, hi]`` (one root, F decreasing) of the tosses ``gi``: the
    outcome codes decided by a narrow bracket ``[a, b]`` around the Hermite estimate of the
    root (a hundredth of the cell each side), and where they are decided.

    The root is in ``[a, b]`` where ``F(a) > 16 tol`` (or ``a = lo``) and ``F(b) < -16 tol``
    (or ``b = hi``): far beyond F's rounding, so the refinement's root, whose F is within its
    rounding of zero, is there too; then :func:`_band_code` on ``[a, b]``."""
    x0 = _hermite_start(np, lo, hi, flo, fplo, fhi, fphi)
    dl = 0.01 * (hi - lo)
    a = np.maximum(x0 - dl, lo)
    b = np.minimum(x0 + dl, hi)
    k = gi.size
    g2 = np.concatenate([gi, gi])
    q2 = q0.take(g2, Batch.FIELDS + ("tol0", "tol1"))
    t2 = np.concatenate([a, b])
    f, _, sh, _ = _ff(np, t2, q2, thick)
    tol = q2.tol0 + q2.tol1 * t2
    inside = ((a == lo) | (f[:k] > 16.0 * tol[:k])) & ((b == hi) | (f[k:] < -16.0 * tol[k:]))
    hom = q2.hom if isinstance(q2.hom, float) else q2.hom[:k]
    code = _band_code(np, a, b, sh[:k], sh[k:], hom, sp if isinstance(sp, float) else sp[gi],
                      bands)
    return code, inside & (code >= 0)


def _band_code(np, t1, t2, sh1, sh2, hom, sp, bands):
    """The outcome code where ``sin(alpha/2)`` over ``[t1, t2]`` (``x = hom t`` spanning at most
    one multiple of ``pi/2``; ``|sin x|`` at the ends ``sh1``, ``sh2``) lies inside one band of
    ``bands = (sin(theta0/2), cos(theta0/2))`` by more than ``1e-9``, else -1.

    ``sin(alpha/2) = sin psi |sin x|`` is monotone between multiples of ``pi/2``; across an
    even one it reaches 0, across an odd one ``sin psi``.  The ends' ``x`` are those :func:`_ff`
    evaluated, so the quadrants agree with ``sh1``, ``sh2`` (a quadrant misread by rounding
    leaves the value within an ulp of the extreme, inside the margin).  Phases beyond ``1e5``
    are left to the refinement (their rounding nears the margin)."""
    c = 2.0 / math.pi
    j1 = np.floor(hom * t1 * c)
    j2 = np.floor(hom * t2 * c)
    lo = np.minimum(sh1, sh2)
    hi = np.maximum(sh1, sh2)
    cross = np.flatnonzero(j2 != j1)
    if cross.size:  # (about one cell in eight)
        jc = j2[cross]
        even = 0.5 * jc == np.floor(0.5 * jc)
        lo[cross[even]] = 0.0
        hi[cross[~even]] = 1.0
    lo *= sp
    hi *= sp
    sb, cb = bands
    m = 1e-9
    # The band index of each end: 0 heads, 1 sides, 2 tails; the cell is decided where they agree.
    k = (lo > sb + m).view(np.int8) + (lo > cb + m).view(np.int8)
    kh = (hi >= sb - m).view(np.int8) + (hi >= cb - m).view(np.int8)
    k[k != kh] = -1
    if cross.size:
        k[cross[j2[cross] - j1[cross] > 1]] = -1  # (cannot happen: cells are pi/16 of x)
    if not float(hom * t2.max() if isinstance(hom, float) else (hom * t2).max()) < 1e5:
        k[hom * t2 >= 1e5] = -1
    return k


def _multi_cells(np, t, f, fp, sh0, d, wend, old, q, thick):
    """The cell each toss decides on this round (see :func:`first_root`): for the tosses
    ``old``, up to :data:`_MULTI` cells of width ``d`` laid from ``t`` (one evaluation each, all
    at once) and the first that is not certainly free, or the last; for the others ``[t, t +
    d]``.  ``sh0`` is ``|sin x|`` at ``t``.  Returns the cell's ends with F, F' there, sin/cos
    at its end, ``|sin x|`` at its start, and whether it is free."""
    n = t.size
    young = np.flatnonzero(~old)
    olds = np.flatnonzero(old)
    t1, f1, fp1, sh1 = t.copy(), f.copy(), fp.copy(), sh0.copy()
    t2 = np.empty(n)
    f2, fp2, sh, ch = (np.empty(n) for _ in range(4))
    free = np.empty(n, dtype=bool)
    if young.size:
        qy = q.take(young)
        ty = np.minimum(t[young] + d[young], wend[young])
        t2[young] = ty
        f2[young], fp2[young], sh[young], ch[young] = _ff(np, ty, qy, thick)
        dd = ty - t[young]
        k2d = qy.k2p * dd
        mono = fp[young] + k2d < -qy.stol
        m = np.minimum(f[young], f2[young])
        curv = k2d * dd * 0.125
        tol = qy.tol0 + qy.tol1 * ty
        free[young] = (mono & (f2[young] > 0)) | ((m > 0) & ((m - curv > tol) | (curv <= tol)))
    k = olds.size
    qo = q.take(olds)
    rep = np.repeat(np.arange(k), _MULTI)
    qr = qo.take(rep)
    j = np.arange(1, _MULTI + 1, dtype=float)
    to = t[olds]
    tt = np.minimum(to[:, None] + d[olds][:, None] * j, wend[olds][:, None])  # (k, _MULTI)
    ff, ffp, fsh, fch = (v.reshape(k, _MULTI) for v in _ff(np, tt.ravel(), qr, thick))
    ta = np.concatenate([to[:, None], tt[:, :-1]], axis=1)  # the cells' starts
    fa = np.concatenate([f[olds][:, None], ff[:, :-1]], axis=1)
    fpa = np.concatenate([fp[olds][:, None], ffp[:, :-1]], axis=1)
    sha = np.concatenate([sh0[olds][:, None], fsh[:, :-1]], axis=1)
    dd = tt - ta

    def col(v):
        return v if isinstance(v, float) else v[:, None]

    k2d = col(qo.k2p) * dd
    mono = fpa + k2d < -col(qo.stol)
    m = np.minimum(fa, ff)
    curv = k2d * dd * 0.125
    tol = col(qo.tol0) + col(qo.tol1) * tt
    fr = (mono & (ff > 0)) | ((m > 0) & ((m - curv > tol) | (curv <= tol)))
    allfree = fr.all(axis=1)
    jc = np.where(allfree, _MULTI - 1, np.argmax(~fr, axis=1))  # the cell decided on
    r = np.arange(k)
    t1[olds], f1[olds], fp1[olds], sh1[olds] = ta[r, jc], fa[r, jc], fpa[r, jc], sha[r, jc]
    t2[olds], f2[olds], fp2[olds] = tt[r, jc], ff[r, jc], ffp[r, jc]
    sh[olds], ch[olds] = fsh[r, jc], fch[r, jc]
    free[olds] = fr[r, jc]
    return t1, t2, f1, fp1, f2, fp2, sh, ch, sh1, free


def _hermite_start(np, lo, hi, flo, fplo, fhi, fphi):
    """The root of the cubic Hermite interpolant of F, F' at the ends of ``[lo, hi]`` (from the
    root of the quadratic through ``F(lo), F'(lo), F(hi)``, a Newton step on the cubic), in the
    bracket: :func:`newton`'s start."""
    h = hi - lo
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        m1 = fplo * h  # slopes and coefficients in s = (t - lo) / h
        df = fhi - flo
        c2 = df - m1  # the quadratic's
        sv = 2.0 * flo / (np.sqrt(np.maximum(m1 * m1 - 4.0 * c2 * flo, 0.0)) - m1)
        m2 = fphi * h
        c3 = m1 + m2 - 2.0 * df  # the cubic's: flo + m1 s + c2 s^2 + c3 s^3
        c2 = 3.0 * df - 2.0 * m1 - m2
        p = flo + sv * (m1 + sv * (c2 + sv * c3))
        dp = m1 + sv * (2.0 * c2 + 3.0 * c3 * sv)
        sn = sv - p / dp
        sv = np.where((sn >= 0) & (sn <= 1), sn, sv)
        x = lo + sv * h
    x = np.where(np.isfinite(x), np.clip(x, lo, hi), hi)
    x[fhi == 0] = hi[fhi == 0]
    return x


def newton(np, lo, hi, flo, fplo, fhi, fphi, q, thick):
    """The single root of a decreasing F in each ``[lo, hi]`` (``F(lo) > 0 >= F(hi)``), with
    ``|sin x|`` and ``cos x'`` there (as :func:`_ff`).

    The start is the root of the cubic Hermite interpolant of F and F' at the ends (from the
    root of the quadratic through ``F(lo), F'(lo), F(hi)``, a Newton step on the cubic; no
    evaluation of F).  Then Newton's method on F, bisecting whenever a step would leave the
    bracket, until F is zero, a step is below the last two bits of ``t`` or the bracket is four
    ulps wide.  (The first step is taken without a test: it hardly ever converges.)  The sine
    and cosine of the last evaluation are carried to the root by a rotation through the last
    (sub-ulp) step.
    """
    x = _hermite_start(np, lo, hi, flo, fplo, fhi, fphi)
    # The first step, for all.
    f, fp, _, _ = _ff(np, x, q, thick)
    pos = f > 0
    lo = np.where(pos, x, lo)
    hi = np.where(pos, hi, x)
    with np.errstate(divide="ignore", invalid="ignore"):
        xn = x - f / fp
    ok = (xn >= lo) & (xn <= hi) & (fp < 0)  # (at lo or hi: the loop sees it converge)
    xp, fpp = x, fp  # the last point and slope, for the curvature of the convergence test
    x = np.where(f == 0, x, np.where(ok, xn, lo + 0.5 * (hi - lo)))  # F(x) = 0: the root
    n = x.size
    out = np.empty(n)
    osh = np.empty(n)
    och = np.empty(n)
    g = np.arange(n)
    qa = q
    for _ in range(200):
        if g.size == 0:
            break
        f, fp, sa, ca = _ff(np, x, qa, thick)
        pos = f > 0
        lo = np.where(pos, x, lo)
        hi = np.where(pos, hi, x)
        with np.errstate(divide="ignore", invalid="ignore"):
            step = f / fp
        xn = x - step
        down = fp < 0
        ok = (xn >= lo) & (xn <= hi) & down
        # Converged: F is zero, a Newton step below the last bits of t or so small that the
        # point it reaches is exact (Newton's error after a step s is F'' s^2 / (2 F'), with
        # F'' measured between the last two points, which are within 1e-6 of each other), or
        # a bracket four ulps wide.
        zero = f == 0
        ast = np.abs(step)
        with np.errstate(divide="ignore", invalid="ignore"):
            curv = np.abs((fp - fpp) / (x - xp))
        e = ast * (qa.hom if isinstance(qa.hom, float) else qa.hom)  # the phase it turns
        near = (ast <= 1e-6 * x) & (np.abs(x - xp) <= 1e-6 * x) & (e <= 1e-4)
        conv = zero | (ok & ((ast <= 2 * EPS * x) | (near & (curv * ast * ast <= 0.5 * EPS
                                                               * x * np.abs(fp))))) | (
            hi - lo <= 4 * EPS * hi)
        stay = zero | (conv & ~ok)
        # Not converged: Newton strictly inside the bracket (so that it always shrinks), else
        # bisection.
        inner = conv | ((xn > lo) & (xn < hi) & down)
        xnext = np.where(stay, x, np.where(inner, xn, lo + 0.5 * (hi - lo)))
        if conv.any():
            # The sine and cosine of x' at the root: at x, turned by e = omega (xnext - x) / 2
            # (|e| is below ~1e-15: sin e = e, cos e = 1 to the last bit).
            ci = np.flatnonzero(conv)
            cg = g[ci]
            xc = xnext[ci]
            e = (xc - x[ci]) * (qa.hom if isinstance(qa.hom, float) else qa.hom[ci])
            e2 = e * e
            se = e - e * e2 / 6.0  # |e| <= 1e-4: to the last bit
            ce = 1.0 - 0.5 * e2
            sc, cc = sa[ci], ca[ci]
            out[cg] = xc
            osh[cg] = np.abs(sc * ce + cc * se)
            och[cg] = cc * ce - sc * se
            keep = np.flatnonzero(~conv)
            xp, fpp = x[keep], fp[keep]
            x, lo, hi, g = xnext[keep], lo[keep], hi[keep], g[keep]
            qa = qa.take(keep)
        else:
            xp, fpp = x, fp
            x = xnext
    else:  # pragma: no cover - the bracket halves at least every other step
        raise RuntimeError("the root refinement did not converge")
    return out, osh, och
