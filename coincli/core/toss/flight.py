r"""Real tosses: time of flight, outcome, many tosses and phase-space maps (Sec. II, Fig. 3).

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
    :func:`toss_many` runs the three steps on numpy arrays, one evaluation of ``F`` and ``F'``
    a toss a round, dropping tosses as they finish; certified cells are refined together.
    :func:`toss` and :func:`flight_time` are a batch of one: the same code, the same bits, no
    scipy.  ``sin`` and ``cos`` of the half phase are fdlibm's polynomials after a Cody-Waite
    reduction (``omega t / 2 < 1.5e6``; numpy's beyond), within two ulps.  Against an
    independent 40-digit reference (tests/test_toss_mpmath.py) ``t_f`` is within 4 ulps plus
    the time ``F`` takes to cross its rounding band; ordinary tosses run at several million a
    second (``benchmarks/toss_bench.py``, docs/performance.md).

Outcomes only
    :func:`simulate` needs outcomes, not times of flight, and :func:`_outcomes` reads each off
    the first proof that settles it; the outcome is :func:`toss_many`'s, toss by toss
    (tests/test_toss.py compares them on seeded hand and ordinary tosses, at the side boundary,
    on other coins and planets, and end to end).

    - Rim contact (:func:`_descent_outcomes`): a rim touching at ``t_f`` has ``a sin alpha_f =
      z(t_f)``, so it lands on its side exactly when it touches while its centre is above ``c =
      a sin theta0``, before ``Tc``, when the centre falls through ``c``.  The coin's tilt just
      before ``Tc`` inside the side band (``a sin alpha > z``: it has touched) proves sides; a
      tilt kept out of the side band from ``w2s`` to just after ``Tc`` (``a sin alpha < z``
      throughout: no contact yet, and none on the side after) proves the face down then.  Both
      from ``sin(alpha/2) = sin psi |sin x|`` (``x = omega t / 2``), monotone between multiples
      of ``pi/2`` in ``x``, at the ends of ``[w2s, Tc]``: some 90 array operations a toss on
      reused scratch, no root finding (95% of hand tosses, 99% of ordinary ones).  The rest,
      whose coin tilted through its side band on the way down, are settled by ``F`` sampled at
      four points of ``[w2s, Tc]`` and just beyond, with the semi-concave bound between them
      (``F < -M`` at a sample above ``c``: sides; ``F > M`` up to a sample below ``c``: the
      face), then at 46 points closing in on ``Tc``.  Every bound carries ``M``, over a
      hundred times the scan's rounding band ``tol``: the scan can neither step over a dip
      deeper than ``M`` nor stop where ``F > M``, so a proof at ``M`` is a proof about the
      scan's own root, grazing contacts included.  Hardly a toss goes on (none of 2^21 hand
      or ordinary tosses; those outside the bounds' limits do: very fast spins or throws,
      ``u < 0.6 m/s``).
    - Thick contact: ``sin(alpha/2)`` over the contact window ``[w2s, t_end]`` inside one
      outcome's band (by ``1e-9``) decides it (:func:`_window_outcomes`).
    - What is left of either goes to the scan of :func:`toss_many`, cell for cell, which stops
      as soon as ``[front, t_end]``, a certified cell or a bracket of two evaluations around
      the cell's Hermite estimate of the root lies in one band; the rest are refined.

Nothing here prints or exits; bad input raises :class:`ValueError` naming the argument and its
allowed range.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable, Iterator

from coincli.core.models import Outcome, conditional

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
    "Toss",
    "Tosses",
    "Boundary",
    "PhaseMap",
    "Dist",
    "Frequency",
    "Simulation",
    "HAND_TOSS",
    "HAND_TOSS_TEXT",
    "default_z0",
    "lowest_point",
    "alpha_at",
    "classify",
    "flight_time",
    "flight_limits",
    "check_toss",
    "toss",
    "toss_many",
    "hyperbolae",
    "phase_map",
    "parse_dist",
    "as_dist",
    "sample_conditions",
    "simulate_chunks",
    "simulate",
    "wilson_interval",
    "vigorous_limit",
]

DEFAULT_DIAMETER = 0.02426  #: m, a US quarter (the paper's coin)
STANDARD_G = 9.81  #: m/s^2
CONTACTS = ("rim", "thick")
HEADS, SIDES, TAILS = 0, 1, 2  #: outcome codes
NAMES = ("heads", "sides", "tails")
LETTERS = ("H", "S", "T")
MAX_PHASE = 1e12  #: rad; omega * t_end beyond this is refused (the phase would be noise)
MAX_TOSSES = 10**8  #: the most tosses one simulate run makes (~20 s of hand tosses)
U_MAX = 1e8  #: m/s, the largest launch speed accepted

_TWO_PI = 2.0 * math.pi
_EPS = 2.220446049250313e-16
_SQRT3_2 = math.sqrt(3.0) / 2.0
_CELLS_PER_TURN = 16  # scan step: a sixteenth of a precession period
_ZOOM = 8  # refinement factor of the vectorized scan
_CHUNK = 1 << 16  # tosses drawn at once by simulate (this fixes its random stream)
_BATCH = 1 << 13  # tosses refined together: arrays of 64 kB stay in cache (1.5 to 2x the speed of 2^16)


# --------------------------------------------------------------------------- records

_NEW_LIST = object()  #: a record field's default: a new empty list for each instance


def _record(frozen=False, skip_compare=()):
    """A light dataclass: ``__init__`` (fields by position or name, defaults), ``repr``,
    ``==`` (and ``hash`` when frozen) from the class's annotated fields.  Decorating costs a few
    microseconds, where the dataclasses module costs most of a millisecond of start-up a
    class."""

    def wrap(cls):
        names = tuple(cls.__dict__.get("__annotations__", {}))
        defaults = {}
        for k in names:
            if k in cls.__dict__:
                defaults[k] = cls.__dict__[k]
                delattr(cls, k)
        cls._fields, cls._defaults = names, defaults
        cls._compared = tuple(k for k in names if k not in skip_compare)
        cls.__init__, cls.__repr__, cls.__eq__ = _rec_init, _rec_repr, _rec_eq
        if frozen:
            cls.__setattr__ = _rec_frozen
            cls.__delattr__ = _rec_frozen
            cls.__hash__ = _rec_hash
        else:
            cls.__hash__ = None
        return cls

    return wrap


def _rec_init(self, *args, **kwargs):
    names = self._fields
    if len(args) > len(names):
        raise TypeError(f"{type(self).__name__}() takes at most {len(names)} arguments")
    values = dict(zip(names, args))
    for k, v in kwargs.items():
        if k not in names or k in values:
            raise TypeError(f"{type(self).__name__}() got an unexpected or repeated argument "
                            f"{k!r}")
        values[k] = v
    for k in names:
        if k not in values:
            if k not in self._defaults:
                raise TypeError(f"{type(self).__name__}() missing argument {k!r}")
            d = self._defaults[k]
            values[k] = [] if d is _NEW_LIST else d
        object.__setattr__(self, k, values[k])


def _rec_repr(self):
    inner = ", ".join(f"{k}={getattr(self, k)!r}" for k in self._fields)
    return f"{type(self).__name__}({inner})"


def _rec_eq(self, other):
    if other.__class__ is not self.__class__:
        return NotImplemented
    return all(getattr(self, k) == getattr(other, k) for k in self._compared)


def _rec_hash(self):
    return hash(tuple(getattr(self, k) for k in self._compared))


def _rec_frozen(self, *args):
    raise AttributeError(f"{type(self).__name__} is frozen: its fields cannot be changed")


# --------------------------------------------------------------------------- validation


def _range_text(lo, hi, lo_open, hi_open, unit, allow_inf=False):
    u = f" {unit}" if unit else ""
    if hi == math.inf:
        return f"{'>' if lo_open else '>='} {lo:g}{u}" + ("" if allow_inf else " (finite)")
    hi_s = "pi" if hi == math.pi else f"{hi:g}"
    return f"in {'(' if lo_open else '['}{lo:g}, {hi_s}{')' if hi_open else ']'}{u}"


def _check(name, value, lo, hi=math.inf, *, lo_open=False, hi_open=False, unit="",
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


def _normal_mass(a, b):
    """``Phi(b) - Phi(a)`` for the standard normal, from ``erfc`` on the side where it does not
    cancel (the statistics module would cost 3 ms of start-up)."""
    r2 = math.sqrt(2.0)
    if a >= 0:
        return 0.5 * (math.erfc(a / r2) - math.erfc(b / r2))
    if b <= 0:
        return 0.5 * (math.erfc(-b / r2) - math.erfc(-a / r2))
    return 1.0 - 0.5 * (math.erfc(b / r2) + math.erfc(-a / r2))




def _check_contact(contact):
    if contact not in CONTACTS:
        raise ValueError(f"contact must be 'rim' or 'thick', got {contact!r}")
    return contact == "thick"


def _check_all(xi, psi, u, omega, diameter, g, contact):
    thick = _check_contact(contact)
    xi = _check("xi", xi, 0.0, 1e100, allow_inf=not thick) if thick else _check(
        "xi", xi, 0.0, allow_inf=True)
    psi = _check("psi", psi, 0.0, math.pi, unit="rad")
    u = _check("u", u, 0.0, U_MAX, unit="m/s")
    omega = _check("omega", omega, 0.0, unit="rad/s")
    diameter = _check("diameter", diameter, 0.0, 1e100, lo_open=True, unit="m")
    g = _check("g", g, 0.0, 1e100, lo_open=True, unit="m/s^2")
    return xi, psi, u, omega, diameter, g, thick


# --------------------------------------------------------------------------- geometry


def default_z0(xi, diameter=DEFAULT_DIAMETER, contact="rim"):
    """Launch height of the centre: ``(sqrt 3 / 2) a`` (eq. 5), plus ``h / 2`` for thick contact."""
    thick = _check_contact(contact)
    a = diameter / 2
    return _SQRT3_2 * a + (xi * diameter / 2 if thick else 0.0)


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
    thick = _check_contact(contact)
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
    xi = _check("xi", xi, 0.0, allow_inf=True)
    if isinstance(alpha_f, (int, float)) and isinstance(xi, float):
        t0, t1 = math.atan2(1.0, xi), math.atan2(1.0, -xi)
        return HEADS if alpha_f <= t0 else (SIDES if alpha_f <= t1 else TAILS)
    import numpy as np

    a = np.asarray(alpha_f, dtype=float)
    t0, t1 = np.arctan2(1.0, xi), np.arctan2(1.0, -np.asarray(xi))
    return np.where(a <= t0, HEADS, np.where(a <= t1, SIDES, TAILS)).astype(np.int8)


@_record()
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


def _setup(xp, xi, psi, u, om, diameter, g, thick, z0):
    """Per-toss constants; xp is ``math`` (via coincli.core._numerics.backend.M) or numpy."""
    a = diameter / 2
    hh = xi * diameter / 2 if thick else 0.0 * a
    if z0 is None:
        z0 = _SQRT3_2 * a + hh
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
    lmax = lmax * (1.0 + 8 * _EPS)  # a rounded-down bound must not shrink the window
    t_end = (u + xp.sqrt(u * u + 2.0 * g * z0)) / g
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
    tol0 = 16 * _EPS * (zscale + 2.0 * lmax)
    tol1 = 16 * _EPS * lmax * om
    stol = 16 * _EPS * (u + g * t_end + om * (a + hh) * (1.0 + om * t_end))
    step = xp.where(om > 0, _TWO_PI / (_CELLS_PER_TURN * xp.maximum(om, 1e-300)), xp.inf)
    clear = z0 - lw1 * (1.0 + 8 * _EPS) > 2.0 * (tol0 + tol1 * xp.maximum(w1, 0.0))
    w1 = xp.where(clear, -1.0, w1)
    return _Setup(om, sp, cp, a, hh, z0, u, g, t_end, lmax, w1, w2s, k2, tol0, tol1, stol, step)


def _sin_cos_psi(xp, psi):
    """``sin psi, cos psi`` for ``psi`` in ``[0, pi]``: by :func:`_half_sincos` for numpy (an
    array or one number alike, so that a toss gives the same bits alone or in a batch), by the
    math module for the scalar checks."""
    if xp is _M():
        return math.sin(psi), math.cos(psi)
    arr = xp.asarray(psi, dtype=float)
    sp, cp = _half_sincos(xp, xp.atleast_1d(arr))
    if arr.ndim == 0:
        return float(sp[0]), float(cp[0])
    return sp.reshape(arr.shape), cp.reshape(arr.shape)


def _M():
    from coincli.core._numerics.backend import M

    return M


# --------------------------------------------------------------------------- F and F'


class _Batch:
    """The root finder's per-toss constants: each a float (shared by the whole batch) or a 1-D
    float array with one value a toss.  Built from a :class:`_Setup` by :func:`_batch`.

    ``hom = omega/2``; F reads ``z0, u, hg = g/2, c2a = 2 a sin psi, cp2 = cos^2 psi,
    c2psi = cos 2 psi, hh``; F' also ``g, c1 = omega a sin psi, c3 = 2 omega (h/2) sin^2 psi``.
    """

    __slots__ = ("hom", "z0", "u", "g", "hg", "c2a", "cp2", "c2psi", "hh", "c1", "c3", "k2p",
                 "tol0", "tol1", "stol")
    _F = ("hom", "z0", "u", "g", "hg", "c2a", "cp2", "c2psi", "hh", "c1", "c3")  # what _ff reads

    def take(self, sel, names=None):
        """The constants ``names`` (default: all that are set) of the tosses ``sel`` (an index
        array or a boolean mask)."""
        out = _Batch.__new__(_Batch)
        for k in names or [k for k in _Batch.__slots__ if hasattr(self, k)]:
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
    q = _Batch.__new__(_Batch)
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


# Half-angle sine and cosine by polynomials: numpy's sin and cos are scalar loops, several times
# the cost of these array operations.  x = j pi/2 + r with j = rint(2x/pi) (Cody and Waite: pi/2
# to 33 bits, so j * _P1 is exact for j < 2^20, plus its remainder), |r| <= pi/4; sin r and cos r
# by fdlibm's kernels (errors below an ulp), the quadrant by the parity of j.  No cancellation:
# the sine is accurate relatively near x = k pi (a coin flat on its face) as numpy's is.
_P1 = 1.57079632673412561417e+00  # fdlibm pio2_1
_P1T = 6.07710050650619224932e-11  # pi/2 - _P1 (fdlibm pio2_1t)
_X_POLY = 1.5e6  # x below this uses the polynomials (j < 2^20), above it np.sin and np.cos
_KS = (1.58969099521155010221e-10, -2.50507602534068634195e-08, 2.75573137070700676789e-06,
       -1.98412698298579493134e-04, 8.33333333332248946124e-03, -1.66666666666666324348e-01)
_KC = (-1.13596475577881948265e-11, 2.08757232129817482790e-09, -2.75573143513906633035e-07,
       2.48015872894767294178e-05, -1.38888888888741095749e-03, 4.16666666666666019037e-02)


def _half_sincos(np, x):
    """``(|sin x|, cos x * sign(sin x))`` for an array ``x >= 0``: the sine and cosine of ``x``
    modulo pi, in ``[0, pi)`` (``(0, 1)`` at ``x = 0``), each within an ulp or two."""
    # (In place where the operations are the same: fewer arrays through the cache.)
    j = np.multiply(x, 2.0 / math.pi)
    np.rint(j, out=j)
    w = np.multiply(j, _P1)  # scratch
    r = np.subtract(x, w)
    np.multiply(j, _P1T, out=w)
    r -= w  # x - j pi/2, |r| <= pi/4 (+ rounding)
    z = r * r
    s = z * _KS[0]
    for k in _KS[1:]:
        s += k
        s *= z
    s *= r
    s += r  # sin r
    c = z * _KC[0]
    for k in _KC[1:]:
        c += k
        c *= z
    c *= z
    np.multiply(z, 0.5, out=w)
    c -= w
    c += 1.0  # cos r
    # j even, x = k pi + r: |sin x| = |sin r|, cos x sign(sin x) = cos r sign(r);
    # j odd, x = k pi + pi/2 + r: |sin x| = cos r, cos x sign(sin x) = -sin r.
    np.multiply(j, 0.5, out=w)
    np.floor(w, out=z)
    odd = w != z
    sh = np.abs(s)
    np.copyto(sh, c, where=odd)
    ch = np.copysign(c, s, out=c)
    np.negative(s, out=s)
    np.copyto(ch, s, where=odd)
    if x.size and not float(x.max()) < _X_POLY:  # element by element: no dependence on the batch
        big = np.flatnonzero(x >= _X_POLY)
        sb, cb = np.sin(x[big]), np.cos(x[big])
        sh[big] = np.abs(sb)
        ch[big] = np.where(sb < 0, -cb, cb)
    return sh, ch


def _ff(np, t, q: _Batch, thick):
    """``F(t)``, an upper bound of its right derivative ``F'(t+)`` (exact except at a corner),
    and ``|sin x|``, ``cos x'`` (arrays over the tosses of ``q``; ``x = omega t / 2``, ``x'`` its
    representative modulo pi in ``[0, pi)``).

    ``sin(alpha/2) = sin psi |sin x|``, ``cos(alpha/2) = sqrt(cos^2 x + cos^2 psi sin^2 x)``,
    ``cos alpha = cos^2 x + cos 2psi sin^2 x``; ``L = a sin alpha (+ (h/2)|cos alpha|)``;
    ``d alpha / d theta = sin psi cos x' / cos(alpha/2)``.  At the corners (``cos(alpha/2) = 0``,
    the coin upside down; ``cos alpha = 0`` for a thick coin) the corner's term is taken as 0,
    above the right derivative: the monotonicity certificate stays sound.
    """
    sh, ch = _half_sincos(np, q.hom * t)
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


def _alpha(np, sp, cp, sh, ch):
    """The tilt ``alpha`` from ``|sin x|``, ``cos x`` (``x`` half the precession phase), as
    :func:`alpha_at`: ``2 atan2(sin psi |sin x|, hypot(cos x, cos psi sin x))``."""
    cs = cp * sh
    return 2.0 * np.arctan2(sp * sh, np.sqrt(ch * ch + cs * cs))  # (no overflow: both <= 1)


# --------------------------------------------------------------------------- one toss


@_record(frozen=True)
class Toss:
    """One toss: time of flight, turns, final tilt and outcome."""

    t_f: float  #: s, time of flight (first contact with the catch plane z = 0)
    turns: float  #: omega t_f / (2 pi), precession turns in the air
    alpha_f: float  #: rad, tilt of the normal at contact
    theta0: float  #: rad, the static angle atan2(1, xi)
    vigor: float  #: u omega / g (>> 1 for the closed forms)
    outcome: str  #: 'heads', 'sides' or 'tails'
    code: int  #: 0, 1, 2
    z0: float  #: m, launch height of the centre
    contact: str  #: 'rim' or 'thick'


def flight_time(xi, psi, u, omega, *, diameter=DEFAULT_DIAMETER, g=STANDARD_G, contact="rim",
                z0=None):
    """Time of flight ``t_f`` (s): the smallest positive root of ``z(t) - L(alpha(t)) = 0``.

    Parameters are SI scalars: ``psi`` in radians, ``u`` in m/s, ``omega`` in rad/s,
    ``diameter`` in m.  ``z0`` overrides the launch height (see :func:`default_z0`); it must
    exceed the initial depth of the lowest point (0 for rim, ``h/2`` for thick).
    See the module docstring for the algorithm and its guarantee.
    """
    _scalar_setup(xi, psi, u, omega, diameter, g, contact, z0)
    return float(toss_many(xi, psi, u, omega, diameter=diameter, g=g, contact=contact,
                           z0=z0).t_f)


def check_toss(xi, psi, u, omega, *, diameter=DEFAULT_DIAMETER, g=STANDARD_G, contact="rim",
               z0=None):
    """Raise the ValueError :func:`toss` would raise for these numbers (out of range, or a toss
    the scan cannot follow), without tossing; return None when the toss can be made."""
    _scalar_setup(xi, psi, u, omega, diameter, g, contact, z0)


def _scalar_setup(xi, psi, u, omega, diameter, g, contact, z0):
    for name, v in (("xi", xi), ("psi", psi), ("u", u), ("omega", omega),
                    ("diameter", diameter), ("g", g)):
        if not isinstance(v, (int, float)) or isinstance(v, bool):
            raise ValueError(f"{name} must be a number, got {v!r} (use toss_many for arrays)")
    xi, psi, u, omega, diameter, g, thick = _check_all(xi, psi, u, omega, diameter, g, contact)
    z0 = _check_z0(z0, xi, diameter, thick)
    s = _setup(_M(), xi, psi, u, omega, diameter, g, thick, z0)
    problem = _problem(_M(), s)
    if problem:
        raise ValueError(_problem_message(problem, omega, u, g, s.z0, omega * s.t_end))
    return s


def _problem(xp, s: _Setup):
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


def _problem_message(problem, omega, u, g, z0, phase):
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
    thick = _check_contact(contact)
    M = _M()
    if all(isinstance(v, (int, float)) for v in (xi, psi, u, omega, diameter, g)) and (
            z0 is None or isinstance(z0, (int, float))):
        s = _setup(M, float(xi), float(psi), float(u), float(omega), float(diameter), float(g),
                   thick, None if z0 is None else float(z0))
        return s.t_end, omega * s.t_end, _problem(M, s)
    import numpy as np

    arrs = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (
        xi, psi, u, omega, diameter, g, 0.0 if z0 is None else z0)))
    with np.errstate(over="ignore", invalid="ignore"):
        s = _setup(np, *arrs[:6], thick, None if z0 is None else arrs[6])
        return s.t_end, arrs[3] * s.t_end, _problem(np, s)


def _check_z0(z0, xi, diameter, thick):
    if z0 is None:
        return None
    z0 = _check("z0", z0, 0.0, lo_open=True, unit="m")
    floor = xi * diameter / 2 if thick else 0.0
    if z0 <= floor:
        raise ValueError(f"z0 must be > h/2 = {floor:g} m for thick contact (the coin would start "
                         f"below the catch plane), got {z0!r}")
    return z0


_MAX_ROUNDS = 100_000
_AGE_MULTI = 3  #: rounds after which a toss lays several cells a round
_MULTI = 8  #: cells a round then


def _first_root(np, s: _Setup, n, thick, bands=None):
    """The first root of F for each of the ``n`` tosses of a batch (scalars or 1-D arrays in s).

    Returns ``(t_f, |sin x|, cos x')`` at the roots (``x = omega t_f / 2``, as :func:`_ff`).

    With ``bands = (sin(theta0/2), cos(theta0/2))`` (the outcome boundaries of eq. 7 in
    ``sin(alpha/2) = sin psi |sin x|``) only outcomes are wanted: a fourth array is returned,
    the outcome code of each toss decided without refining its root (-1 where the three arrays
    hold the root as above, -2 where a certified cell is left to :func:`_newton`; elsewhere
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
      queued for :func:`_newton`;
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
        she = _abs_sin_rough(np, np.broadcast_to(q0.hom * t_end, (n,)))
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
            tiny = rest & (dd <= 4 * _EPS * t2)
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
                fn, fpn, shn, chn = _ff(np, t[nxt], q.take(nxt, _Batch._F), thick)
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
        _, _, osh[g], och[g] = _ff(np, te, q0.take(g, _Batch._F), thick)
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
        qn = q0 if in_order else q0.take(gi, _Batch._F)
        if bands is not None:  # refined by the caller, with those of other batches
            code[gi] = -2
            return out, osh, och, code, (gi, lo, hi, flo, fplo, fhi, fphi, qn)
        out[gi], osh[gi], och[gi] = _newton(np, lo, hi, flo, fplo, fhi, fphi, qn, thick)
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
    q2 = q0.take(g2, _Batch._F + ("tol0", "tol1"))
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
    """The cell each toss decides on this round (see :func:`_first_root`): for the tosses
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
    bracket: :func:`_newton`'s start."""
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


def _newton(np, lo, hi, flo, fplo, fhi, fphi, q, thick):
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
        conv = zero | (ok & ((ast <= 2 * _EPS * x) | (near & (curv * ast * ast <= 0.5 * _EPS
                                                               * x * np.abs(fp))))) | (
            hi - lo <= 4 * _EPS * hi)
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


def toss(xi, psi, u, omega, *, diameter=DEFAULT_DIAMETER, g=STANDARD_G, contact="rim", z0=None):
    """Simulate one toss (SI scalars, ``psi`` in radians); return a :class:`Toss`.

    The same computation as :func:`toss_many` (one toss is a batch of one)."""
    s = _scalar_setup(xi, psi, u, omega, diameter, g, contact, z0)
    r = toss_many(xi, psi, u, omega, diameter=diameter, g=g, contact=contact, z0=z0)
    t_f, code = float(r.t_f), int(r.code)
    return Toss(
        t_f=t_f,
        turns=omega * t_f / _TWO_PI,
        alpha_f=float(r.alpha_f),
        theta0=math.atan2(1.0, float(xi)),
        vigor=u * omega / g,
        outcome=NAMES[code],
        code=code,
        z0=float(s.z0),
        contact=contact,
    )


# --------------------------------------------------------------------------- many tosses


@_record()
class Tosses:
    """Many tosses (arrays of one shape)."""

    t_f: object  #: s
    alpha_f: object  #: rad
    code: object  #: int8: 0 heads, 1 sides, 2 tails

    def counts(self):
        """(heads, sides, tails) counts."""
        import numpy as np

        c = np.bincount(np.asarray(self.code).ravel(), minlength=3)
        return int(c[0]), int(c[1]), int(c[2])


def toss_many(xi, psi, u, omega, *, diameter=DEFAULT_DIAMETER, g=STANDARD_G, contact="rim",
              z0=None):
    """Vectorized :func:`toss`: arguments broadcast (numbers or arrays); returns :class:`Tosses`.

    Same model, same certified first-root guarantee as :func:`flight_time` (which is this
    function on one toss).  Work is done in batches of 8192 tosses; arguments that are one
    number stay one number (no array of copies).
    """
    return _toss_many(xi, psi, u, omega, diameter, g, contact, z0, False)


def _outcomes(xi, psi, u, omega, *, diameter=DEFAULT_DIAMETER, g=STANDARD_G, contact="rim"):
    """The outcome codes of :func:`toss_many` (an int8 array), for one number ``xi``: the same
    codes, without refining the roots whose outcome their certified cell already decides."""
    return _toss_many(xi, psi, u, omega, diameter, g, contact, None, True)


def _toss_many(xi, psi, u, omega, diameter, g, contact, z0, outcomes_only):
    import numpy as np

    xi, psi, u, omega, diameter, g, thick = _check_all(xi, psi, u, omega, diameter, g, contact)
    if z0 is not None:
        z0 = _check("z0", z0, 0.0, lo_open=True, unit="m")
        floor = np.asarray(xi) * np.asarray(diameter) / 2 if thick else 0.0
        if np.any(np.asarray(z0) <= floor):
            raise ValueError("z0 must be > h/2 for thick contact (the coin would start below the "
                             "catch plane)")
    args = [xi, psi, u, omega, diameter, g, z0]
    shape = np.broadcast_shapes(*(np.shape(v) for v in args if v is not None))
    n = math.prod(shape)
    flat = [None if v is None else (float(np.ravel(v)[0]) if np.size(v) == 1 else
                                    np.broadcast_to(np.asarray(v, dtype=float), shape).ravel())
            for v in args]
    if outcomes_only:
        # psi, u and omega as arrays of n: the outcome engine's window and band tests index
        # them per toss (one fixed number among them raised IndexError there)
        flat[1:4] = [np.full(n, v) if isinstance(v, float) else v for v in flat[1:4]]
        return _outcomes_flat(np, flat, n, thick).reshape(shape)
    t_f = np.empty(n)
    alpha_f = np.empty(n)
    code = np.empty(n, dtype=np.int8)
    for lo in range(0, n, _BATCH):
        sl = slice(lo, min(n, lo + _BATCH))
        m = sl.stop - sl.start
        xi_c, psi_c, u_c, om_c, dia_c, g_c, z0_c = (v if v is None or isinstance(v, float)
                                                    else v[sl] for v in flat)
        s = _checked_setup(np, xi_c, psi_c, u_c, om_c, dia_c, g_c, thick, z0_c, m)
        t, sh, ch = _first_root(np, s, m, thick)
        t_f[sl] = t
        a = _alpha(np, s.sp, s.cp, sh, ch)
        alpha_f[sl] = a
        code[sl] = classify(a, xi_c)
    return Tosses(t_f.reshape(shape), alpha_f.reshape(shape), code.reshape(shape))


def _checked_setup(np, xi, psi, u, om, dia, g, thick, z0, m):
    """:func:`_setup` of a batch of ``m`` tosses, refusing the first one the scan cannot follow."""
    with np.errstate(over="ignore", invalid="ignore"):  # refused below, not warned about
        s = _setup(np, xi, psi, u, om, dia, g, thick, z0)
        problem = np.broadcast_to(_problem(np, s), (m,))
    if problem.any():
        k = int(np.argmax(problem != 0))

        def at(v, k=k):
            return float(np.broadcast_to(v, (m,))[k])

        raise ValueError(_problem_message(int(problem[k]), at(om), at(u), at(g), at(s.z0),
                                          at(om) * at(s.t_end)))
    return s


def _outcomes_flat(np, flat, n, thick):
    """The outcome codes of ``n`` tosses (``flat``: xi, psi, u, omega, diameter, g, z0 as
    :func:`_toss_many` flattens them; xi, diameter and g numbers, z0 None).

    First :func:`_descent_outcomes` (rim) or :func:`_window_outcomes` (thick) for all; then the
    undecided ones, gathered into full batches (a batch pays numpy's overhead a call, whatever
    its size), by the scan, without refining the roots whose certified cell decides them
    (:func:`_first_root` with bands).  The first toss the scan cannot follow is refused, as
    :func:`toss_many` does."""
    xi, psi, u, om, dia, g, _ = flat
    xi, dia, g = float(xi), float(dia), float(g)
    t0 = math.atan2(1.0, xi)
    bands = (math.sin(0.5 * t0), math.cos(0.5 * t0))
    if thick:
        code = np.empty(n, dtype=np.int8)
        for lo in range(0, n, _BATCH):
            sl = slice(lo, min(n, lo + _BATCH))
            code[sl] = _window_outcomes(np, *(v if isinstance(v, float) else v[sl]
                                              for v in (psi, u, om)),
                                        xi, dia, g, thick, bands, sl.stop - sl.start)
    else:
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):  # (those not ok)
            code = _descent_outcomes(np, psi, u, om, xi, dia, g, bands, n)
    rest = np.flatnonzero(code < 0)
    pending = []
    for lo in range(0, rest.size, _BATCH):
        r = rest[lo:lo + _BATCH]
        m = r.size
        psi_r, u_r, om_r = (v if isinstance(v, float) else v[r] for v in (psi, u, om))
        s = _checked_setup(np, xi, psi_r, u_r, om_r, dia, g, thick, None, m)
        _, sh, ch, k, cells = _first_root(np, s, m, thick, bands)
        und = np.flatnonzero(k == -1)
        if und.size:
            sp, cp = (v if isinstance(v, float) else v[und] for v in (s.sp, s.cp))
            k[und] = classify(_alpha(np, sp, cp, sh[und], ch[und]), xi)
        code[r] = k
        if cells is not None:
            gi = cells[0]
            pending.append((r[gi], *cells[1:], *(v if isinstance(v, float) else v[gi]
                                                  for v in (s.sp, s.cp))))
    if pending:  # the few roots to refine, all at once (numpy's overhead is per call)
        g_idx, lo, hi, flo, fplo, fhi, fphi = (np.concatenate([p[i] for p in pending])
                                               for i in range(7))
        q = _cat_batches(np, [p[7] for p in pending], [p[0].size for p in pending])
        _, sh, ch = _newton(np, lo, hi, flo, fplo, fhi, fphi, q, thick)
        sp, cp = (np.concatenate([np.broadcast_to(p[i], p[0].shape) for p in pending])
                  for i in (8, 9))
        code[g_idx] = classify(_alpha(np, sp, cp, sh, ch), xi)
    return code


def _cat_batches(np, qs, sizes):
    """The constants of several :class:`_Batch` (of :data:`_Batch._F`) end to end."""
    out = _Batch.__new__(_Batch)
    for k in _Batch._F:
        vs = [getattr(q, k) for q in qs]
        if all(isinstance(v, float) and v == vs[0] for v in vs):
            setattr(out, k, vs[0])
        else:
            setattr(out, k, np.concatenate([np.broadcast_to(v, (m,)) for v, m in zip(vs,
                                                                                     sizes)]))
    return out


# sin r for |r| <= pi/2 + 1e-11: Taylor to r^17 (the next term is below 5e-14).
_SIN_TAYLOR = tuple((-1.0) ** i / math.factorial(2 * i + 1) for i in range(9))[::-1]


def _abs_sin_rough(np, x, terms=9):
    """``|sin x|`` for ``0 <= x < 1e5`` within ``5e-11``: the reduction ``x - k pi`` by a double
    ``pi`` errs by ``k * 1.3e-16`` plus two roundings of the size of ``x`` (an ulp of ``1e5`` is
    ``1.5e-11``), the Taylor polynomial on ``[-pi/2, pi/2]`` by ``5e-14``.  For bounds (with a
    margin of ``1e-9``), not for results.  With ``terms=6`` (to ``r^11``) the polynomial errs by
    ``(pi/2)^13 / 13! < 6e-8``."""
    r = np.rint(x * (1.0 / math.pi))
    r *= -math.pi
    r += x
    z = r * r
    taylor = _SIN_TAYLOR[9 - terms:]
    p = z * taylor[0]
    for c in taylor[1:-1]:
        p += c
        p *= z
    p += 1.0
    p *= r
    return np.abs(p, out=p)


def _window_outcomes(np, psi, u, om, xi, dia, g, thick, bands, m):
    """Outcome codes (``-1`` where undecided) of the tosses whose first contact, wherever it
    falls in the window where it can happen, has one outcome: no root finding at all.

    Contact happens while the centre is below ``Lmax``: in ``[w2s, t_end]``, the descent from
    ``z = Lmax`` to ``z = 0`` (:func:`_setup`), once the launch window ``[0, w1]`` is clear
    (there ``z >= z0`` and ``L <= a min(omega t sin psi, 1) + h/2``).  Where ``Lmax`` is the
    plain ``a`` (rim; ``hypot(a, h/2)`` thick), i.e. ``psi`` lets the coin tilt far enough,
    the window needs no trigonometry.  Over it ``x = omega t / 2`` spans ``[x1, x2]``, and
    ``sin(alpha/2) = sin psi |sin x|`` lies between its values at the ends, or reaches 0 or
    ``sin psi`` where a multiple of ``pi/2`` is crossed.  When that range lies inside one band
    of eq. (7) by more than ``1e-9``, the scan's ``alpha_f`` (at a root within the window, to a
    few ulps) has that outcome.  Every bound is widened beyond the rounding of the scan's own
    ``w2s``, ``t_end``, ``w1`` (relative ``1e-12``) and of these rough sines (``5e-11``), and
    the launch window must clear by ``1e-6 z0``, far beyond any rounding of ``F``.
    """
    psi, u, om = (np.broadcast_to(np.asarray(v, dtype=float), (m,)) for v in (psi, u, om))
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):  # (those not ok)
        if not thick:
            return _descent_outcomes(np, psi, u, om, xi, dia, g, bands, m)
        return _window_codes(np, psi, u, om, xi, dia, g, thick, bands, m)


