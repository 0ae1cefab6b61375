r"""Closed-form chances of heads, sides and tails for a thick coin (Yong & Mahadevan).

Notation of the paper: a coin of diameter ``D = 2a`` and thickness ``h`` has aspect ratio
``xi = h / D``.  The diagonal from the centre to the rim makes the angle

.. math:: \theta_0 = \cos^{-1}\frac{\xi}{\sqrt{1+\xi^2}} = \operatorname{atan2}(1, \xi)

with the coin's normal.  ``psi`` is the angle between the angular momentum and the normal at
launch (the coin starts heads up).

Every function here takes Python floats or array_likes (broadcasting like a ufunc) and returns an
:class:`Outcome` of the same shape.  Python floats never touch numpy: the ``math`` module does the
work, so the closed forms stay cheap for a command-line call.  Each formula is written once, against
``xp`` (``math`` or ``numpy``; see :mod:`coincli.core._numerics.backend`).

Accuracy.  The textbook forms lose digits: ``1 - 2 theta0/pi`` for a thin coin, ``1 - theta2/pi``
when tails is rare, ``arccos`` near 1, ``sqrt(1 + xi**2)`` overflowing past 1e154.  The forms used
below are the half-angle ones; each identity is stated where it is used.  Measured errors against
mpmath are in ``docs/accuracy.md``.
"""

from __future__ import annotations

import functools
import math
from typing import NamedTuple

from coincli.core._numerics.backend import M, long_double_64, namespace

__all__ = [
    "Outcome",
    "geometric",
    "dynamic",
    "conditional",
    "geometric_inverse",
    "dynamic_inverse",
    "theta0",
    "psi_boundaries",
    "asymptotic_sides",
    "FAIR_XI_GEOMETRIC",
    "FAIR_XI_DYNAMIC",
]

HALF_PI = math.pi / 2
# pi/2 and pi as unevaluated sums hi + lo (hi is the double nearest; lo the rest, to 2**-107).
_PIO2_HI = 1.5707963267948966
_PIO2_LO = 6.123233995736766e-17
_PI_HI = 3.141592653589793
_PI_LO = 1.2246467991473532e-16
# The next 53 bits of each, for offsets near pi/2 that are far smaller than 2**-107.
_PIO2_LO2 = -1.4973849048591698e-33
_PI_LO2 = -2.9947698097183397e-33
# Beyond this, xi/hypot(1, xi) is 1.0 in double; clamping keeps xi = inf away from inf/inf.
_XI_BIG = 2.0**600
# Beyond this, 1 + xi**2 rounds to xi**2 and sqrt(1 + xi**2) to xi: the geometric chances are flat.
_XI_FLAT = 2.0**27

FAIR_XI_GEOMETRIC = 1 / (2 * math.sqrt(2))  #: von Neumann's fair three-sided coin, eq. (11)
FAIR_XI_DYNAMIC = 1 / math.sqrt(3)  #: the Keller-flip fair three-sided coin, eq. (12)


class Outcome(NamedTuple):
    """Chances of heads, sides and tails (floats or arrays of one shape)."""

    heads: object
    sides: object
    tails: object


# --------------------------------------------------------------------------- validation


def _as_input(name, value, lo, hi, *, allow_inf):
    """Check that value (scalar or array_like) lies in [lo, hi]; return it as float or ndarray."""
    if isinstance(value, bool):
        raise ValueError(f"{name} must be a number, got {value!r}")
    if isinstance(value, (int, float)):
        v = float(value)
        if math.isnan(v) or v < lo or v > hi or (math.isinf(v) and not allow_inf):
            raise ValueError(_range_message(name, v, lo, hi, allow_inf))
        return v
    import numpy as np

    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a number or an array of numbers, got {value!r}") from None
    if arr.size == 0:
        return arr
    # Two reductions, not a full-size mask: min and max propagate NaN, which fails both tests.
    top = hi if allow_inf or hi < math.inf else np.finfo(float).max
    if not (arr.min() >= lo and arr.max() <= top):
        bad = ~((arr >= lo) & (arr <= top))  # the slow path, only to name the first bad value
        raise ValueError(_range_message(name, float(arr[bad].flat[0]), lo, hi, allow_inf))
    return arr


def _range_message(name, v, lo, hi, allow_inf):
    if hi == math.inf:
        allowed = f">= {lo:g}" + (" (inf allowed)" if allow_inf else "")
    elif hi == math.pi and lo == 0:
        allowed = "in [0, pi] radians"
    else:
        allowed = f"in [{lo:g}, {hi:g}]"
    return f"{name} must be {allowed}, got {v!r}"


def check_xi(xi):
    """Validate an aspect ratio: a number >= 0, or inf.  Returns a float or ndarray."""
    return _as_input("xi", xi, 0.0, math.inf, allow_inf=True)


def check_psi(psi):
    """Validate an angle psi in radians: [0, pi].  Returns a float or ndarray."""
    return _as_input("psi", psi, 0.0, math.pi, allow_inf=False)


def check_p(p, name="p"):
    """Validate a probability: [0, 1].  Returns a float or ndarray."""
    return _as_input(name, p, 0.0, 1.0, allow_inf=False)


def _errstate(xp):
    if xp is M:
        import contextlib

        return contextlib.nullcontext()
    return xp.errstate(all="ignore")


def _shape_like(xp, value, *like):
    """Broadcast a scalar result back to the arrays' shape (numpy path only)."""
    if xp is M:
        return value
    return xp.broadcast_to(value, xp.broadcast_shapes(*(xp.shape(a) for a in like))).copy()


# --------------------------------------------------------------------------- building blocks


