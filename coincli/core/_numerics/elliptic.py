r"""Elliptic integrals and Jacobi's elliptic functions, accurate next to ``m = 1``.

The free rigid body (:mod:`coincli.core.rigid`) needs them next to the separatrix, where the
parameter ``m`` is within rounding of 1.  Every function here takes ``m`` *and* its complement
``m1 = 1 - m`` (``scipy.special.ellipj`` takes ``m`` alone, and rounding ``1 - m1`` to a double
costs ``eps / m1`` of relative accuracy: 1e-4 at ``m1 = 1e-12``):

- :func:`ellip_agm`, the arithmetic-geometric mean sequence of the descending Landen transform
  (Abramowitz & Stegun 16.4), and :func:`ellip_k`, the complete integral ``K`` from it;
- :func:`ellip_rf`, Carlson's :math:`R_F` by duplication, and :func:`ellip_f`, the incomplete
  integral ``F`` from it;
- :func:`ellip_j`, ``sn, cn, dn`` with the argument reduced to an eighth of a period by the
  quarter-period shifts (:func:`_sncndn_eighth` evaluates the eighth: the backward Landen
  recurrence, or A&S 16.15 for ``m1 <= 1e-11``).

Each runs on Python floats (through :class:`FloatShim`, without numpy) or on numpy arrays
(:func:`backend_of` picks).  docs/book.md has the measured accuracy (a few eps against mpmath, m1 from
1 to 1e-300).
"""

from __future__ import annotations

import math

__all__ = ["ellip_agm", "ellip_k", "ellip_f", "ellip_rf", "ellip_j"]

EPS = 2.220446049250313e-16
_MAX_AGM = 64  # AGM steps; m1 = 1e-308 needs 14
_M1_HYPERBOLIC = 1e-11  # below: sn, cn, dn on [0, K/2] from the expansion about m = 1


class FloatShim:
    """The handful of numpy functions the elliptic code uses, on Python floats, so that the
    scalar summary runs without numpy."""

    sqrt = staticmethod(math.sqrt)
    sinh = staticmethod(math.sinh)
    cosh = staticmethod(math.cosh)
    tanh = staticmethod(math.tanh)
    sin = staticmethod(math.sin)
    cos = staticmethod(math.cos)
    arcsin = staticmethod(math.asin)
    arctan2 = staticmethod(math.atan2)
    floor = staticmethod(math.floor)
    copysign = staticmethod(math.copysign)
    abs = staticmethod(abs)
    maximum = staticmethod(max)
    minimum = staticmethod(min)
    fmod = staticmethod(math.fmod)
    pi = math.pi

    @staticmethod
    def where(c, a, b):
        return a if c else b

    @staticmethod
    def any(x):
        return bool(x)

    @staticmethod
    def rint(x):
        return float(round(x))


def backend_of(*values):
    """numpy if any value is a numpy array, else the scalar shim."""
    for v in values:
        if type(v).__module__ == "numpy":
            import numpy

            return numpy
    return FloatShim


def ellip_agm(m, m1):
    """The arithmetic-geometric mean sequence of the descending Landen transform for parameter
    ``m`` with complement ``m1 = 1 - m`` (both given, both in [0, 1], ``m1 > 0``):
    lists ``a, b, c`` with :math:`a_0 = 1, b_0 = \\sqrt{m_1}, c_0 = \\sqrt m` and
    :math:`c_{n+1} = c_n^2 / (4 a_{n+1})` (no cancellation).  Works on floats and on numpy
    arrays (then all elements run the same number of steps, enough for the slowest)."""
    xp = backend_of(m, m1)
    a = m1 * 0 + 1.0
    b = xp.sqrt(m1)
    c = xp.sqrt(m)
    A, B, C = [a], [b], [c]
    for _ in range(_MAX_AGM):
        if not xp.any(c > EPS * a):
            break
        a_next = (a + b) / 2
        c = c * c / (4 * a_next)
        b = xp.sqrt(a * b)
        a = a_next
        A.append(a)
        B.append(b)
        C.append(c)
    return A, B, C


def ellip_k(m, m1, agm=None):
    """The complete elliptic integral of the first kind :math:`K(m) = \\pi / (2\\,
    \\mathrm{AGM}(1, \\sqrt{m_1}))`; ``m1 = 1 - m`` given separately (``m1 > 0``)."""
    A, _, _ = agm if agm is not None else ellip_agm(m, m1)
    return math.pi / (2 * A[-1])


