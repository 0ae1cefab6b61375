r"""Reference values for :mod:`coincli.core.models`, from the paper's textbook formulas in mpmath.

Written independently of ``models.py``: no half-angle forms, no error-free transformations, just

- ``theta0 = acos(xi / sqrt(1 + xi^2))`` (Fig. 1b; ``0`` for ``xi = inf``);
- ``P_G(sides) = cos theta0``, ``P_G(heads) = P_G(tails) = (1 - cos theta0) / 2`` (eq. 11);
- ``P_D(heads) = P_D(tails) = theta0 / pi``, ``P_D(sides) = 1 - 2 theta0 / pi`` (eq. 12);
- Table I with ``theta1 = acos((cos theta0 - cos^2 psi) / sin^2 psi)`` and
  ``theta2 = acos((-cos theta0 - cos^2 psi) / sin^2 psi)`` (eqs. 9-10);
- the inverses ``xi = p / sqrt(1 - p^2)`` (of eq. 11) and ``xi = tan(pi p / 2)`` (of eq. 12).

Every double input is converted exactly (``mpf(float)``).  These forms cancel catastrophically
(``1 - 2 theta0/pi`` for a thin coin, ``1 + xi^2`` for a thick one, ``acos`` near 1), so each value
is evaluated at a working precision of 50 digits *plus* the digits such cancellation can cost for
the given inputs, and again at twice that; the two must agree to 50 significant digits (or the
precision doubles again).  The answer is therefore correct to 50 digits, far beyond a double.
"""

from __future__ import annotations

import math

import mpmath
from mpmath import mp, mpf

DPS = 50  #: significant digits the reference values are accurate to

__all__ = [
    "DPS",
    "ref_theta0",
    "ref_geometric",
    "ref_dynamic",
    "ref_conditional",
    "ref_geometric_inverse",
    "ref_dynamic_inverse",
    "ref_boundaries",
    "ref_conditional_inverse",
    "inverse_condition",
    "ulp",
    "ulp_error",
]


# --------------------------------------------------------------------------- adaptive precision


