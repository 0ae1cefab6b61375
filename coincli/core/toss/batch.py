r"""Many tosses: :func:`toss_many`, the vectorized path of :mod:`coincli.core.toss.flight` (one
evaluation of ``F`` and ``F'`` a toss a round, certified cells refined together, in batches of
8192), and :func:`outcome_codes`, the outcome codes alone, which ``coin simulate`` runs.

Outcomes only
    :func:`simulate` needs outcomes, not times of flight, and :func:`outcome_codes` reads each off
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

from coincli.core._numerics.records import record
from coincli.core._numerics.trig import SIN_TAYLOR, abs_sin_rough, sin_into
from coincli.core.toss.flight import (
    DEFAULT_DIAMETER,
    EPS,
    FALL_TINY,
    HEADS,
    NAMES,
    SIDES,
    SQRT3_2,
    STANDARD_G,
    TAILS,
    Batch,
    alpha_from,
    check_all,
    check_number,
    classify,
    fall_time,
    first_root,
    newton,
    problem_code,
    problem_message,
    scalar_setup,
    setup,
)

__all__ = ["Tosses", "toss_many", "Toss", "toss", "flight_time"]

_TWO_PI = 2.0 * math.pi
_BATCH = 1 << 13  # tosses refined together: arrays of 64 kB stay in cache (1.5 to 2x the speed of 2^16)


# --------------------------------------------------------------------------- many tosses


@record()
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


def outcome_codes(xi, psi, u, omega, *, diameter=DEFAULT_DIAMETER, g=STANDARD_G, contact="rim"):
    """The outcome codes of :func:`toss_many` (an int8 array), for one number ``xi``: the same
    codes, without refining the roots whose outcome their certified cell already decides."""
    return _toss_many(xi, psi, u, omega, diameter, g, contact, None, True)


def _toss_many(xi, psi, u, omega, diameter, g, contact, z0, outcomes_only):
    import numpy as np

    xi, psi, u, omega, diameter, g, thick = check_all(xi, psi, u, omega, diameter, g, contact)
    if z0 is not None:
        z0 = check_number("z0", z0, 0.0, lo_open=True, unit="m")
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
        t, sh, ch = first_root(np, s, m, thick)
        t_f[sl] = t
        a = alpha_from(np, s.sp, s.cp, sh, ch)
        alpha_f[sl] = a
        code[sl] = classify(a, xi_c)
    return Tosses(t_f.reshape(shape), alpha_f.reshape(shape), code.reshape(shape))


def _checked_setup(np, xi, psi, u, om, dia, g, thick, z0, m):
    """:func:`setup` of a batch of ``m`` tosses, refusing the first one the scan cannot follow."""
    with np.errstate(over="ignore", invalid="ignore"):  # refused below, not warned about
        s = setup(np, xi, psi, u, om, dia, g, thick, z0)
        problem = np.broadcast_to(problem_code(np, s), (m,))
    if problem.any():
        k = int(np.argmax(problem != 0))

        def at(v, k=k):
            return float(np.broadcast_to(v, (m,))[k])

        raise ValueError(problem_message(int(problem[k]), at(om), at(u), at(g), at(s.z0),
                                          at(om) * at(s.t_end)))
    return s


def _outcomes_flat(np, flat, n, thick):
    """The outcome codes of ``n`` tosses (``flat``: xi, psi, u, omega, diameter, g, z0 as
    :func:`_toss_many` flattens them; xi, diameter and g numbers, z0 None).

    First :func:`_descent_outcomes` (rim) or :func:`_window_outcomes` (thick) for all; then the
    undecided ones, gathered into full batches (a batch pays numpy's overhead a call, whatever
    its size), by the scan, without refining the roots whose certified cell decides them
    (:func:`first_root` with bands).  The first toss the scan cannot follow is refused, as
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
        _, sh, ch, k, cells = first_root(np, s, m, thick, bands)
        und = np.flatnonzero(k == -1)
        if und.size:
            sp, cp = (v if isinstance(v, float) else v[und] for v in (s.sp, s.cp))
            k[und] = classify(alpha_from(np, sp, cp, sh[und], ch[und]), xi)
        code[r] = k
        if cells is not None:
            gi = cells[0]
            pending.append((r[gi], *cells[1:], *(v if isinstance(v, float) else v[gi]
                                                  for v in (s.sp, s.cp))))
    if pending:  # the few roots to refine, all at once (numpy's overhead is per call)
        g_idx, lo, hi, flo, fplo, fhi, fphi = (np.concatenate([p[i] for p in pending])
                                               for i in range(7))
        q = _cat_batches(np, [p[7] for p in pending], [p[0].size for p in pending])
        _, sh, ch = newton(np, lo, hi, flo, fplo, fhi, fphi, q, thick)
        sp, cp = (np.concatenate([np.broadcast_to(p[i], p[0].shape) for p in pending])
                  for i in (8, 9))
        code[g_idx] = classify(alpha_from(np, sp, cp, sh, ch), xi)
    return code


