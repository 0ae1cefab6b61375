"""Hand-written vectorized sines and cosines: numpy's ``sin`` and ``cos`` are scalar loops,
several times the cost of these array operations.

- :func:`half_sincos`: ``|sin x|`` and ``cos x sign(sin x)`` within an ulp or two (fdlibm's
  kernels after a Cody-Waite reduction; numpy's beyond ``x = 1.5e6``), for the time of flight's
  ``F`` and ``F'`` (:mod:`coincli.core.toss.flight`);
- :func:`abs_sin_rough`, and :func:`sin_into` in place: ``|sin x|`` for ``0 <= x < 1e5`` within
  ``5e-11`` (a Taylor polynomial, :data:`SIN_TAYLOR`), for bounds with a margin, not for results
  (the outcome engine of :mod:`coincli.core.toss.batch`).

Each takes the numpy module as its first argument, so this module imports no numpy.
"""

from __future__ import annotations

import math

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


def half_sincos(np, x):
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


# sin r for |r| <= pi/2 + 1e-11: Taylor to r^17 (the next term is below 5e-14).
SIN_TAYLOR = tuple((-1.0) ** i / math.factorial(2 * i + 1) for i in range(9))[::-1]


def abs_sin_rough(np, x, terms=9):
    """``|sin x|`` for ``0 <= x < 1e5`` within ``5e-11``: the reduction ``x - k pi`` by a double
    ``pi`` errs by ``k * 1.3e-16`` plus two roundings of the size of ``x`` (an ulp of ``1e5`` is
    ``1.5e-11``), the Taylor polynomial on ``[-pi/2, pi/2]`` by ``5e-14``.  For bounds (with a
    margin of ``1e-9``), not for results.  With ``terms=6`` (to ``r^11``) the polynomial errs by
    ``(pi/2)^13 / 13! < 6e-8``."""
    r = np.rint(x * (1.0 / math.pi))
    r *= -math.pi
    r += x
    z = r * r
    taylor = SIN_TAYLOR[9 - terms:]
    p = z * taylor[0]
    for c in taylor[1:-1]:
        p += c
        p *= z
    p += 1.0
    p *= r
    return np.abs(p, out=p)


def sin_into(np, x, out, r, z, taylor):
    """``|sin x|`` for ``0 <= x < 1e5`` into ``out`` (``r``, ``z`` scratch): as
    :func:`abs_sin_rough`, in place, with the Taylor coefficients ``taylor`` (of ``sin r /
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