def theta0(xi):
    """The static angle theta0 = arccos(xi / sqrt(1 + xi^2)) = atan2(1, xi), in radians (Fig. 1b).

    ``atan2(1, xi)`` keeps full relative accuracy for tiny and huge ``xi`` (no square, no arccos).
    """
    xi = check_xi(xi)
    xp = namespace(xi)
    return xp.atan2(1.0, xi)


def _cos_theta0(xp, xi):
    # cos(theta0) = xi / sqrt(1 + xi^2); hypot never overflows, the clamp keeps inf/inf away.
    x = xp.minimum(xi, _XI_BIG)
    return x / xp.hypot(1.0, x)


def psi_boundaries(xi):
    """The regime boundaries of Table I on [0, pi/2]: ``(theta0/2, pi/2 - theta0/2)``.

    Below the first, the coin always lands heads; between them, heads or sides; above the second
    (up to pi/2, mirrored about pi/2), all three outcomes.
    """
    t = theta0(xi) / 2
    return t, HALF_PI - t


# --------------------------------------------------------------------------- the two vigorous models


def geometric(xi):
    r"""Uniform orientations (von Neumann's model), eq. (11).

    .. math:: P_G(\text{sides}) = \cos\theta_0 = \frac{\xi}{\sqrt{1+\xi^2}}, \qquad
              P_G(\text{heads}) = P_G(\text{tails}) = \frac{1 - \cos\theta_0}{2}

    Parameters
    ----------
    xi : float or array_like
        Aspect ratio ``h / D``, ``0 <= xi <= inf``.

    Returns
    -------
    Outcome
        ``(heads, sides, tails)``, floats for a float input, arrays otherwise.

    Notes
    -----
    ``(1 - cos theta0)/2 = 1/(2 r (r + xi)) = 1/(2 (s + xi r))`` with ``s = 1 + xi^2`` and
    ``r = sqrt s`` (multiply by ``r + xi``): a sum of positive terms, nothing cancels.
    ``cos theta0 = 1/sqrt(1 + 1/xi^2)``: every step is a correctly rounded monotone operation,
    so the computed chance of a side never decreases as xi grows (``xi/hypot(1, xi)`` does, by
    an ulp, on a tenth of consecutive doubles).  Past ``xi = 2**27``, ``s``
    rounds to ``xi^2``, so a face is ``1/(4 xi^2)`` (no square to overflow); below ``2**-27``
    the side is ``xi`` itself.
    Fair (1/3 each) at ``xi = 1/(2 sqrt 2)``.

    Examples
    --------
    >>> round(geometric(0.5).sides, 12)
    0.4472135955
    >>> geometric(1 / (2 * 2**0.5)).sides  # doctest: +ELLIPSIS
    0.333333333333333...
    """
    xi = check_xi(xi)
    xp = namespace(xi)
    with _errstate(xp):
        if xp is M and xi > _XI_FLAT:
            face = (0.25 / xi) / xi
            return Outcome(face, 1.0, face)
        s = 1.0 + xi * xi
        face = 0.5 / (s + xi * xp.sqrt(s))
        if xp is M and xi < 1 / _XI_FLAT:
            return Outcome(face, xi, face)
        sides = 1.0 / xp.sqrt(1.0 + 1.0 / (xi * xi))
        if xp is M:
            return Outcome(face, sides, face)
        if xi.size:  # the ends, where a square overflows: rare, so masked
            if xi.max() > _XI_FLAT:  # s = xi**2 and sqrt(s) = xi in double
                face = xp.where(xi > _XI_FLAT, (0.25 / xi) / xi, face)
            if xi.min() < 1 / _XI_FLAT:  # sides = xi (1 - xi**2/2 + ...) = xi in double
                sides = xp.where(xi < 1 / _XI_FLAT, xi, sides)
        return Outcome(face, sides, face)


def dynamic(xi):
    r"""The Keller flip (``psi = pi/2``) tossed vigorously, eq. (12) and Fig. 4b.

    .. math:: P_D(\text{heads}) = P_D(\text{tails}) = \frac{\theta_0}{\pi}, \qquad
              P_D(\text{sides}) = 1 - \frac{2\theta_0}{\pi} = \frac{2}{\pi}\arctan\xi

    Notes
    -----
    ``pi/2 - atan2(1, xi) = atan(xi)`` for ``xi >= 0``, so sides is computed as
    ``atan(xi) / (pi/2)`` and never by subtraction.  Fair at ``xi = 1/sqrt 3``.

    Examples
    --------
    >>> dynamic(3 ** -0.5)  # doctest: +ELLIPSIS
    Outcome(heads=0.333333333333333..., sides=0.33333333333333..., tails=0.333333333333333...)
    """
    xi = check_xi(xi)
    xp = namespace(xi)
    face = xp.atan2(1.0, xi) / math.pi
    return Outcome(face, xp.atan(xi) / HALF_PI, face)


# --------------------------------------------------------------------------- the general case


def fold_psi(xp, psi):
    """Return (psi_m, e): psi folded onto [0, pi/2] and e = pi/2 - psi_m, both to full accuracy.

    P(i | psi) = P(i | pi - psi) (Table I is symmetric), so only the folded angle matters.
    ``pi - psi`` and ``pi/2 - psi`` are formed as (hi - psi) + lo: the first difference is exact
    (Sterbenz) on the half where it is used, so no digit of a small result is lost.
    """
    upper = psi > _PIO2_HI
    psi_m = xp.where(upper, (_PI_HI - psi) + _PI_LO, psi)
    e = xp.where(upper, (psi - _PIO2_HI) - _PIO2_LO, (_PIO2_HI - psi) + _PIO2_LO)
    return psi_m, xp.abs(e)


