"""One-dimensional root finders, minimizer and bisection: the one home of each.

:func:`brent_root`
    Brent's bracketed root finder (inverse quadratic interpolation, secant, bisection) as in
    scipy.optimize.brentq, scalar, pure Python, to a tolerance ``xtol + rtol |x|``: the ends of
    the profile-likelihood interval of :func:`coincli.core.stats.fit.fit_spread`.
:func:`brent_minimize`
    Brent's bounded minimizer (golden section with parabolic steps) as in
    scipy.optimize.minimize_scalar(method="bounded"), scalar, pure Python: the maximum-likelihood
    spread of :func:`coincli.core.stats.fit.fit_spread`.
:func:`positive_roots`
    Many roots at once (numpy): bracketing from a guess, then Chandrupatla's method (inverse
    quadratic interpolation safeguarded by bisection) down to two adjacent doubles, the
    tolerance being the answer's own rounding whatever its size: the inverses ``P(sides) = p``
    of :mod:`coincli.core.averages`.

    Two root finders, not one: each caller prints its root in full (``coin design``'s xi,
    ``coin fit``'s profile ends), and each needs its own stopping rule for those digits.
    Brent's rule (``xtol + rtol |x|``, even at ``xtol = 0``, ``rtol = 2.2e-16``) leaves the
    inverses an ulp or more away from the double of smaller residual in a quarter to a half of
    the cases tried, and would loop in Python over each target; Chandrupatla's run to
    adjacent doubles moves the fit's interval ends in their 12th digit and takes three times the
    likelihood evaluations.
:func:`bisect`
    Halving of a bracket around the point where a monotone predicate turns false, at the
    arithmetic or geometric midpoint: the engine limits of :mod:`coincli.core.bounce.engine`,
    the smallest Monte Carlo tolerance of :mod:`coincli.core.estimators`.

scipy.optimize would cost 0.1-0.2 s of import for routines of a few dozen lines; these are the
same algorithms with the same tolerances, so the answers agree with scipy's to those
tolerances.  numpy is imported inside :func:`positive_roots` and its helper alone (the CLI's
start-up budget).
"""

from __future__ import annotations

import math

__all__ = ["brent_root", "brent_minimize", "positive_roots", "bisect", "POSITIVE_MIN",
           "POSITIVE_MAX"]


# --------------------------------------------------------------------------- Brent

_SQRT_EPS = math.sqrt(2.2e-16)
_GOLDEN = 0.5 * (3.0 - math.sqrt(5.0))


def brent_minimize(func, x1: float, x2: float, xatol: float = 1e-5, maxfun: int = 500,
                   known=()):
    """``(x, f(x))`` minimizing ``func`` on ``[x1, x2]``: Brent's method (golden section with
    parabolic steps), scipy.optimize.minimize_scalar(method="bounded")'s algorithm.

    ``known``: three or more ``(x, f(x))`` inside the bracket already evaluated (a grid around
    the minimum); the search then starts from them with a parabolic step instead of spending
    its first evaluations on golden-section points.
    """

    def sign(v: float) -> float:
        return (v > 0) - (v < 0) + (v == 0)

    a, b = x1, x2
    rat = e = 0.0
    pts = sorted((float(f), float(x)) for x, f in known if a <= x <= b)
    if len(pts) >= 3:
        (fx, xf), (fnfc, nfc), (ffulc, fulc) = pts[:3]
        e = b - a  # allow a parabolic first step
        num = 0
    else:
        fulc = a + _GOLDEN * (b - a)
        nfc, xf = fulc, fulc
        fx = func(xf)
        num = 1
        ffulc = fnfc = fx
    x = xf
    xm = 0.5 * (a + b)
    tol1 = _SQRT_EPS * abs(xf) + xatol / 3.0
    tol2 = 2.0 * tol1
    while abs(xf - xm) > (tol2 - 0.5 * (b - a)):
        golden = True
        if abs(e) > tol1:  # try a parabola through the three best points
            golden = False
            r = (xf - nfc) * (fx - ffulc)
            q = (xf - fulc) * (fx - fnfc)
            p = (xf - fulc) * q - (xf - nfc) * r
            q = 2.0 * (q - r)
            if q > 0.0:
                p = -p
            q = abs(q)
            r = e
            e = rat
            if abs(p) < abs(0.5 * q * r) and q * (a - xf) < p < q * (b - xf):
                rat = (p + 0.0) / q
                x = xf + rat
                if (x - a) < tol2 or (b - x) < tol2:
                    rat = tol1 * sign(xm - xf)
            else:
                golden = True
        if golden:
            e = (a - xf) if xf >= xm else (b - xf)
            rat = _GOLDEN * e
        x = xf + sign(rat) * max(abs(rat), tol1)
        fu = func(x)
        num += 1
        if fu <= fx:
            if x >= xf:
                a = xf
            else:
                b = xf
            fulc, ffulc = nfc, fnfc
            nfc, fnfc = xf, fx
            xf, fx = x, fu
        else:
            if x < xf:
                a = x
            else:
                b = x
            if fu <= fnfc or nfc == xf:
                fulc, ffulc = nfc, fnfc
                nfc, fnfc = x, fu
            elif fu <= ffulc or fulc == xf or fulc == nfc:
                fulc, ffulc = x, fu
        xm = 0.5 * (a + b)
        tol1 = _SQRT_EPS * abs(xf) + xatol / 3.0
        tol2 = 2.0 * tol1
        if num >= maxfun:
            break
    return xf, fx


