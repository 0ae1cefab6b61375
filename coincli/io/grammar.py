"""Parsing of the values people type: probabilities, lengths, angles, lists and ranges, and the
psi densities of ``--psi-dist`` (:func:`parse_density`).

Pure functions: text in, numbers (or a :class:`coincli.core.densities.Density`) out, ValueError
with a one-line message otherwise.  Nothing here evaluates user text as code; the one file read
is a ``table:FILE`` of ``--psi-dist`` (through :func:`coincli.io.files.read_text`).
"""

from __future__ import annotations

import math
import re
from typing import TYPE_CHECKING

from coincli.errors import shown

if TYPE_CHECKING:
    from coincli.core.densities import Density

__all__ = [
    "parse_number",
    "parse_probability",
    "parse_length_mm",
    "parse_angle_deg",
    "parse_values",
    "parse_range",
    "Range",
    "parse_count",
    "parse_ratio",
    "parse_seed",
    "MAX_ROWS",
    "MAX_COUNT",
    "parse_speed_ms",
    "parse_spin_rads",
    "split_unit",
    "SPEED_UNITS",
    "LENGTH_UNITS",
    "SPIN_UNITS",
    "parse_density",
    "DENSITY_FORMS",
    "MAX_TABLE_BYTES",
]

MAX_ROWS = 1_000_000  #: the most rows a range or list may expand to
MAX_COUNT = 2**53  #: the largest count (of coins) that a double still holds exactly
MAX_SEED_DIGITS = 40  #: the longest seed, in decimal digits

_NUM = re.compile(r"^[+-]?(\d+(\.\d*)?|\.\d+)([eE][+-]?\d+)?$", re.ASCII)  # 0-9 only
_INT = re.compile(r"^[+-]?\d+$", re.ASCII)
# exact factors (as text for Fraction), so 0.955in is the double nearest 24.257 mm
LENGTH_UNITS = {"mm": "1", "cm": "10", "m": "1000", "in": "25.4", '"': "25.4"}


def _underflow_check(v: float, s: str, what: str, text) -> None:
    """Refuse a nonzero number typed that rounds to 0 (``1e-400``): it is not the 0 it became."""
    if v == 0.0:
        mant = re.split(r"[eE]", s.partition("/")[0], maxsplit=1)[0]
        if any(c in "123456789" for c in mant):
            raise ValueError(f"{what} {text!r} is nonzero but below the smallest positive double "
                             "(4.9e-324): type 0, or a value of at least 5e-324")


def parse_number(text: str, what: str = "value", *, allow_inf: bool = False) -> float:
    """A decimal number (``0.5``, ``1e-3``); ``inf`` only if allowed.  No NaN."""
    s = str(text).strip()
    if allow_inf and s.lower() in ("inf", "+inf", "infinity"):
        return math.inf
    if not _NUM.match(s):
        raise ValueError(f"{what} must be a number, got {text!r}")
    v = float(s)
    if math.isinf(v) and not allow_inf:
        raise ValueError(f"{what} must be a finite number, got {text!r}")
    _underflow_check(v, s, what, text)
    return v


def parse_probability(text: str, what: str = "probability") -> float:
    """``0.33``, ``1/3`` or ``33%``, in [0, 1].  Fractions are exact before rounding to a float."""
    s = str(text).strip()
    num, slash, den = s.partition("/")
    if s.endswith("%") and s[:-1].strip().isdigit() and s.isascii():
        num, slash, den = s[:-1], "/", "100"
    try:
        if slash and num.strip().isdigit() and den.strip().isdigit() and s.isascii():
            # whole numbers (1/3, 33%): Python's int / int is correctly rounded, as
            # float(Fraction) is, without importing fractions and decimal (2 ms of start-up)
            if int(den) == 0:
                raise ValueError(f"{what} {text!r} divides by zero")
            v = int(num) / int(den)
        elif s.endswith("%"):
            v = float(_plain(s[:-1], what, text) / 100)
        elif "/" in s:
            num, _, den = s.partition("/")
            d = _plain(den, what, text)
            if d == 0:
                raise ValueError(f"{what} {text!r} divides by zero")
            v = float(_plain(num, what, text) / d)
        else:  # a plain decimal: float() rounds correctly, as float(Fraction(s)) would
            if not _NUM.match(s):
                _plain(s, what, text)
            v = float(s) + 0.0  # -0 -> 0.0
    except OverflowError:  # beyond the double range: certainly not in [0, 1]
        v = math.inf
    except (ValueError, ZeroDivisionError) as exc:
        msg = str(exc)
        if what in msg:
            raise ValueError(msg) from None
        raise ValueError(f"{what} must be a number like 0.33, 1/3 or 33%, got {text!r}") from None
    if not 0.0 <= v <= 1.0:
        raise ValueError(f"{what} must be in [0, 1] (or 0% to 100%), got {text!r}")
    _underflow_check(v, s.rstrip("%"), what, text)
    return v