def _parts(xp, xi):
    """(t, s0, c0, c) with t = theta0/2, s0 = sin t, c0 = cos t, c = cos theta0."""
    t = xp.atan2(1.0, xi) / 2
    return t, xp.sin(t), xp.cos(t), _cos_theta0(xp, xi)


def _from_offsets(xp, sigma, t, s0, c0, c, u1, u2):
    r"""Table I from the offsets to the two regime boundaries.

    ``sigma = sin psi``; ``u1 = psi_m - theta0/2`` and ``u2 = psi_m - (pi/2 - theta0/2)`` for the
    folded angle ``psi_m`` in [0, pi/2].  Heads only when ``u1 <= 0``; tails possible when
    ``u2 > 0``.  With ``D1 = sin^2 psi - s0^2`` and ``D2 = sin^2 psi - c0^2``:

    - ``1 - cos theta1 = (1 - c)/sin^2 psi`` and ``1 + cos theta1 = (c - cos 2psi)/sin^2 psi``, so
      ``theta1/2 = atan2(s0, sqrt D1)``;
    - ``1 - cos theta2 = (1 + c)/sin^2 psi`` and ``1 + cos theta2 = -(c + cos 2psi)/sin^2 psi``, so
      ``(pi - theta2)/2 = atan2(sqrt D2, c0)``;
    - ``sin((theta2 - theta1)/2) = (c0 sqrt D1 - s0 sqrt D2)/sin^2 psi
      = c/(c0 sqrt D1 + s0 sqrt D2)`` (sine of a difference, then the conjugate:
      ``c0^2 D1 - s0^2 D2 = c sin^2 psi``), and ``cos((theta2 - theta1)/2)
      = (sqrt D1 sqrt D2 + c0 s0)/sin^2 psi``: asin for the small angle, atan2 past pi/4.

    ``sin^2 psi - sin^2 t = sin(psi - t) sin(psi + t)`` and ``sin^2 psi - cos^2 t
    = -cos(psi + t) cos(psi - t)``, with ``psi + t = pi/2 + u2``: ``D1 = sin u1 cos u2`` and
    ``D2 = sin u2 cos u1``, products that keep their relative accuracy when the offsets do.
    """
    # cos u2 = sin(psi + t) and cos u1 = sin(e + t): the sine of the small sum where it is small
    a1 = xp.where(u2 > -0.7853981633974483, xp.cos(u2), xp.sin(2 * t + u1))
    a2 = xp.where(u1 < 0.7853981633974483, xp.cos(u1), xp.sin(2 * t - u2))
    q1 = _sqrt_prod(xp, xp.maximum(xp.sin(u1), 0.0), a1)  # sqrt(D1)
    q2 = _sqrt_prod(xp, xp.maximum(xp.sin(u2), 0.0), a2)  # sqrt(D2)
    heads = xp.where(u1 > 0, _over_half_pi(xp, xp.atan2(s0, q1)), 1.0)
    tails = xp.where(u2 > 0, _over_half_pi(xp, xp.atan2(q2, c0)), 0.0)
    two = _over_half_pi(xp, xp.atan2(q1, s0))
    p, e = two_prod(xp, c0, q1)
    den = p + (s0 * q2 + e)  # c0 sqrt D1 + s0 sqrt D2 with the larger product exact
    w = c / xp.where(den > 0, den, 1.0)  # sin((theta2 - theta1)/2); the guard spares math a 0/0
    wide = xp.atan2(sigma * sigma * c, (q1 * q2 + c0 * s0) * den)  # (theta2 - theta1)/2 by atan2
    three = _over_half_pi(xp, xp.where(w < 0.7, xp.asin(xp.minimum(w, 0.7)), wide))
    sides = xp.where(u1 > 0, xp.where(u2 > 0, three, two), 0.0)
    return heads, sides, tails


def _sqrt_prod(xp, a, b):
    """sqrt(a b) for a, b >= 0: a rounding fewer than sqrt(a) sqrt(b), kept for tiny a b."""
    ab = a * b
    return xp.where(ab > 2.0**-1000, xp.sqrt(ab), xp.sqrt(a) * xp.sqrt(xp.maximum(b, 0.0)))


# 2/pi as hi + lo (hi the nearest double).
_TWO_OVER_PI_HI = 0.6366197723675814
_TWO_OVER_PI_LO = -3.935735335036497e-17


def _over_half_pi(xp, a):
    """a / (pi/2) as a (2/pi)_hi + a (2/pi)_lo, the first product exact (Dekker): one rounding."""
    p, e = two_prod(xp, a, _TWO_OVER_PI_HI)
    return p + (e + a * _TWO_OVER_PI_LO)


