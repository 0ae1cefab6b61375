r"""The free rigid body: a tossed book, a die, any box with three different moments.

Problem 1 of E. H. Yong and L. Mahadevan, *Probability, geometry, and dynamics in the toss of a
thick coin* (arXiv:1008.4559): a body with principal moments :math:`I_1 < I_2 < I_3` flipped
with :math:`\boldsymbol\omega(0) = (0, 0, \omega_0)` keeps :math:`\omega_3` nearly constant
while :math:`\omega_1, \omega_2` oscillate with frequency :math:`\Gamma`,
:math:`\Gamma^2 = (I_3 - I_1)(I_3 - I_2)\,\omega_0^2 / (I_1 I_2)`; flipped about the middle
axis it does not stay put (the tennis-racket, or Dzhanibekov, flip).

The torque-free body is solved exactly (Landau & Lifshitz, *Mechanics*, sections 35 and 37).
In a right-handed frame of principal axes ``a, b, c`` with ``b`` the middle moment and ``c``
the axis the angular velocity circulates about (the largest or the smallest moment: the one
whose component of omega never changes sign),

.. math::

    \omega_a = s_a A_{cn}\,\mathrm{cn}(\tau \mid m), \quad
    \omega_b = s_b A_{sn}\,\mathrm{sn}(\tau \mid m), \quad
    \omega_c = s_c A_{dn}\,\mathrm{dn}(\tau \mid m), \quad \tau = r t + \tau_0,

with, writing :math:`p = (I_c - I_b)/(I_c - I_a)`, :math:`q = (I_b - I_a)/(I_c - I_a)`
(both in [0, 1] whichever extreme ``c`` is),

.. math::

    A_{cn}^2 = \omega_a^2 + \tfrac{I_b}{I_a} p\, \omega_b^2, \quad
    A_{sn}^2 = \tfrac{I_a}{I_b p} A_{cn}^2, \quad
    A_{dn}^2 = \tfrac{I_b}{I_c} q\, \omega_b^2 + \omega_c^2, \quad
    r = \operatorname{sign}(I_c - I_a)\, A_{dn} \sqrt{\tfrac{(I_c - I_a)(I_c - I_b)}{I_a I_b}},

    m = \frac{q I_a A_{cn}^2}{p I_c A_{dn}^2}, \qquad
    1 - m = \frac{\omega_c^2 - \frac{q I_a}{p I_c}\omega_a^2}{A_{dn}^2}.

Both ``m`` and its complement ``m1 = 1 - m`` are computed from the initial omega without
cancellation, which is what keeps the solution accurate next to the separatrix (``m1 -> 0``,
where the period :math:`4K(m)/|r|` grows like :math:`(2/|r|) \ln(16/m_1)`).  The Jacobi
functions (:mod:`coincli.core._numerics.elliptic`) are computed by the arithmetic-geometric
mean (descending Landen transform, Abramowitz & Stegun 16.4) from ``m`` *and* ``m1``:
``scipy.special.ellipj`` takes ``m`` alone, and rounding ``1 - m1`` to a double costs
``eps / m1`` of relative accuracy there (1e-4 at ``m1 = 1e-12``).  The argument is first
reduced to an eighth of a period with the quarter-period shifts, so small ``cn`` and ``dn``
keep their relative accuracy; for ``m1 <= 1e-11`` the eighth is evaluated by A&S 16.15
instead (within 2 eps there), and the phase at launch is ``F = sn R_F(cn^2, dn^2, 1)``
(Carlson).  docs/book.md has the derivations and the measured accuracy (a few eps against
mpmath, m1 from 1 to 1e-300).

The attitude has a closed form too: with the space frame's z along the (fixed) angular
momentum and Euler angles (phi, theta, psi) of the body axes ``(a, b, c)``,
:math:`\cos\theta = I_c\omega_c/L`, :math:`\tan\psi = I_a\omega_a/(I_b\omega_b)`, and

.. math::

    \varphi(t) - \varphi(0) = \frac{L}{I_a} t + \frac{L (I_c - I_a)}{I_c I_a r}
    \bigl[G(\tau) - G(\tau_0)\bigr], \qquad
    G(\tau) = \Pi(n; \mathrm{am}\,\tau \mid m) - \tau, \quad
    n = -\frac{I_c q}{I_a p} \le 0,

with the incomplete elliptic integral of the third kind written with Carlson's
:math:`R_J` (``scipy.special.elliprj``), after reducing :math:`\tau` to a half period with
:math:`\Pi(n; \varphi + \pi) = \Pi(n; \varphi) + 2\Pi(n)`.

Two catch rules name the face that is up when the box is caught, from the lab's vertical in
body axes ``v``:

- ``centre`` (default): the face that the vertical through the centre passes through,
  i.e. the largest :math:`|v_i|/s_i` (``s_i`` the side along axis ``i``).  This is the coin's
  catch model of the paper (heads when the angle of the normal to the vertical is below the
  diagonal's angle :math:`\theta_0`), and the rule under which the geometric model (every
  orientation equally likely) gives each face its solid angle from the centre over 4 pi;
- ``normal``: the face whose outward normal is nearest the vertical, the largest
  :math:`|v_i|` (for a cube the two agree; the geometric model then gives 1/6 a face).

Pure functions: numbers in, numbers out.  The scalar summary (:func:`motion`) needs only
:mod:`math`; the vectorized evaluators import numpy, and the attitude also
``scipy.special.elliprj``.
"""

from __future__ import annotations

import math
import sys

from coincli.core._numerics.elliptic import EPS, FloatShim, backend_of, ellip_agm, ellip_f, ellip_j
from coincli.core._numerics.quaternion import frame_quat, qconj, qmul, zxz
from coincli.limits import MAX_PHASE

__all__ = [
    "MAX_PHASE",
    "M1_MIN",
    "MOMENT_SPAN",
    "check_moments",
    "FACES",
    "RULES",
    "box_moments",
    "box_sides",
    "face_shares",
    "Motion",
    "motion",
    "gamma",
    "paper_frequency_shift",
    "flip_asymptote",
    "Orbit",
    "orbit",
    "omega_at",
    "attitude_at",
    "up_vector",
    "face_up",
    "start_quaternion",
]

#: the six faces, by outward normal along +-(body axis): index 2*i for +, 2*i + 1 for -
FACES = ("+1", "-1", "+2", "-2", "+3", "-3")
RULES = ("centre", "normal")


# --------------------------------------------------------------------------- boxes


#: the side of the smallest cube whose moments per unit mass, 2 s^2 / 12, are normal doubles
SMALLEST_CUBE = math.nextafter(math.sqrt(6 * sys.float_info.min), math.inf)