def _cat_batches(np, qs, sizes):
    """The constants of several :class:`Batch` (of :data:`Batch.FIELDS`) end to end."""
    out = Batch.__new__(Batch)
    for k in Batch.FIELDS:
        vs = [getattr(q, k) for q in qs]
        if all(isinstance(v, float) and v == vs[0] for v in vs):
            setattr(out, k, vs[0])
        else:
            setattr(out, k, np.concatenate([np.broadcast_to(v, (m,)) for v, m in zip(vs,
                                                                                     sizes)]))
    return out


# ------------------------------------------------------------------- window and descent paths


def _window_outcomes(np, psi, u, om, xi, dia, g, thick, bands, m):
    """Outcome codes (``-1`` where undecided) of the tosses whose first contact, wherever it
    falls in the window where it can happen, has one outcome: no root finding at all.

    Contact happens while the centre is below ``Lmax``: in ``[w2s, t_end]``, the descent from
    ``z = Lmax`` to ``z = 0`` (:func:`setup`), once the launch window ``[0, w1]`` is clear
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
    z0 = SQRT3_2 * a + hh
    if thick:
        lmax = math.hypot(a, hh) * (1.0 + 8 * EPS)
        half_width = 0.5 * math.pi - 0.5 * math.atan2(a, hh)  # |psi - pi/2| for amax >= atan2
    else:
        lmax = a * (1.0 + 8 * EPS)
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
    if 2.0 * g * z0 < FALL_TINY:  # may have underflowed (a subnormal g): see fall_time
        t_end = fall_time(np, u, g, z0) * (1.0 + 1e-12)
    hom = 0.5 * om
    x1 = w2s * hom
    x2 = t_end * hom
    sp = abs_sin_rough(np, np.broadcast_to(psi, (m,)))
    ok &= np.abs(psi - 0.5 * math.pi) <= half_width - 1e-9
    ok &= (om > 0) & (x2 < 1e5)
    if d > 0:  # a launch window [0, w1], w1 = 2 d / (u + root): must be clear
        w1 = (2.0 * d * (1.0 + 1e-12)) / root
        ok &= a * np.minimum(om * w1 * (sp + 1e-10), 1.0) + hh < z0 * (1.0 - 1e-6)
    s1 = abs_sin_rough(np, x1)
    s2 = abs_sin_rough(np, x2)
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
_SIN5 = SIN_TAYLOR[4:]  # sin r / r to r^8, |r| <= pi/2: within (pi/2)^11 / 11! < 3.6e-6
_SIN6 = SIN_TAYLOR[3:]  # to r^10: within (pi/2)^13 / 13! < 6e-8
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
    z0 = SQRT3_2 * a
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
    d = a * (1.0 + 8 * EPS) - z0  # Lmax - z0 > 0
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
    sp = abs_sin_rough(np, psi)
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
    sin_into(np, G, B, C, E, _SIN5)  # B: |sin x1|
    sin_into(np, H, F, C, E, _SIN5)  # F: |sin xc|
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
    by :func:`abs_sin_rough` with ``terms`` terms), so ``L = 2a S sqrt(1 - S^2)`` is bounded by
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
    s = abs_sin_rough(np, p * (0.5 * om), terms)
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


# --------------------------------------------------------------------------- one toss


@record(frozen=True)
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
    scalar_setup(xi, psi, u, omega, diameter, g, contact, z0)
    return float(toss_many(xi, psi, u, omega, diameter=diameter, g=g, contact=contact,
                           z0=z0).t_f)


def toss(xi, psi, u, omega, *, diameter=DEFAULT_DIAMETER, g=STANDARD_G, contact="rim", z0=None):
    """Simulate one toss (SI scalars, ``psi`` in radians); return a :class:`Toss`.

    The same computation as :func:`toss_many` (one toss is a batch of one)."""
    s = scalar_setup(xi, psi, u, omega, diameter, g, contact, z0)
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