def conditional(xi, psi):
    r"""Chances for a fixed angle ``psi`` between angular momentum and normal: Table I.

    With :math:`A = \cos^2\psi`, :math:`B = \sin^2\psi` (eq. 3) and

    .. math:: \theta_1 = \cos^{-1}\frac{\cos\theta_0 - A}{B}, \qquad
              \theta_2 = \cos^{-1}\frac{-\cos\theta_0 - A}{B}

    - ``psi`` in ``[0, theta0/2)`` (or its mirror): heads 1, sides 0, tails 0;
    - ``[theta0/2, pi/2 - theta0/2)``: heads ``theta1/pi``, sides ``1 - theta1/pi``, tails 0;
    - ``[pi/2 - theta0/2, pi/2 + theta0/2]``: heads ``theta1/pi``, sides ``(theta2 - theta1)/pi``,
      tails ``1 - theta2/pi``.

    Parameters
    ----------
    xi : float or array_like
        Aspect ratio, ``0 <= xi <= inf``.  ``xi = 0`` is the zero-thickness coin of Diaconis,
        Holmes and Montgomery; ``xi = inf`` always lands on a side unless ``psi`` is 0 or pi.
    psi : float or array_like
        Angle in radians, ``0 <= psi <= pi``; broadcast against ``xi``.  ``psi = pi/2`` is the
        Keller flip (:func:`dynamic`); ``psi = 0`` or ``pi`` never precesses: always heads.

    Notes
    -----
    The half-angle forms of :func:`_from_offsets` keep every output's relative accuracy given
    accurate offsets ``u`` from psi to the regime boundaries.  Near a boundary (``|u| < theta0/4``)
    the chance of the rarer outcome goes like ``sqrt(u)``, so the offsets are recomputed: in long
    double where it has 64 bits (numpy path, ``|u| >= 2**-8 theta0/2``), else as double-doubles
    (:func:`_near_boundary`), and below ``2**-40 theta0/2`` exactly (:func:`_offsets_exact`).
    Measured against mpmath: within 4 ulps everywhere, the doubles adjacent to a boundary
    included (docs/accuracy.md).  Where long double has 64 bits, the numpy path then runs the
    same forms again in long double and rounds once (:func:`_extended_finish`, for theta0/2 at
    least 2**-40): the chances are monotone in xi over consecutive doubles (P(sides)
    non-decreasing, heads and tails non-increasing), which the double forms are not.

    Examples
    --------
    >>> [round(v, 12) for v in conditional(3 ** -0.5, math.pi / 2)]
    [0.333333333333, 0.333333333333, 0.333333333333]
    >>> conditional(0.1, 0.2)  # below theta0/2: no precession reaches a side
    Outcome(heads=1.0, sides=0.0, tails=0.0)
    """
    xi = check_xi(xi)
    psi = check_psi(psi)
    xp = namespace(xi, psi)
    with _errstate(xp):
        t, s0, c0, c = _parts(xp, xi)
        psi_m, e = fold_psi(xp, psi)
        args = [xp.sin(psi_m), t, s0, c0, c, psi_m - t, t - e]  # sigma, t, s0, c0, c, u1, u2
        if xp is not M:  # full-shape copies, for the masked updates below
            xi, psi, *args = (a.copy() for a in xp.broadcast_arrays(xi, psi, *args))
            t = args[1]
        # Offsets under half of t carry t's rounding error amplified; redo them in double-double.
        near = (xp.abs(args[5]) < t * _NEAR) | (xp.abs(args[6]) < t * _NEAR) | (psi_m < _PLANAR_T)
        if xp is M:
            if near:
                args = _near_boundary(M, xi, psi, *args)
        elif near.any():
            band = near & _long_double_band(xp, args[1], args[5], args[6])
            if band.any():  # most of the near ones: offsets rounded from 64-bit long doubles
                args[5][band], args[6][band] = _offsets_long_double(xp, xi[band], psi[band])
                near = near & ~band
            if near.any():
                for a, v in zip(args, _near_boundary(xp, xi[near], psi[near],
                                                     *(a[near] for a in args)), strict=True):
                    a[near] = v
        heads, sides, tails = _from_offsets(xp, *args)
        tails = xp.minimum(tails, heads)  # theta1 + theta2 >= pi; rounding near psi = pi/2 aside
        if xp is not M:
            heads, sides, tails = (xp.asarray(v, dtype=float) for v in (heads, sides, tails))
            if long_double_64(xp) and heads.size:
                _extended_finish(xp, xi, psi, args[5], args[6], near, heads, sides, tails)
        return Outcome(heads, sides, tails)


# Relative offset |u| / t under which conditional() takes the double-double path.
_NEAR = 0.5
# Below this t = theta0/2 (xi > 2**899) the offsets are redone in a frame scaled by _PLANAR_SCALE:
# every angle there is so small that sin x = x and cos x = 1 in double, Table I depends only on
# psi/t, and scaling keeps u1 and the low part of t out of the subnormal range.
_PLANAR_T = 2.0**-900
_PLANAR_SCALE = 2.0**840


# Long-double band (numpy path, where long double has a 64-bit significand, as on x86): offsets
# at least _BAND_REL t from both boundaries, with t above _BAND_T_MIN, are formed in long double;
# their relative error is then below 2**-63 t/|u| <= 2**-55, a quarter of an ulp before the
# square root halves it.  Closer offsets (and every offset where long double is a plain double)
# take the double-double path of _near_boundary.
_BAND_REL = 2.0**-8
_BAND_T_MIN = 2.0**-40


def _long_double_band(xp, t, u1, u2):
    """Mask of the elements whose offsets long double computes to full double accuracy."""
    if not long_double_64(xp):
        return xp.zeros(xp.shape(t), dtype=bool)
    return (xp.minimum(xp.abs(u1), xp.abs(u2)) >= _BAND_REL * t) & (t >= _BAND_T_MIN)