def box_moments(sides):
    """Principal moments per unit mass of a uniform box with sides ``(s1, s2, s3)``:
    :math:`I_1/m = (s_2^2 + s_3^2)/12` and cyclically (units: the sides' unit squared).

    Sides whose moments overflow, or fall below the smallest normal double (a cube's side below
    :data:`SMALLEST_CUBE`), raise ValueError.

    >>> box_moments((2.0, 2.0, 2.0))
    (0.6666666666666666, 0.6666666666666666, 0.6666666666666666)
    """
    s = _positive3(sides, "sides")
    top = max(s)  # scaled first: no overflow for a side below ~1e154 times the others
    x = [v / top for v in s]
    out = tuple(top * top * (x[(i + 1) % 3] ** 2 + x[(i + 2) % 3] ** 2) / 12 for i in range(3))
    if not all(math.isfinite(v) for v in out):
        raise ValueError("the box is too large: its moments overflow a double")
    if not min(out) >= sys.float_info.min:  # 0 or subnormal: the sides' squares underflow
        raise ValueError(f"the sides are too small for double precision: the moments per unit "
                         f"mass (sides squared over 12) fall below {sys.float_info.min:.3g}, "
                         "the smallest normal double")
    return out


def box_sides(moments):
    """The sides of the uniform box with principal moments ``moments``, scaled so that the
    longest is 1: :math:`s_1^2 \\propto I_2 + I_3 - I_1` and cyclically.

    Every rigid body has :math:`I_i \\le I_j + I_k` (equality: a flat plate, one side 0);
    moments that break it belong to no body, and raise ValueError.
    """
    m = _positive3(moments, "moments")
    top = max(m)
    x = [v / top for v in m]
    sq = []
    for i in range(3):
        j, k = (i + 1) % 3, (i + 2) % 3
        v = x[j] + x[k] - x[i]
        if v < -8 * EPS:
            d = _distinct(*m, m[j] + m[k])  # enough digits to show I_i > I_j + I_k
            a, b, c, s = (f"{x:.{d}g}" for x in (*m, m[j] + m[k]))
            raise ValueError(
                f"moments {a}, {b}, {c} belong to no rigid body: each must be at most the sum "
                f"of the other two (I{i + 1} = {(a, b, c)[i]} > I{j + 1} + I{k + 1} = {s})")
        sq.append(max(v, 0.0))
    s = [math.sqrt(v) for v in sq]
    top = max(s)
    return tuple(v / top for v in s)


def face_shares(sides, rule: str = "centre"):
    """The geometric model: each face's chance of being up when every orientation is equally
    likely, in the order of :data:`FACES` (+1, -1, +2, -2, +3, -3).

    Under the ``centre`` rule, face ``+-k`` is up when the vertical through the centre passes
    through it: its chance is its solid angle from the centre over 4 pi,

    .. math:: P(\\pm k) = \\frac{1}{\\pi}\\arctan\\frac{s_i s_j}{s_k \\sqrt{s_1^2 + s_2^2 + s_3^2}}

    (the solid angle of a rectangle of sides ``2A x 2B`` seen from distance ``C`` on its axis is
    :math:`4\\arctan(AB / (C\\sqrt{A^2+B^2+C^2}))`).  Under ``normal`` every face has 1/6 for any
    box (the three axes are alike for a uniformly random rotation).  Sides may be 0 (a flat
    plate, as :func:`box_sides` gives for moments with :math:`I_3 = I_1 + I_2`).

    >>> [round(p, 12) for p in face_shares((1, 1, 1))]
    [0.166666666667, 0.166666666667, 0.166666666667, 0.166666666667, 0.166666666667, 0.166666666667]
    """
    if rule not in RULES:
        raise ValueError(f"rule must be one of {', '.join(RULES)}, got {rule!r}")
    s = [float(v) for v in sides]
    if len(s) != 3 or not all(math.isfinite(v) and v >= 0 for v in s) or max(s) <= 0:
        raise ValueError(f"sides must be three finite lengths >= 0, not all 0; got {sides!r}")
    if rule == "normal":
        return (1 / 6,) * 6
    top = max(s)
    x = [v / top for v in s]
    diag = math.sqrt(x[0] ** 2 + x[1] ** 2 + x[2] ** 2)
    out = []
    for k in range(3):
        i, j = (k + 1) % 3, (k + 2) % 3
        p = math.atan2(x[i] * x[j], x[k] * diag) / math.pi
        out += [p, p]
    return tuple(out)


def _positive3(values, what):
    try:
        v = tuple(float(x) for x in values)
    except (TypeError, ValueError):
        raise ValueError(f"{what} must be three numbers, got {values!r}") from None
    if len(v) != 3:
        raise ValueError(f"{what} must be three numbers, got {len(v)}")
    if not all(math.isfinite(x) and x > 0 for x in v):
        raise ValueError(f"{what} must be finite and > 0, got {', '.join(_g(x) for x in v)}")
    return v


def _g(x: float) -> str:
    return f"{x:.6g}"


def _distinct(*xs: float) -> int:
    """The fewest significant digits (6 at least, 17 at most) that show different numbers of
    ``xs`` differently: ``2.0000001 > 2`` rather than ``2 > 2``."""
    for digits in range(6, 17):
        shown = [f"{x:.{digits}g}" for x in xs]
        if all((a == b) == (x == y) for (a, x) in zip(shown, xs, strict=True)
               for (b, y) in zip(shown, xs, strict=True)):
            return digits
    return 17


# --------------------------------------------------------------------------- the motion


class Orbit:
    """The constants of torque-free motions (floats, or numpy arrays for many at once).

    Internal frame: ``I = (Ia, Ib, Ic)`` with omega circulating about ``c``; ``frame_perm`` and
    ``frame_sign`` map the user's body axes to it (``w_frame[k] = sign[k] * w_user[perm[k]]``,
    a proper rotation).  Everything is in scaled units: moments over the largest, omega over
    ``scale`` (its largest |component|), time ``t * scale``.
    """

    __slots__ = ("moments", "omega0", "scale", "mom", "perm_c", "perm_a", "sign_c", "sign_a",
                 "rev", "Ia", "Ib", "Ic", "wa", "wb", "wc", "sa", "sb", "sc", "acn", "asn",
                 "adn", "m", "m1", "r", "n", "tau0", "sn0", "cn0", "dn0", "agm", "K",
                 "stationary", "separatrix", "sphere", "L", "xp")

    def __repr__(self):
        return f"Orbit(moments={self.moments}, omega0={self.omega0!r})"


