"""Real coins and stacks of them.

A stack of ``N`` coins of diameter ``D`` and thickness ``h`` is a cylinder with aspect ratio
``xi = N h / D``.  The paper's fair three-sided coin is eight US quarters glued together
(``xi ~ 0.58``, Fig. 5c); it took the quarter as 24 mm by 1.75 mm.
"""

from __future__ import annotations

import difflib
import math
from typing import NamedTuple

from coincli.core import models

__all__ = ["Coin", "CATALOG", "get_coin", "custom_coin", "stack_xi", "stack_xis", "nearest_stack",
           "nearest_stacks", "StackChoice", "NoStackError", "MAX_STACK"]

_US_MINT = "US Mint, coin specifications (usmint.gov/learn/coins-and-medals/circulating-coins)"
_EU_REG = (
    "Council Regulation (EC) No 975/98 as amended by No 423/1999, Annex "
    "(diameters and thicknesses of the euro coins)"
)


class Coin(NamedTuple):
    """A coin: its catalog name, diameter and thickness in millimetres, and where they come from.

    Immutable (a NamedTuple: a frozen dataclass costs most of a millisecond to create at import,
    paid by every ``coin`` run).
    """

    name: str
    diameter_mm: float
    thickness_mm: float
    source: str
    label: str = ""

    @property
    def xi(self) -> float:
        """Aspect ratio of one coin, thickness / diameter: :func:`stack_xi` of one coin."""
        return stack_xi(self, 1)


CATALOG: dict[str, Coin] = {
    c.name: c
    for c in (
        Coin("cent", 19.05, 1.52, _US_MINT, "US cent"),
        Coin("nickel", 21.21, 1.95, _US_MINT, "US nickel"),
        Coin("dime", 17.91, 1.35, _US_MINT, "US dime"),
        Coin("quarter", 24.26, 1.75, _US_MINT, "US quarter"),
        Coin("half-dollar", 30.61, 2.15, _US_MINT, "US half dollar"),
        Coin("dollar", 26.49, 2.00, _US_MINT, "US dollar coin"),
        Coin("paper-quarter", 24.0, 1.75, "Yong & Mahadevan, Sec. IV (the quarter as the paper "
             "rounded it)", "US quarter as in the paper"),
        Coin("euro-1c", 16.25, 1.67, _EU_REG, "1 euro cent"),
        Coin("euro-2c", 18.75, 1.67, _EU_REG, "2 euro cent"),
        Coin("euro-5c", 21.25, 1.67, _EU_REG, "5 euro cent"),
        Coin("euro-10c", 19.75, 1.93, _EU_REG, "10 euro cent"),
        Coin("euro-20c", 22.25, 2.14, _EU_REG, "20 euro cent"),
        Coin("euro-50c", 24.25, 2.38, _EU_REG, "50 euro cent"),
        Coin("euro-1", 23.25, 2.33, _EU_REG, "1 euro"),
        Coin("euro-2", 25.75, 2.20, _EU_REG, "2 euro"),
    )
}

_ALIASES = {"penny": "cent", "half": "half-dollar", "halfdollar": "half-dollar",
            "half_dollar": "half-dollar", "quarters": "quarter"}


def get_coin(name: str) -> Coin:
    """Look a coin up by name (case-insensitive); a ValueError suggests the nearest names."""
    key = name.strip().lower()
    key = _ALIASES.get(key, key)
    if key in CATALOG:
        return CATALOG[key]
    near = difflib.get_close_matches(key, list(CATALOG), n=2, cutoff=0.5)
    hint = f"; did you mean {' or '.join(repr(n) for n in near)}?" if near else ""
    raise ValueError(
        f"unknown coin {name!r}{hint} (known: {', '.join(CATALOG)}; see `coin coins`)"
    )


def custom_coin(diameter_mm: float, thickness_mm: float) -> Coin:
    """A coin given by its dimensions (both finite and > 0, in millimetres)."""
    for label, v in (("diameter", diameter_mm), ("thickness", thickness_mm)):
        if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
            raise ValueError(f"{label} must be a finite length > 0 mm, got {v!r}")
    return Coin("custom", float(diameter_mm), float(thickness_mm), "given on the command line",
                f"{diameter_mm:g} x {thickness_mm:g} mm")