def _plain(s: str, what: str, shown: str | None = None):
    """The exact value of a plain decimal, its exponent clamped to +-(1000 + its length).

    ``Fraction('1e-99999999')`` builds a hundred-million-digit integer (minutes); clamped, the
    value is still far outside the double range, so it rounds (or fails a range check) the same.
    An error quotes ``shown``, the whole text the user typed (``'1/3%'``, not the ``'1/3'`` of
    it that is not a decimal); ``s`` itself by default.
    """
    from fractions import Fraction  # imported when needed: it costs a millisecond

    s = s.strip()
    m = _NUM.match(s)
    if not m:
        typed = s if shown is None else shown
        raise ValueError(f"{what} must be a number like 0.33, 1/3 or 33%, got {typed!r}")
    if m.group(3):
        mant, _, exp = s.partition("e") if "e" in s else s.partition("E")
        lim = 1000 + len(s)
        e = int(exp)
        if abs(e) > lim:
            s = f"{mant}e{lim if e > 0 else -lim}"
    return Fraction(s)


def parse_ratio(text: str, what: str = "xi", *, allow_inf: bool = False) -> float:
    """A ratio >= 0: a decimal (``0.577``, ``1e-3``) or a fraction (``17/30``, ``1/3.5``).

    A fraction is exact before its one rounding to a float (``17/30`` is the double nearest
    17/30, as ``parse_probability`` gives ``1/3``); ``inf`` only if allowed.  No NaN, no
    negative value.
    """
    s = str(text).strip()
    allowed = f"a number >= 0 like 0.577 or 17/30{' (or inf)' if allow_inf else ''}"
    if allow_inf and s.lower() in ("inf", "+inf", "infinity"):
        return math.inf
    num, slash, den = s.partition("/")
    try:
        if not slash:
            if not _NUM.match(s):
                raise ValueError
            v = float(s) + 0.0
        elif num.strip().isdigit() and den.strip().isdigit() and s.isascii():
            if int(den) == 0:
                raise ZeroDivisionError
            v = int(num) / int(den)  # correctly rounded, as float(Fraction) is
        else:
            d = _plain(den, what, text)
            if d == 0:
                raise ZeroDivisionError
            v = float(_plain(num, what, text) / d)
    except ZeroDivisionError:
        raise ValueError(f"{what} {text!r} divides by zero") from None
    except OverflowError:
        v = math.inf
    except ValueError:
        raise ValueError(f"{what} must be {allowed}, got {text!r}") from None
    if not v >= 0 or (math.isinf(v) and not allow_inf):
        raise ValueError(f"{what} must be {allowed}, got {text!r}")
    _underflow_check(v, s, what, text)
    return v


def parse_seed(text: str, what: str = "--seed") -> int:
    """A seed: a whole number >= 0 of at most 40 digits (numpy's SeedSequence takes any)."""
    s = str(text).strip()
    if not (s.isascii() and s.isdigit()) or len(s) > MAX_SEED_DIGITS:
        raise ValueError(f"{what} must be a whole number >= 0 (at most {MAX_SEED_DIGITS} digits), "
                         f"got {text!r}")
    return int(s)


