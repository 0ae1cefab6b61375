"""The typer declarations of the options every command spells the same way.

- **A coin**: ``--xi``, ``--coin``, ``--count``, ``--quarters``, ``--diameter``,
  ``--thickness``;
- **Tosses**: ``-n/--n/--tosses N`` (:func:`tosses_value`); stacked coins are always
  ``--count`` (the old ``-n`` of ``coin table`` and ``coin stack`` fails naming ``--count``:
  :data:`OldCountOpt`, refused by :func:`coincli.io.options.refuse_old_count`);
- **A seed**: ``--seed N``;
- **psi**: ``--psi DEG`` and ``--psi-dist SPEC[,SPEC...]``;
- launch ranges and distributions with a unit typed once (:func:`unit_at_end`,
  :func:`range_unit`).

Commands declare the options with these ``Annotated`` aliases (parameter names ``xi``,
``coin``, ``count``, ``quarters``, ``diameter``, ``thickness``, ``tosses``, ``seed``, ``psi``,
``psi_dist``) and pass the typed text to the parsers of :mod:`coincli.io.options` (the coin
group, seeds, psi), which hold the grammar itself.  No numpy, scipy or rich at import.
"""

from __future__ import annotations

from typing import Annotated

import typer

from coincli.io import grammar as parse
from coincli.io.table import usage_error

__all__ = [
    "XiOpt", "XisOpt", "CoinOpt", "CountOpt", "CountsOpt", "QuartersOpt", "QuartersManyOpt",
    "DiameterOpt", "ThicknessOpt", "TossesOpt", "OldCountOpt", "SeedOpt", "PsiOpt", "PsisOpt",
    "PsiDistOpt", "PsiDistsOpt", "tosses_value",
]

# --------------------------------------------------------------------------- the coin group

XiOpt = Annotated[
    str | None,
    typer.Option("--xi", "-x", metavar="XI", help="Aspect ratio h/D: 0.577 or 17/30."),
]
XisOpt = Annotated[
    str | None,
    typer.Option("--xi", "-x", metavar="XI", help="Aspect ratio h/D: 0.577, 17/30, a list a,b, "
                 "a range lo:hi:step, or - (stdin)."),
]
CoinOpt = Annotated[
    str | None,
    typer.Option("--coin", "-c", metavar="NAME", help="Catalog coin (see coin coins)."),
]
CountOpt = Annotated[
    str | None,
    typer.Option("--count", metavar="N", help="Stack N of the --coin (or --diameter) coins."),
]
CountsOpt = Annotated[
    str | None,
    typer.Option("--count", metavar="N", help="Stack N coins: N, a list, a range or -."),
]
QuartersOpt = Annotated[
    str | None,
    typer.Option("--quarters", metavar="N", help="N US quarters stacked (--coin quarter "
                 "--count N)."),
]
QuartersManyOpt = Annotated[
    str | None,
    typer.Option("--quarters", metavar="N", help="N US quarters stacked: N, a list, a range "
                 "or -."),
]
DiameterOpt = Annotated[
    str | None,
    typer.Option("--diameter", "-d", metavar="D", help="Diameter: 24.26 (mm), 2.4cm or "
                 "0.955in."),
]
ThicknessOpt = Annotated[
    str | None,
    typer.Option("--thickness", "-t", metavar="H", help="Thickness (mm or a unit), with "
                 "--diameter."),
]

# --------------------------------------------------------------------------- tosses, seeds

TossesOpt = Annotated[
    str | None,
    typer.Option("-n", "--n", "--tosses", metavar="N", help="Number of tosses."),
]
#: the retired ``-n`` (stacked coins) of ``coin table`` and ``coin stack``: hidden, it fails
#: naming ``--count`` (``-n`` is always a number of tosses)
OldCountOpt = Annotated[str | None, typer.Option("-n", hidden=True, metavar="N")]


def tosses_value(text: str, *, low: int = 1, high: int = parse.MAX_COUNT,
                 what: str = "-n") -> int:
    """A number of tosses, a whole number from ``low`` to ``high``."""
    s = str(text).strip()
    digits = s.removeprefix("+")
    if not (digits.isascii() and digits.isdigit()):
        raise usage_error(f"{what} must be a whole number from {low} to {high}, got "
                          f"{_shown(text)}")
    digits = digits.lstrip("0") or "0"
    if len(digits) > 19 or not low <= int(digits) <= high:  # and no int() of 5000 digits
        raise usage_error(f"{what} must be a whole number from {low} to {high}, got "
                          f"{_shown(text)}")
    return int(digits)


def _shown(text: str) -> str:
    from coincli.io.table import shown

    return shown(text)


SeedOpt = Annotated[
    str | None,
    typer.Option("--seed", metavar="SEED", help="Seed, a whole number >= 0 (default: drawn, "
                 "and reported)."),
]


def unit_at_end(nums: list[str], units, what: str, example: str, text: str) -> list[str]:
    """The numbers of a range or distribution with a unit typed once at the end applied to each
    (``normal:38:4rev/s`` is ``normal:38rev/s:4rev/s``), as typed when every number or none has
    one; a unit on some numbers only is ambiguous and refused in one line."""
    has = [parse.split_unit(p, units)[1] is not None for p in nums]
    if any(has) and not all(has):
        if not has[-1] or any(has[:-1]):
            raise usage_error(f"{what}: give the unit once at the end ({example}) or after "
                              f"every number, got {text!r}")
        unit = parse.split_unit(nums[-1], units)[1]
        nums = [p + unit for p in nums[:-1]] + nums[-1:]
    return nums


def range_unit(text: str, units, what: str, example: str) -> tuple[str, str | None]:
    """A range ``start:stop:step`` with its unit typed once at the end (``0:500:100ms``) or the
    same after every number (``0ms:500ms:100ms``), as ``(numbers, unit)``; ``unit`` None when
    no number has one.  A unit on some numbers only, or two different units, is refused in one
    line that shows the forms allowed."""
    parts = [p.strip() for p in text.strip().split(":")]
    split = [parse.split_unit(p, units) for p in parts]
    found = [u for _, u in split]
    if not any(found):
        return text.strip(), None
    unit = found[-1]
    if unit is None or (any(found[:-1]) and set(found) != {unit}):
        raise usage_error(f"{what}: give a range's unit once at the end ({example}) or the same "
                          f"after every number, got {text.strip()!r}")
    return ":".join(num for num, _ in split), unit


def typed_range_error(exc: Exception, head: str, text: str) -> Exception:
    """A range error about the numbers ``head`` of a range typed as ``text`` (with its unit),
    shown as typed."""
    return usage_error(str(exc).replace(repr(head), repr(text.strip())))


# --------------------------------------------------------------------------- psi

PsiOpt = Annotated[
    str | None,
    typer.Option("--psi", metavar="DEG", help="Angle psi of the angular momentum to the "
                 "normal, degrees [0, 180]."),
]
PsisOpt = Annotated[
    str | None,
    typer.Option("--psi", metavar="DEG", help="Angle psi, degrees [0, 180]: a value, a list "
                 "a,b or a range lo:hi:step."),
]
PsiDistOpt = Annotated[
    str | None,
    typer.Option("--psi-dist", metavar="SPEC", help="psi density: uniform[:LOW:HIGH], cosine, "
                 "normal[:MEAN:SD] (deg), table:FILE."),
]
PsiDistsOpt = Annotated[
    str | None,
    typer.Option("--psi-dist", metavar="SPECS", help="psi densities, comma-separated: "
                 "uniform[:LOW:HIGH], cosine, normal[:MEAN:SD], table:FILE."),
]