def brent_root(func, xa: float, xb: float, xtol: float = 1e-12, rtol: float = 8.9e-16,
               maxiter: int = 100, fa: float | None = None, fb: float | None = None) -> float:
    """A zero of ``func`` in ``[xa, xb]`` (the signs at the ends differ): Brent's method as in
    scipy.optimize.brentq (inverse quadratic interpolation, secant, bisection).  ``fa``, ``fb``:
    the values at the ends, when already known."""
    xpre, xcur = xa, xb
    xblk = fblk = spre = scur = 0.0
    fpre = func(xpre) if fa is None else fa
    fcur = func(xcur) if fb is None else fb
    if fpre == 0:
        return xpre
    if fcur == 0:
        return xcur
    if (fpre > 0) == (fcur > 0):
        raise ValueError("the function has the same sign at both ends of the bracket")
    for _ in range(maxiter):
        if fpre != 0 and fcur != 0 and (fpre < 0) != (fcur < 0):
            xblk, fblk = xpre, fpre
            spre = scur = xcur - xpre
        if abs(fblk) < abs(fcur):
            xpre, xcur, xblk = xcur, xblk, xcur
            fpre, fcur, fblk = fcur, fblk, fcur
        delta = (xtol + rtol * abs(xcur)) / 2
        sbis = (xblk - xcur) / 2
        if fcur == 0 or abs(sbis) < delta:
            return xcur
        if abs(spre) > delta and abs(fcur) < abs(fpre):
            if xpre == xblk:  # interpolate
                stry = -fcur * (xcur - xpre) / (fcur - fpre)
            else:  # extrapolate
                dpre = (fpre - fcur) / (xpre - xcur)
                dblk = (fblk - fcur) / (xblk - xcur)
                stry = -fcur * (fblk * dblk - fpre * dpre) / (dblk * dpre * (fblk - fpre))
            if 2 * abs(stry) < min(abs(spre), 3 * abs(sbis) - delta):
                spre, scur = scur, stry  # a good short step
            else:
                spre = scur = sbis
        else:
            spre = scur = sbis
        xpre, fpre = xcur, fcur
        xcur += scur if abs(scur) > delta else (delta if sbis > 0 else -delta)
        fcur = func(xcur)
    return xcur


# --------------------------------------------------------------------------- many roots

POSITIVE_MIN = 5e-324  #: the smallest positive double
POSITIVE_MAX = 1.7976931348623157e308  #: the largest double
_GROW = 32.0  #: the bracketing step (in log x) grows by this factor until the root is caught