def _window_codes(np, psi, u, om, xi, dia, g, thick, bands, m):
    a = 0.5 * dia
    hh = 0.5 * xi * dia if thick else 0.0
    z0 = _SQRT3_2 * a + hh
    if thick:
        lmax = math.hypot(a, hh) * (1.0 + 8 * _EPS)
        half_width = 0.5 * math.pi - 0.5 * math.atan2(a, hh)  # |psi - pi/2| for amax >= atan2
    else:
        lmax = a * (1.0 + 8 * _EPS)
        half_width = 0.25 * math.pi
    d = lmax - z0
    u2 = u * u
    disc = u2 - 2.0 * g * d
    disc -= 1e-12 * (u2 + 2.0 * g * abs(d))  # below the scan's, whatever its rounding
    ok = disc > 0  # (else the coin never rises above Lmax: the window is the whole flight)
    root = np.sqrt(np.maximum(disc, 0.0))
    root += u
    w2s = root * ((1.0 - 1e-12) / g)
    t_end = np.sqrt(u2 + 2.0 * g * z0)
    t_end += u
    t_end *= (1.0 + 1e-12) / g
    hom = 0.5 * om
    x1 = w2s * hom
    x2 = t_end * hom
    sp = _abs_sin_rough(np, np.broadcast_to(psi, (m,)))
    ok &= np.abs(psi - 0.5 * math.pi) <= half_width - 1e-9
    ok &= (om > 0) & (x2 < 1e5)
    if d > 0:  # a launch window [0, w1], w1 = 2 d / (u + root): must be clear
        w1 = (2.0 * d * (1.0 + 1e-12)) / root
        ok &= a * np.minimum(om * w1 * (sp + 1e-10), 1.0) + hh < z0 * (1.0 - 1e-6)
    s1 = _abs_sin_rough(np, x1)
    s2 = _abs_sin_rough(np, x2)
    c = 2.0 / math.pi
    q1 = np.floor(x1 * c)
    q2 = np.floor(x2 * c)
    lo = np.minimum(s1, s2)
    hi = np.maximum(s1, s2)
    span = q2 - q1
    cross = np.flatnonzero(span > 0)
    if cross.size:
        sc, qc = span[cross], q2[cross]
        even_end = 0.5 * qc == np.floor(0.5 * qc)  # the multiple q2 pi/2 is one of pi
        lo[cross[even_end | (sc > 1)]] = 0.0
        hi[cross[~even_end | (sc > 1)]] = 1.0
    lo *= sp
    hi *= sp
    sb, cb = bands
    mg = 1e-9 + 1e-10  # the margin, plus the rough sines' error (and sin psi's)
    k = (lo > sb + mg).view(np.int8) + (lo > cb + mg).view(np.int8)
    kh = (hi >= sb - mg).view(np.int8) + (hi >= cb - mg).view(np.int8)
    k[(k != kh) | ~ok] = -1
    return k