def orbit(moments, omega) -> Orbit:
    """The constants of the free motion of a body with principal ``moments`` (any positive
    numbers, any order) started with body angular velocity ``omega`` (rad/s about the same
    axes): three floats, or an array of shape ``(..., 3)`` for many motions at once."""
    I = check_moments(moments)
    xp = backend_of(omega)
    if xp is FloatShim:
        w = tuple(float(x) for x in omega)
        if len(w) != 3 or not all(math.isfinite(x) for x in w):
            raise ValueError(f"omega must be three finite numbers, got {omega!r}")
        w1, w2, w3 = w
        scale = max(abs(x) for x in w)
    else:
        w = xp.asarray(omega, dtype=float)
        if w.shape[-1:] != (3,):
            raise ValueError(f"omega must have shape (..., 3), got {w.shape}")
        if not xp.isfinite(w).all():
            raise ValueError("omega must be finite")
        w1, w2, w3 = w[..., 0], w[..., 1], w[..., 2]
        scale = xp.abs(w).max(axis=-1)
    o = Orbit()
    o.xp, o.moments, o.omega0, o.scale = xp, I, omega, scale
    top = max(I)
    mom = tuple(v / top for v in I)
    o.mom = mom
    # sorted frame (a proper rotation: an odd permutation flips the middle axis)
    order = sorted(range(3), key=lambda k: (mom[k], k))
    parity = _parity(order)
    o.perm_c, o.sign_c = tuple(order), (1.0, parity, 1.0)
    o.perm_a, o.sign_a = (order[2], order[1], order[0]), (1.0, -parity, 1.0)
    Ia, Ib, Ic = (mom[k] for k in order)
    sc_ = xp.where(scale > 0, scale, 1.0)
    ws = [(w1, w2, w3)[order[k]] / sc_ for k in range(3)]
    ws[1] = ws[1] * parity
    wa, wb, wc = ws
    o.sphere = Ia == Ic
    dca = Ic - Ia
    if o.sphere:
        p = q = 0.0
    else:
        p, q = (Ic - Ib) / dca, (Ib - Ia) / dca
    # which extreme axis omega circulates about: the sign of L^2 - 2 E Ib (the separatrix at 0)
    big = xp.maximum(xp.abs(wa), xp.abs(wc))
    bs = xp.where(big > 0, big, 1.0)
    d = Ic * p * (wc / bs) ** 2 - Ia * q * (wa / bs) ** 2  # the sign of L^2 - 2 E Ib
    exact = None
    if Ia == Ib:
        rev = d != d  # False, shaped like d
    elif Ib == Ic:
        rev = d == d  # True
    else:
        rev = d < 0
        if xp is FloatShim or w.ndim == 1:  # one motion: the separatrix decided in exact rationals
            exact = _exact_m1(I, (w1, w2, w3), order)
            if exact is not None:
                rev = exact[0] < 0 if xp is FloatShim else xp.asarray(exact[0] < 0)
    o.rev = rev
    # the circulation frame: (a, b, c) = sorted, or reversed with b negated (proper)
    o.Ia = xp.where(rev, Ic, Ia)
    o.Ib = Ib
    o.Ic = xp.where(rev, Ia, Ic)
    o.wa = xp.where(rev, wc, wa)
    o.wb = xp.where(rev, -wb, wb)
    o.wc = xp.where(rev, wa, wc)
    P_, Q_ = xp.where(rev, q, p), xp.where(rev, p, q)
    wa, wb, wc, Ia_, Ic_ = o.wa, o.wb, o.wc, o.Ia, o.Ic
    zero = scale == 0
    one_axis = ((w1 == 0) & (w2 == 0)) | ((w2 == 0) & (w3 == 0)) | ((w1 == 0) & (w3 == 0)) \
        if xp is not FloatShim else sum(x != 0 for x in (w1, w2, w3)) <= 1
    in_plane = (Ia == Ib) & (ws[2] == 0) | (Ib == Ic) & (ws[0] == 0) if xp is not FloatShim else (
        (Ia == Ib and ws[2] == 0) or (Ib == Ic and ws[0] == 0))
    stationary = zero | one_axis | in_plane if xp is not FloatShim else bool(
        zero or one_axis or in_plane)
    if o.sphere:
        stationary = stationary | True if xp is not FloatShim else True
    o.stationary = stationary
    Psafe = xp.where(P_ > 0, P_, 1.0)
    # amplitudes as scaled hypotenuses, ratios of them: no square underflows (a perturbation
    # of 1e-140 of the spin still counts; below ~1e-150 m1 leaves the double range: _check_m1)
    kab = (Ib / Ia_) * P_
    acn = _hypot(xp, wa, wb, kab)
    adn = _hypot(xp, wc, wb, (Ib / Ic_) * Q_)
    asn = acn * xp.sqrt(Ia_ / (Ib * Psafe))
    adn_s = xp.where(adn > 0, adn, 1.0)
    kac = Q_ * Ia_ / (Psafe * Ic_)  # <= 1e16 or so (p is 1 ulp at least, or 0 and replaced)
    # ratios clamped at 1e100 (m and m1 are clamped to [0, 1] anyway): no overflow when the
    # moments differ by 1e17 and more
    m = xp.where(adn > 0, kac * xp.minimum(acn / adn_s, 1e100) ** 2, 0.0)
    m1 = xp.where(adn > 0, (wc / adn_s) ** 2 - kac * xp.minimum(xp.abs(wa) / adn_s, 1e100) ** 2,
                  1.0)
    m1 = xp.maximum(m1, 0.0)
    m = xp.minimum(m, 1.0)
    if exact is not None:  # correctly rounded: 0 exactly on the separatrix, no cancellation
        D, num, den = exact
        m1 = num / den + 0.0 * m1
        m = (den - num) / den + 0.0 * m
        if num != 0 and m1 < M1_MIN:
            raise ValueError(_M1_TOO_SMALL)
    else:
        _check_m1(xp, m1, wa, wc, adn_s)
    if o.sphere:
        m, m1 = m * 0.0, m1 * 0.0 + 1.0
    o.m, o.m1 = m, m1
    o.acn, o.asn, o.adn = acn, asn, adn
    o.sa = xp.where(wa < 0, -1.0, 1.0)
    o.sc = xp.where(wc < 0, -1.0, 1.0)
    o.sb = o.sa * o.sc
    rr = (Ic_ - Ib) * (Ic_ - Ia_) / (Ia_ * Ib)
    o.r = xp.where(Ic_ > Ia_, 1.0, -1.0) * adn * xp.sqrt(xp.maximum(rr, 0.0))
    o.n = xp.where(Psafe > 0, -(Ic_ * Q_) / (Ia_ * Psafe), 0.0)
    # a rate that underflows (moments 1e-17 apart, spins 1e-300) leaves omega constant on any
    # time a double can hold: the motion is steady there
    stationary = stationary | (o.r == 0) if xp is not FloatShim else bool(stationary or o.r == 0)
    o.stationary = stationary
    # the phase at t = 0: cn0 = |wa| / acn >= 0 (so |tau0| <= K), sn0 = sb * wb / asn
    acn_s = xp.where(acn > 0, acn, 1.0)
    good = acn > 0
    o.cn0 = xp.where(good, xp.minimum(xp.abs(wa) / acn_s, 1.0), 1.0)
    o.sn0 = xp.where(good, o.sb * xp.minimum(
        xp.abs(wb) * xp.sqrt(kab) / acn_s, 1.0) * xp.where(wb < 0, -1.0, 1.0), 0.0)
    o.dn0 = xp.sqrt(o.cn0 * o.cn0 + m1 * o.sn0 * o.sn0)
    o.separatrix = (m1 == 0) & ~stationary if xp is not FloatShim else (m1 == 0 and not stationary)
    m1_agm = xp.where(m1 > 0, m1, 1.0)
    m_agm = xp.where(m1 > 0, m, 0.0)
    o.agm = ellip_agm(m_agm, m1_agm)
    o.K = xp.where(m1 > 0, xp.pi / (2 * o.agm[0][-1]), math.inf)
    # F(phi0 | m) with cn0 > 0 unless the motion is steady (then tau0 is not used)
    cn0 = xp.where(stationary, 1.0, o.cn0)
    sn0 = xp.where(stationary, 0.0, xp.abs(o.sn0))
    tau0 = ellip_f(sn0, cn0, m1)
    tau0 = xp.where(o.sn0 < 0, -tau0, tau0)
    o.tau0 = xp.where(stationary, 0.0, tau0)
    o.L = xp.sqrt((Ia * ws[0]) ** 2 + (Ib * ws[1]) ** 2 + (Ic * ws[2]) ** 2)
    return o


