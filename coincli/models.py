r"""Closed-form chances of heads, sides and tails for a thick coin (Yong & Mahadevan).

Notation of the paper: a coin of diameter ``D = 2a`` and thickness ``h`` has aspect ratio
``xi = h / D``.  The diagonal from the centre to the rim makes the angle

.. math:: \theta_0 = \cos^{-1}\frac{\xi}{\sqrt{1+\xi^2}} = \operatorname{atan2}(1, \xi)

with the coin's normal.  ``psi`` is the angle between the angular momentum and the normal at
launch (the coin starts heads up).

Every function here takes Python floats or array_likes (broadcasting like a ufunc) and returns an
:class:`Outcome` of the same shape.  Python floats never touch numpy: the ``math`` module does the
work, so the closed forms stay cheap for a command-line call.  Each formula is written once, against
``xp`` (``math`` or ``numpy``; see :mod:`coincli._backend`).

Accuracy.  The textbook forms lose digits: ``1 - 2 theta0/pi`` for a thin coin, ``1 - theta2/pi``
when tails is rare, ``arccos`` near 1, ``sqrt(1 + xi**2)`` overflowing past 1e154.  The forms used
below are the half-angle ones; each identity is stated where it is used.  Measured errors against
mpmath are in ``docs/accuracy.md``.
"""

from __future__ import annotations

import math
from typing import NamedTuple

from coincli._backend import M, namespace

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
# Beyond this, xi/hypot(1, xi) is 1.0 in double; clamping keeps xi = inf away from inf/inf.
_XI_BIG = 2.0**600

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
    bad = np.isnan(arr) | (arr < lo) | (arr > hi)
    if not allow_inf:
        bad |= np.isinf(arr)
    if bad.any():
        first = arr[bad].flat[0]
        raise ValueError(_range_message(name, float(first), lo, hi, allow_inf))
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
    ``(1 - cos theta0)/2 = 1/(2 r (r + xi))`` with ``r = hypot(1, xi)`` (multiply by ``r + xi``),
    evaluated as ``(0.5/r)/(r + xi)`` so that nothing cancels, overflows or underflows early.
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
        x = xp.minimum(xi, _XI_BIG)
        r = xp.hypot(1.0, x)
        face = (0.5 / r) / (r + x)
        return Outcome(face, x / r, face)


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


def _fold_psi(xp, psi):
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
    - ``c0 sqrt D1 - s0 sqrt D2 = sin^2 psi * c / (c0 sqrt D1 + s0 sqrt D2)`` (multiply by the
      conjugate; ``c0^2 D1 - s0^2 D2 = c sin^2 psi``), which gives ``(theta2 - theta1)/2`` by the
      atan2 difference formula without cancellation.

    ``sin psi - sin t = 2 cos((psi + t)/2) sin(u1/2)`` and
    ``sin psi - cos t = 2 sin(t - u2/2) sin(u2/2)`` (sum-to-product), so ``D1``, ``D2`` keep their
    relative accuracy when the offsets do.
    """
    p1 = 2 * xp.cos(t + u1 / 2) * xp.sin(u1 / 2)  # sin psi - s0
    p2 = 2 * xp.sin(t - u2 / 2) * xp.sin(u2 / 2)  # sin psi - c0
    q1 = xp.sqrt(xp.maximum(p1, 0.0)) * xp.sqrt(sigma + s0)  # sqrt(D1), no underflow of D1
    q2 = xp.sqrt(xp.maximum(p2, 0.0)) * xp.sqrt(sigma + c0)  # sqrt(D2)
    heads = xp.where(u1 > 0, xp.atan2(s0, q1) / HALF_PI, 1.0)
    tails = xp.where(u2 > 0, xp.atan2(q2, c0) / HALF_PI, 0.0)
    two = xp.atan2(q1, s0) / HALF_PI
    # atan2(y/den, x) = atan2(y, x*den) for den > 0; no division, so the scalar path cannot raise
    three = xp.atan2(sigma * sigma * c, (q1 * q2 + c0 * s0) * (c0 * q1 + s0 * q2)) / HALF_PI
    sides = xp.where(u1 > 0, xp.where(u2 > 0, three, two), 0.0)
    return heads, sides, tails


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
    The half-angle forms of :func:`_from_offsets` keep every output's relative accuracy away
    from the regime boundaries.  Within a few ulps of a boundary the result is as accurate as
    ``theta0/2`` rounded to a double allows (the chance of the rarer outcome there goes like the
    square root of the distance to the boundary).

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
        psi_m, e = _fold_psi(xp, psi)
        sigma = xp.sin(psi_m)
        heads, sides, tails = _from_offsets(xp, sigma, t, s0, c0, c, psi_m - t, t - e)
        if xp is not M:
            heads, sides, tails = (xp.asarray(v, dtype=float) for v in (heads, sides, tails))
        return Outcome(heads, sides, tails)


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
        return xp.where(den == 0, xp.inf, p / xp.where(den == 0, 1.0, den))


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
        hi, lo = _two_prod(xp, q, _PIO2_HI)
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


def _two_prod(xp, a, b):
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