def _extended_finish(xp, xi, psi, u1, u2, dd, heads, sides, tails):
    """Table I again in 64-bit long double, rounded once to double, into heads, sides, tails.

    Monotone to the last bit.  In double, ``t = theta0/2`` (and with it ``sin t``, ``cos t`` and
    the offsets) is rounded once, ``cos theta0`` is rounded from xi on its own, and each of the
    twenty operations after them rounds again: a chance is within 4 ulps, but the errors come
    and go from one double xi to the next, so that P(sides) stepped down (and heads, tails up)
    by 1 to 6 ulps over runs of consecutive doubles.  Here every input is formed from xi and psi
    in long double (relative error a few 2**-64) and the formulas of :func:`_from_offsets` run
    in long double: the result is the exact chance within a few 2**-64 relative, rounded once.
    Where the exact chances of two adjacent doubles differ by more than that (everywhere the
    chance moves by at least ~2**-60 relative per double step of xi), their roundings keep their
    order, since rounding is monotone; where they differ by less, both round to the same double
    except within ~2**-60 of a rounding boundary.  The result is also correctly rounded outside
    those hairline cases, so it is at least as accurate as the double formulas.

    Offsets within ``_NEAR t`` of a boundary come from the double-double ones as hi + lo (good
    to 2**-104 t); within ``2**-40 t``, the exact offset of :func:`_offsets_exact` rounded to
    double, as the double path has it.  Elements with ``t < 2**-40`` (xi > 2**39, where the
    planar frame and the exact offsets take over) or an infinite xi keep the double result.
    """
    L = xp.longdouble
    shape = heads.shape
    xi_b, psi_b, u1_b, u2_b, dd_b = (xp.broadcast_to(a, shape).ravel()
                                     for a in (xi, psi, u1, u2, dd))
    t_d = xp.arctan2(1.0, xi_b) / 2
    rows = xp.flatnonzero((t_d >= _BAND_T_MIN) & (xi_b < xp.inf))
    if not rows.size:
        return
    x, p = xi_b[rows], psi_b[rows]
    xl = x.astype(L)
    t = xp.arctan2(L(1), xl) / 2
    s0, c0 = xp.sin(t), xp.cos(t)
    c = xl / xp.hypot(L(1), xl)
    upper = p > _PIO2_HI
    psi_m = xp.where(upper, (_PI_HI - p).astype(L) + L(_PI_LO) + L(_PI_LO2), p.astype(L))
    e = xp.abs(xp.where(upper, (p - _PIO2_HI).astype(L) - L(_PIO2_LO) - L(_PIO2_LO2),
                        (_PIO2_HI - p).astype(L) + L(_PIO2_LO) + L(_PIO2_LO2)))
    w1, w2 = psi_m - t, t - e
    close = xp.flatnonzero(dd_b[rows])
    if close.size:  # double-double offsets, hi + lo
        a1, a2 = _dd_offsets(xp, x[close], p[close])
        tc = t_d[rows][close]
        for w, a, u in ((w1, a1, u1_b), (w2, a2, u2_b)):
            exact = xp.abs(a) < _EXACT_REL * tc.astype(L)
            w[close] = xp.where(exact, u[rows][close].astype(L), a)
    h, s, tl = _from_offsets(xp, xp.sin(psi_m), t, s0, c0, c, w1, w2)
    tl = xp.minimum(tl, h)
    for out, v in ((heads, h), (sides, s), (tails, tl)):
        out.reshape(-1)[rows] = v.astype(float)


def _dd_offsets(xp, xi, psi):
    """(u1, u2) of :func:`_from_offsets` in long double from the double-double offsets of
    :func:`_near_boundary` (hi + lo: good to about 2**-104 theta0/2); numpy path, t >= 2**-900."""
    L = xp.longdouble
    (mh, ml), (eh, el) = _dd_fold(xp, psi)
    uniq, inv = xp.unique(xi, return_inverse=True)
    th, tl = (v[inv] for v in _half_theta0_dd(xp, uniq)[:2])
    u1h, u1l = _dd_add(mh, ml, -th, -tl)
    u2h, u2l = _dd_add(th, tl, -eh, -el)
    return u1h.astype(L) + u1l.astype(L), u2h.astype(L) + u2l.astype(L)


def _dd_fold(xp, psi):
    """psi folded onto [0, pi/2] and e = |pi/2 - psi|, both as double-doubles (exact to 2**-160
    of pi): ``(mh, ml), (eh, el)``."""
    upper = psi > _PIO2_HI  # folded onto pi - psi
    # psi_m = pi - psi on the upper half (PI_HI - psi is exact there: two_sum keeps it all)
    mh, ml = _two_sum(xp.where(upper, _PI_HI, psi), xp.where(upper, -psi, 0.0))
    mh, ml = _dd_add(mh, ml, xp.where(upper, _PI_LO, 0.0), xp.where(upper, _PI_LO2, 0.0))
    # e = pi/2 - psi (lower half) or psi - pi/2 (upper half), exactly
    eh, el = _two_sum(xp.where(upper, psi, _PIO2_HI), xp.where(upper, -_PIO2_HI, -psi))
    eh, el = _dd_add(eh, el, xp.where(upper, -_PIO2_LO, _PIO2_LO),
                     xp.where(upper, -_PIO2_LO2, _PIO2_LO2))
    return (mh, ml), (eh, el)


def _offsets_long_double(xp, xi, psi):
    """(u1, u2) of :func:`_from_offsets` computed in long double and rounded to double.

    ``pi - psi`` and ``pi/2 - psi`` are formed as (hi - psi) + lo + lo2: the first difference is
    exact in double (Sterbenz), the constants' parts carry pi to 2**-160, and each long-double
    sum rounds once, to 2**-64 of the (small) result; theta0/2 is long double's own atan2.
    """
    L = xp.longdouble
    upper = psi > _PIO2_HI
    # psi_m = pi - psi (upper half) or psi; e = |pi/2 - psi|
    psi_m = xp.where(upper, (_PI_HI - psi).astype(L) + L(_PI_LO) + L(_PI_LO2), psi.astype(L))
    e = xp.where(upper, (psi - _PIO2_HI).astype(L) - L(_PIO2_LO) - L(_PIO2_LO2),
                 (_PIO2_HI - psi).astype(L) + L(_PIO2_LO) + L(_PIO2_LO2))
    t = xp.arctan2(L(1), xi.astype(L)) / 2
    return (psi_m - t).astype(float), (t - xp.abs(e)).astype(float)