#: the smallest distance ``m1 = 1 - m`` to the separatrix that can be followed: a spin closer to
#: the middle axis than about 1e-150 of it (but not on it) has m1 below the range of a double
M1_MIN = 1e-300


def _exact_m1(moments, omega, order):
    """``(D, num, den)``, whole numbers, for one motion of a body with three different moments
    (``order`` sorts them): the sign of :math:`D = L^2 - 2 E I_b = \\sum_i I_i (I_i - I_b)
    \\omega_i^2` says which extreme axis omega circulates about (0 on the separatrix), and
    ``m1 = num / den``,

    .. math:: m_1 = \\frac{D (I_c - I_a)}{(I_c - I_b)\\,(I_c (I_c - I_a)\\omega_c^2
       + I_b (I_b - I_a)\\omega_b^2)}

    in the circulation frame (``c`` the largest moment when ``D >= 0``, else the smallest).
    The doubles given are taken as exact (each a whole number times a common power of two for
    the moments and another for omega: ``m1`` is homogeneous in both), so a spin exactly on the
    separatrix (moments 3, 4, 6 with omega 2, 1, 1) gives ``m1 = 0`` however the moments are
    scaled, and next to it ``num / den`` (Python's correctly rounded division of integers) has
    no cancellation.  None when nothing circulates (omega 0)."""
    Ia, Ib, Ic = _whole([float(moments[k]) for k in order])
    wa, wb, wc = _whole([float(omega[k]) for k in order])
    D = Ia * (Ia - Ib) * wa * wa + Ic * (Ic - Ib) * wc * wc
    if D < 0:  # about the smallest axis: exchange a and c
        Ia, Ic, wa, wc = Ic, Ia, wc, wa
    num = D * (Ic - Ia)
    den = (Ic - Ib) * (Ic * (Ic - Ia) * wc * wc + Ib * (Ib - Ia) * wb * wb)
    if den == 0:
        return None
    if den < 0:
        num, den = -num, -den
    return D, num, den