def stack_xi(coin: Coin, count: int) -> float:
    """Aspect ratio of ``count`` coins stacked and glued: ``count * h / D``, correctly rounded.

    The one place a stack's xi is computed (``coin stack``, ``table``, ``design`` and ``fair``
    call it or :func:`stack_xis`, ``check`` and ``fit`` for catalog coins): the double nearest
    the exact ratio of the coin's doubles, so ``9 * 1.75 / 24.26`` and ``9 * (1.75 / 24.26)``
    (which differ in the last bit) cannot both appear.  Exact integer arithmetic (Python's
    int / int rounds correctly); inf when the ratio is beyond the double range.
    """
    if isinstance(count, bool) or not isinstance(count, int) or count < 1:
        raise ValueError(f"count must be a whole number >= 1, got {count!r}")
    return _exact_ratio(count, coin.thickness_mm, coin.diameter_mm)


def _exact_ratio(count: int, h: float, d: float) -> float:
    """``count * h / d`` for doubles ``h``, ``d`` > 0, rounded once to the nearest double."""
    hn, hd = h.as_integer_ratio()
    dn, dd = d.as_integer_ratio()
    try:
        return (count * hn * dd) / (hd * dn)
    except OverflowError:
        return math.inf


# Where the vectorized stack_xis trusts its double arithmetic (Dekker's product needs its
# operands and results well inside the double range); outside, it computes exactly.
_SAFE_LO, _SAFE_HI = 2.0**-900, 2.0**900
_MARGIN = 1 - 2.0**-40  # a residual this close to half an ulp is settled exactly


def stack_xis(coin: Coin, counts):
    """:func:`stack_xi` for an array of counts (whole numbers >= 1, as floats): an ndarray.

    Bit for bit the same doubles as :func:`stack_xi`, without a Python call per count: the
    quotient is refined once from the exact residual ``count*h - q*D`` (Dekker's products) and
    then verified to lie within half an ulp of the exact ratio; the few counts where that
    cannot be decided in double arithmetic (a residual within 2**-40 of the rounding boundary,
    or values near the ends of the double range) are computed exactly.
    """
    import numpy as np

    from coincli.core.models import two_prod

    n = np.asarray(counts, dtype=float)
    h, d = coin.thickness_mm, coin.diameter_mm
    if not (_SAFE_LO < h < _SAFE_HI and _SAFE_LO < d < _SAFE_HI):
        return np.array([_exact_ratio(int(k), h, d) for k in n.ravel()]).reshape(n.shape)
    with np.errstate(all="ignore"):
        p, e = two_prod(np, n, h)  # count * h = p + e exactly

        def residual(q):  # count*h - q*D, to ~2**-52 ulp(p): p - s is exact (Sterbenz)
            s, t = two_prod(np, q, d)  # q * D = s + t exactly
            return (p - s) + (e - t)

        q = p / d
        q = q + residual(q) / d  # within a hair of the exact ratio
        r = residual(q)  # the exact ratio is q + r / D
        up = np.nextafter(q, np.inf) - q
        down = q - np.nextafter(q, 0.0)
        half = 0.5 * d * np.where(r >= 0, up, down)
        ok = ((np.abs(r) < half * _MARGIN) & (n >= 1) & (p > _SAFE_LO) & (p < _SAFE_HI)
              & (q > _SAFE_LO) & (q < _SAFE_HI))
    if not ok.all():
        q = np.array(q, dtype=float)
        for k in np.flatnonzero(~ok):
            q.flat[k] = _exact_ratio(int(n.flat[k]), h, d)
    return q


MAX_STACK = 2**40  #: the tallest stack :func:`nearest_stack` considers under a searched model
MAX_STACK_WORDS = "2^40 (about 1.1 x 10^12)"  #: :data:`MAX_STACK` as messages say it


class NoStackError(ValueError):
    """No stack of up to :data:`MAX_STACK` coins reaches the target chance of a side."""


class StackChoice(NamedTuple):
    """The stack nearest a target: its count and the (count, xi, P(sides)) of its neighbours."""

    count: int
    xi: float
    p_sides: float
    neighbours: tuple  # ((count, xi, p_sides), ...) for count-1 (if >= 1), count, count+1