def _guard_digits(*args):
    """Digits that cancellation may cost for these inputs: about twice their decimal exponent."""
    g = 0
    for a in args:
        if a != 0 and math.isfinite(a):
            g = max(g, 2 * abs(math.frexp(a)[1]) * 30103 // 100000 + 10)
    return g


def _agree(a, b):
    if a == b:
        return True
    if mpmath.isinf(a) or mpmath.isinf(b):
        return False
    return abs(a - b) <= abs(b) * mpf(10) ** (-DPS - 2)


def _adaptive(fn, *args):
    """Evaluate ``fn`` on the exact values of the double ``args`` until two precisions agree."""
    dps = DPS + 20 + _guard_digits(*args)
    prev = None
    for _ in range(8):
        with mp.workdps(dps):
            val = fn(*(mpf(a) for a in args))
        if prev is not None and all(_agree(x, y) for x, y in zip(prev, val, strict=True)):
            with mp.workdps(DPS):
                return tuple(+v for v in val)  # rounded to DPS digits
        prev = val
        dps *= 2
    raise ArithmeticError(f"reference did not converge for {fn.__name__}{args}")


# --------------------------------------------------------------------------- textbook formulas


def _cos_theta0(xi):
    if mpmath.isinf(xi):
        return mpf(1)
    return xi / mpmath.sqrt(1 + xi**2)


def _theta0(xi):
    return mpmath.acos(_cos_theta0(xi))


def _geometric(xi):
    c = _cos_theta0(xi)
    face = (1 - c) / 2
    return face, c, face


def _dynamic(xi):
    th0 = _theta0(xi)
    face = th0 / mpmath.pi
    return face, 1 - 2 * th0 / mpmath.pi, face


def _clamped_acos(x):
    return mpmath.acos(min(max(x, mpf(-1)), mpf(1)))


def _conditional(xi, psi):
    pi = mpmath.pi
    c = _cos_theta0(xi)
    t = _theta0(xi) / 2
    A = mpmath.cos(psi) ** 2
    B = mpmath.sin(psi) ** 2
    if B == 0:  # psi = 0: the normal never leaves the vertical
        return mpf(1), mpf(0), mpf(0)
    if psi < t or psi > pi - t:  # [0, theta0/2) U (pi - theta0/2, pi]
        return mpf(1), mpf(0), mpf(0)
    # xi = inf: cos theta0 = 1 and theta1 = acos(1) = 0 exactly (the rounded quotient hovers at 1)
    theta1 = mpf(0) if mpmath.isinf(xi) else _clamped_acos((c - A) / B)
    if psi < pi / 2 - t or psi > pi / 2 + t:  # [theta0/2, pi/2 - theta0/2) U mirror
        return theta1 / pi, 1 - theta1 / pi, mpf(0)
    theta2 = _clamped_acos((-c - A) / B)  # [pi/2 - theta0/2, pi/2 + theta0/2]
    return theta1 / pi, (theta2 - theta1) / pi, 1 - theta2 / pi


def _geometric_inverse(p):
    if p == 1:
        return (mpmath.inf,)
    return (p / mpmath.sqrt(1 - p**2),)


def _dynamic_inverse(p):
    if p == 1:
        return (mpmath.inf,)
    return (mpmath.tan(mpmath.pi * p / 2),)


def _sides_equation(p, psi):
    """F(u) increasing in u = log xi, zero at the xi with Table I's P(sides | psi) = p: the
    sides minus p, or (1 - p) minus heads and tails for p > 1/2 (the form that keeps its
    relative accuracy near p = 1, like the code under test; both are the textbook Table I)."""
    q = 1 - p

    def f(u):
        h, s, t = _conditional(mpmath.exp(u), psi)
        return q - (h + t) if p > 0.5 else s - p

    return f


def _root_in_log(f, lo=-800, hi=800):
    """The root of an increasing f on [lo, hi] (in u = log xi): bisection to 1e-6, then the
    Illinois variant of regula falsi (it keeps the bracket) until the bracket is below
    10**-(dps - 5); None when f does not change sign there."""
    lo, hi = mpf(lo), mpf(hi)
    flo, fhi = f(lo), f(hi)
    if flo > 0 or fhi < 0:
        return None
    while hi - lo > mpf(10) ** -6:
        mid = (lo + hi) / 2
        fm = f(mid)
        if fm == 0:
            return mid
        lo, hi, flo, fhi = (mid, hi, fm, fhi) if fm < 0 else (lo, mid, flo, fm)
    eps, side = mpf(10) ** -(mp.dps - 5), 0
    for k in range(10 * mp.dps):
        if hi - lo <= eps * max(1, abs(lo)) or flo == 0 or fhi == 0:
            break
        mid = (lo * fhi - hi * flo) / (fhi - flo)
        if not lo < mid < hi or k % 8 == 7:  # a bisection now and then: no slow crawl
            mid = (lo + hi) / 2
        fm = f(mid)
        if fm < 0:
            lo, flo = mid, fm
            fhi = fhi / 2 if side == -1 else fhi
            side = -1
        else:
            hi, fhi = mid, fm
            flo = flo / 2 if side == 1 else flo
            side = 1
    else:
        raise ArithmeticError("reference root finding did not converge")
    return lo if abs(flo) <= abs(fhi) else hi


def _conditional_inverse(p, psi):
    f = _sides_equation(p, psi)
    psi_m = min(psi, mpmath.pi - psi)
    if psi_m < mpmath.pi / 4:
        # heads only below xi_b = cot(2 psi) (psi = theta0/2 there), and P(sides) grows like
        # sqrt(xi - xi_b) above it: solve in v, u = log xi_b + v**2, where f is smooth
        ub = mpmath.log(mpmath.cot(2 * psi_m))
        if ub >= 800:
            return (mpmath.inf,)
        v = _root_in_log(lambda v: f(ub + v * v), 0, mpmath.sqrt(800 - ub))
        return (mpmath.inf,) if v is None else (mpmath.exp(ub + v * v),)
    u = _root_in_log(f)
    if u is None:  # beyond e**800 or below e**-800: outside the doubles
        return (mpf(0) if f(mpf(-800)) > 0 else mpmath.inf,)
    return (mpmath.exp(u),)


def _boundaries(xi):
    t = _theta0(xi) / 2
    pi = mpmath.pi
    return t, pi / 2 - t, pi / 2 + t, pi - t


# --------------------------------------------------------------------------- public API


def ref_theta0(xi: float):
    """theta0 for the double ``xi``, to ``DPS`` digits (an mpf)."""
    return _adaptive(lambda x: (_theta0(x),), xi)[0]


def ref_geometric(xi: float):
    """(heads, sides, tails) of eq. (11) as mpf values."""
    return _adaptive(_geometric, xi)


def ref_dynamic(xi: float):
    """(heads, sides, tails) of eq. (12) as mpf values."""
    return _adaptive(_dynamic, xi)


def ref_conditional(xi: float, psi: float):
    """(heads, sides, tails) of Table I as mpf values."""
    return _adaptive(_conditional, xi, psi)


def ref_geometric_inverse(p: float):
    """xi with P_G(sides) = p, as an mpf (inf for p = 1)."""
    return _adaptive(_geometric_inverse, p)[0]


def ref_dynamic_inverse(p: float):
    """xi with P_D(sides) = p, as an mpf (inf for p = 1)."""
    return _adaptive(_dynamic_inverse, p)[0]


def ref_conditional_inverse(p: float, psi: float):
    """xi with Table I's P(sides | psi) = p, by root finding on the textbook forms (0 < p < 1,
    sin psi > 0), as an mpf; 0 or inf where the root lies outside [e**-800, e**800]."""
    return _adaptive(_conditional_inverse, p, psi)[0]


def inverse_condition(xi, p: float, psi: float):
    """The condition number of xi with respect to the target the code solves for: the relative
    change in xi per relative change in p (p <= 1/2) or in 1 - p (p > 1/2), at the root xi
    (an mpf), from Table I differentiated numerically at 60 digits."""
    with mp.workdps(60 + _guard_digits(p, 1 - p, psi, float(xi))):
        xi = mpf(xi)
        f = _sides_equation(mpf(p), mpf(psi))
        h = mpf(10) ** -25
        r = mpf(p) if p <= 0.5 else 1 - mpf(p)
        d = (f(mpmath.log(xi) + h) - f(mpmath.log(xi) - h)) / (2 * h)  # d target / d log xi
        return abs(r / d) if d else mpmath.inf


def ref_boundaries(xi: float):
    """The four regime boundaries of Table I on [0, pi], as mpf values."""
    return _adaptive(_boundaries, xi)


# --------------------------------------------------------------------------- error measure

_TINY = mpf(2) ** -1074


def ulp(ref):
    """Spacing of doubles at the exact value ``ref`` (2**-1074 for subnormals)."""
    ref = abs(mpf(ref))
    if ref == 0:
        return _TINY
    _, e = mpmath.frexp(ref)  # ref = m * 2**e, 0.5 <= m < 1
    return max(mpmath.ldexp(mpf(1), int(e) - 53), _TINY)


def ulp_error(computed: float, ref) -> float:
    """``|computed - ref| / ulp(ref)`` as a float; exact zeros and infs must match (else inf)."""
    computed = float(computed)
    if ref == 0 or mpmath.isinf(ref):
        return 0.0 if computed == ref else math.inf
    if not math.isfinite(computed):
        return math.inf
    with mp.workdps(DPS + 10):
        return float(abs(mpf(computed) - ref) / ulp(ref))


# --------------------------------------------------------------------------- input grids
# Shared by tests/test_accuracy.py and benchmarks/accuracy.py, so that the committed table and the
# tests measure the same kind of inputs.

BOUNDARY_OFFSETS = (1e-12, 1e-9, 1e-6)  #: relative and absolute distances from each boundary
#: relative distances farther out: where conditional() rounds its offsets in long double
BAND_OFFSETS = (1e-4, 1e-3, 4e-3, 1e-2, 0.1, 0.3, 0.49)


def xi_grid(n_log: int = 121, n_random: int = 200, n_coin: int = 2000, seed: int = 0) -> list[float]:
    """0, inf, log-spaced and log-uniform random xi in [1e-300, 1e300], and the fair coins.

    Plus ``n_coin`` random xi where real coins and stacks live (uniform on [0, 3] and log-uniform
    on [1e-3, 1e3]): 600 decades at a few points each would leave that band almost unvisited.
    """
    import random

    rng = random.Random(seed)
    out = [0.0, math.inf, 1 / (2 * math.sqrt(2)), 1 / math.sqrt(3), 1.0, 1e-8, 1e8]
    out += [10.0 ** (-300 + 600 * k / (n_log - 1)) for k in range(n_log)]
    out += [10.0 ** rng.uniform(-300, 300) for _ in range(n_random)]
    out += [rng.uniform(0, 3) for _ in range(n_coin // 2)]
    out += [10.0 ** rng.uniform(-3, 3) for _ in range(n_coin - n_coin // 2)]
    return out


def p_grid(n_log: int = 121, n_random: int = 200, seed: int = 0) -> list[float]:
    """p in [1e-300, 1 - 2**-53]: log-spaced towards 0 and towards 1, random, plus 0 and 1."""
    import random

    rng = random.Random(seed)
    out = [0.0, 1.0, 1 - 2.0**-53, 1 - 2.0**-52, 0.5, math.nextafter(0.5, 1), 1 / 3, 2.0**-1074]
    out += [10.0 ** (-300 + 300 * k / (n_log - 1)) for k in range(n_log)]  # towards 0
    out += [1 - 10.0 ** (-15.9 + 15.6 * k / (n_log - 1)) for k in range(n_log)]  # towards 1
    out += [rng.random() for _ in range(n_random)]
    out += [10.0 ** rng.uniform(-300, 0) for _ in range(n_random)]
    out += [1 - 10.0 ** rng.uniform(-16, 0) for _ in range(n_random)]
    return [p for p in out if 0 <= p <= 1]


def boundary_psis(xi: float) -> list[tuple[float, str]]:
    """(psi, kind) near the four regime boundaries of Table I for this xi.

    kind is ``"boundary"`` for points 1e-12, 1e-9, 1e-6 away (relative and absolute) and
    ``BAND_OFFSETS`` times theta0/2 away, and
    ``"adjacent"`` for the doubles nearest to the boundary and their neighbours (closer still).
    """
    out = []
    for b in (float(v) for v in ref_boundaries(xi)):
        for d in BOUNDARY_OFFSETS:
            out += [(b * (1 + d), "boundary"), (b * (1 - d), "boundary"),
                    (b + d, "boundary"), (b - d, "boundary")]
        t = float(ref_boundaries(xi)[0])  # offsets relative to theta0/2, the scale of the band
        for d in BAND_OFFSETS:
            out += [(b + d * t, "boundary"), (b - d * t, "boundary")]
        p = b
        q = b
        for _ in range(3):
            out += [(p, "adjacent"), (q, "adjacent")]
            p, q = math.nextafter(p, -1.0), math.nextafter(q, 4.0)
    return [(p, k) for p, k in out if 0 <= p <= math.pi]


def conditional_cases(n_xi_log: int = 25, n_xi_random: int = 15, n_psi_random: int = 8,
                      seed: int = 0) -> list[tuple[float, float, str]]:
    """(xi, psi, kind): every boundary neighbourhood for a spread of xi, plus interior points.

    kind is ``"boundary"``, ``"adjacent"`` (see :func:`boundary_psis`) or ``"interior"``.
    """
    import random

    rng = random.Random(seed)
    xis = [0.0, math.inf, 1 / (2 * math.sqrt(2)), 1 / math.sqrt(3), 1.0, 1e-8, 1e8]
    xis += [10.0 ** (-300 + 600 * k / (n_xi_log - 1)) for k in range(n_xi_log)]
    xis += [10.0 ** rng.uniform(-300, 300) for _ in range(n_xi_random)]
    xis += [10.0 ** rng.uniform(-6, 6) for _ in range(n_xi_random)]
    out = []
    for xi in xis:
        out += [(xi, p, k) for p, k in boundary_psis(xi)]
        specials = [0.0, math.pi / 2, math.pi, 2.0**-1074, 1e-300]
        out += [(xi, p, "interior") for p in specials]
        out += [(xi, rng.uniform(0, math.pi), "interior") for _ in range(n_psi_random)]
    return out