_DESCENT_EPS = 1e-10  #: T1, T2 = Tc (1 -+ this): just before and after z = a sin theta0
_R2 = math.sqrt(0.5)  #: sin(alpha/2) at alpha = pi/2
#: Samples of F (evenly spaced, approaching Tc, about Tc) and the sine's Taylor terms, in turn,
#: for the tosses left open.
_SAMPLES = ((2, 0, (-2e-10, 2e-10), 6),
            (32, 8, (-2e-10, -2e-11, -3e-12, 3e-12, 2e-11, 2e-10), 9))
_SUB = 3900  #: tosses sampled at once (4 rows of them below 128 kB: malloc reuses, no page faults)
_DBATCH = 1 << 15  #: tosses of one pass of the bounds (scratch reused: numpy's per-call cost)
# cos r for |r| <= pi/4: Taylor to r^6 (the next term is below 3.6e-6) for _descent_batch, to
# r^8 (below 2.5e-8) for _descent_setup.
_COS3 = tuple((-1.0) ** i / math.factorial(2 * i) for i in range(4))[::-1]
_COS4 = tuple((-1.0) ** i / math.factorial(2 * i) for i in range(5))[::-1]
_SIN5 = _SIN_TAYLOR[4:]  # sin r / r to r^8, |r| <= pi/2: within (pi/2)^11 / 11! < 3.6e-6
_SIN6 = _SIN_TAYLOR[3:]  # to r^10: within (pi/2)^13 / 13! < 6e-8
_E_MAX = 1e-6  #: the most (2D + M) / 2a may be (see _descent_limits)
_W1 = 1e-5  #: S's error in _descent_batch: sines 3.6e-6, sin psi 3.6e-6, the x turned 1e-6
#: S's error in _sampled_codes by the sine's Taylor terms: 6e-8 (6) or 5e-11 (9), sin psi
#: 5e-11, x's rounding 2e-12.
_W2 = {6: 2e-7, 9: 2e-10}