def parse_length_mm(text: str, what: str = "length") -> float:
    """A length in millimetres: ``24.26``, ``24.26mm``, ``2.4cm``, ``0.955in``; finite, > 0."""
    s = str(text).strip().lower()
    factor = "1"
    for unit, f in sorted(LENGTH_UNITS.items(), key=lambda kv: -len(kv[0])):
        if s.endswith(unit) and _NUM.match(s[: -len(unit)].strip() or "x"):
            s, factor = s[: -len(unit)].strip(), f
            break
    if not _NUM.match(s):
        raise ValueError(
            f"{what} must be a length like 24.26, 24.26mm, 2.4cm or 0.955in, got {text!r}"
        )
    if factor == "1":
        v = float(s)
    else:
        try:
            v = float(_plain(s, what) * _plain(factor, what))
        except OverflowError:
            v = math.inf
    if not (math.isfinite(v) and v > 0):
        raise ValueError(f"{what} must be a finite length > 0, got {text!r}")
    return v


def parse_angle_deg(text: str, what: str = "psi") -> float:
    """An angle in degrees in [0, 180], returned in radians (180 maps to the double nearest pi)."""
    v = parse_number(text, what)
    if not 0.0 <= v <= 180.0:
        raise ValueError(f"{what} must be an angle in [0, 180] degrees, got {text!r}")
    return math.pi if v == 180.0 else math.radians(v)


# Speeds in m/s and spins in rad/s, each unit's factor exact (a decimal, or a rational multiple
# of pi, as text): the value typed times the factor is rounded once.
_PI = "3.14159265358979323846264338327950288419716939937510582097494459"
SPEED_UNITS = {"m/s": ("1", 0), "cm/s": ("0.01", 0), "mm/s": ("0.001", 0),
               "km/h": ("1000/3600", 0), "kph": ("1000/3600", 0), "km/s": ("1000", 0),
               "ft/s": ("0.3048", 0), "fps": ("0.3048", 0), "in/s": ("0.0254", 0),
               "mph": ("0.44704", 0)}  #: unit -> (factor to m/s, power of pi)
SPIN_UNITS = {"rad/s": ("1", 0), "rev/s": ("2", 1), "rps": ("2", 1), "hz": ("2", 1),
              "rpm": ("2/60", 1), "rev/min": ("2/60", 1), "deg/s": ("1/180", 1),
              "°/s": ("1/180", 1)}  #: unit -> (factor, power of pi) to rad/s
_SPEED_SHOWN = "m/s (the default), cm/s, mm/s, km/h, km/s, ft/s, in/s, mph"
_SPIN_SHOWN = "rad/s (the default), rev/s (= Hz), rpm, deg/s"


def split_unit(text: str, units) -> tuple[str, str | None]:
    """``('240', 'cm/s')`` from ``'240cm/s'`` or ``'240 cm/s'``: the text before a unit of
    ``units`` (a dict keyed by lower-case names) that ends it, and the unit; ``(text, None)``
    when none does."""
    s = str(text).strip()
    low = s.lower()
    for unit in sorted(units, key=len, reverse=True):
        if low.endswith(unit) and len(s) > len(unit):
            return s[: -len(unit)].strip(), unit
    return s, None


def _quantity(text: str, what: str, units, default: str, shown: str, noun: str,
              example: str) -> float:
    num, unit = split_unit(text, units)
    if not _NUM.match(num):
        raise ValueError(f"{what} must be a {noun} like {example} (units: {shown}), got {text!r}")
    factor, pi_power = units[unit or default]
    if factor == "1" and not pi_power:
        v = float(num) + 0.0
    else:
        from fractions import Fraction

        try:
            v = float(_plain(num, what) * Fraction(factor) * Fraction(_PI) ** pi_power)
        except OverflowError:
            v = math.inf
    if not (math.isfinite(v) and v >= 0):
        raise ValueError(f"{what} must be a finite {noun} >= 0 (units: {shown}), got {text!r}")
    _underflow_check(v, num, what, text)
    return v


