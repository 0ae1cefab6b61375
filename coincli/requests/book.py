"""The inputs of ``coin book`` (the paper's Problem 1), declared once
(:class:`~coincli.requests.fields.Command`)."""

from __future__ import annotations

from coincli.requests.common import OUTPUT, SeedOpt, TossesOpt
from coincli.requests.fields import Command
from coincli.requests.fields import Opt as option

__all__ = ["BOOK"]

BOOK = Command(
    "book",
    ("size", option("--size", "AxBxC", "The box's three sides AxBxC along body axes 1, 2, 3: mm, "
                    "or with a unit per side (23.5cmx15.5cmx3cm, 1inx1inx1in)."), None),
    ("moments", option("--moments", "I1,I2,I3", "Principal moments I1,I2,I3 instead of a size "
                       "(any unit; each at most the sum of the other two).  Faces are those of "
                       "the uniform box with these moments."), None),
    ("spin", option("--spin", "W1,W2,W3", "Angular velocity at launch about body axes 1, 2, 3: "
                    "w1,w2,w3 in rad/s (or with a unit: rev/s, rpm, deg/s).  With --toss each "
                    "component may be a distribution: normal:MEAN:SD or uniform:LOW:HIGH (a unit "
                    "once at the end applies to both numbers: normal:6:1rev/s)."), None),
    ("times", option("--times", "TIMES", "Times (s) for the time series of omega, the attitude "
                     "and the face up: a list a,b,c, a range START:STOP:STEP, or - for stdin; "
                     "units s or ms (500ms, 0:600:100ms)."), None),
    ("toss", option("--toss", None, "Toss many boxes with random spins and flight times; give "
                    "the chance of each face beside the geometric model.", kind=bool), False),
    ("tosses", TossesOpt, None),
    ("seed", SeedOpt, None),
    ("flight", option("--flight", "SPEC", "Flight time from launch to catch, s: a value, or with "
                      "--toss normal:MEAN:SD (truncated at 0) or uniform:LOW:HIGH.  Default 0.5 "
                      "with --toss; without --toss it adds the face up at that catch to the "
                      "motion table."), None),
    ("start", option("--start", "FACE", "Face up at launch (+1 -1 +2 -2 +3 -3: outward normal "
                     "along +-body axis; default +3), or random (a uniformly random attitude, "
                     "with --toss)."), None),
    ("rule", option("--rule", "centre|normal", "Which face is up at the catch: centre (the "
                    "vertical through the centre passes through it: the coin's rule, matched by "
                    "solid angles) or normal (its outward normal is nearest the vertical).  "
                    "Default centre."), None),
    ("out", option("--out -o", "FILE", "Write to FILE: a figure when it ends in .png, .svg or "
                   ".pdf (omega(t) and the face up; with --toss the face chances), else the "
                   "output in --format."), None),
    output=OUTPUT,
)