def _whole(values):
    """Whole numbers proportional to the doubles ``values`` (exactly: a common power of 2)."""
    pairs = [v.as_integer_ratio() for v in values]
    top = max(d for _, d in pairs)  # every denominator is a power of 2
    return [n * (top // d) for n, d in pairs]


def _check_m1(xp, m1, wa, wc, adn):
    """ValueError when the motion is next to the separatrix but ``m1`` is below :data:`M1_MIN`
    (it would round to 0 and the motion pass for the separatrix, flipping once and never back):
    the spin is within about 1e-150 of the middle axis without being on it."""
    big = xp.maximum(xp.abs(wa), xp.abs(wc)) / adn
    bad = (m1 < M1_MIN) & (big > 0) & (big < 1e-140)
    if xp.any(bad):
        raise ValueError(_M1_TOO_SMALL)


_M1_TOO_SMALL = (
    "the spin is too close to the middle axis without being on it (about 1e-150 of the spin "
    f"or less: m1 = 1 - m below {M1_MIN:.0e}) for a double to follow; give a perturbation of "
    "at least 1e-140 of the spin, or exactly 0")


#: the smallest moment over the largest that the motion can be followed for: beyond, ratios of
#: moments overflow a double (a needle 1e-150 thick and 1e150 long spans 1e-300 and is fine)
MOMENT_SPAN = 1e-305


def check_moments(moments):
    """The three moments as floats; ValueError unless they are finite and > 0 and the smallest
    is at least :data:`MOMENT_SPAN` of the largest."""
    I = _positive3(moments, "moments")
    if min(I) < MOMENT_SPAN * max(I):
        raise ValueError(
            f"the moments {_g(I[0])}, {_g(I[1])}, {_g(I[2])} span more than 1e305 (smallest over "
            f"largest {min(I) / max(I):.3g}); at most that span can be followed in doubles")
    return I


def _hypot(xp, x, y, k):
    """sqrt(x^2 + k y^2), k >= 0, scaled so that no square underflows or overflows."""
    big = xp.maximum(xp.abs(x), xp.abs(y))
    bs = xp.where(big > 0, big, 1.0)
    return big * xp.sqrt((x / bs) ** 2 + k * (y / bs) ** 2)


def _parity(order) -> float:
    inv = sum(1 for i in range(3) for j in range(i + 1, 3) if order[i] > order[j])
    return -1.0 if inv % 2 else 1.0


def _frame_values(o: Orbit, tau):
    """(sn, cn, dn, quarter, nper) of tau for the orbit's parameter; separatrix and stationary
    motions included (their quarter and nper are 0)."""
    xp = o.xp
    m1 = xp.where(o.m1 > 0, o.m1, 1.0)
    m = xp.where(o.m1 > 0, o.m, 0.0)
    s, c, d, q, nper = ellip_j(tau, m, m1, o.agm)
    if xp.any(o.separatrix):
        ts = xp.where(o.separatrix, tau, 0.0)
        th = xp.tanh(ts)
        se = 1 / xp.cosh(xp.minimum(xp.abs(ts), 710.0))
        s = xp.where(o.separatrix, th, s)
        c = xp.where(o.separatrix, se, c)
        d = xp.where(o.separatrix, se, d)
        q = xp.where(o.separatrix, 0.0, q)
        nper = xp.where(o.separatrix, 0.0, nper)
    return s, c, d, q, nper


def _user_from_frame(o: Orbit, va, vb, vc):
    """Vector components in the circulation frame -> the user's body axes."""
    xp = o.xp
    comps = (va, vb, vc)
    user_c, user_a = [0.0] * 3, [0.0] * 3
    for k in range(3):  # user axis perm[k] gets sign[k] * frame component k
        user_c[o.perm_c[k]] = o.sign_c[k] * comps[k]
        user_a[o.perm_a[k]] = o.sign_a[k] * comps[k]
    return [xp.where(o.rev, user_a[i], user_c[i]) for i in range(3)]


def omega_at(o: Orbit, t):
    """Body angular velocity (rad/s, the user's axes) at times ``t`` (s): numpy array of shape
    ``broadcast(o, t) + (3,)``; exactly the launch value at ``t = 0``."""
    import numpy as np

    t = np.asarray(t, dtype=float)
    ts = t * o.scale
    tau = o.r * ts + o.tau0
    s, c, d, _, _ = _frame_values(_as_np(o), tau)
    va = o.sa * o.acn * c
    vb = o.sb * o.asn * s
    vc = o.sc * o.adn * d
    st = np.asarray(o.stationary)
    if st.any():
        va = np.where(st, o.wa, va)
        vb = np.where(st, o.wb, vb)
        vc = np.where(st, o.wc, vc)
    u = _user_from_frame(_as_np(o), va, vb, vc)
    out = np.stack(np.broadcast_arrays(*u), axis=-1) * np.asarray(o.scale)[..., None]
    # at t = 0 the launch values themselves (the solution returns them to a few ulps)
    w0 = np.broadcast_to(np.asarray(o.omega0, dtype=float), out.shape)
    return np.where((np.broadcast_to(t, out.shape[:-1]) == 0)[..., None], w0, out)


def _as_np(o: Orbit) -> Orbit:
    if o.xp is not FloatShim:
        return o
    import numpy as np

    o.xp = np
    return o


# --------------------------------------------------------------------------- attitude


def attitude_at(o: Orbit, t, start=(1.0, 0.0, 0.0, 0.0)):
    """The body's attitude at times ``t`` (s): a unit quaternion (w, x, y, z), ``w >= 0``, as a
    numpy array of shape ``broadcast + (4,)``, rotating body (user's axes) to lab coordinates,
    given the attitude ``start`` at t = 0 (a quaternion, or an array of them ``(..., 4)``;
    returned exactly at t = 0)."""
    import numpy as np

    o = _as_np(o)
    t = np.asarray(t, dtype=float)
    ts = t * o.scale
    tau = o.r * ts + o.tau0
    s, c, d, q, nper = _frame_values(o, tau)
    s0, c0, d0 = o.sn0, o.cn0, o.dn0
    Ia, Ib, Ic = (np.asarray(v, dtype=float) for v in (o.Ia, o.Ib, o.Ic))
    L = np.asarray(o.L, dtype=float)
    # Euler angles (phi, theta, psi) of the frame (a, b, c) about L
    ka = np.sqrt(Ia / np.abs(np.where(Ic != Ia, Ic - Ia, 1.0)))
    kb = np.sqrt(Ib / np.abs(np.where(Ic != Ib, Ic - Ib, 1.0)))

    def angles(sn, cn, dn):
        wa = o.sa * o.acn * cn
        wb = o.sb * o.asn * sn
        wc = o.sc * o.adn * dn
        Ls = np.where(L > 0, L, 1.0)
        theta = np.arctan2(np.hypot(Ia * wa, Ib * wb) / Ls, Ic * wc / Ls)
        psi = np.arctan2(o.sa * ka * cn, o.sb * kb * sn)
        return theta, psi

    theta, psi = angles(s, c, d)
    theta0, psi0 = angles(s0, c0, d0)
    # phi(t) - phi(0)
    n = np.asarray(o.n, dtype=float)
    r = np.asarray(o.r, dtype=float)
    # a rate below 1e-100 (moments 1e-17 apart and more) turns tau by less than 1e-88 in any
    # time allowed (|omega| t <= 1e12): there G(tau) - G(tau0) = G'(tau0) r t to the last bit,
    # and dividing by r would overflow
    slow = np.abs(r) < 1e-100
    rs = np.where(slow, 1.0, r)
    with np.errstate(over="ignore"):
        coef = L * (Ic - Ia) / (Ic * Ia * rs)
    Gt = _Gfun(o, s, c, d, q, nper, tau, np)
    G0 = _Gfun(o, s0, c0, d0, np.zeros_like(np.asarray(s0, dtype=float)),
               np.zeros_like(np.asarray(s0, dtype=float)), o.tau0, np)
    slope = L * (Ic - Ia) / (Ic * Ia) * (1 / (1 - n * s0 * s0) - 1)  # r * coef * G'(tau0)
    # a symmetric top (n = 0) has G = 0 exactly, where coef may overflow (its smallest moment
    # 1e-300 of the others: a needle spun about its axis): no inf * 0
    dG = Gt - G0
    with np.errstate(over="ignore", invalid="ignore"):
        turn = np.where(dG == 0, 0.0, coef * dG)
    dphi = L / Ia * ts + np.where(slow, slope * ts, turn)
    # q = q0 * conj(qP) * conj(E(0)) * E(t) * qP with E = Euler z-x-z (phi, theta, psi): the
    # constant factors once per motion, E(t) by the closed form of a z-x-z rotation (two sines
    # and cosines of half-angle sums) instead of three rotations and two products a time
    qc, qa = frame_quat(o.perm_c, o.sign_c), frame_quat(o.perm_a, o.sign_a)
    rev = np.asarray(o.rev)
    qP = tuple(np.where(rev, qa[k], qc[k]) for k in range(4))
    q0 = np.asarray(start, dtype=float)
    q0 = tuple(q0[..., k] for k in range(4))
    left = qmul(qmul(q0, qconj(qP)), qconj(zxz(np, 0.0, theta0, psi0)))
    qm = qmul(qmul(left, zxz(np, dphi, theta, psi)), qP)
    # stationary motions: a rotation about the (constant) omega by |omega| t
    st = np.asarray(o.stationary)
    if st.any():
        w = np.asarray(o.omega0, dtype=float)
        sc = np.asarray(o.scale, dtype=float)
        sc = np.where(sc > 0, sc, 1.0)
        wn = np.linalg.norm(w / sc[..., None], axis=-1) * sc  # |omega| 1e300: no overflow
        ang = wn * t
        h = ang / 2
        axis = w / np.where(wn > 0, wn, 1.0)[..., None]
        sh = np.sin(h)
        qs = (np.cos(h), axis[..., 0] * sh, axis[..., 1] * sh, axis[..., 2] * sh)
        qm = tuple(np.where(st, qmul(q0, qs)[k], qm[k]) for k in range(4))
    out = np.stack(np.broadcast_arrays(*qm), axis=-1)
    out = out / np.linalg.norm(out, axis=-1, keepdims=True)
    # at t = 0 the start itself, exactly; then the sign with w >= 0 (q and -q are one attitude)
    start_b = np.broadcast_to(np.stack(q0, axis=-1), out.shape)
    out = np.where((np.broadcast_to(t, out.shape[:-1]) == 0)[..., None], start_b, out)
    return np.where(out[..., :1] < 0, -out, out)


def _Gfun(o, s, c, d, q, nper, tau, np):
    """G(tau) = Pi(n; am tau | m) - tau for periodic motions, and its separatrix form
    [sqrt(nu) atan(sqrt(nu) tanh tau) - nu tau] / (1 + nu), nu = -n."""
    from scipy.special import elliprj

    n = np.asarray(o.n, dtype=float)
    jl = np.where(q == 0, 0.0, np.where(q == 3, 2.0, 1.0))
    sign = np.where(jl == 1, -1.0, 1.0)
    sr, cr = s * sign, c * sign
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        g = n / 3 * sr**3 * elliprj(cr * cr, d * d, 1.0, 1 - n * sr * sr)
        m1 = np.where(np.asarray(o.m1) > 0, o.m1, 1.0)
        half = n / 3 * elliprj(0.0, m1, 1.0, 1 - n)  # Pi(n | m) - K
        j = 2 * nper + jl
        g = np.where(j != 0, g + 2 * j * half, g)
        sep = np.asarray(o.separatrix)
        if sep.any():
            nu = -n
            rn = np.sqrt(nu)
            g_sep = (rn * np.arctan(rn * np.tanh(tau)) - nu * tau) / (1 + nu)
            g = np.where(sep, g_sep, g)
        g = np.where(np.asarray(o.stationary), 0.0, g)
    return g


# --------------------------------------------------------------------------- the paper's exercise


def axis_roles(moments):
    """'smallest', 'middle', 'largest' for each axis, or 'tied' when it equals another."""
    out = []
    for i in range(3):
        others = [moments[j] for j in range(3) if j != i]
        if moments[i] in others:
            out.append("tied")
        elif moments[i] < min(others):
            out.append("smallest")
        elif moments[i] > max(others):
            out.append("largest")
        else:
            out.append("middle")
    return out


def gamma(moments, omega0: float, axis: int):
    """The paper's linearized rate for a spin ``omega0`` about body ``axis`` (0, 1 or 2):
    :math:`\\Gamma^2 = \\omega_0^2 (I_x - I_y)(I_x - I_z) / (I_y I_z)`.

    Returns ``(kind, value)``: ``("oscillation", Gamma)`` about the largest or the smallest
    axis (:math:`\\Gamma^2 > 0`; for ``axis = 2`` the largest this is the paper's
    :math:`\\Gamma^2 = (I_3 - I_1)(I_3 - I_2)\\omega_0^2 / (I_1 I_2)`), ``("growth", lambda)``
    about the middle one (:math:`\\Gamma^2 = -\\lambda^2`,
    :math:`\\lambda = \\omega_0\\sqrt{(I_3 - I_2)(I_2 - I_1)/(I_1 I_3)}`), ``("neutral", 0.0)``
    when the axis's moment equals another's.
    """
    I = _positive3(moments, "moments")
    top = max(I)
    x, y, z = I[axis] / top, I[(axis + 1) % 3] / top, I[(axis + 2) % 3] / top
    prod = (x - y) * (x - z)
    val = abs(float(omega0)) * math.sqrt(abs(prod) / (y * z))
    if prod > 0:
        return "oscillation", val
    if prod < 0:
        return "growth", val
    return "neutral", 0.0


def _extreme_frame(moments, axis):
    """(Ia, Ib, Ic, ia, ib) for a spin about ``axis`` = c, an extreme axis: b the middle."""
    I = moments
    j, k = (axis + 1) % 3, (axis + 2) % 3
    # b is the other axis whose moment is nearer I_c's... the middle one of the three
    ib, ia = (j, k) if abs(I[j] - I[axis]) < abs(I[k] - I[axis]) else (k, j)
    if min(I[j], I[k]) <= I[axis] <= max(I[j], I[k]):
        raise ValueError("the axis must be the largest or the smallest moment")
    return I[ia], I[ib], I[axis], ia, ib


def paper_frequency_shift(moments, omega, axis=None):
    """The exact expansion of the paper's exercise: for ``omega`` near an extreme axis ``c``
    (the largest or the smallest moment; ``b`` the middle axis, ``a`` the other extreme), the
    relative difference between the exact frequency of omega_a, omega_b and the paper's
    :math:`\\Gamma` (with :math:`\\omega_0 = \\omega_c(0)`) is

    .. math:: \\frac{\\Omega}{\\Gamma} - 1 = \\frac{q}{4 I_c}\\Bigl(I_b\\,\\varepsilon_b^2
       - \\frac{I_a}{p}\\,\\varepsilon_a^2\\Bigr) + O(\\varepsilon^4), \\qquad
       \\varepsilon_a = \\frac{\\omega_a(0)}{\\omega_c(0)},\\;
       \\varepsilon_b = \\frac{\\omega_b(0)}{\\omega_c(0)},

    :math:`p = (I_c - I_b)/(I_c - I_a)`, :math:`q = (I_b - I_a)/(I_c - I_a)`: second order in
    the perturbation, of either sign, and 0 for a symmetric top (``q = 0``: the regular
    precession's frequency is exactly Gamma).  For the largest axis (the paper's case, with
    ``I1 < I2 < I3``) the coefficient reads
    :math:`\\frac{I_2 - I_1}{4 I_3 (I_3 - I_1)}\\bigl(I_2\\varepsilon_2^2 - \\frac{I_1 (I_3 - I_1)}
    {I_3 - I_2}\\varepsilon_1^2\\bigr)`.

    Derivation: :math:`\\Omega = \\pi |r| / (2K(m))`, :math:`|r| = \\Gamma\\,A_{dn}/|\\omega_c(0)|
    = \\Gamma (1 + \\frac{I_b q}{2 I_c}\\varepsilon_b^2 + \\dots)`,
    :math:`K = \\frac{\\pi}{2}(1 + \\frac m4 + \\dots)`, :math:`m = \\frac{q I_a}{p I_c}
    (\\varepsilon_a^2 + \\frac{I_b}{I_a} p\\,\\varepsilon_b^2) + \\dots`.

    Returns the second-order term (a float).  ``omega`` is given in the user's axes; the spin
    axis ``axis`` (default: the one with the largest :math:`|I_i \\omega_i|`) must be an
    extreme one.
    """
    I = _positive3(moments, "moments")
    w = [float(v) for v in omega]
    top = max(I)
    I = tuple(v / top for v in I)
    big = max(abs(v) for v in w)
    if not (math.isfinite(big) and big > 0):
        raise ValueError(f"omega must be three finite numbers, not all 0; got {omega!r}")
    w = [v / big for v in w]  # scaled: no underflow of I * omega, no overflow of ratios
    if axis is None:
        axis = max(range(3), key=lambda i: abs(I[i] * w[i]))
    if w[axis] == 0:
        raise ValueError(f"omega has no component about axis {axis + 1}: no perturbation of a "
                         "spin about it to expand in")
    Ia, Ib, Ic, ia, ib = _extreme_frame(I, axis)
    p, q = (Ic - Ib) / (Ic - Ia), (Ib - Ia) / (Ic - Ia)
    if q == 0:  # a symmetric top: regular precession, the frequency is Gamma exactly
        return 0.0
    ea, eb = w[ia] / w[axis], w[ib] / w[axis]
    return q / (4 * Ic) * (Ib * eb * eb - Ia / p * ea * ea) + 0.0  # no -0.0


def flip_asymptote(moments, omega):
    """The time between flips for a spin near the middle axis, from the separatrix asymptotics:
    with ``omega = omega_0 (eps_a, 1, eps_c)`` about the middle axis ``b``,

    .. math:: T_{flip} \\approx \\frac{1}{\\lambda} \\ln \\frac{16 I_b (I_c - I_b)(I_b - I_a)}
       {(I_c - I_a)\\,\\lvert I_c (I_c - I_b)\\varepsilon_c^2 - I_a (I_b - I_a)\\varepsilon_a^2
       \\rvert}, \\qquad \\lambda = \\omega_0 \\sqrt{\\frac{(I_c - I_b)(I_b - I_a)}{I_a I_c}},

    (a the smallest moment, c the largest), from :math:`T_{flip} = 2K(m)/|r|`,
    :math:`K = \\frac12 \\ln(16/m_1) + O(m_1 \\ln m_1)`,
    :math:`|r| = \\lambda(1 + O(\\varepsilon^2))`
    and :math:`m_1 = (I_c - I_a)\\lvert\\dots\\rvert / (I_b (I_c - I_b)(I_b - I_a)) +
    O(\\varepsilon^4)`.  Relative error :math:`O(\\varepsilon^2)`; the flips are
    :math:`\\ln(1/\\varepsilon)/\\lambda` apart, the time a perturbation growing like
    :math:`e^{\\lambda t}` takes to become of order 1.  Returns seconds (inf when the
    perturbation lies on the separatrix to this order, or is 0).
    """
    I = _positive3(moments, "moments")
    w = [float(v) for v in omega]
    top = max(I)
    I = tuple(v / top for v in I)
    order = sorted(range(3), key=lambda k: I[k])
    ia, ib, ic = order
    Ia, Ib, Ic = I[ia], I[ib], I[ic]
    if not Ia < Ib < Ic:
        raise ValueError("the flip needs three different moments")
    if w[ib] == 0:
        raise ValueError("omega has no component about the middle axis: no flip to time")
    kind, lam = gamma(I, w[ib], ib)
    ea, ec = w[ia] / w[ib], w[ic] / w[ib]
    den = (Ic - Ia) * abs(Ic * (Ic - Ib) * ec * ec - Ia * (Ib - Ia) * ea * ea)
    if den == 0 or lam == 0:
        return math.inf
    return math.log(16 * Ib * (Ic - Ib) * (Ib - Ia) / den) / lam


# --------------------------------------------------------------------------- the summary


def _overflow_inf(f):
    try:
        return f()
    except (OverflowError, ZeroDivisionError):
        return math.inf


class Motion:
    """What :func:`motion` finds: plain floats (seconds, rad/s, the user's axes).

    ``kind``: 'rest' (omega = 0), 'steady' (a spin about a principal axis, or any spin of a
    body with three equal moments: omega stays constant), 'periodic', or 'separatrix' (exactly
    on it: one flip, never back).  ``axis``: the body axis omega circulates about (its
    component never changes sign); ``spin_axis``: the axis nearest the angular momentum at
    launch (largest :math:`|I_i\\omega_i|`), ``role`` that axis's moment (smallest, middle,
    largest, tied).  ``period``: of the angular velocity (inf on the separatrix, None when
    steady); ``half_period``: between successive reversals of the middle-axis component (the
    flips, when the spin is near the middle axis); ``first_flip``: the first such reversal
    after launch.  ``omega_min``, ``omega_max``: each component's range over the motion.
    ``gamma_kind``, ``gamma``: :func:`gamma` about ``spin_axis``; ``frequency`` the exact
    2 pi / period; ``gamma_shift`` its relative difference to Gamma and ``gamma_shift_2`` the
    second-order prediction (:func:`paper_frequency_shift`); ``flip_asymptote``
    (:func:`flip_asymptote`) for a spin near the middle axis.
    """

    __slots__ = ("moments", "omega0", "kind", "axis", "spin_axis", "role", "m", "m1", "rate",
                 "period", "half_period", "first_flip", "omega_min", "omega_max", "gamma_kind",
                 "gamma", "frequency", "gamma_shift", "gamma_shift_2", "flip_asymptote",
                 "energy", "momentum")

    def __init__(self, **kw):
        for k in self.__slots__:
            setattr(self, k, kw.get(k))

    def __repr__(self):
        return "Motion(" + ", ".join(f"{k}={getattr(self, k)!r}" for k in self.__slots__) + ")"


def motion(moments, omega) -> Motion:
    """The summary of the free motion started with body angular velocity ``omega`` (rad/s
    about the axes of ``moments``): scalars only, computed with :mod:`math` (no numpy)."""
    w = tuple(float(v) for v in omega)
    o = orbit(moments, w)  # on floats: no numpy
    I = o.moments
    s = o.scale
    roles = axis_roles(I)
    ws = tuple(v / s for v in w) if s else w  # scaled: I * 5e-324 must not underflow to 0
    spin_axis = max(range(3), key=lambda i: (abs(I[i] * ws[i]), -i))
    energy = momentum = 0.0
    if s:
        energy = _overflow_inf(lambda: sum(I[i] * (w[i] / s) ** 2 for i in range(3)) * s * s / 2)
        momentum = _overflow_inf(
            lambda: math.sqrt(sum((I[i] * w[i] / s) ** 2 for i in range(3))) * s)
    out = Motion(moments=I, omega0=w, spin_axis=spin_axis, role=roles[spin_axis], m=o.m,
                 m1=o.m1, energy=energy, momentum=momentum)
    if s == 0:
        out.kind = "rest"
    elif o.stationary:
        out.kind = "steady"
    elif o.separatrix:
        out.kind = "separatrix"
    else:
        out.kind = "periodic"
    if out.kind in ("rest", "steady"):
        out.omega_min = out.omega_max = w
        out.rate = 0.0
        out.axis = spin_axis
    else:
        rate = abs(o.r) * s
        out.rate = rate
        perm, sign = (o.perm_a, o.sign_a) if o.rev else (o.perm_c, o.sign_c)
        out.axis = perm[2]
        kp = math.sqrt(o.m1)
        sep = out.kind == "separatrix"
        ranges = [
            (0.0, o.acn) if sep and o.sa > 0 else (-o.acn, 0.0) if sep else (-o.acn, o.acn),
            (-o.asn, o.asn),
            (o.adn * kp, o.adn) if o.sc > 0 else (-o.adn, -o.adn * kp),
        ]
        lo, hi = [0.0] * 3, [0.0] * 3
        for k in range(3):
            a, b = ranges[k]
            if sign[k] < 0:
                a, b = -b, -a
            lo[perm[k]], hi[perm[k]] = a * s + 0.0, b * s + 0.0  # no -0.0
        out.omega_min, out.omega_max = tuple(lo), tuple(hi)
        K = o.K
        out.period = 4 * K / rate if not sep else math.inf
        out.half_period = 2 * K / rate if not sep else math.inf
        tau0, fwd = o.tau0, o.r > 0
        if sep:
            ahead = (fwd and tau0 < 0) or (not fwd and tau0 > 0)
            out.first_flip = abs(tau0) / rate if ahead else math.inf
        elif fwd:
            out.first_flip = (-tau0 if tau0 < 0 else 2 * K - tau0) / rate
        else:
            out.first_flip = (tau0 if tau0 > 0 else 2 * K + tau0) / rate
        out.frequency = 2 * math.pi / out.period if not sep else 0.0
    if roles[spin_axis] == "tied" and out.kind in ("periodic", "separatrix") and \
            roles[out.axis] != "tied":
        # a symmetric top: the paper's question is about its symmetry axis (regular precession)
        spin_axis = out.spin_axis = out.axis
        out.role = roles[spin_axis]
    out.gamma_kind, out.gamma = gamma(I, w[spin_axis], spin_axis)
    if out.gamma_kind == "oscillation" and out.kind in ("periodic", "steady"):
        if out.kind == "steady":  # the limit of a vanishing perturbation
            out.frequency = out.gamma
            out.gamma_shift = 0.0
        elif out.axis == spin_axis:
            out.gamma_shift = out.frequency / out.gamma - 1
        shift = paper_frequency_shift(I, w, spin_axis)
        # a perturbation beyond the double range (inf - inf) has no second-order term to give
        out.gamma_shift_2 = shift if math.isfinite(shift) else None
    if out.gamma_kind == "growth" and out.kind != "rest":
        out.flip_asymptote = flip_asymptote(I, w)
    return out


# --------------------------------------------------------------------------- the catch


def start_quaternion(face: str):
    """A unit quaternion (w, x, y, z) for a box launched with ``face`` (one of :data:`FACES`)
    up: its outward normal along the lab's +z.  (Which way the box points about the vertical
    does not matter for which face is up later: the whole motion turns with it.)"""
    h = math.sqrt(0.5)
    table = {"+3": (1.0, 0.0, 0.0, 0.0), "-3": (0.0, 1.0, 0.0, 0.0),
             "+1": (h, 0.0, -h, 0.0), "-1": (h, 0.0, h, 0.0),
             "+2": (h, h, 0.0, 0.0), "-2": (h, -h, 0.0, 0.0)}
    if face not in table:
        raise ValueError(f"face must be one of {', '.join(FACES)}, got {face!r}")
    return table[face]


def up_vector(quat):
    """The lab's vertical (+z) in body axes for attitudes ``quat`` (array ``(..., 4)``, body to
    lab): the third row of the rotation matrix."""
    import numpy as np

    q = np.asarray(quat, dtype=float)
    w, x, y, z = q[..., 0], q[..., 1], q[..., 2], q[..., 3]
    return np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], axis=-1)