def ellip_rf(x, y, z):
    r"""Carlson's symmetric integral :math:`R_F(x, y, z) = \frac12\int_0^\infty
    \frac{dt}{\sqrt{(t+x)(t+y)(t+z)}}` (``x, y, z >= 0``, at most one 0) by duplication
    (Carlson 1995; DLMF 19.36.1), on floats or numpy arrays: a few ulps, with no cancellation
    however small ``x`` and ``y`` are (``F`` near ``K`` next to the separatrix needs that)."""
    xp = backend_of(x, y, z)
    x0, y0 = x, y
    A0 = (x + y + z) / 3
    A = A0
    big = xp.maximum(xp.maximum(xp.abs(A0 - x), xp.abs(A0 - y)), xp.abs(A0 - z))
    Q = (3 * EPS) ** (-1 / 6) * big
    f = 1.0
    for _ in range(200):
        if not xp.any(f * Q >= xp.abs(A)):
            break
        sx, sy, sz = xp.sqrt(x), xp.sqrt(y), xp.sqrt(z)
        lam = sx * sy + sy * sz + sz * sx
        x, y, z = (x + lam) / 4, (y + lam) / 4, (z + lam) / 4
        A = (A + lam) / 4
        f /= 4
    As = xp.where(A > 0, A, 1.0)
    X = (A0 - x0) * f / As
    Y = (A0 - y0) * f / As
    Z = -(X + Y)
    E2 = X * Y - Z * Z
    E3 = X * Y * Z
    return (1 - E2 / 10 + E3 / 14 + E2 * E2 / 24 - 3 * E2 * E3 / 44) / xp.sqrt(A)


def ellip_f(s, c, m1):
    r"""The incomplete integral :math:`F(\varphi \mid m)` for the amplitude
    :math:`\varphi \in [0, \pi/2]` given by ``s = sin(phi) >= 0`` and ``c = cos(phi) >= 0``
    (with :math:`s^2 + c^2 = 1`) and the complement ``m1 = 1 - m`` of the parameter:
    :math:`F = s\,R_F(c^2, c^2 + m_1 s^2, 1)` (``1 - m s^2 = c^2 + m_1 s^2``, no
    cancellation).  Accurate to a few ulps even at ``phi -> pi/2`` with ``m1 -> 0``, where
    F is large and depends on ``c`` alone (the angle itself could not carry that); ``m1 = 0``
    gives :math:`\operatorname{artanh} s`."""
    return s * ellip_rf(c * c, c * c + m1 * s * s, s * 0 + 1.0)


def _sncndn_eighth(xp, u, m1, A, B, C):
    """sn, cn, dn for ``0 <= u <= K/2`` by the backward Landen recurrence (A&S 16.4.3),
    :math:`\\varphi_{n-1} = (\\varphi_n + \\arcsin x_n)/2`, :math:`x_n = (c_n/a_n)\\sin\\varphi_n`;
    dn from :math:`\\sqrt{cn^2 + m_1 sn^2}` (no cancellation).

    Next to ``m = 1`` the ratios :math:`c_n/a_n` are close to 1 for several steps, and
    ``arcsin`` of an ``x`` within rounding of +-1 would lose half the digits (cephes' ellipj
    does).  There :math:`1 - |x_n| = b_{n-1}/a_n + (c_n/a_n)\\, 2\\sin^2(\\delta/2)` is formed
    without cancellation (:math:`a_n - c_n = b_{n-1}` exactly; ``delta`` the distance of
    :math:`\\varphi_n` from the nearest odd multiple of pi/2) and
    :math:`\\arcsin x = \\pm(\\pi/2 - 2\\arcsin\\sqrt{(1 - |x|)/2})`.
    """
    N = len(A) - 1
    phi = (2.0**N) * A[-1] * u
    half_pi = math.pi / 2
    for n in range(N, 0, -1):
        ratio = C[n] / A[n]
        sp = xp.sin(phi)
        if not xp.any(B[n - 1] < 0.5 * A[n]):  # 1 - |x| >= b/a >= 1/2: arcsin is accurate
            phi = (phi + xp.arcsin(ratio * sp)) / 2
            continue
        k = xp.floor(phi / math.pi)
        delta = phi - (k * math.pi + half_pi)  # |sin phi| = cos(delta)
        y = B[n - 1] / A[n] + ratio * 2 * xp.sin(delta / 2) ** 2  # 1 - |x|
        near = y < 0.5
        a = xp.arcsin(xp.where(near, xp.sqrt(xp.maximum(y, 0.0) / 2), ratio * sp))
        a_near = xp.copysign(half_pi - 2 * a, sp)
        phi = (phi + xp.where(near, a_near, a)) / 2
    s, c = xp.sin(phi), xp.cos(phi)
    d = xp.sqrt(c * c + m1 * s * s)
    near1 = m1 < _M1_HYPERBOLIC
    if xp.any(near1):
        # Next to m = 1 cn and dn at K/2 are ~ m1^(1/4), below the absolute accuracy (eps) of
        # cos(phi) above; there A&S 16.15 (first order in m1) is within 2 eps of sn, cn, dn on
        # [0, K/2] (measured against mpmath for m1 <= 1e-10): relative accuracy however small.
        uh = xp.where(near1, u, 0.0)
        sh, ch, th = xp.sinh(uh), xp.cosh(uh), xp.tanh(uh)
        se = 1 / ch
        q = m1 / 4
        s = xp.where(near1, th + q * (sh * ch - uh) * se * se, s)
        c = xp.where(near1, se * (1 - q * (sh * ch - uh) * th), c)
        d = xp.where(near1, se * (1 + q * (sh * ch + uh) * th), d)
    return s, c, d