def _near_boundary(xp, xi, psi, sigma, t, s0, c0, c, u1, u2):
    """The arguments of :func:`_from_offsets` with the offsets u1, u2 exact to a few ulps.

    ``theta0/2``, ``psi_m`` and ``e = pi/2 - psi_m`` are formed as double-doubles (hi + lo), so
    ``u1 = psi_m - t`` and ``u2 = t - e`` keep their relative accuracy however close ``psi`` is to
    a boundary (down to ~2**-104 t).  Elementwise; xp is math or numpy.
    """
    (mh, ml), (eh, el) = _dd_fold(xp, psi)
    if xp is M:
        th, tl, ts, tsl = _half_theta0_dd(xp, xi)
    else:  # theta0/2 depends on xi alone: once per distinct xi (a sweep over psi has one)
        uniq, inv = xp.unique(xi, return_inverse=True)
        th, tl, ts, tsl = (v[inv] for v in _half_theta0_dd(xp, uniq))
    u1 = _dd_add(mh, ml, -th, -tl)[0]
    u2 = _dd_add(th, tl, -eh, -el)[0]
    # Planar frame (t < 2**-900): psi_m and t scaled by 2**840 (exact); u2 < 0 there.
    planar = t < _PLANAR_T
    ms, msl = mh * _PLANAR_SCALE, ml * _PLANAR_SCALE
    us = _dd_add(ms, msl, -ts, -tsl)[0]
    # Closer than _EXACT_REL t, the 2**-104 of the double-double shows: exact arithmetic instead.
    exact = xp.where(planar, xp.abs(us) < _EXACT_REL * ts,
                     (xp.abs(u1) < _EXACT_REL * t) | (xp.abs(u2) < _EXACT_REL * t)) & (xi < xp.inf)
    if xp is M:
        if exact and planar:
            us = _offsets_exact(xi, psi, _PLANAR_EXP)[0]
        elif exact:
            u1, u2 = _offsets_exact(xi, psi)
    elif exact.any():
        u1, u2, us = u1.copy(), u2.copy(), us.copy()
        for i in xp.flatnonzero(exact):
            if planar[i]:
                us[i] = _offsets_exact(float(xi[i]), float(psi[i]), _PLANAR_EXP)[0]
            else:
                u1[i], u2[i] = _offsets_exact(float(xi[i]), float(psi[i]))
    return (xp.where(planar, ms, sigma), xp.where(planar, ts, t), xp.where(planar, ts, s0),
            xp.where(planar, 1.0, c0), xp.where(planar, 1.0, c), xp.where(planar, us, u1),
            xp.where(planar, -1.0, u2))


# Offsets below this fraction of t are computed exactly (_offsets_exact): at most a handful of
# inputs, the doubles nearest a boundary.  2**-40: the double-double's 2**-104 then leaves u
# good to 2**-64, far more than needed, so the switch itself costs no accuracy.
_EXACT_REL = 2.0**-40
_PLANAR_EXP = 840  # log2 of _PLANAR_SCALE