def _descent_outcomes(np, psi, u, om, xi, dia, g, bands, n):
    r"""Rim contact: outcome codes (-1 where the scan must decide) of ``n`` tosses (``psi``,
    ``u``, ``om`` numbers or arrays of length ``n``), from where the coin is when its centre
    falls through the height ``c = a sin theta0``: no root finding.

    A rim touching at ``t_f`` has ``a sin alpha_f = L = z(t_f)``, so it lands on its side (eq. 7,
    ``sin alpha_f > sin theta0``) exactly when ``z(t_f) > c``: when the first contact comes
    before ``Tc``, the time ``z = c`` on the descent.  Take ``T1 < Tc < T2`` a hair apart,
    ``Tc (1 -+ 1e-10)``: ``z(T1) >= c + D/2``, ``z(T2) <= c - D/2``, both within ``2D`` of ``c``
    (``D = r Tc 1e-10``, ``r`` the speed at ``Tc``; ``Tc``'s own rounding is far below), with
    ``D`` over four times ``M = 4e-13 (u^2/g + a (3 + 6.1 x_c))``, over a hundred times the
    scan's ``tol`` at ``t_end`` (``omega t_end < 3.7 x_c``, ``x_c = omega Tc / 2``), which bounds
    both the deepest dip the scan steps over and how far ``F`` can be from zero at the root it
    returns:

    - ``F(T1) < -M``: the scan stops at or before ``T1``, where ``L = z >= c + D/2``: sides.
    - ``F > M`` over all of ``[w2s, T2]``: the scan goes beyond ``T2``, where ``L = z <= c -
      D/2``: not sides; heads or tails as the coin faces at ``T2``, for alpha cannot pass
      ``pi/2`` before contact (there ``L = a > z``).

    First (:func:`_descent_batch`) by bounds of ``sin(alpha/2)`` at ``T1`` and over ``[w2s,
    T2]`` (95% of hand tosses, 99% of ordinary ones); then (:func:`_sampled_codes`, in batches
    of :data:`_SUB`) by ``F`` sampled at 4, then 46 points from ``w2s`` to just beyond ``Tc``
    (nearly all the rest: tosses whose coin tilted through its side band on the way down, a few
    thousandths of them touching within ``1e-8`` of ``Tc``).  What is left (none of 2^21 hand
    or ordinary tosses; those outside :func:`_descent_limits`) goes to the scan.
    """
    a = 0.5 * dia
    z0 = _SQRT3_2 * a
    sb, cb = bands
    c = 2.0 * a * sb * cb  # a sin theta0
    lim = _descent_limits(a, z0, g, c, sb, cb)
    code = np.empty(n, dtype=np.int8)
    work, flags = _descent_scratch(np)
    cand = []
    for lo in range(0, n, _DBATCH):
        sl = slice(lo, min(n, lo + _DBATCH))
        k = sl.stop - sl.start
        args = (np.broadcast_to(v, (k,)) if isinstance(v, float) else v[sl] for v in (psi, u, om))
        ci = _descent_batch(np, *args, a, z0, g, lim, work[:, :k], flags[:, :k], code[sl])
        cand.append(ci + lo)
    cand = np.concatenate(cand) if cand else np.empty(0, dtype=np.intp)
    for ns, geo, tail, terms in _SAMPLES:
        left = []
        for lo in range(0, cand.size, _SUB):
            ci = cand[lo:lo + _SUB]
            p_, u_, o_ = (np.broadcast_to(v, ci.shape) if isinstance(v, float) else v[ci]
                          for v in (psi, u, om))
            kk = _sampled_codes(np, p_, u_, o_, a, z0, g, c, lim, ns, geo, tail, terms)
            code[ci] = kk
            left.append(ci[kk < 0])
        if not left:
            break
        cand = np.concatenate(left)
    return code