def parse_speed_ms(text: str, what: str = "speed") -> float:
    """A speed in m/s: ``2``, ``2m/s``, ``240cm/s``, ``8.6km/h``, ``7.9ft/s``, ``94in/s``,
    ``5.4mph``; finite and >= 0, the unit's exact factor applied with one rounding."""
    return _quantity(text, what, SPEED_UNITS, "m/s", _SPEED_SHOWN, "speed", "2, 240cm/s or "
                     "8.6km/h")


def parse_spin_rads(text: str, what: str = "spin") -> float:
    """A spin (angular speed) in rad/s: ``40``, ``40rad/s``, ``38rev/s`` (= ``38Hz``),
    ``2300rpm``, ``13700deg/s``; finite and >= 0, one rounding of the exact value."""
    return _quantity(text, what, SPIN_UNITS, "rad/s", _SPIN_SHOWN, "spin rate", "240, 38rev/s or "
                     "2300rpm")


def parse_count(text: str, what: str = "count") -> int:
    """A whole number from 1 to :data:`MAX_COUNT`."""
    s = str(text).strip()
    digits = s.lstrip("+").lstrip("0")
    if not re.fullmatch(r"\+?\d+", s, re.ASCII) or not digits:
        raise ValueError(f"{what} must be a whole number >= 1, got {text!r}")
    if len(digits) > 16 or int(digits) > MAX_COUNT:  # no 5000-digit int() either
        raise ValueError(f"{what} must be a whole number from 1 to {MAX_COUNT}, got {text!r}")
    return int(digits)


def _range_bound(text: str, what: str) -> float:
    """A range's start, stop or step: a decimal, or a fraction such as ``1/10``."""
    if "/" in text:
        try:
            return parse_ratio(text, what)
        except ValueError:
            raise ValueError(f"{what} must be a number like 0.1 or 1/10, got {text!r}") from None
    return parse_number(text, what)


_EXACT_PART = re.compile(r"^[+-]?(\d{1,30}(\.\d{0,30})?|\.\d{1,30})([eE][+-]?\d{1,2})?$",
                         re.ASCII)


def _exact(text: str):
    """A range part as a Fraction when it is a short decimal or a fraction of two short ones
    (``0.35``, ``1e-3``, ``17/30``), else None."""
    from fractions import Fraction

    parts = [p.strip() for p in text.strip().split("/")]
    if len(parts) > 2 or not all(_EXACT_PART.match(p) for p in parts):
        return None
    num = Fraction(parts[0])
    if len(parts) == 1:
        return num
    den = Fraction(parts[1])
    return num / den if den else None


class Range:
    """An inclusive range ``start:stop:step``: its ``count`` values are ``start + k*step`` for
    k < count, the last one held to ``stop`` (which is included when within a millionth of a
    step of it).  A range of whole numbers is counted exactly: its last value is the largest
    ``start + k*step`` that does not pass ``stop``.

    When ``start`` and ``step`` are short decimals or fractions, each value is the double nearest
    the exact decimal (``0.3:0.4:0.05`` gives 0.35, not 0.35000000000000003): the values are
    ``(S + k T) / D`` in integers, divided once (correctly rounded), the same in
    :meth:`value` (Python) and :meth:`chunk` (numpy) while ``|S| + k |T|`` and ``D`` stay below
    2^53.  Otherwise they are ``start + k*step`` in doubles.
    """

    __slots__ = ("start", "stop", "step", "count", "whole", "_sdt")

    def __init__(self, start, stop, step, count, whole, sdt=None):
        self.start, self.stop, self.step, self.count, self.whole = start, stop, step, count, whole
        self._sdt = sdt  # (S, T, D) integers, when exact

    def value(self, k: int) -> float:
        """The ``k``-th value (a float)."""
        if self._sdt is not None:
            s, t, d = self._sdt
            v = (s + k * t) / d
        else:
            v = self.start + k * self.step
        return min(v, self.stop) if k == self.count - 1 else v

    def chunk(self, k0: int, k1: int):
        """Values ``k0 <= k < k1`` as a float64 array, equal to :meth:`value` one by one."""
        import numpy as np

        k = np.arange(k0, k1, dtype=float)
        if self._sdt is not None:
            s, t, d = self._sdt
            v = (float(s) + k * float(t)) / float(d)  # exact numerator and denominator
        else:
            v = self.start + k * self.step
        if k1 >= self.count and v.size:
            v[-1] = min(v[-1], self.stop)
        return v + 0.0  # no -0.0


