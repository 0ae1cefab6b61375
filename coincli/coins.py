"""Real coins and stacks of them.

A stack of ``N`` coins of diameter ``D`` and thickness ``h`` is a cylinder with aspect ratio
``xi = N h / D``.  The paper's fair three-sided coin is eight US quarters glued together
(``xi ~ 0.58``, Fig. 5c); it took the quarter as 24 mm by 1.75 mm.
"""

from __future__ import annotations

import difflib
import math
from typing import NamedTuple

from coincli import models

__all__ = ["Coin", "CATALOG", "get_coin", "custom_coin", "stack_xi", "nearest_stack", "StackChoice"]

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
        """Aspect ratio of one coin, thickness / diameter."""
        return self.thickness_mm / self.diameter_mm


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
    """Aspect ratio of ``count`` coins stacked and glued: ``count * h / D``."""
    if isinstance(count, bool) or not isinstance(count, int) or count < 1:
        raise ValueError(f"count must be a whole number >= 1, got {count!r}")
    return count * coin.thickness_mm / coin.diameter_mm


MAX_STACK = 2**40  #: the tallest stack :func:`nearest_stack` considers under a searched model


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
    ``xi* D / h``, whichever lands nearer the target (ties go to the smaller stack).
    A ValueError if no stack of up to :data:`MAX_STACK` coins reaches ``p_sides``.
    """
    models.check_p(p_sides, "p_sides")
    if sides_of is None:
        def sides_of(x):
            return models.dynamic(x).sides

        target_xi = models.dynamic_inverse(p_sides)
    else:
        target_xi = None
    per_coin = coin.xi
    if target_xi is None:
        # bracket the count by doubling, then bisect on whole numbers
        lo, hi = 1, 1
        while sides_of(hi * per_coin) < p_sides and hi < MAX_STACK:
            lo, hi = hi, hi * 2
        if sides_of(hi * per_coin) < p_sides:
            # the model never gets there (psi = 0 never lands on a side): no "nearest" stack
            raise ValueError(
                f"no stack of up to {MAX_STACK} coins reaches P(sides) = {p_sides:.6g} under "
                f"this model (it gives {sides_of(hi * per_coin):.6g} there)"
            )
        while hi - lo > 1:
            mid = (lo + hi) // 2
            if sides_of(mid * per_coin) < p_sides:
                lo = mid
            else:
                hi = mid
        candidates = {lo, hi}
    else:
        if math.isinf(target_xi):
            raise ValueError("p_sides = 1 needs an infinitely tall stack; choose p_sides < 1")
        n = target_xi / per_coin
        candidates = {max(1, math.floor(n)), max(1, math.ceil(n))}
    best = min(sorted(candidates), key=lambda k: abs(sides_of(k * per_coin) - p_sides))
    neigh = tuple((k, k * per_coin, sides_of(k * per_coin))
                  for k in (best - 1, best, best + 1) if k >= 1)
    return StackChoice(best, best * per_coin, sides_of(best * per_coin), neigh)
