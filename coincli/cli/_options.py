"""The one grammar of ``coin``: the options every command spells the same way.

- **A coin**: ``--xi X`` (``0.577``, ``17/30``; lists, ranges and ``-`` where a command takes
  many), ``--coin NAME [--count N]`` (a catalog coin, N of them stacked), ``--quarters N`` (N US
  quarters) or ``--diameter D --thickness H`` (lengths with units, ``--count N`` stacks them);
  ``--diameter D`` with ``--xi X`` gives the coin its size.
  :func:`coincli.io.options.resolve_coin` turns the options into
  :class:`coincli.io.options.Coins` and refuses every contradiction with the same one-line
  message in every command.
- **Tosses**: ``-n/--n/--tosses N``; stacked coins are always ``--count`` (the old ``-n`` of
  ``coin table`` and ``coin stack`` fails naming ``--count``: :data:`OldCountOpt`).
- **A seed**: ``--seed N``; when absent one is drawn (:func:`coincli.io.options.seed_value`)
  and reported.
- **psi**: ``--psi DEG`` (a list or a range where a command takes many) and
  ``--psi-dist SPEC[,SPEC...]``, parsed by :func:`coincli.core.densities.parse_density` everywhere.

Commands declare the options with these ``Annotated`` aliases (parameter names ``xi``,
``coin``, ``count``, ``quarters``, ``diameter``, ``thickness``, ``tosses``, ``seed``, ``psi``,
``psi_dist``) and pass the typed text to the resolvers of :mod:`coincli.io.options` (text to
values, no typer).  No numpy, scipy or rich at import.
"""

from __future__ import annotations

import math
from typing import Annotated

import typer

from coincli.io import grammar as parse
from coincli.io.table import shown, usage_error

__all__ = [
    "XiOpt", "XisOpt", "CoinOpt", "CountOpt", "CountsOpt", "QuartersOpt", "QuartersManyOpt",
    "DiameterOpt", "ThicknessOpt", "TossesOpt", "OldCountOpt", "SeedOpt", "PsiOpt", "PsisOpt",
    "PsiDistOpt", "PsiDistsOpt", "refuse_old_count", "psi_angle", "psi_angles", "radians",
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


def refuse_old_count(value: str | None, example: str) -> None:
    """The old ``-n N`` of table/stack: a usage error naming ``--count N``."""
    if value is not None:
        n = value.strip()
        n = n if n.isascii() and n.isdigit() and len(n) < 20 else "N"
        raise usage_error(f"-n is a number of tosses; stacked coins are --count N (e.g. "
                          f"{example.format(n=n)})")


SeedOpt = Annotated[
    str | None,
    typer.Option("--seed", metavar="SEED", help="Seed, a whole number >= 0 (default: drawn, "
                 "and reported)."),
]


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


def _deg_item(text: str, what: str) -> float:
    try:
        v = parse.parse_number(text, what)
    except ValueError:
        v = math.nan
    if not 0.0 <= v <= 180.0:  # NaN fails
        raise ValueError(f"{what} must be an angle in [0, 180] degrees, got {text!r}")
    return v + 0.0


PSI_AND_DIST = "give --psi DEG (a fixed angle) or --psi-dist SPEC (a distribution), not both"


def refuse_psi_and_dist(psi, psi_dist) -> None:
    """The one usage error for --psi and --psi-dist given together."""
    if psi is not None and psi_dist is not None:
        raise usage_error(PSI_AND_DIST)


def _a_list(text: str) -> bool:
    return any(c in text for c in ",:") and str(text).strip() != "-"


def psi_angle(text: str, what: str = "--psi") -> float:
    """One angle in degrees, in [0, 180]; a list or range is refused as such (a command that
    takes many uses :func:`psi_angles`)."""
    try:
        return _deg_item(text, what)
    except ValueError as exc:
        if _a_list(text):
            raise usage_error(f"{what} takes one angle here (degrees, 0 to 180), not a list or "
                              f"range; got {shown(text)}") from None
        raise usage_error(str(exc)) from None


def psi_angles(text: str, what: str = "--psi", *, max_rows: int = parse.MAX_ROWS) -> list[float]:
    """Angles in degrees: a value, a list ``a,b`` or a range ``lo:hi:step`` (no stdin)."""
    try:
        return [float(v) for v in parse.parse_values(text, what, _deg_item, max_rows=max_rows)]
    except ValueError as exc:
        raise usage_error(str(exc)) from None


def radians(deg: float) -> float:
    """Degrees to radians, 180 to the double nearest pi (as :func:`parse.parse_angle_deg`)."""
    return math.pi if deg == 180.0 else math.radians(deg)