def ellip_j(u, m, m1, agm=None):
    """Jacobi's ``sn, cn, dn`` of ``u`` for parameter ``m`` with complement ``m1 = 1 - m``
    (both given; ``m1 > 0``), accurate next to ``m = 1``.

    ``u`` is reduced to ``[0, 4K)`` (exactly, by ``fmod``), then to an eighth of the period with
    the quarter-period shifts :math:`\\mathrm{sn}(K - v) = \\mathrm{cn}\\,v / \\mathrm{dn}\\,v`,
    :math:`\\mathrm{cn}(K - v) = \\sqrt{m_1}\\,\\mathrm{sn}\\,v/\\mathrm{dn}\\,v`,
    :math:`\\mathrm{dn}(K - v) = \\sqrt{m_1}/\\mathrm{dn}\\,v`, so that values near a zero keep
    their relative accuracy.  Returns ``(sn, cn, dn, quarter)``, ``quarter`` in {0, 1, 2, 3}
    the quarter period ``u`` falls in, and ``nper`` the whole periods removed.
    """
    agm = agm if agm is not None else ellip_agm(m, m1)
    A, B, C = agm
    xp = backend_of(u, m, m1)
    K = math.pi / (2 * A[-1]) if xp is FloatShim else xp.pi / (2 * A[-1])
    P = 4 * K
    u4 = xp.fmod(u, P)
    u4 = xp.where(u4 < 0, u4 + P, u4)
    u4 = xp.where(u4 >= P, u4 - P, u4)  # -tiny + P rounds to P
    q = xp.minimum(xp.maximum(xp.floor(u4 / K), 0.0), 3.0)
    v = u4 - q * K
    v = xp.minimum(xp.maximum(v, 0.0), K)
    far = v > K / 2
    w = xp.where(far, K - v, v)
    s, c, d = _sncndn_eighth(xp, w, m1, A, B, C)
    kp = xp.sqrt(m1)
    s, c, d = (xp.where(far, c / d, s), xp.where(far, kp * s / d, c), xp.where(far, kp / d, d))
    # quarter shifts: u = K + v: (cn/dn, -k' sn/dn, k'/dn); 2K + v: (-sn, -cn, dn);
    # 3K + v: (-cn/dn, k' sn/dn, k'/dn)
    odd = (q == 1) | (q == 3) if xp is not FloatShim else q in (1.0, 3.0)
    s2 = xp.where(odd, c / d, s)
    c2 = xp.where(odd, -kp * s / d, c)
    d2 = xp.where(odd, kp / d, d)
    flip = q >= 2
    s2 = xp.where(flip, -s2, s2)
    c2 = xp.where(flip, -c2, c2)
    nper = xp.rint((u - u4) / P)
    return s2, c2, d2, q, nper