def parse_range(text: str, what: str, *, max_rows: int = MAX_ROWS) -> Range:
    """An inclusive range ``start:stop:step`` (step > 0; decimals or fractions) as a
    :class:`Range` (``whole`` when all three parts are whole numbers).  More than ``max_rows`` values is an error naming the
    limit."""
    s = str(text).strip()
    parts = s.split(":")
    if len(parts) != 3:
        raise ValueError(f"{what} range must be start:stop:step, got {text!r}")
    start, stop, step = (_range_bound(p, f"{what} range") for p in parts)
    if not step > 0:
        raise ValueError(f"{what} range step must be > 0, got {parts[2]!r}")
    if stop < start:
        raise ValueError(f"{what} range must have start <= stop, got {text!r}")
    whole = all(_INT.match(p.strip()) for p in parts)
    if whole:  # whole numbers are exact: the last value is the last start + k*step <= stop
        span = (int(parts[1]) - int(parts[0])) // int(parts[2])
    else:
        span = (stop - start) / step + 1e-6  # inf when the range is absurdly long
    if not span < max_rows:  # then it has more than max_rows values (or nan, inf)
        # the exact count it would have, floor(span) + 1, while that is a sane number
        has = f"{math.floor(span) + 1}" if span < 1e18 else f"more than {max_rows}"
        raise ValueError(f"{what} range {text!r} has {has} values; at most {max_rows} are allowed")
    count = math.floor(span) + 1
    sdt = None
    a, b = _exact(parts[0]), _exact(parts[2])
    if a is not None and b is not None and b > 0:
        d = math.lcm(a.denominator, b.denominator)
        num0, dnum = a.numerator * (d // a.denominator), b.numerator * (d // b.denominator)
        if d < 2**53 and abs(num0) + (count - 1) * abs(dnum) < 2**53:
            sdt = (num0, dnum, d)
    return Range(start, stop, step, count, whole, sdt)


_DIGITS = re.compile(r"^[0-9]+$", re.ASCII)


def _decimal_comma(items: list, zero_first: bool) -> bool:
    """Whether a list of a real-valued option, as split at its commas, is a number written with
    a decimal comma: exactly two items, both digits only (no sign, point, exponent, fraction or
    unit), and either with a leading zero (``1,05``, ``05,3``: no list of whole numbers is
    written so), or, for an option whose 0 is a degenerate value (``zero_first``: ``--xi``,
    where xi 0 is the coin of no thickness), the first ``0`` (``--xi 0,5``, ``0,33``: a list
    of the flat coin and a coin 5 or 33 times as thick as it is wide is what a decimal comma
    makes of 0.5).  (Two such items are also read so when the option refuses one of them:
    :func:`parse_values`.)"""
    if len(items) != 2:
        return False
    a, b = (p.strip() for p in items)
    return bool(_DIGITS.match(a) and _DIGITS.match(b)) and (
        (zero_first and a == "0") or any(len(x) > 1 and x[0] == "0" for x in (a, b)))


def _decimal_comma_error(text: str, what: str, refused: ValueError | None = None
                         ) -> ValueError:
    """The one line of a list that reads as a decimal comma; ``refused``: the error of the
    item the option refused, when that is why."""
    a, b = (p.strip() for p in str(text).split(","))
    typed = shown(str(text).strip())

    def whole(x: str) -> str:  # no int(): a 5,000-digit item is past int()'s digit limit
        x = x.lstrip("0") or "0"
        return x if len(x) <= 20 else x[:17] + "..."

    if len(a) + len(b) > 40:
        a, b = whole(a), whole(b)
    ia, ib = whole(a), whole(b)
    if refused is not None:
        return ValueError(f"{what} {typed} is the list {ia} and {ib}, and {refused}; if it "
                          f"is one number, a decimal comma was read: the decimal point is '.' "
                          f"({what} {a}.{b}) and ',' separates the values of a list")
    return ValueError(f"{what} {typed}: a decimal comma was read; the decimal point is '.' "
                      f"({what} {a}.{b}) and ',' separates the values of a list (the two "
                      f"values {ia} and {ib}: {ia}.0,{ib})")


def parse_values(text: str, what: str, item=parse_number, *, max_rows: int = MAX_ROWS,
                 whole: bool | None = None) -> list:
    """``a``, a list ``a,b,c`` or an inclusive range ``start:stop:step`` (step > 0; its three
    numbers decimals or fractions such as ``1/10``).

    Each item is parsed by ``item(text, what)``; a range's values are :meth:`Range.value` (no
    accumulated rounding; a decimal grid gives its decimals) and include ``stop`` when it is
    within a millionth of a step of it.
    More than ``max_rows`` values is an error naming the limit.

    A decimal comma: for an option of real numbers (``whole`` false; by default, unless ``item``
    is :func:`parse_count` or has ``item.whole`` true, as counts do: ``--count 1,5`` is a
    list), a list of two items of digits only is refused in one line saying that a decimal
    comma was read, when an item has a leading zero (``1,05``) or, for an option whose item
    has ``item.zero_first`` (``--xi``), its first item is ``0`` (``--xi 0,5``); when the option
    refuses one of the two (``-p 0,33``, ``-p 1,25``: 33 and 25 are no probabilities), the line
    gives that refusal and says that a decimal comma may be why.  Other lists are lists:
    ``0.1,0.2``, ``1,2``, ``-p 0,1``, ``--psi 0,180``, ``--xi 0.0,5``.
    """
    s = str(text).strip()
    if not s:
        raise ValueError(f"{what} is empty; give a value, a list a,b,c or a range start:stop:step")
    if ":" in s:
        rng = parse_range(s, what, max_rows=max_rows)
        if rng.whole:
            # whole numbers stay whole: counts (1:12:1) must not turn into '1.0'
            parts = s.split(":")
            a, d = int(parts[0]), int(parts[2])
            texts = (str(a + k * d) for k in range(rng.count))
        else:
            texts = (repr(rng.value(k)) for k in range(rng.count))
        out = []
        for t in texts:
            try:
                out.append(item(t, what))
            except ValueError as exc:  # a value the user did not type: name the range typed
                raise ValueError(f"{exc} (a value of the range {text.strip()!r})") from None
        return out
    items = s.split(",")
    if len(items) > max_rows:
        raise ValueError(f"{what} lists {len(items)} values; at most {max_rows} are allowed")
    if whole is None:
        whole = item is parse_count or bool(getattr(item, "whole", False))
    pair = not whole and len(items) == 2 and all(_DIGITS.match(p.strip()) for p in items)
    if pair and _decimal_comma(items, bool(getattr(item, "zero_first", False))):
        raise _decimal_comma_error(s, what)
    try:
        return [item(p, what) for p in items]
    except ValueError as exc:
        if pair:  # 1,25 where 25 is refused: say that it may be a decimal comma
            raise _decimal_comma_error(s, what, exc) from None
        raise


# --------------------------------------------------------------------------- psi densities

MAX_TABLE_BYTES = 10_000_000  #: the largest psi table file (``--psi-dist table:FILE``)

DENSITY_FORMS = ("uniform, uniform:LOW:HIGH, cosine, normal (the paper's), normal:MEAN:SD "
                 "(degrees) or table:FILE")


def parse_density(text: str) -> Density:
    """``uniform``, ``uniform:LOW:HIGH``, ``cosine``, ``normal`` (the paper's),
    ``normal:MEAN:SD`` (degrees) or ``table:FILE`` (lines ``psi_degrees,weight``): the one
    parser of ``--psi-dist`` for every command."""
    from coincli.core.densities import PAPER_DENSITIES, Normal, Table

    s = str(text).strip()
    kind, _, rest = s.partition(":")
    kind = kind.lower()
    if kind in ("uniform", "cosine") and not rest:
        return PAPER_DENSITIES[kind]()
    if kind == "uniform":
        return _uniform_on(rest, text)
    if kind == "normal":
        if not rest:
            return Normal()
        parts = rest.split(":")
        if len(parts) != 2:
            raise ValueError(f"psi density must be normal:MEAN:SD in degrees, got {text!r}")
        mean = parse_number(parts[0], "normal mean (degrees)")
        sd = parse_number(parts[1], "normal sd (degrees)")
        if not sd > 0:
            raise ValueError(f"normal sd must be > 0 degrees, got {parts[1]!r}")
        d = Normal(math.radians(mean), math.radians(sd))
        if 90.0 < mean <= 180.0:  # Table I's mirror of the mean, taken in degrees (exact)
            d.mirror = math.radians(180.0 - mean)
        return d
    if kind == "table" and rest:
        return Table.from_text(_read_table_file(rest), label=rest)
    raise ValueError(f"psi density must be {DENSITY_FORMS}; got {shown(str(text))}")


def _uniform_on(rest: str, text: str) -> Density:
    """``uniform:LOW:HIGH`` (degrees, 0 <= LOW < HIGH <= 180): the two-point table of equal
    weights, sampled and integrated exactly; ``uniform:0:180`` is :class:`Uniform` itself."""
    from coincli.core.densities import Table, Uniform

    parts = rest.split(":")
    rule = "uniform:LOW:HIGH in degrees with 0 <= LOW < HIGH <= 180"
    if len(parts) != 2:
        raise ValueError(f"psi density must be {rule}, got {shown(str(text))}")
    try:
        lo, hi = (parse_number(p, "uniform bound (degrees)") for p in parts)
    except ValueError:
        raise ValueError(f"psi density must be {rule}, got {shown(str(text))}") from None
    if lo == hi and 0 <= lo <= 180:
        raise ValueError(f"psi density {shown(str(text))} is a single angle; give it as "
                         f"--psi {parts[0].strip()}, or make LOW < HIGH")
    if not 0 <= lo < hi <= 180:
        raise ValueError(f"psi density must be {rule}, got {shown(str(text))}")
    if lo == 0 and hi == 180:
        return Uniform()
    rad = [math.pi if v == 180 else math.radians(v) for v in (lo, hi)]
    return Table(rad, [1.0, 1.0], label=f"uniform {lo:g} to {hi:g} deg",
                 spec=f"uniform:{lo + 0.0:.10g}:{hi:.10g}")


def _read_table_file(path: str) -> str:
    """The text of a psi table file, read in chunks and never more than ``MAX_TABLE_BYTES + 1``
    bytes (a device such as /dev/zero has no size to check first); a NUL byte stops it at once.
    Only a regular file is read (:func:`coincli.io.files.read_text`: a FIFO or a device is
    refused without blocking).  UTF-8, a leading byte-order mark dropped."""
    from coincli.core.densities import MAX_TABLE_POINTS
    from coincli.io.files import Unreadable, read_text

    try:
        return read_text(path, MAX_TABLE_BYTES)
    except Unreadable as exc:
        name = shown(path)
        raise ValueError({
            "kind": f"psi table {name} is {exc.detail}, not a regular file; expected a text "
                    "file of psi,weight lines",
            "system": f"cannot read psi table {name}: {exc.detail}",
            "size": f"psi table {name} is larger than {MAX_TABLE_BYTES} bytes; a table is at "
                    f"most {MAX_TABLE_BYTES // 10**6} MB and {MAX_TABLE_POINTS} points",
            "nul": f"psi table {name} contains a NUL byte; expected a text file of psi,weight "
                   "lines",
            "utf8": f"psi table {name} is not UTF-8 text",
        }[exc.reason]) from None
