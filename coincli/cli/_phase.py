"""The options of the phase-space picture (Fig. 3), shared by ``coin phase`` and
``coin plot phase``.

Both commands draw the same thing, so they take the same options with the same defaults: the
coin group (default: the fair coin 1/sqrt 3, a quarter's size), ``--psi`` (90), ``--u LOW:HIGH``
(0:3 m/s) and ``--omega LOW:HIGH`` (0:60 rad/s), with units, ``--cols``/``--rows`` (the grid),
``--exact``, ``--no-curves``, ``--toss U:OMEGA`` (marks), ``--g`` and ``--contact``.  The old
spellings of ``coin plot phase`` (``--u-range``, ``--omega-range``, ``--exact-curves``,
``--resolution``) still work, hidden.  These are the typer declarations and their groups
(:data:`PHASE`, :data:`FLIGHT`, :data:`OLD`); they are resolved
and drawn by :mod:`coincli.reports.phase`.  No numpy, scipy or rich at import.
"""

from __future__ import annotations

from typing import Annotated

import typer

from coincli.cli._options import Group
from coincli.reports.phase import DATA_CELLS, FIGURE_CELLS, OMEGA_DEFAULT, U_DEFAULT

PsiOpt = Annotated[str, typer.Option("--psi", metavar="DEG", help="Angle psi of the angular "
                                     "momentum to the normal, degrees [0, 180].")]
URangeOpt = Annotated[str | None, typer.Option(
    "--u", metavar="LOW:HIGH", help=f"Launch speeds: {U_DEFAULT} (m/s) or with a unit, "
    "0:300cm/s.")]
OmegaRangeOpt = Annotated[str | None, typer.Option(
    "--omega", metavar="LOW:HIGH", help=f"Spins: {OMEGA_DEFAULT} (rad/s) or with a unit, "
    "0:10rev/s.")]
ColsOpt = Annotated[str | None, typer.Option(
    "--cols", metavar="N", help=f"Grid cells along u (default: fit the terminal; "
    f"{FIGURE_CELLS} for a figure, {DATA_CELLS} for csv/json).")]
RowsOpt = Annotated[str | None, typer.Option(
    "--rows", metavar="N", help="Grid cells along omega (defaults as --cols).")]
ExactOpt = Annotated[bool, typer.Option(
    "--exact", help="Boundaries at the exact contact time, not eq. 10's t_f = 2u/g.")]
NoCurvesOpt = Annotated[bool, typer.Option("--no-curves", help="Draw no boundary curves.")]
TossMarkOpt = Annotated[str | None, typer.Option(
    "--toss", metavar="U:OMEGA", help="Mark tosses: 1.2:40 (m/s:rad/s, units allowed); a list "
    "a:b,c:d.")]
GOpt = Annotated[str, typer.Option("--g", metavar="G", help="Gravity, m/s^2 (> 0).")]
ContactOpt = Annotated[str, typer.Option(
    "--contact", metavar="rim|thick", help="rim (the paper's) or thick (the cylinder's "
    "corner).")]
# The old spellings of coin plot phase, hidden: they still work.
OldURangeOpt = Annotated[str | None, typer.Option("--u-range", hidden=True)]
OldOmegaRangeOpt = Annotated[str | None, typer.Option("--omega-range", hidden=True)]
OldExactOpt = Annotated[bool, typer.Option("--exact-curves", hidden=True)]
OldResolutionOpt = Annotated[str | None, typer.Option("--resolution", hidden=True)]

#: gravity and the contact rule of a finite toss (``coin toss``, ``simulate``, ``phase``)
FLIGHT = Group(("g", GOpt, "9.81"), ("contact", ContactOpt, "rim"))
#: the picture's options after the coin's, the same in ``coin phase`` and ``coin plot phase``
PHASE = Group(("psi", PsiOpt, "90"), ("u", URangeOpt, None), ("omega", OmegaRangeOpt, None),
              ("cols", ColsOpt, None), ("rows", RowsOpt, None), ("exact", ExactOpt, False),
              ("no_curves", NoCurvesOpt, False), ("toss", TossMarkOpt, None), FLIGHT)
#: the old spellings of ``coin plot phase``
OLD = Group(("u_range", OldURangeOpt, None), ("omega_range", OldOmegaRangeOpt, None),
            ("exact_curves", OldExactOpt, False), ("resolution", OldResolutionOpt, None))