def _bit_mid(lo, hi):
    """The double halfway between positive doubles ``lo < hi`` in the order of the doubles (their
    bit patterns are ordered like their values): bisection that ends in at most 64 steps."""
    import numpy as np

    a, b = lo.view(np.int64), hi.view(np.int64)
    return (a + (b - a) // 2).view(np.float64)


def positive_roots(resid, x0, step):
    """Doubles ``x > 0`` where ``resid(x, idx)`` (increasing in x, numpy in and out; ``idx``
    names the elements evaluated) changes sign, for each element of ``x0`` (the guesses).

    Bracketing first: from ``x0``, steps of ``step`` (natural log of x) that grow by
    ``_GROW`` until the sign changes, within [5e-324, 1.8e308].  Then Chandrupatla's method on
    the bracket (in log x while its ends differ by more than 2x, then in x), its smallest step
    one ulp of x, with a bisection of the doubles whenever two steps fail to halve the bracket.
    It stops at two adjacent doubles (or an exact zero) and returns the one with the smaller
    ``|resid|``.  A root above the largest double raises ``ValueError`` whose argument is the
    element's index (the caller words it); one below the smallest positive double gives 0 or
    5e-324, whichever fits better.
    """
    import numpy as np

    m = x0.size
    step = np.broadcast_to(np.asarray(step, dtype=float), (m,)).copy()
    a = np.clip(np.where(np.isfinite(x0) & (x0 > 0), x0, 1.0), POSITIVE_MIN, POSITIVE_MAX)
    fa = resid(a, np.arange(m))
    b, fb = np.full(m, np.nan), np.full(m, np.nan)  # the other end of the bracket
    c, fc = np.full(m, np.nan), np.full(m, np.nan)  # the previous point
    out = np.where(fa == 0, a, np.nan)
    hunt = fa != 0
    with np.errstate(over="ignore", under="ignore"):
        while hunt.any():  # -------------------------------------------------- bracketing
            i = np.flatnonzero(hunt)
            up = fa[i] < 0
            at_end = np.where(up, a[i] == POSITIVE_MAX, a[i] == POSITIVE_MIN)
            if at_end.any():
                j = i[at_end]
                if up[at_end].any():
                    raise ValueError(int(j[up[at_end]][0]))
                f0 = resid(np.zeros(j.size), j)  # the root lies in (0, 5e-324)
                out[j] = np.where(np.abs(fa[j]) <= np.abs(f0), POSITIVE_MIN, 0.0)
                hunt[j] = False
                i, up = i[~at_end], up[~at_end]
                if not i.size:
                    break
            xt = np.clip(a[i] * np.exp(np.where(up, step[i], -step[i])), POSITIVE_MIN,
                         POSITIVE_MAX)
            ft = resid(xt, i)
            caught = np.sign(ft) != np.sign(fa[i])
            k, n = i[caught], i[~caught]
            b[k], fb[k] = a[k], fa[k]  # the bracket [xt, a]; c keeps the point before a
            c[n], fc[n] = a[n], fa[n]
            a[i], fa[i] = xt, ft
            step[n] *= _GROW
            hunt[k] = False
        zero = (fa == 0) & np.isnan(out)
        out[zero] = a[zero]
        live = np.isnan(out)
        slow = np.zeros(m, dtype=np.int8)  # steps in a row that did not halve the bracket
        while live.any():  # ---------------------------------------------- Chandrupatla
            i = np.flatnonzero(live)
            ai, bi, ci, fai, fbi, fci = a[i], b[i], c[i], fa[i], fb[i], fc[i]
            lo, hi = np.minimum(ai, bi), np.maximum(ai, bi)
            logv = hi > 2 * lo
            ya, yb = np.where(logv, np.log(ai), ai), np.where(logv, np.log(bi), bi)
            yc = np.where(logv, np.log(np.where(ci > 0, ci, 1.0)), ci)
            with np.errstate(divide="ignore", invalid="ignore"):
                xi_ = (ya - yb) / (yc - yb)
                phi = (fai - fbi) / (fci - fbi)
                iqi = (phi * phi < xi_) & ((1 - phi) ** 2 < 1 - xi_)
                t = np.where(iqi, fai / (fbi - fai) * fci / (fbi - fci)
                             + (yc - ya) / (yb - ya) * fai / (fci - fai) * fbi / (fci - fbi),
                             np.where(np.isnan(ci), fai / (fai - fbi), 0.5))
                tl = np.where(logv, 2.0**-52, np.spacing(hi)) / np.abs(yb - ya)
            t = np.clip(np.where(np.isfinite(t), t, 0.5), np.minimum(tl, 0.5),
                        1 - np.minimum(tl, 0.5))
            yt = ya + t * (yb - ya)
            xt = np.where(logv, np.exp(yt), yt)
            halve = ~((xt > lo) & (xt < hi)) | (slow[i] >= 2)
            xt = np.where(halve, _bit_mid(lo, hi), xt)
            ft = resid(xt, i)
            same = np.sign(ft) == np.sign(fai)
            c[i], fc[i] = np.where(same, ai, bi), np.where(same, fai, fbi)
            b[i], fb[i] = np.where(same, bi, ai), np.where(same, fbi, fai)
            a[i], fa[i] = xt, ft
            width = hi.view(np.int64) - lo.view(np.int64)
            new = np.abs(b[i].view(np.int64) - xt.view(np.int64))
            slow[i] = np.where(2 * new > width, slow[i] + 1, 0)
            done = (ft == 0) | (new <= 1)
            out[i[done]] = np.where((ft[done] == 0) | (np.abs(ft[done]) <= np.abs(fb[i[done]])),
                                    xt[done], b[i[done]])
            live[i[done]] = False
    return out


# --------------------------------------------------------------------------- bisection


def bisect(below, lo: float, hi: float, *, log: bool = False, rtol: float = 0.0,
           maxiter: int = 200) -> tuple[float, float]:
    """Narrow the bracket ``[lo, hi]`` around the point where the monotone predicate ``below``
    turns false (true at ``lo``, false at ``hi``; neither end is evaluated) and return the final
    ``(lo, hi)``: ``hi`` is the smallest point found where ``below`` is false.

    Each step evaluates ``below`` at the midpoint, geometric (``sqrt(lo hi)``, both ends > 0)
    when ``log``, else arithmetic; it stops after ``maxiter`` steps, or, with ``rtol > 0``, once
    ``hi / lo < 1 + rtol``.
    """
    for _ in range(maxiter):
        mid = math.sqrt(lo * hi) if log else 0.5 * (lo + hi)
        if below(mid):
            lo = mid
        else:
            hi = mid
        if rtol > 0 and hi / lo < 1 + rtol:
            break
    return lo, hi
