"""The inputs of ``coin design``, ``coin table``, ``coin stack``, ``coin coins`` and
``coin fair``, declared once (:class:`~coincli.requests.fields.Command`)."""

from __future__ import annotations

from coincli.limits import BOUNCE_DESIGN_TOSSES, MAX_BOUNCE_TOSSES
from coincli.requests.common import (
    BOUNCE,
    COINS,
    LAUNCH,
    OUTPUT,
    RUNS,
    DesignMethodOpt,
    McSeedOpt,
    MethodOpt,
    OldCountOpt,
    PsiDistOpt,
    PsiDistsOpt,
    PsiOpt,
    PsisOpt,
    TolOpt,
)
from coincli.requests.fields import REQUIRED, Command, Group, Param
from coincli.requests.fields import Opt as option

__all__ = ["DESIGN", "TABLE", "STACK", "COINS_LIST", "FAIR"]

ModelOpt = option("--model -m", "MODEL", "geometric, dynamic (default) or psi.")
#: ``--tol`` of ``coin design``: an error of a chance when caught, of xi on a table
DesignTolOpt = option("--tol", "TOL", "Caught (the models): the absolute error wanted on each "
                      "psi-averaged chance, e.g. 1e-6 (the error is shown).  With --landing "
                      "bounce: the half-width wanted of each 95% interval of xi (default 0.01).")
#: the catalog coin of a stack
StackCoinOpt = option("--coin -c", "NAME", "Catalog coin of the stack (see coin coins).", kind=str)

# --------------------------------------------------------------------------- design

PSidesOpt = option("--p-sides -p", "P", "Target chance of a side: 0.33, 1/3 or 33%; a list a,b; a "
                   "range lo:hi:step; or - (stdin).", kind=str)
SizedDiameterOpt = option("--diameter -d", "D", "Diameter (24.26, 2.4cm, 0.955in); the thickness "
                          "is computed.  Default: the --coin's.")
SizedThicknessOpt = option("--thickness -t", "H", "Thickness (mm or a unit); the diameter is "
                           "computed instead.")
#: ``--landing bounce`` of ``coin design``: the table, and the tosses simulated on it
DESIGN_TABLE = Group(
    BOUNCE.only("landing", "surface", "restitution", "friction", "torsional", "rolling"),
    LAUNCH.only("u", "omega"),
    BOUNCE.only("release_height", "vx"),
    LAUNCH.only("seed"),
    ("max_tosses", option("--max-tosses", "N", "With --landing bounce: stop before simulating "
                          f"more tosses than this (default {BOUNCE_DESIGN_TOSSES}, from 180 to "
                          f"{MAX_BOUNCE_TOSSES})."), None),
    ("time_limit", option("--time-limit", "S", "With --landing bounce: stop at the end of the "
                          "first round after this many seconds (default: no limit, so the "
                          "answer depends on the inputs and the seed only); the note then says "
                          "so, and gives the --max-tosses that reproduces the result."), None),
    BOUNCE.only(*RUNS, "dt", "t_max", "calibration"),
    ("no_table", option("--no-table", None, "With --landing bounce: simulate every toss, "
                        "not starting from the table shipped for a surface preset with the "
                        "default launch and coin (see docs/bounce.md).", kind=bool), False),
)

DESIGN = Command(
    "design",
    ("p_sides", PSidesOpt, REQUIRED),
    ("model", ModelOpt, None),
    ("psi", PsiOpt, None),
    ("psi_dist", PsiDistOpt, None),
    ("diameter", SizedDiameterOpt, None),
    ("thickness", SizedThicknessOpt, None),
    ("coin", StackCoinOpt, "quarter"),
    ("tol", DesignTolOpt, None),
    ("method", DesignMethodOpt, None),
    table=DESIGN_TABLE,
    output=OUTPUT,
)

# --------------------------------------------------------------------------- table

TABLE_OUTPUT = OUTPUT.but(quiet=option(
    "--quiet -q", None, "Print only P(sides), a line a row: each coin's geometric, then dynamic, "
    "then the other models.", kind=bool))
#: ``--landing bounce`` of ``coin table``: a parameter study of tables, a row per coin and
#: table (--restitution and --friction take lists and ranges as --xi does)
TABLE_TABLE = Group(
    BOUNCE.only("landing", "calibration", "surface", "restitution", "friction", "torsional",
                "rolling").but(
        restitution=option("--restitution", "E", "With --landing bounce: the surface's "
                           "coefficient of restitution, 0.06 to 0.95; a list or a range "
                           "(0.3:0.7:0.1) is a study, a row each."),
        friction=option("--friction", "MU", "With --landing bounce: the sliding friction "
                        "coefficient, 0 to 10; a list or a range is a study, a row each.")),
    LAUNCH.only("u", "omega"),
    ("tosses", option("-n --n --tosses", "N", "With --landing bounce: tosses simulated in each "
                      "cell (coin x restitution x friction), default 1000."), None),
    BOUNCE.only("release_height", "vx", *RUNS, "dt", "t_max"),
)
LayoutOpt = option("--layout", "long|wide", "long (default): a row per coin and model (per coin "
                   "and table with --landing bounce); wide: a row per coin, the models (tables) "
                   "side by side, for a spreadsheet.")

TABLE = Command(
    "table",
    COINS,
    ("psi", PsisOpt, None),
    ("psi_dist", PsiDistsOpt, None),
    ("all", option("--all", None, "Also Table II's densities: uniform, cosine, normal.",
                   kind=bool), False),
    ("vs", option("--vs", "psi", "psi: one row per --psi angle (default 0:180:15), regimes "
                  "named."), None),
    ("tol", TolOpt, None),
    ("method", MethodOpt, None),
    ("seed", McSeedOpt, None),
    ("layout", LayoutOpt, None),
    bounce=TABLE_TABLE,
    output=TABLE_OUTPUT,
)

# --------------------------------------------------------------------------- stack, coins

STACK = Command(
    "stack",
    COINS.only("coin", "count"),
    ("p_sides", option("--p-sides -p", "P", "Find the stack nearest this chance of a side (0.33, "
                       "1/3, 33%), and its neighbours; a list, a range or - for one row each."),
     None),
    COINS.only("quarters", "diameter", "thickness"),
    Param("xi", option("--xi -x", None, hidden=True), None, api=False),
    ("model", ModelOpt, None),
    ("psi", PsiOpt, None),
    ("psi_dist", PsiDistOpt, None),
    Param("old_n", OldCountOpt, None, api=False),
    output=OUTPUT,
)

COINS_LIST = Command("coins", output=OUTPUT)

# --------------------------------------------------------------------------- fair

FAIR = Command(
    "fair",
    ("diameter", option("--diameter -d", "D", "Diameter for the thickness column (default: the "
                        "--coin's)."), None),
    ("coin", StackCoinOpt, "quarter"),
    ("psi_dist", PsiDistOpt, None),
    output=OUTPUT,
)