def face_up(up, sides, rule: str = "centre"):
    """Index into :data:`FACES` of the face up for lab verticals ``up`` (body axes, array
    ``(..., 3)``): under ``centre`` the largest :math:`|v_i| / s_i` (compared as
    :math:`|v_i| s_j s_k`, so a side of 0 is allowed), under ``normal`` the largest
    :math:`|v_i|`; ``2 i`` when :math:`v_i > 0` (face +i), ``2 i + 1`` otherwise."""
    import numpy as np

    if rule not in RULES:
        raise ValueError(f"rule must be one of {', '.join(RULES)}, got {rule!r}")
    v = np.asarray(up, dtype=float)
    s = [float(x) for x in sides]
    top = max(s)
    s = [x / top for x in s]
    if rule == "centre":
        weight = np.array([s[1] * s[2], s[2] * s[0], s[0] * s[1]])
    else:
        weight = np.ones(3)
    i = np.argmax(np.abs(v) * weight, axis=-1)
    comp = np.take_along_axis(v, i[..., None], axis=-1)[..., 0]
    return 2 * i + (comp < 0)


CHUNK = 1 << 16  # tosses per vectorized batch (also fixes the random stream)


def toss_chunks(n: int, seed: int, *, moments, sides, spin, flight, start="+3",
                rule="centre"):
    """Face codes (indices into :data:`FACES`) of ``n`` boxes caught after their flight, in
    batches (numpy int8 arrays), from ``numpy.random.default_rng(seed)``.

    ``spin``: three distributions of omega_1, omega_2, omega_3 (rad/s, body axes), ``flight``
    one of the flight time (s), each an object with ``sample(rng, k)`` (a float for a fixed
    value, else an array), like :class:`coincli.core.toss.launch.Dist`.  ``start``: a face of
    :data:`FACES` up at launch, or 'random' (a uniformly random attitude: Haar measure, from
    four normals).  Each batch draws a full :data:`CHUNK` of every quantity in a fixed order
    (omega_1, omega_2, omega_3, flight time, then the start attitude), so a seed gives the same
    tosses on every machine and a shorter run is a prefix of a longer one.
    """
    import numpy as np

    rng = np.random.default_rng(seed)
    q0 = None if start == "random" else start_quaternion(start)
    done = 0
    while done < n:
        k = min(CHUNK, n - done)
        w = np.empty((CHUNK, 3))
        for i in range(3):
            w[:, i] = spin[i].sample(rng, CHUNK)
        tf = np.broadcast_to(np.asarray(flight.sample(rng, CHUNK), dtype=float), (CHUNK,))
        if q0 is None:
            qs = rng.normal(size=(CHUNK, 4))
            qs /= np.linalg.norm(qs, axis=1, keepdims=True)
        else:
            qs = q0
        w, tf = w[:k], tf[:k]
        qs = qs if q0 is not None else qs[:k]
        codes = catch(moments, sides, w, tf, qs, rule)
        yield codes.astype(np.int8)
        done += k


