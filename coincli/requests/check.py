"""The inputs of ``coin check`` and ``coin fit``, declared once
(:class:`~coincli.requests.fields.Command`)."""

from __future__ import annotations

from coincli.requests.common import BOUNCE, COIN, LAUNCH, OUTPUT, RUNS, PsiDistsOpt, TossesOpt
from coincli.requests.fields import REQUIRED, Arg, Command, Group
from coincli.requests.fields import Opt as option

__all__ = ["CHECK", "FIT"]

AlphaOpt = option("--alpha", "A", "Significance level of the verdicts.", kind=str)
ConfidenceOpt = option("--confidence", "C", "Confidence level of the intervals.", kind=str)
#: the levels of the verdicts and of the intervals
LEVELS = Group(("alpha", AlphaOpt, "0.05"), ("confidence", ConfidenceOpt, "0.95"))

ExpectOpt = option("--expect", "H,S,T", "Also test against chances you state: heads, sides, "
                   "tails (0.3,0.4,0.3; 1/3,1/3,1/3; 30%,40%,30%; they add up to 1).  The coin is "
                   "then optional.")
FairOpt = option("--fair", None, "Also test against a fair three-sided coin: --expect "
                 "1/3,1/3,1/3.", kind=bool)

#: ``--landing bounce`` of ``coin check``: the table your tosses are compared with, and the
#: launch of the tosses simulated on it (as ``coin simulate`` takes them)
CHECK_TABLE = Group(
    BOUNCE.only("landing", "calibration", "surface", "restitution", "friction", "torsional",
                "rolling"),
    LAUNCH.only("u", "omega", "psi", "seed"),
    BOUNCE.only("release_height", "vx", *RUNS, "dt", "t_max"),
)

CHECK = Command(
    "check",
    COIN.only("xi", "quarters", "coin", "count", "diameter", "thickness"),
    ("heads", option("--heads", "H", "Tosses that landed heads."), None),
    ("sides", option("--sides -s", "S", "Tosses that landed on a side."), None),
    ("tails", option("--tails", "T", "Tosses that landed tails."), None),
    ("tosses", TossesOpt, None),
    ("same", option("--same", "S", "Caught flips (faces only) that landed on the side they "
                    "started on."), None),
    ("different", option("--different", "D", "Caught flips that landed on the other side."),
     None),
    ("psi_dist", PsiDistsOpt, None),
    ("expect", ExpectOpt, None),
    ("fair", FairOpt, False),
    table=CHECK_TABLE,
    levels=LEVELS,
    output=OUTPUT,
)

#: ``coin fit --landing bounce``: calibrate the table the prototypes were tossed on
FIT_TABLE = Group(
    BOUNCE.only("landing"),
    ("fit", option("--fit", "PARAMS", "With --landing bounce: what to estimate, comma-separated: "
                   "restitution, friction (default both), psi-spread."), None),
    ("seed", option("--seed", "SEED", "With --landing bounce or --calibration: the seed of the "
                    "simulated tosses (default: drawn, and reported)."), None),
    ("save", option("--save", "CAL.json", "With --landing bounce: write the calibration there, "
                    "for --calibration."), None),
    ("design_tosses", option("--design-tosses", "N", "With --landing bounce: simulated tosses of "
                             "each prototype at each designed table (default 256).  With "
                             "--calibration: the most tosses of each tosser's design (default "
                             "2000)."), None),
    BOUNCE.only("surface", "restitution", "friction", "torsional", "rolling"),
    LAUNCH.only("u", "omega", "psi"),
    BOUNCE.only("release_height", "vx", *RUNS, "dt", "t_max"),
    ("calibration", option("--calibration", "CAL.json", "With --design: each tosser's coin "
                           "designed on your table too, calibrated from tosses (coin fit "
                           "--landing bounce FILE --save CAL.json): a bouncing design per "
                           "tosser (MuJoCo), at most --design-tosses tosses each."), None),
)

FIT = Command(
    "fit",
    ("file", Arg("FILE", "Experiments CSV, or - for stdin."), REQUIRED),
    ("psi_dist", PsiDistsOpt, None),
    ("no_spread", option("--no-spread", None, "Skip the fit of the spread of psi.", kind=bool),
     False),
    ("delimiter", option("--delimiter", "SEP", "Separator of FILE: comma, semicolon or tab "
                         "(default: the one the header uses)."), None),
    ("design", option("--design", "P", "For caught rows: each tosser's coin with this chance of "
                      "a side (1/3: fair three-sided) under their fitted spread."), None),
    levels=LEVELS,
    table=FIT_TABLE,
    output=OUTPUT,
)