_SCRATCH = None  # a threading.local, once needed


def _descent_scratch(np):
    """:func:`_descent_batch`'s scratch (9 float rows and 4 bool rows of :data:`_DBATCH`), one
    per thread, kept from call to call: 2.4 MB that the kernel would otherwise map afresh (and
    fault in page by page) for every chunk of :func:`simulate_chunks`."""
    global _SCRATCH
    if _SCRATCH is None:
        import threading

        _SCRATCH = threading.local()
    s = getattr(_SCRATCH, "arrays", None)
    if s is None:
        s = _SCRATCH.arrays = (np.empty((9, _DBATCH)), np.empty((4, _DBATCH), dtype=bool))
    return s


def _descent_limits(a, z0, g, c, sb, cb):
    """The constants of :func:`_descent_outcomes`'s preconditions and thresholds (a dict).

    A toss is tried where ``x_c < 1e4``, the launch window ``[0, w1]`` is clear by ``1e-6 z0``
    (there ``z >= z0`` and ``L <= a omega t sin psi``), ``r > 0.1464 a omega`` and ``u^2`` lies
    between ``u2lo`` and ``u2hi``: above the least that rises above ``a`` (the second window
    then starts at ``w2s``, taken ``1e-12`` early, beyond the scan's rounding of its own; when
    ``psi`` keeps alpha below ``pi/2`` the scan's ``Lmax`` is lower and its ``w2s`` later),
    makes the speed at ``Tc`` ``r > 0.0481 u`` and ``r Tc > 0.1441 a`` (so ``D > 4M``: each of
    ``4M``'s three terms is below ``D/3``; and ``D`` bounds ``|z - c|`` at ``T1``, ``T2``, and
    ``omega t_end < 3.7 x_c``); below what keeps ``M < 1e-7 z0`` (far below the launch window's
    clearance) and ``e = (2D + M)/2a <= 1e-6`` (``2D <= 4 (u^2 + max(K, 0)) 1e-10 / g``, ``K =
    2g (z0 - c)``).  The bounds pass also needs ``|psi - pi/2| < pi/4`` (``sin psi >= 0.7``, a
    Taylor polynomial in ``psi - pi/2`` within ``3.6e-6``); the sampled passes take any ``psi``.

    The thresholds of ``S = sin(alpha/2)`` (``S`` known within ``W``): at ``z = c`` the band
    of eq. (7) is ``sb^2 < S^2 < cb^2``: ``L > z`` where ``(L/2a)^2 = S^2 (1 - S^2) > (z/2a)^2``,
    i.e. ``|S^2 - 1/2| < sqrt(1/4 - (z/2a)^2)``, which is ``Y0 = cos(theta0)/2`` at ``z = c``, at
    least ``sqrt(Y0^2 - e (1 + e))`` at ``z = c + 2a e`` and at most ``sqrt(Y0^2 + e)`` at ``z = c
    - 2a e`` (``c = 2a sb cb``, ``sb^2 + cb^2 = 1``)."""
    d = a * (1.0 + 8 * _EPS) - z0  # Lmax - z0 > 0
    k = 2.0 * g * (z0 - c)  # r^2 = u^2 + k
    lo = max(2.0 * g * d * (1.0 + 1e-12) / (1.0 - 1e-12),  # the coin rises above Lmax
             -k / (1.0 - 0.0481 ** 2),  # r > 0.0481 u
             0.1441 * a * g / 0.0481)  # r Tc > 0.0481 u^2 / g > 0.1441 a
    hi_m = 1.55e5 * a * g  # 4e-13 u^2 / g + 2.44e-8 a < 1e-7 z0 (x_c < 1e4)
    hi_e = (2.0 * _E_MAX * a - 2.44e-8 * a - 4.0 * _DESCENT_EPS * max(k, 0.0) / g) * g / (
        4.0 * _DESCENT_EPS + 4e-13)
    y0 = 0.5 * (cb - sb) * (cb + sb)  # cos(theta0) / 2
    e = _E_MAX
    ys = math.sqrt(max(y0 * y0 - e * (1.0 + e), 0.0))  # |S^2 - 1/2| below this: L > z at T1
    yh = math.sqrt(y0 * y0 + e)  # above this: L < z over [w2s, T2]
    sides = ((math.sqrt(0.5 - ys + 1e-12) * (1.0 + 1e-15) + _W1,
              math.sqrt(0.5 + ys - 1e-12) * (1.0 - 1e-15) - _W1) if ys > 0 else (2.0, 0.0))
    return {
        "d": d, "k": k, "u2lo": lo * (1.0 + 1e-13), "u2hi": min(hi_m, hi_e) * (1.0 - 1e-13),
        # a omega w1 sin psi < z0 (1 - 1e-6), w1 = 2 d / (u + sqrt(disc)); sin psi's error
        # (relative, at >= 0.7) within 1e-5 (_descent_batch) or 4e-8 (_descent_setup).
        "launch": 2.0 * d * (1.0 + 1e-12) * (1.0 + 1e-5) * a / (z0 * (1.0 - 1e-6)),
        # D > 4M: r Tc 1e-10 / 3 exceeds each of 4M's three terms: r > 0.0481 u and r Tc >
        # 0.1441 a (u2lo), and r > 0.1464 a omega.
        "spin": 0.1464 * a * (1.0 + 1e-12),
        "sides": sides,  # S(T1) strictly between these: sides
        "heads": math.sqrt(max(0.5 - yh - 1e-12, 0.0)) * (1.0 - 1e-15) - _W1,  # S below
        "tails": math.sqrt(0.5 + yh + 1e-12) * (1.0 + 1e-15) + _W1,  # S above
    }


def _descent_setup(np, psi, u, om, a, z0, g, lim):
    """Per toss: whether :func:`_descent_outcomes` can decide it (``ok``, see
    :func:`_descent_limits`), ``sin psi``, ``w2s`` (the scan's, or a little before), ``Tc``, ``M``.
    :func:`_descent_batch` is the same arithmetic, in place, for ``|psi - pi/2| < pi/4``; here
    ``psi`` is free (``sin psi`` within ``5e-11``: when ``psi`` keeps alpha below ``pi/2``, the
    scan's ``Lmax`` is below ``a`` and its ``w2s`` later)."""
    sp = _abs_sin_rough(np, psi)
    ok = np.ones(sp.shape, dtype=bool)
    u2 = u * u
    ok &= (u2 > lim["u2lo"]) & (u2 < lim["u2hi"])
    root = np.sqrt(np.maximum(u2 * (1.0 - 1e-12) - 2.0 * g * lim["d"] * (1.0 + 1e-12), 0.0))
    root += u
    ok &= om * (sp + 1e-10) * lim["launch"] < root
    w2s = root * ((1.0 - 1e-12) / g)
    r = np.sqrt(np.maximum(u2 + lim["k"], 0.0))
    ok &= om * lim["spin"] < r
    tc = (u + r) * (1.0 / g)
    xc = tc * (0.5 * om)
    ok &= xc < 1e4
    mm = xc * (6.1 * 4e-13 * a) + u2 * (4e-13 / g) + 3.0 * 4e-13 * a
    return ok, sp, w2s, tc, mm


def _descent_batch(np, psi, u, om, a, z0, g, lim, work, flags, code):
    """:func:`_descent_outcomes`'s first test on one batch, into ``code`` (-1 where undecided);
    returns the undecided tosses :func:`_sampled_codes` should look at.  :func:`_descent_setup`'s
    arithmetic, then ``S = sin(alpha/2) = sin psi |sin x|`` (``x = omega t / 2``) bounded at
    ``T1`` and over ``[w2s, T2]`` and compared with :func:`_descent_limits`'s thresholds; in
    place, in the scratch ``work`` (9 float rows) and ``flags`` (4 bool rows), reused from batch
    to batch (numpy then spends its time on arithmetic, not on allocating memory).

    ``S`` is monotone between multiples of ``pi/2`` in ``x``: over ``[w2s, Tc]`` it lies between
    its values at the ends, or reaches 0 or ``sin psi`` where such a multiple is crossed (as
    :func:`_window_codes`), and it moves by at most ``1e-6`` between ``Tc`` and ``T1`` or
    ``T2`` (``x_c < 1e4``)."""
    A, B, C, D, E, F, G, H, I = work
    ok, f1, f2, pk = flags
    # sin psi = cos(psi - pi/2) for |psi - pi/2| <= pi/4 (pk; the others are not decided here).
    np.subtract(psi, 0.5 * math.pi, out=A)
    np.multiply(A, A, out=B)
    np.less_equal(B, (0.25 * math.pi - 1e-9) ** 2, out=pk)
    np.multiply(B, _COS3[0], out=A)
    for k in _COS3[1:-1]:
        A += k
        A *= B
    A += 1.0  # A: sin psi
    np.multiply(u, u, out=B)  # B: u^2
    np.greater(B, lim["u2lo"], out=ok)
    np.less(B, lim["u2hi"], out=f1)
    ok &= f1
    np.multiply(B, 1.0 - 1e-12, out=C)
    C -= 2.0 * g * lim["d"] * (1.0 + 1e-12)  # below the scan's disc, whatever its rounding
    np.sqrt(C, out=C)
    C += u  # C: u + sqrt(disc) = g w2s
    np.multiply(om, A, out=D)
    D *= lim["launch"]
    np.less(D, C, out=f1)
    ok &= f1  # the launch window is clear
    np.add(B, lim["k"], out=D)
    np.sqrt(D, out=D)  # D: r, the speed at Tc
    np.multiply(om, lim["spin"], out=E)
    np.less(E, D, out=f1)
    ok &= f1  # D > 4M
    np.add(u, D, out=E)
    E *= 0.5 / g  # E: Tc / 2
    np.multiply(E, om, out=H)  # H: xc = x at Tc
    np.less(H, 1e4, out=f1)
    ok &= f1
    np.multiply(C, om, out=G)
    G *= 0.5 * (1.0 - 1e-12) / g  # G: x1 = x at w2s (a little early)
    _sin_into(np, G, B, C, E, _SIN5)  # B: |sin x1|
    _sin_into(np, H, F, C, E, _SIN5)  # F: |sin xc|
    np.multiply(G, 2.0 / math.pi, out=C)
    np.floor(C, out=C)  # C: q1
    np.multiply(H, 2.0 / math.pi, out=E)
    np.floor(E, out=E)  # E: q2
    np.minimum(B, F, out=I)  # I: lo
    np.maximum(B, F, out=D)  # D: hi
    np.greater(E, C, out=f1)
    cross = np.flatnonzero(f1)
    if cross.size:
        qc = E[cross]
        far = qc - C[cross] > 1
        even_end = 0.5 * qc == np.floor(0.5 * qc)  # the multiple q2 pi/2 is one of pi
        I[cross[even_end | far]] = 0.0
        D[cross[~even_end | far]] = 1.0
    F *= A  # S(Tc)
    I *= A  # S over [w2s, T2] from I
    D *= A  # to D
    pk &= ok
    s1, s2 = lim["sides"]
    np.greater(F, s1, out=f1)
    np.less(F, s2, out=f2)
    f1 &= f2
    f1 &= pk  # sides
    np.less(D, lim["heads"], out=f2)
    f2 &= pk  # heads
    # -1, plus 1 heads, 2 sides, 3 tails.
    np.subtract(f2.view(np.int8), 1, out=code)
    np.left_shift(f1.view(np.int8), 1, out=f2.view(np.int8))
    code += f2.view(np.int8)
    np.greater(I, lim["tails"], out=f1)
    f1 &= pk  # tails
    np.multiply(f1.view(np.int8), 3, out=f2.view(np.int8))
    code += f2.view(np.int8)
    np.less(code, 0, out=f1)
    f1 &= ok  # (psi free: _sampled_codes takes any)
    return np.flatnonzero(f1)  # for _sampled_codes


