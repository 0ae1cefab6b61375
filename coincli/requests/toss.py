"""The inputs of ``coin toss``, ``coin simulate`` and ``coin phase``, declared once
(:class:`~coincli.requests.fields.Command`)."""

from __future__ import annotations

from coincli.limits import BOUNCE_OMEGA_MAX, HAND, SPEC_FORM
from coincli.requests.common import (
    BOUNCE,
    COIN,
    FLIGHT,
    OUTPUT,
    PHASE,
    RUNS,
    SeedOpt,
    TossesOpt,
    XisOpt,
)
from coincli.requests.fields import Command, Param
from coincli.requests.fields import Opt as option

__all__ = ["TOSS", "SIMULATE", "PHASE_PICTURE"]

# --------------------------------------------------------------------------- coin toss

UValuesOpt = option("--u", "SPEED", "Launch speed: 2 (m/s), 240cm/s, 8.6km/h; a list, a range or "
                    "-.  Default: drawn (hand toss).")
OmegaValuesOpt = option("--omega", "SPIN", "Spin omega_N = M/I1 of eq. (2): 40 (rad/s), 38rev/s, "
                        "2300rpm; a list, a range or -.  Default: drawn.  At most "
                        f"{BOUNCE_OMEGA_MAX:.0f} rad/s with --landing bounce.")
PsiValuesOpt = option("--psi", "DEG", "Angle psi of the angular momentum to the normal, degrees "
                      "[0, 180]; a list, a range or -.  Default: drawn.")
Z0Opt = option("--z0", "MM", "Launch height of the centre, mm or with a unit (default: (sqrt 3/2) "
               "a, plus h/2 for thick contact).")
TrajectoryOpt = option("--trajectory", "FILE.csv", "With --landing bounce: write the time series "
                       "(time, position, quaternion, velocities, tilt, energy, contacts) to this "
                       "CSV file.")

TOSS = Command(
    "toss",
    COIN.but(xi=XisOpt),
    ("psi", PsiValuesOpt, None),
    ("u", UValuesOpt, None),
    ("omega", OmegaValuesOpt, None),
    ("seed", SeedOpt, None),
    FLIGHT,
    ("z0", Z0Opt, None),
    BOUNCE.without(*RUNS),  # one toss: no worker processes
    ("trajectory", TrajectoryOpt, None),
    output=OUTPUT,
)

# --------------------------------------------------------------------------- coin simulate

SpecUOpt = option(
    "--u", "SPEC", f"Launch speed: {SPEC_FORM}, in m/s or with a unit "
    f"(normal:240:30cm/s).  Default: {HAND['u']} (hand toss).")
SpecOmegaOpt = option(
    "--omega", "SPEC", f"Spin: {SPEC_FORM}, in rad/s or with a unit.  "
    f"Default: {HAND['omega']} (hand toss).  At most {BOUNCE_OMEGA_MAX:.0f} rad/s with --landing "
    "bounce.")
FixedPsiOpt = option("--psi", "DEG", "A fixed angle psi, degrees [0, 180].")
HandPsiDistOpt = option(
    "--psi-dist", "SPEC", "psi density: uniform[:LOW:HIGH], cosine, "
    f"normal[:MEAN:SD] (deg), table:FILE.  Default: {HAND['psi']}.")
StreamOpt = option("--stream", None, "Print one outcome a line (H, S or T) instead of the summary.",
                   kind=bool)

SIMULATE = Command(
    "simulate",
    COIN,
    ("u", SpecUOpt, None),
    ("omega", SpecOmegaOpt, None),
    ("psi", FixedPsiOpt, None),
    ("psi_dist", HandPsiDistOpt, None),
    ("tosses", TossesOpt, None),
    ("seed", SeedOpt, None),
    Param("stream", StreamOpt, False, api=False),  # a way of printing, not a result
    FLIGHT,
    BOUNCE,
    output=OUTPUT,
)

# --------------------------------------------------------------------------- coin phase

PhaseOutOpt = option("--out -o", "FILE", "Write a figure: .png, .svg or .pdf (needs matplotlib: "
                     "pip install 'thickcoin\\[plot]').")

PHASE_PICTURE = Command(
    "phase",
    COIN,
    PHASE,
    Param("out", PhaseOutOpt, None, api=False),  # a way of drawing, not a result
    output=OUTPUT.only("fmt"),  # a picture: no -q
)
