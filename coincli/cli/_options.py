"""The typer declarations of the options every command spells the same way.

- **A coin**: ``--xi``, ``--coin``, ``--count``, ``--quarters``, ``--diameter``,
  ``--thickness``;
- **Tosses**: ``-n/--n/--tosses N``; stacked coins are always
  ``--count`` (the old ``-n`` of ``coin table`` and ``coin stack`` fails naming ``--count``:
  :data:`OldCountOpt`, refused by :func:`coincli.io.options.refuse_old_count`);
- **A seed**: ``--seed N``;
- **psi**: ``--psi DEG`` and ``--psi-dist SPEC[,SPEC...]``.

Commands declare the options with these ``Annotated`` aliases (parameter names ``xi``,
``coin``, ``count``, ``quarters``, ``diameter``, ``thickness``, ``tosses``, ``seed``, ``psi``,
``psi_dist``) and pass the typed text to the parsers of :mod:`coincli.io.options` (the coin
group, tosses, seeds, units typed once, psi), which hold the grammar itself.  No numpy, scipy or rich at import.
"""

from __future__ import annotations

from typing import Annotated

import typer

__all__ = [
    "XiOpt", "XisOpt", "CoinOpt", "CountOpt", "CountsOpt", "QuartersOpt", "QuartersManyOpt",
    "DiameterOpt", "ThicknessOpt", "TossesOpt", "OldCountOpt", "SeedOpt", "PsiOpt", "PsisOpt",
    "PsiDistOpt", "PsiDistsOpt", "FormatOpt", "QuietOpt",
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

# --------------------------------------------------------------------------- output

FormatOpt = Annotated[
    str,
    typer.Option(
        "--format",
        "-f",
        help="Output format: table (default: aligned text, folded to fit a terminal), csv, "
        "tsv, json, jsonl or markdown (a pipe table).",
        metavar="FORMAT",
    ),
]
QuietOpt = Annotated[
    bool, typer.Option("--quiet", "-q", help="Print only the main number (for shell scripts).")
]