def _sin_into(np, x, out, r, z, taylor):
    """``|sin x|`` for ``0 <= x < 1e5`` into ``out`` (``r``, ``z`` scratch): as
    :func:`_abs_sin_rough`, in place, with the Taylor coefficients ``taylor`` (of ``sin r /
    r``, highest first)."""
    np.multiply(x, 1.0 / math.pi, out=r)
    np.rint(r, out=r)
    r *= -math.pi
    r += x
    np.multiply(r, r, out=z)
    np.multiply(z, taylor[0], out=out)
    for k in taylor[1:-1]:
        out += k
        out *= z
    out += 1.0
    out *= r
    np.abs(out, out=out)


def _sampled_codes(np, psi, u, om, a, z0, g, c, lim, ns, geo, tail, terms):
    """Outcome codes (-1 where undecided) of tosses the bounds on the tilt leave open
    (:func:`_descent_outcomes`), from ``F`` sampled at ``ns`` points evenly spaced from ``w2s``
    to ``Tc - h`` (``h = (Tc - w2s)/ns``), ``geo`` more approaching ``Tc`` tenfold each (``Tc -
    h/10``, ...; never closer than ``2e-10 Tc``), and at ``Tc (1 + d)`` for ``d`` in ``tail``.

    Sides where some sample has ``F < -M`` and ``z > c + 2M`` (the scan stops there or before,
    where ``L = z > c``); heads or tails where, up to some sample with ``z < c - 2M``, every gap
    between samples is free, ``min(F_i, F_i+1) - K2 h_i^2 / 8 > M`` (``F'' <= K2 <= omega^2 a
    sin psi``: the module's semi-concavity), and ``S`` there is below or above ``1/sqrt 2`` (the
    face down when the scan goes beyond).  ``S`` is known within ``_W2[terms]`` (the sines
    by :func:`_abs_sin_rough` with ``terms`` terms), so ``L = 2a S sqrt(1 - S^2)`` is bounded by
    bounding each factor; ``z`` (within ``7e-15 (u^2/g + a)``) and ``F`` within ``M``."""
    ok, sp, w2s, tc, mm = _descent_setup(np, psi, u, om, a, z0, g, lim)
    n = u.size
    h = (tc - w2s) * (1.0 / ns)
    ok &= h > 0
    # One row a sample (rows contiguous: numpy reduces across rows fast, along them slowly).
    p = np.empty((ns + geo + len(tail), n))
    np.multiply.outer(np.arange(ns, dtype=float), h, out=p[:ns])
    p[:ns] += w2s
    for j in range(geo):
        p[ns + j] = tc - np.maximum(h * 0.1 ** (j + 1), 2.0 * _DESCENT_EPS * tc)
    for j, d in enumerate(tail):
        p[ns + geo + j] = tc * (1.0 + d)
    s = _abs_sin_rough(np, p * (0.5 * om), terms)
    w = _W2[terms]
    s *= sp
    slo = np.maximum(s - w, 0.0)
    shi = s + w
    lhi = np.sqrt(np.maximum(1.0 - slo * slo, 0.0)) * shi
    llo = np.sqrt(np.maximum(1.0 - shi * shi, 0.0)) * slo
    zz = z0 + p * (u - 0.5 * g * p)
    flo = zz - lhi * (2.0 * a * (1.0 + 1e-12)) - mm
    fhi = zz - llo * (2.0 * a * (1.0 - 1e-12)) + mm
    sides = ((fhi < -mm) & (zz > c + 3.0 * mm)).any(axis=0)
    gap = p[1:] - p[:-1]
    gap *= 1.001  # (beyond the rounding of p)
    gap *= gap
    gap *= om * om * (sp + w) * (a / 8.0)  # K2 gap^2 / 8
    free = (np.minimum(flo[:-1], flo[1:]) - gap) > mm
    np.logical_and.accumulate(free, axis=0, out=free)  # free from w2s to each sample
    free &= zz[1:] < c - 3.0 * mm
    heads = (free & (s[1:] + w < _R2)).any(axis=0)
    tails = (free & (s[1:] - w > _R2)).any(axis=0)
    code = np.full(n, -1, dtype=np.int8)
    code[heads] = HEADS
    code[tails] = TAILS
    code[sides] = SIDES
    code[~ok] = -1
    return code

# --------------------------------------------------------------------------- phase space


@_record(frozen=True)
class Boundary:
    """One boundary curve ``omega(u) = phase / t_star(u)`` in the (u, omega) plane."""

    kind: str  #: 'heads|sides' or 'sides|tails'
    phase: float  #: omega t_f at the boundary: 2 n pi +- theta1 or 2 n pi +- theta2
    omega: object  #: ndarray over the u grid (nan where undefined)

    @property
    def coefficient(self):
        """``c`` in eq. (10)'s ``omega = c pi g / (2 u)``: ``phase / pi``."""
        return self.phase / math.pi


def _boundary_phases(xi, psi):
    """Phases theta1 (heads|sides) and theta2 (sides|tails) in (0, pi), or None (Table I)."""
    c0 = math.cos(math.atan2(1.0, xi))
    A, B = math.cos(psi) ** 2, math.sin(psi) ** 2
    if B == 0:
        return None, None
    x1 = (c0 - A) / B
    x2 = (-c0 - A) / B
    th1 = math.acos(x1) if -1 < x1 < 1 else None
    th2 = math.acos(x2) if -1 < x2 < 1 else None
    return th1, th2


def hyperbolae(xi, psi, u, omega_max, *, g=STANDARD_G, exact=False, diameter=DEFAULT_DIAMETER,
               contact="rim", z0=None, max_curves=4000):
    r"""The outcome boundaries of Fig. 3 as curves over the ``u`` grid.

    The boundaries are where contact happens exactly at ``alpha_f = theta0`` (heads|sides) or
    ``pi - theta0`` (sides|tails): ``omega t_f = 2 n pi +- theta1`` or ``2 n pi +- theta2``
    (``theta1``, ``theta2`` of Table I; for ``psi = pi/2`` they are ``theta0`` and
    ``pi - theta0``).  With the vigorous ``t_f = 2u/g`` this is eq. (10):

    .. math:: \omega_N = \left(2n \pm \tfrac{\theta_0}{\pi}\right)\frac{\pi g}{2u},\qquad
              \omega_N = \left(2n + 1 \pm \tfrac{\theta_0}{\pi}\right)\frac{\pi g}{2u}

    (``theta0/pi = 1/3`` for ``xi = 1/sqrt 3``).  ``exact=True`` uses instead the time at which
    the descending centre is at the contact height ``L(theta0)`` (``a sin theta0``, or
    ``hypot(a, h/2)`` for a thick coin): ``t* = (u + sqrt(u^2 + 2 g (z0 - L)))/g``.  For the fair
    coin with the paper's ``z0 = a sin theta0`` this *is* ``2u/g``: eq. (10) is then exact
    wherever that contact is the first one, i.e. for ``omega a / u`` small.

    Returns a list of :class:`Boundary`, sorted by phase, with ``omega`` over ``u`` (an array;
    NaN where ``t*`` is undefined, and at ``u = 0`` for eq. 10).  Only curves reaching below
    ``omega_max`` somewhere on the grid are returned, at most ``max_curves``.
    """
    import numpy as np

    thick = _check_contact(contact)
    xi = _check("xi", xi, 0.0, allow_inf=not thick)
    psi = _check("psi", psi, 0.0, math.pi, unit="rad")
    g = _check("g", g, 0.0, lo_open=True, unit="m/s^2")
    u = np.atleast_1d(_check("u", u, 0.0, unit="m/s"))
    omega_max = _check("omega_max", omega_max, 0.0, unit="rad/s")
    th1, th2 = _boundary_phases(xi, psi)
    with np.errstate(divide="ignore", invalid="ignore"):
        if exact:
            a = diameter / 2
            hh = xi * diameter / 2 if thick else 0.0
            zz = default_z0(xi, diameter, contact) if z0 is None else z0
            low = math.hypot(a, hh) if thick else a * math.sin(math.atan2(1.0, xi))
            rad = u * u + 2 * g * (zz - low)
            tstar = np.where(rad >= 0, (u + np.sqrt(np.maximum(rad, 0))) / g, np.nan)
        else:
            tstar = np.where(u > 0, 2 * u / g, np.nan)
    tmax = np.nanmax(tstar) if np.any(np.isfinite(tstar)) else 0.0
    phase_max = omega_max * tmax
    out = []
    for kind, th in (("heads|sides", th1), ("sides|tails", th2)):
        if th is None:
            continue
        n = 0
        while 2 * n * math.pi - th <= phase_max and len(out) < 2 * max_curves:
            for ph in (2 * n * math.pi - th, 2 * n * math.pi + th):
                if 0 < ph <= phase_max:
                    with np.errstate(divide="ignore", invalid="ignore"):
                        out.append(Boundary(kind, ph, ph / tstar))
            n += 1
    out.sort(key=lambda b: b.phase)
    return out[:max_curves]


@_record()
class PhaseMap:
    """Outcome codes on a grid of (u, omega), with the boundary curves."""

    u: object  #: (nu,) m/s, cell centres
    omega: object  #: (nw,) rad/s, cell centres
    codes: object  #: (nw, nu) int8: rows omega (ascending), columns u
    xi: float
    psi: float
    contact: str
    curves: list = _NEW_LIST  #: eq. (10) boundaries (:func:`hyperbolae`)

    def fractions(self):
        """Fractions of the grid that land heads, sides, tails."""
        import numpy as np

        c = np.bincount(np.asarray(self.codes).ravel(), minlength=3) / self.codes.size
        return Outcome(float(c[0]), float(c[1]), float(c[2]))