def _offsets_exact(xi, psi, scale_exp=0):
    """(u1, u2) times 2**scale_exp for one finite xi and psi, correctly rounded to doubles.

    Fixed-point integers with F fractional bits, F ample for the scale of theta0/2 (about
    2**-exponent(xi)) plus 200 bits: every input double is exact there, and atan and pi
    (Machin's formula) are summed from their series with truncation errors of a few units of
    2**-F.  A double psi lies at least ~2**-120 t from the irrational boundary t (the
    table-maker's bound for such functions), so u comes out correct to the last bit.
    Pure Python (big integers): slow, for the rare inputs that need it.
    """
    bits = 230 + max(0, math.frexp(xi)[1]) + scale_exp
    pi = _fixed_pi(bits)
    a, b = xi.as_integer_ratio()
    if a <= b:  # theta0 = pi/2 - atan(xi)
        theta = pi // 2 - _fixed_atan((a << bits) // b, bits)
    else:  # theta0 = atan(1/xi)
        theta = _fixed_atan((b << bits) // a, bits)
    t = theta // 2
    pa, pb = psi.as_integer_ratio()
    p = (pa << bits) // pb
    psi_m = pi - p if 2 * p > pi else p
    e = abs(pi // 2 - p)
    scale = 1 << (bits - scale_exp)
    return (psi_m - t) / scale, (t - e) / scale


def _fixed_atan(x, bits):
    """atan(x / 2**bits) * 2**bits for 0 <= x <= 2**bits: three half-angle steps, then the series.

    ``atan x = 2 atan(x / (1 + sqrt(1 + x^2)))`` takes x below tan(pi/32) < 0.1, where the series
    ``x - x^3/3 + x^5/5 - ...`` gains more than 6 bits a term.
    """
    one = 1 << bits
    for _ in range(3):
        x = (x << bits) // (one + math.isqrt(one * one + x * x))
    x2 = (x * x) >> bits
    total, power, k = 0, x, 1
    while power:
        total += power // k if k % 4 == 1 else -(power // k)
        power = (power * x2) >> bits
        k += 2
    return total << 3


@functools.lru_cache(maxsize=16)
def _fixed_pi(bits):
    """pi * 2**bits by Machin: pi = 16 atan(1/5) - 4 atan(1/239), with 20 guard bits."""
    g = bits + 20

    def acot(n):  # atan(1/n) * 2**g, the series directly (1/n is small)
        total, power, k, n2 = 0, (1 << g) // n, 1, n * n
        while power:
            total += power // k if k % 4 == 1 else -(power // k)
            power //= n2
            k += 2
        return total

    return (16 * acot(5) - 4 * acot(239)) >> 20


def _half_theta0_dd(xp, xi):
    """theta0/2 as a double-double (th, tl), and (ts, tsl) = 2**840 theta0/2 for xi > 2**899.

    ``theta0 = atan(1/xi)`` for ``xi > 1``, ``pi/2 - atan(xi)`` otherwise, so that the argument of
    :func:`_dd_atan` is in [0, 1]; ``1/xi`` is carried as hi + lo (Dekker's product gives the
    remainder ``1 - hi xi`` exactly).  Past ``xi = 2**899``, ``theta0 = 1/xi`` to 2**-1800 and only
    the scaled value is meaningful (its low part would underflow unscaled).
    """
    big = xi > 1
    x = xp.minimum(xi, 1 / _PLANAR_T)  # keeps inf (handled by the planar frame) out of the way
    wh = xp.where(big, 1 / xp.maximum(x, 1.0), x)
    ph, pl = two_prod(xp, wh, x)
    wl = xp.where(big, ((1.0 - ph) - pl) / xp.maximum(x, 1.0), 0.0)  # 1/xi - wh = (1 - wh xi)/xi
    ah, al = _dd_atan(xp, wh, wl)
    th, tl = _dd_add(xp.where(big, ah, _PIO2_HI), xp.where(big, al, _PIO2_LO),
                     xp.where(big, 0.0, -ah), xp.where(big, 0.0, -al))
    tl = tl + xp.where(big, 0.0, _PIO2_LO2)  # pi/2 to 2**-160: th + tl stays good to 2**-106
    # Planar frame: 2**840 / (2 xi) = 2**-61 / xs with xs = xi 2**-900 in [1, 2**125) (or inf)
    xs = xp.maximum(xi, 1 / _PLANAR_T) * _PLANAR_T
    qh = 1 / xs
    ph, pl = two_prod(xp, qh, xp.minimum(xs, 2.0**125))
    ql = xp.where(xs < xp.inf, ((1.0 - ph) - pl) / xs, 0.0)  # 1/xs = qh + ql
    scale = _PLANAR_T * _PLANAR_SCALE / 2
    return th / 2, tl / 2, qh * scale, ql * scale


# --------------------------------------------------------------------------- inverses


def geometric_inverse(p_sides):
    r"""The aspect ratio whose geometric chance of a side is ``p_sides``: inverse of eq. (11).

    .. math:: \xi = \frac{p}{\sqrt{(1 - p)(1 + p)}}

    ``1 - p`` is exact for ``p >= 1/2`` (Sterbenz), so nothing cancels near ``p = 1``.
    ``p = 0`` gives 0 and ``p = 1`` gives ``inf``.

    >>> geometric_inverse(1 / 3) == 1 / (2 * 2**0.5)
    True
    """
    p = check_p(p_sides, "p_sides")
    xp = namespace(p)
    with _errstate(xp):
        den = xp.sqrt((1.0 - p) * (1.0 + p))
        if xp is M:
            return math.inf if den == 0 else p / den
        return p / den  # den = 0 only at p = 1: 1/0 = inf (warning silenced by _errstate)


def dynamic_inverse(p_sides):
    r"""The aspect ratio whose dynamic chance of a side is ``p_sides``: ``xi = tan(pi p / 2)``.

    Near ``p = 1`` the argument is reflected, ``tan(pi p/2) = 1/tan(pi (1 - p)/2)`` with
    ``1 - p`` exact, and ``pi p / 2`` is carried as a double-double so that its rounding does not
    reach the answer: ``tan(x + d) = tan x + d (1 + tan^2 x)`` to first order in the tiny ``d``.

    >>> dynamic_inverse(1 / 3)  # doctest: +ELLIPSIS
    0.577350269189625...
    """
    p = check_p(p_sides, "p_sides")
    xp = namespace(p)
    with _errstate(xp):
        upper = p > 0.5
        q = xp.where(upper, 1.0 - p, p)  # exact for p > 1/2
        # x = (pi/2) q as hi + lo: Dekker's product of q with _PIO2_HI, plus q * _PIO2_LO.
        hi, lo = two_prod(xp, q, _PIO2_HI)
        lo = lo + q * _PIO2_LO
        x = hi + lo
        lo = lo - (x - hi)
        tx = xp.tan(x)
        tq = tx + lo * (1.0 + tx * tx)
        if xp is M:
            if upper:
                return math.inf if tq == 0 else 1.0 / tq
            return tq
        return xp.where(upper, 1.0 / tq, tq)


def two_prod(xp, a, b):
    """a * b = p + e exactly (Dekker, no fma): for |a|, |b| well inside the double range."""
    p = a * b
    split = 134217729.0  # 2**27 + 1
    ca = split * a
    ahi = ca - (ca - a)
    alo = a - ahi
    cb = split * b
    bhi = cb - (cb - b)
    blo = b - bhi
    e = ((ahi * bhi - p) + ahi * blo + alo * bhi) + alo * blo
    return p, e


# --------------------------------------------------------------------------- double-double
# A double-double is an unevaluated sum hi + lo with |lo| <= ulp(hi)/2: about 106 bits.  These
# helpers are plain arithmetic (plus xp.atan), so they run elementwise on floats and arrays.


def _two_sum(a, b):
    """a + b = s + e exactly (Knuth), any a, b."""
    s = a + b
    bb = s - a
    return s, (a - (s - bb)) + (b - bb)


def _fast_two_sum(a, b):
    """a + b = s + e exactly when |a| >= |b| (Dekker)."""
    s = a + b
    return s, b - (s - a)


def _dd_add(ah, al, bh, bl):
    """(ah + al) + (bh + bl), both parts two-summed (accurate even under cancellation)."""
    s, e = _two_sum(ah, bh)
    f, g = _two_sum(al, bl)
    s, e = _fast_two_sum(s, e + f)
    return _fast_two_sum(s, e + g)


def _dd_mul(xp, ah, al, bh, bl):
    """(ah + al) * (bh + bl) to about 2**-104 relative."""
    p, e = two_prod(xp, ah, bh)
    return _fast_two_sum(p, e + (ah * bl + al * bh))


def _dd_div_int(xp, ah, al, n):
    """(ah + al) / n for a small integer n (exact as a double)."""
    q = ah / n
    p, e = two_prod(xp, q, float(n))
    return _fast_two_sum(q, (((ah - p) - e) + al) / n)


def _dd_sincos(xp, y):
    """(sin y, cos y) as double-doubles for a double y in [0, pi/4]: Taylor series.

    Terms y**n/n! for n <= 17 are carried as double-doubles; the rest (each below 2**-57, the
    last, n = 29, below 2**-110) are summed in plain double, whose errors stay under 2**-110.
    """
    zero = 0.0 * y
    sh, sl, ch, cl = y, zero, 1.0 + zero, zero
    th, tl = y, zero  # y**n / n!
    tail_s, tail_c = zero, zero
    for n in range(2, 30):
        sign = -1.0 if n % 4 in (2, 3) else 1.0  # cos: + - + ... (n even); sin: + - ... (n odd)
        if n <= 17:
            th, tl = _dd_mul(xp, th, tl, y, 0.0)
            th, tl = _dd_div_int(xp, th, tl, n)
            if n % 2:
                sh, sl = _dd_add(sh, sl, sign * th, sign * tl)
            else:
                ch, cl = _dd_add(ch, cl, sign * th, sign * tl)
        else:
            th = th * y / n
            if n % 2:
                tail_s = tail_s + sign * th
            else:
                tail_c = tail_c + sign * th
    return _dd_add(sh, sl, tail_s, 0.0), _dd_add(ch, cl, tail_c, 0.0)


def _dd_atan(xp, xh, xl):
    """atan(xh + xl) as a double-double for 0 <= xh + xl <= 1.

    One correction of y = atan(xh) (a double within an ulp): atan x - y = atan(d) with
    d = (x cos y - sin y)/(cos y + x sin y) (tangent of a difference); the numerator cancels, so
    it is formed in double-double; |d| <= 2**-52 makes atan d = d to 2**-156.
    """
    y = xp.atan(xh)
    (sh, sl), (ch, cl) = _dd_sincos(xp, y)
    nh, nl = _dd_mul(xp, xh, xl, ch, cl)
    nh, nl = _dd_add(nh, nl, -sh, -sl)
    d = (nh + nl) / (ch + xh * sh)
    return _fast_two_sum(y, d)


# --------------------------------------------------------------------------- asymptotics


def asymptotic_sides(xi, model="dynamic", regime="small", order=None):
    r"""Series for the chance of a side, eqs. (13) (small ``xi``) and (14) (large ``xi``).

    Small ``xi``: ``P_G = xi - xi^3/2 + 3 xi^5/8 - ...`` (binomial series of
    ``xi (1 + xi^2)^(-1/2)``), ``P_D = (2/pi)(xi - xi^3/3 + xi^5/5 - ...)`` (series of atan).
    Large ``xi``: ``P_G = 1 - 1/(2 xi^2) + 3/(8 xi^4) - ...``,
    ``P_D = 1 - (2/pi)(1/xi - 1/(3 xi^3) + ...)``.  The paper prints two terms of each; its
    ``O(1/xi^2)`` remainder for ``P_D`` is in fact ``O(1/xi^3)``.

    ``order`` is the number of terms kept (default: the paper's two).
    """
    if model not in ("geometric", "dynamic"):
        raise ValueError(f"model must be 'geometric' or 'dynamic', got {model!r}")
    if regime not in ("small", "large"):
        raise ValueError(f"regime must be 'small' or 'large', got {regime!r}")
    n = 2 if order is None else int(order)
    if n < 1:
        raise ValueError(f"order must be >= 1, got {order!r}")
    xi = check_xi(xi)
    xp = namespace(xi)
    with _errstate(xp):
        y = xi if regime == "small" else 1.0 / xp.maximum(xi, 5e-324)  # expansion variable
        if model == "geometric":
            # (1 + y^2)^(-1/2) = sum_k C(-1/2, k) y^(2k); small: xi * that; large: that with y = 1/xi
            series, coeff = 0.0 * y, 1.0
            for k in range(n):
                series = series + coeff * y ** (2 * k)
                coeff *= (-0.5 - k) / (k + 1)
            return y * series if regime == "small" else series
        # atan y = sum_k (-1)^k y^(2k+1)/(2k+1); atan xi = pi/2 - atan(1/xi)
        series = 0.0 * y
        for k in range(n):
            series = series + (-1) ** k * y ** (2 * k + 1) / (2 * k + 1)
        return 2 / math.pi * series if regime == "small" else 1.0 - 2 / math.pi * series