def nearest_stack(coin: Coin, p_sides: float, sides_of=None) -> StackChoice:
    """The number of stacked coins whose chance of a side is nearest ``p_sides``.

    ``sides_of(xi) -> P(sides)`` is the model (default: the dynamic one, eq. 12).  The chance
    is increasing in ``xi``, so the answer is the floor or ceiling of the continuous count
    ``xi* D / h``, whichever lands nearer the target (ties go to the smaller stack).  Every
    stack's xi is :func:`stack_xi`.  A :class:`NoStackError` (a ValueError) if no stack of up
    to :data:`MAX_STACK` coins reaches ``p_sides`` under a given model.
    """
    models.check_p(p_sides, "p_sides")
    if sides_of is None:
        def sides_of(x):
            return models.dynamic(x).sides

        target_xi = models.dynamic_inverse(p_sides)
    else:
        target_xi = None

    def sides(k):
        return sides_of(stack_xi(coin, k))

    if target_xi is None:
        # bracket the count by doubling, then bisect on whole numbers
        lo, hi = 1, 1
        while sides(hi) < p_sides and hi < MAX_STACK:
            lo, hi = hi, hi * 2
        if sides(hi) < p_sides:
            # the model never gets there (psi = 0 never lands on a side), or only past the cap
            raise NoStackError(
                f"no stack of up to {MAX_STACK_WORDS} coins reaches P(sides) = {p_sides:.6g} under "
                f"this model (it gives {sides(hi):.6g} there)"
            )
        while hi - lo > 1:
            mid = (lo + hi) // 2
            if sides(mid) < p_sides:
                lo = mid
            else:
                hi = mid
        candidates = {lo, hi}
    else:
        if math.isinf(target_xi):
            raise ValueError("p_sides = 1 needs an infinitely tall stack; choose p_sides < 1")
        n = target_xi / coin.xi
        candidates = {max(1, math.floor(n)), max(1, math.ceil(n))}
    best = min(sorted(candidates), key=lambda k: abs(sides(k) - p_sides))
    neigh = tuple((k, stack_xi(coin, k), sides(k)) for k in (best - 1, best, best + 1) if k >= 1)
    return StackChoice(best, stack_xi(coin, best), sides(best), neigh)


def nearest_stacks(coin: Coin, p_sides, xi, sides_of) -> list[list]:
    """:func:`nearest_stack` for arrays of targets whose exact aspect ratios ``xi`` are known.

    ``sides_of`` maps an array of xi to an array of P(sides).  The same rule as the scalar
    closed form: the floor or ceiling of ``xi / (h/D)``, whichever lands nearer (ties to the
    smaller).  Returns five lists: the count, its xi, and P(sides) at count, count - 1 and
    count + 1; None where ``xi`` is inf (no finite stack) and for the stack of 0 coins.
    """
    import numpy as np

    p = np.asarray(p_sides, dtype=float)
    with np.errstate(all="ignore"):
        cont = np.asarray(xi, dtype=float) / coin.xi
        finite = np.isfinite(cont)
        c = np.where(finite, cont, 1.0)
        lo = np.maximum(1.0, np.floor(c))
        hi = np.maximum(1.0, np.ceil(c))
        xlo, xhi = stack_xis(coin, lo), stack_xis(coin, hi)
        slo, shi = sides_of(xlo), sides_of(xhi)
        nearer_lo = np.abs(slo - p) <= np.abs(shi - p)
        n = np.where(nearer_lo, lo, hi)
        xn = np.where(nearer_lo, xlo, xhi)  # stack_xis(coin, n): each is correctly rounded
        sn = sides_of(xn)
        sm = np.where(n > 1, sides_of(stack_xis(coin, np.maximum(n - 1, 1.0))), np.nan)
        sp = sides_of(stack_xis(coin, n + 1))
    cols = [n.astype(np.int64).tolist(), xn.tolist(), sn.tolist(), sm.tolist(), sp.tolist()]
    for k in (~finite).nonzero()[0].tolist():
        for col in cols:
            col[k] = None
    for k in np.flatnonzero(np.isnan(sm)).tolist():  # no stack of 0 coins
        cols[3][k] = None
    return cols