def phase_map(xi, psi, u_range, omega_range, shape=(200, 200), *, diameter=DEFAULT_DIAMETER,
              g=STANDARD_G, contact="rim", z0=None, exact_curves=False):
    """The pre-images of heads, sides and tails (Fig. 3) on a ``shape = (nu, nomega)`` grid.

    ``u_range = (u_lo, u_hi)`` in m/s, ``omega_range`` in rad/s; the grid samples cell centres.
    Curves are :func:`hyperbolae` over the same u grid (eq. 10 unless ``exact_curves``).
    """
    import numpy as np

    nu, nw = (int(v) for v in shape)
    if nu < 1 or nw < 1 or nu * nw > 50_000_000:
        raise ValueError(f"shape must be two positive sizes with at most 5e7 cells, got {shape!r}")
    (u0, u1), (w0, w1) = _range("u", u_range, "m/s"), _range("omega", omega_range, "rad/s")
    u = u0 + (np.arange(nu) + 0.5) * (u1 - u0) / nu
    w = w0 + (np.arange(nw) + 0.5) * (w1 - w0) / nw
    res = toss_many(xi, psi, u[None, :], w[:, None], diameter=diameter, g=g, contact=contact,
                    z0=z0)
    curves = hyperbolae(xi, psi, u, w1, g=g, exact=exact_curves, diameter=diameter,
                        contact=contact, z0=z0)
    return PhaseMap(u, w, res.code, float(xi), float(psi), contact, curves)


def _range(name, r, unit):
    try:
        lo, hi = (float(v) for v in r)
    except (TypeError, ValueError):
        raise ValueError(f"{name} range must be two numbers (low, high), got {r!r}") from None
    if not (math.isfinite(lo) and math.isfinite(hi) and 0 <= lo < hi):
        raise ValueError(f"{name} range must satisfy 0 <= low < high (finite, {unit}), "
                         f"got ({lo:g}, {hi:g})")
    return lo, hi


# --------------------------------------------------------------------------- distributions


_NUM = r"[+-]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][+-]?\d+)?"
_NUM_RE = re.compile(_NUM, re.ASCII)


@_record(frozen=True, skip_compare=("density",))
class Dist:
    """A fixed value or a distribution of one initial condition.

    ``kind`` is 'fixed' (``p1``), 'normal' (mean ``p1``, sd ``p2``, truncated to the quantity's
    allowed range ``[lo, hi]``) or 'uniform' (``[p1, p2]``).
    """

    kind: str
    p1: float
    p2: float = 0.0
    lo: float = -math.inf
    hi: float = math.inf
    density: object = None  #: for kind 'density' (psi only; not compared)

    @classmethod
    def from_density(cls, density):
        """A psi distribution from a :mod:`coincli.core.densities` density (radians on [0, pi]).

        A normal or uniform density samples exactly; any other (cosine, table) by inverting its
        CDF tabulated on 2^16 + 1 points (plus the table's own points), accurate to ~1e-9 rad.
        """
        return cls("density", math.nan, math.nan, 0.0, math.pi, density)

    def __str__(self):
        if self.kind == "fixed":
            return f"{self.p1:g}"
        if self.kind == "density":
            return str(getattr(self.density, "spec", "density"))
        return f"{self.kind}:{self.p1:g}:{self.p2:g}"

    @property
    def is_fixed(self):
        if self.kind == "density":
            return False
        return self.kind == "fixed" or (self.kind == "normal" and self.p2 == 0) or (
            self.kind == "uniform" and self.p1 == self.p2)

    def scaled(self, factor):
        """The same distribution in other units (e.g. degrees to radians): all values times
        ``factor > 0``."""
        if self.kind == "density":
            raise ValueError("a psi density is already in radians; it cannot be rescaled")
        f = float(factor)
        return Dist(self.kind, self.p1 * f, self.p2 * f, self.lo * f, self.hi * f)

    def sample(self, rng, n):
        """``n`` draws (a float for a fixed value) from a numpy Generator."""
        import numpy as np

        if self.kind == "fixed":
            return self.p1
        if self.kind == "density":
            return _sample_density(np, rng, self.density, n)
        if self.kind == "uniform":
            if self.p1 == self.p2:
                return self.p1
            return rng.uniform(self.p1, self.p2, n)
        mu, sd = self.p1, self.p2
        if sd == 0:
            return mu
        return _truncnorm(np, rng, mu, sd, self.lo, self.hi, n)

    def pdf_interval(self):
        """The support ``(low, high)`` of the distribution."""
        if self.kind == "uniform":
            return self.p1, self.p2
        if self.kind == "fixed":
            return self.p1, self.p1
        return self.lo, self.hi


def _sample_density(np, rng, density, n):
    """n draws of psi (radians) from a coincli.core.densities density."""
    name = type(density).__name__
    if name == "Uniform":
        return rng.uniform(0.0, math.pi, n)
    if name == "Normal":
        from coincli.core.estimators import normal_is_exponential, sample_psi

        if normal_is_exponential(density):  # beyond what Phi resolves: exact by its own inverse
            return sample_psi(density, rng.random(n))
        return _truncnorm(np, rng, density.mean, density.sd, 0.0, math.pi, n)
    grid = np.linspace(0.0, math.pi, (1 << 16) + 1)
    kinks = [k for k in density.kinks() if 0.0 < k < math.pi]
    if kinks:
        grid = np.union1d(grid, kinks)
    pdf = np.maximum(np.asarray(density.pdf(grid), dtype=float), 0.0)
    area = np.diff(grid) * (pdf[1:] + pdf[:-1]) / 2
    total = float(area.sum())
    if not total > 0:
        raise ValueError(f"psi density {density.spec!r} has no mass on [0, 180] degrees")
    pdf = pdf / total
    cdf = np.concatenate([[0.0], np.cumsum(area) / total])
    # The pdf is linear on each grid interval, its CDF a quadratic: invert it there exactly,
    # x = 2 r / (f0 + sqrt(f0^2 + 2 s r)) (the root that does not cancel; s = 0 gives r / f0).
    q = rng.random(n)
    k = np.clip(np.searchsorted(cdf, q, side="right") - 1, 0, grid.size - 2)
    h = grid[k + 1] - grid[k]
    with np.errstate(over="ignore", divide="ignore", invalid="ignore"):  # kinks 1e-300 apart
        f0, slope, r = pdf[k], (pdf[k + 1] - pdf[k]) / h, np.maximum(q - cdf[k], 0.0)
        den = f0 + np.sqrt(np.fmax(f0 * f0 + 2 * slope * r, 0.0))  # fmax: NaN (inf - inf) is 0
        x = np.where(den > 0, 2 * r / den, 0.5 * h)
    return np.clip(grid[k] + np.clip(x, 0.0, h), 0.0, math.pi)


def _truncnorm(np, rng, mu, sd, lo, hi, n):
    """Normal(mu, sd) truncated to [lo, hi], exact, by rejection (numpy only).

    With a mass above 0.2 the normal itself is the proposal.  Otherwise (Robert, Statistics and
    Computing 5 (1995) 121), in standard units ``[a, b]`` reflected so that ``b > 0`` and
    ``a >= 0`` unless the window straddles the mean: a uniform proposal on a window where the
    density varies by less than a factor e, else the exponential proposal of rate
    ``(a + sqrt(a^2 + 4))/2`` above ``a``, both accepted at least a third of the time.
    """
    a, b = (lo - mu) / sd, (hi - mu) / sd
    mass = _normal_mass(a, b) if math.isfinite(hi) or math.isfinite(lo) else 1.0
    out = np.empty(n)
    filled = 0
    if mass > 0.2:
        while filled < n:
            draw = rng.normal(mu, sd, max(64, int((n - filled) / mass * 1.1) + 16))
            draw = draw[(draw >= lo) & (draw <= hi)][: n - filled]
            out[filled:filled + draw.size] = draw
            filled += draw.size
        return out
    flip = b <= 0  # the window is below the mean: reflect it above
    if flip:
        a, b = -b, -a
    lo_sq = 0.0 if a < 0 else a * a  # the density's largest value is exp(-lo_sq / 2)
    uniform = a < 0 or b * b - a * a <= 2.0  # (a < 0: a narrow window around the mean)
    lam = 0.5 * (a + math.sqrt(a * a + 4.0))
    while filled < n:
        m = max(64, 2 * (n - filled) + 16)
        if uniform:
            z = rng.uniform(a, b, m)
            keep = rng.random(m) <= np.exp(0.5 * (lo_sq - z * z))
        else:
            z = a + rng.standard_exponential(m) / lam
            keep = (z <= b) & (rng.random(m) <= np.exp(-0.5 * (z - lam) ** 2))
        z = z[keep][: n - filled]
        out[filled:filled + z.size] = z
        filled += z.size
    return mu + sd * (-out if flip else out)


_KINDS = {"normal": "normal", "norm": "normal", "gauss": "normal", "uniform": "uniform",
          "unif": "uniform", "fixed": "fixed"}


def parse_dist(spec, name, lo=-math.inf, hi=math.inf, unit=""):
    """Parse ``"2.4"``, ``"fixed:2.4"``, ``"normal:MEAN:SD"`` or ``"uniform:LOW:HIGH"``.

    ``[lo, hi]`` is the quantity's allowed range (e.g. ``u >= 0``): a fixed value and a uniform
    interval must lie in it, a normal is truncated to it and must put some mass there.  No
    ``eval``; numbers are plain decimals.  Raises ValueError naming ``name``.
    """
    u = f" {unit}" if unit else ""
    form = "a number, normal:MEAN:SD or uniform:LOW:HIGH"
    if isinstance(spec, (int, float)) and not isinstance(spec, bool):
        parts = [repr(float(spec))]
        kind = "fixed"
    else:
        if not isinstance(spec, str):
            raise ValueError(f"{name} must be {form}, got {spec!r}")
        text = spec.strip()
        parts = [p.strip() for p in text.split(":")]
        if len(parts) == 1:
            kind = "fixed"
        else:
            kind = _KINDS.get(parts[0].lower())
            parts = parts[1:]
            if kind is None:
                raise ValueError(f"{name}: unknown distribution {spec!r}; expected {form}")
        want = 1 if kind == "fixed" else 2
        if len(parts) != want or not all(_NUM_RE.fullmatch(p) for p in parts):
            raise ValueError(f"{name}: cannot read {spec!r}; expected {form} "
                             "(plain decimal numbers)")
    vals = [float(p) for p in parts]
    if not all(math.isfinite(v) for v in vals):
        raise ValueError(f"{name}: numbers must be finite, got {spec!r}")
    rng = (f"[{lo:g}, {hi:g}]{u}" if math.isfinite(hi) else f">= {lo:g}{u}"
           if math.isfinite(lo) else f"finite{u}")
    if kind == "fixed":
        v = vals[0]
        if not lo <= v <= hi:
            raise ValueError(f"{name} must be {'in ' if math.isfinite(hi) else ''}{rng}, got "
                             f"{v:g}")
        return Dist("fixed", v, 0.0, lo, hi)
    if kind == "uniform":
        a, b = vals
        if not (lo <= a <= b <= hi):
            raise ValueError(f"{name}: uniform:LOW:HIGH needs LOW <= HIGH, both "
                             f"{'in ' if math.isfinite(hi) else ''}{rng}; got {spec!r}")
        return Dist("uniform", a, b, lo, hi)
    mu, sd = vals
    if sd < 0:
        raise ValueError(f"{name}: normal:MEAN:SD needs SD >= 0, got {spec!r}")
    if sd == 0:
        if not lo <= mu <= hi:
            raise ValueError(f"{name} must be {'in ' if math.isfinite(hi) else ''}{rng}, got "
                             f"{mu:g}")
        return Dist("normal", mu, 0.0, lo, hi)
    check_normal_mass(name, spec, mu, sd, lo, hi, rng)
    return Dist("normal", mu, sd, lo, hi)


