"""The inputs of ``coin plot sides|psi|map|phase``, declared once
(:class:`~coincli.requests.fields.Command`).  The figures have no :mod:`coincli.api` function:
a figure is drawn, not returned."""

from __future__ import annotations

from coincli.requests.common import (
    BOUNCE,
    COIN,
    COINS,
    OLD,
    PHASE,
    RUNS,
    PsiDistsOpt,
    PsisOpt,
    SeedOpt,
    TossesOpt,
)
from coincli.requests.fields import Command, Group
from coincli.requests.fields import Opt as option

__all__ = ["SIDES", "PSI", "MAP", "PHASE_FIGURE"]

OutOpt = option("--out -o", "FILE", "Figure file .png, .svg or .pdf; - or none: a text plot.")
TerminalOpt = option("--terminal", None, "A text plot on stdout (needs no matplotlib).", kind=bool)
# Sizes are parsed by coincli.reports.plot, not by click: click's FloatRange lets nan through
# (nan < 1 is False) and its messages do not say what is allowed.  Limits:
# coincli.render.figures.FIGURE_INCHES, DPI_RANGE and MAX_PIXELS (width x dpi times height x
# dpi, so a figure cannot exhaust the memory).
DpiOpt = option("--dpi", "DPI", "Dots per inch of a PNG, 10 to 2000 (50 Mpixel at most).", kind=str)
WidthOpt = option("--width", "INCHES", "Figure width, 1 to 100 inches.")
HeightOpt = option("--height", "INCHES", "Figure height, 1 to 100 inches.")
TitleOpt = option("--title", None, "Replace the figure's title.")
LogOpt = option("--log", None, "Logarithmic xi axis (0.01 to 100).", kind=bool)
XiRangeOpt = option("--xi-range", "LOW:HIGH", "The xi axis LOW:HIGH (default: 0:2, widened to "
                    "show your marks).")
PsiMarkOpt = option("--psi", "DEG", "Mark tossing angles psi, degrees [0, 180]: a value, a list "
                    "a,b or a range.")
#: the xi axis of ``sides`` and ``map``
XI_AXIS = Group(("log", LogOpt, False), ("xi_range", XiRangeOpt, None))
#: ``--landing bounce`` of ``coin plot sides``: the surface, and the tosses simulated on it
SIDES_TABLE = Group(BOUNCE.only("landing", "surface", "restitution", "friction"),
                    ("seed", SeedOpt, None), ("tosses", TossesOpt, None),
                    BOUNCE.only(*RUNS, "calibration"))
#: where the figure goes, and its size and title
FIGURE = Group(("out", OutOpt, None), ("terminal", TerminalOpt, False), ("dpi", DpiOpt, "150"),
               ("width", WidthOpt, None), ("height", HeightOpt, None), ("title", TitleOpt, None))

SIDES = Command(
    "plot sides",
    COINS,
    ("p_sides", option("--p-sides -p", "P", "Mark target chances of a side (0.33, 1/3, 33%; a "
                       "list a,b)."), None),
    ("psi", PsisOpt, None),
    ("psi_dist", PsiDistsOpt, None),
    ("data", option("--data", "FILE", "Your tosses, a coin fit CSV, or - (stdin)."), None),
    XI_AXIS,
    FIGURE,
    SIDES_TABLE,
)

PSI = Command("plot psi", COIN, ("psi", PsiMarkOpt, None), FIGURE)

MAP = Command(
    "plot map",
    ("style", option("--style", None, "panels (three maps, one per outcome) or ternary (one map, "
                     "colours mixed by the three chances).", kind=str), "panels"),
    COINS,
    ("psi", PsiMarkOpt, None),
    XI_AXIS,
    FIGURE,
)

PHASE_FIGURE = Command("plot phase", COIN, PHASE, OLD, FIGURE)
