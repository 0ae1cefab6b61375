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

from coincli.cli._options import Group, option
from coincli.limits import BOUNCE_G_MAX, G_MAX, G_MIN
from coincli.reports.phase import DATA_CELLS, FIGURE_CELLS, OMEGA_DEFAULT, U_DEFAULT

PsiOpt = option("--psi", "DEG", "Angle psi of the angular momentum to the normal, degrees [0, "
                "180].", kind=str)
URangeOpt = option(
    "--u", "LOW:HIGH", f"Launch speeds: {U_DEFAULT} (m/s) or with a unit, "
    "0:300cm/s.")
OmegaRangeOpt = option(
    "--omega", "LOW:HIGH", f"Spins: {OMEGA_DEFAULT} (rad/s) or with a unit, "
    "0:10rev/s.")
ColsOpt = option(
    "--cols", "N", f"Grid cells along u (default: fit the terminal; "
    f"{FIGURE_CELLS} for a figure, {DATA_CELLS} for csv/json).")
RowsOpt = option("--rows", "N", "Grid cells along omega (defaults as --cols).")
ExactOpt = option("--exact", None, "Boundaries at the exact contact time, not eq. 10's t_f = 2u/g.",
                  kind=bool)
NoCurvesOpt = option("--no-curves", None, "Draw no boundary curves.", kind=bool)
TossMarkOpt = option("--toss", "U:OMEGA", "Mark tosses: 1.2:40 (m/s:rad/s, units allowed); a list "
                     "a:b,c:d.")
GOpt = option("--g", "G", f"Gravity, m/s^2, {G_MIN:g} to {G_MAX:g} (at most {BOUNCE_G_MAX:g} with "
              "--landing bounce).", kind=str)
ContactOpt = option("--contact", "rim|thick", "rim (the paper's) or thick (the cylinder's corner).",
                    kind=str)
# The old spellings of coin plot phase, hidden: they still work.
OldURangeOpt = option("--u-range", None, hidden=True)
OldOmegaRangeOpt = option("--omega-range", None, hidden=True)
OldExactOpt = option("--exact-curves", None, kind=bool, hidden=True)
OldResolutionOpt = option("--resolution", None, hidden=True)

#: gravity and the contact rule of a finite toss (``coin toss``, ``simulate``, ``phase``)
FLIGHT = Group(("g", GOpt, "9.81"), ("contact", ContactOpt, "rim"))
#: the picture's options after the coin's, the same in ``coin phase`` and ``coin plot phase``
PHASE = Group(("psi", PsiOpt, "90"), ("u", URangeOpt, None), ("omega", OmegaRangeOpt, None),
              ("cols", ColsOpt, None), ("rows", RowsOpt, None), ("exact", ExactOpt, False),
              ("no_curves", NoCurvesOpt, False), ("toss", TossMarkOpt, None), FLIGHT)
#: the old spellings of ``coin plot phase``
OLD = Group(("u_range", OldURangeOpt, None), ("omega_range", OldOmegaRangeOpt, None),
            ("exact_curves", OldExactOpt, False), ("resolution", OldResolutionOpt, None))