def check_normal_mass(name, spec, mu, sd, lo, hi, rng):
    """Refuse a normal(mu, sd > 0) that puts at most 1e-9 of its probability in ``[lo, hi]``
    (``rng``, that range as text): a ValueError saying how much it puts there."""
    mass = _normal_mass((lo - mu) / sd, (hi - mu) / sd)
    if not mass > 1e-9:
        share = "no probability" if not mass > 0 else f"only {mass:.2g} of its probability"
        raise ValueError(f"{name}: {spec!r} puts {share} in the allowed range {rng}; at least "
                         "1e-9 is needed")


def as_dist(value, name, lo=-math.inf, hi=math.inf):
    """A :class:`Dist` from a Dist, a number, a spec string or (psi) a densities.Density."""
    if isinstance(value, Dist):
        return value
    if hasattr(value, "pdf") and hasattr(value, "kinks"):
        return Dist.from_density(value)
    return parse_dist(value, name, lo, hi)


_DOMAINS = {"u": (0.0, U_MAX), "omega": (0.0, math.inf), "psi": (0.0, math.pi)}

#: A natural hand toss: the initial conditions ``coin toss`` and ``coin simulate`` draw when
#: ``--u``, ``--omega`` or ``--psi`` is not given (SI units; normals truncated to the domain).
#:
#: - ``omega ~ normal(38, 4) rev/s``: Diaconis, Holmes and Montgomery, "Dynamical bias in the
#:   coin toss", SIAM Review 49 (2007) 211, filmed natural flips at 1000 frames a second; their
#:   coins turned at about 38 revolutions a second (omega_N, the precession rate, is the
#:   turning rate of a coin flipped about a diameter).
#: - ``u ~ normal(2.4, 0.3) m/s``: a flight of 2u/g = 0.49 s, about half a second, the time a
#:   hand-caught flip spends in the air (some 19 turns at 38 rev/s).
#: - ``psi ~ normal(90, 10) degrees``: DHM's flips were close to the Keller flip (psi = 90)
#:   but not at it; with their p(psi) = 1/2 + asin(cot^2 psi)/pi (thin coin, same side up) a
#:   normal spread of 10 degrees gives the 0.51 same-side chance they report (8.9 degrees
#:   gives the 0.508 of Bartos et al.'s 350,757 hand flips, arXiv:2310.04153).
#:
#: The spreads of u and omega are this module's choice (the films give typical values, not
#: distributions); the vigorous limit does not depend on them.
HAND_TOSS = {
    "u": Dist("normal", 2.4, 0.3, 0.0, U_MAX),
    "omega": Dist("normal", 238.7610416728243, 25.132741228718345, 0.0, math.inf),  # 38, 4 rev/s
    "psi": Dist("normal", math.pi / 2, 0.17453292519943295, 0.0, math.pi),  # 90, 10 degrees
}
#: The same, as a person would type it.
HAND_TOSS_TEXT = {"u": "normal:2.4:0.3 m/s", "omega": "normal:38:4 rev/s",
                  "psi": "normal:90:10 deg"}


def sample_conditions(n, rng, *, u, omega, psi):
    """Draw ``n`` initial conditions from a numpy Generator (or an int seed).

    ``u`` (m/s), ``omega`` (rad/s) and ``psi`` (radians) are numbers, spec strings or
    :class:`Dist`.  Normals are truncated to the allowed range (``u, omega >= 0``,
    ``0 <= psi <= pi``).  Returns a dict of arrays (floats for fixed values).  The draws are made
    in the order u, omega, psi, so a seed gives the same stream on every run.
    """
    import numpy as np

    from coincli.core._numerics.backend import numpy_random

    n = _count(n)
    npr = numpy_random()
    rng = npr.default_rng(rng) if not isinstance(rng, npr.Generator) else rng
    out = {}
    for name, val in (("u", u), ("omega", omega), ("psi", psi)):
        lo, hi = _DOMAINS[name]
        dist = as_dist(val, name, lo, hi)
        if dist.kind != "density" and (dist.lo < lo or dist.hi > hi):
            dist = Dist(dist.kind, dist.p1, dist.p2, max(dist.lo, lo), min(dist.hi, hi))
        if dist.kind in ("fixed", "uniform"):
            a, b = dist.p1, (dist.p2 if dist.kind == "uniform" else dist.p1)
            slack = 4 * _EPS * max(abs(lo), abs(hi) if math.isfinite(hi) else 0.0)
            if not (lo - slack <= a <= b <= hi + slack):
                raise ValueError(f"{name}: {dist} lies outside the allowed range "
                                 f"[{lo:g}, {hi:g}]")
        v = dist.sample(rng, n)
        # Degrees converted to radians may land an ulp beyond pi: clamp to the domain.
        out[name] = min(max(v, lo), hi) if isinstance(v, float) else np.clip(v, lo, hi)
    return out


def _count(n):
    if isinstance(n, bool) or not isinstance(n, (int,)) and not (
            isinstance(n, float) and n.is_integer()):
        raise ValueError(f"n must be a whole number >= 1, got {n!r}")
    n = int(n)
    if not 1 <= n <= MAX_TOSSES:
        raise ValueError(f"n must be a whole number from 1 to {MAX_TOSSES} (1e8), got {n}; for "
                         "more tosses, run again with another seed and add the counts")
    return n


def simulate_chunks(n, seed, *, xi, u, omega, psi, diameter=DEFAULT_DIAMETER, g=STANDARD_G,
                    contact="rim") -> Iterator:
    """Yield the outcome codes (int8 arrays) of ``n`` seeded tosses, batch by batch.

    Each batch of 65536 tosses draws its initial conditions from one
    ``numpy.random.default_rng(seed)`` (a full batch even when fewer are needed), so a seed
    always gives the same sequence of outcomes, and a shorter run is a prefix of a longer one.
    Arguments as :func:`sample_conditions`; ``xi``, ``diameter``, ``g`` are fixed numbers.
    """
    import numpy as np

    n = _count(n)
    thick = _check_contact(contact)
    xi = _check("xi", xi, 0.0, allow_inf=not thick)
    dists = {k: as_dist(v, k, *_DOMAINS[k]) for k, v in (("u", u), ("omega", omega),
                                                          ("psi", psi))}
    from coincli.core._numerics.backend import numpy_random

    rng = numpy_random().default_rng(seed)
    done = 0
    while done < n:
        m = min(_CHUNK, n - done)
        # Always draw a full batch, so that the first m tosses of a run are those of any longer
        # run with the same seed.
        c = {k: (v if isinstance(v, float) else v[:m])
             for k, v in sample_conditions(_CHUNK, rng, **dists).items()}
        code = np.broadcast_to(_outcomes(xi, c["psi"], c["u"], c["omega"], diameter=diameter,
                                         g=g, contact=contact), (m,))
        yield code
        done += m


@_record(frozen=True)
class Frequency:
    """Observed frequency of one outcome with its Wilson score interval."""

    outcome: str
    count: int
    p: float
    lo: float
    hi: float


def wilson_interval(k, n, level=0.95):
    """Wilson score interval ``(low, high)`` (floats) for ``k`` successes in ``n`` trials:
    :func:`coincli.core.stats.tests.wilson_interval`, the one implementation (no scipy at the common
    levels 0.9, 0.95, 0.99; imported from its small module, not the whole of stats)."""
    if n <= 0:
        raise ValueError(f"n must be >= 1, got {n}")
    if not 0 < level < 1:
        raise ValueError(f"level must be in (0, 1), got {level}")
    from coincli.core._numerics.wilson import wilson_interval as _wilson

    lo, hi = _wilson(k, n, level)
    return float(lo), float(hi)


@_record()
class Simulation:
    """Result of :func:`simulate`."""

    n: int
    counts: tuple
    frequencies: list  #: list of :class:`Frequency` (heads, sides, tails)
    vigorous: Outcome | None  #: closed-form prediction for the same psi distribution
    level: float = 0.95


def simulate(n, seed, *, xi, u, omega, psi, diameter=DEFAULT_DIAMETER, g=STANDARD_G,
             contact="rim", level=0.95, progress: Callable[[int], None] | None = None):
    """Toss ``n`` coins (at most :data:`MAX_TOSSES`, about 20 seconds of hand
    tosses) with seeded random initial conditions; count the outcomes.

    Returns a :class:`Simulation` with Wilson intervals and :func:`vigorous_limit` for the same
    psi distribution.  ``progress(done)`` is called after each batch.
    """
    counts = [0, 0, 0]
    import numpy as np

    done = 0
    for code in simulate_chunks(n, seed, xi=xi, u=u, omega=omega, psi=psi, diameter=diameter,
                                g=g, contact=contact):
        c = np.bincount(code, minlength=3)
        for i in range(3):
            counts[i] += int(c[i])
        done += code.size
        if progress is not None:
            progress(done)
    freqs = []
    for i in range(3):
        lo, hi = wilson_interval(counts[i], done, level)
        freqs.append(Frequency(NAMES[i], counts[i], counts[i] / done, lo, hi))
    return Simulation(done, tuple(counts), freqs, vigorous_limit(xi, psi), level)


def vigorous_limit(xi, psi):
    """The vigorous-toss chances (Table I) averaged over a psi distribution (radians).

    ``psi`` is a number, a spec string, a :class:`Dist` on [0, pi] or a density.  A fixed value
    gives :func:`coincli.core.models.conditional`; otherwise :func:`coincli.core.averages.marginal` (Gauss-
    Legendre between the regime boundaries, double precision): a normal is the density
    :class:`coincli.core.densities.Normal` truncated to [0, pi], as it is sampled, and
    ``uniform:LOW:HIGH`` the two-point table of equal weights.
    """
    dist = as_dist(psi, "psi", 0.0, math.pi)
    xi = _check("xi", xi, 0.0, allow_inf=True)
    if dist.is_fixed:
        return conditional(xi, min(max(dist.p1, 0.0), math.pi))
    from coincli.core.averages import marginal

    if dist.kind == "density":
        density = dist.density
    elif dist.kind == "uniform":
        from coincli.core.densities import Table

        density = Table([max(dist.p1, 0.0), min(dist.p2, math.pi)], [1.0, 1.0], "uniform")
    else:
        from coincli.core.densities import Normal

        density = Normal(dist.p1, dist.p2)
    # The vectorized path of marginal (one element): its scalar path gives NaN for a narrow
    # normal and a thin coin (marginal(0.05, Normal(pi/2, 10 deg))), reported; never print one.
    import numpy as np

    out = marginal(np.array([float(xi)]), density)
    return Outcome(*(float(v[0]) for v in out))