def catch(moments, sides, omega, t, start, rule="centre"):
    """Faces up (indices into :data:`FACES`) of boxes launched with body angular velocities
    ``omega`` (``(..., 3)``, rad/s) from attitudes ``start`` (quaternions) and caught after
    ``t`` seconds.  ValueError when some |omega| t exceeds :data:`MAX_PHASE`."""
    import numpy as np

    w = np.asarray(omega, dtype=float)
    tt = np.asarray(t, dtype=float)
    check_phase(np.abs(w).max(axis=-1) * (np.sqrt(3) * tt))  # 1e308 * 0 is 0, not inf * 0
    # no time, no motion: a box caught at once shows its start face whatever its spin (even one
    # whose motion could not be followed, next to the separatrix beyond the double range)
    w = np.where((np.broadcast_to(tt, w.shape[:-1]) == 0)[..., None], 0.0, w)
    o = orbit(moments, w)
    q = attitude_at(o, tt, start)
    return face_up(up_vector(q), sides, rule)


def check_phase(phase):
    """ValueError when some |omega| t (rad) is beyond :data:`MAX_PHASE`, or not finite."""
    import numpy as np

    ph = np.asarray(phase, dtype=float)
    if ph.size and not (np.all(np.isfinite(ph)) and ph.max() <= MAX_PHASE):
        top = float(np.nanmax(np.where(np.isfinite(ph), ph, np.inf)))
        raise ValueError(f"the body would turn {top:.3g} rad; at most {MAX_PHASE:.0e} rad "
                         "(|omega| t) can be followed before rounding makes the attitude noise")
