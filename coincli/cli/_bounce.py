"""``--landing bounce``: the options shared by ``coin simulate``, ``coin toss``, ``coin design``
and ``coin plot sides`` for tosses that land on a surface (issue 16), and the progress bar of a
bounce design.

These are the typer declarations, and their :class:`~coincli.cli._options.Group`
(:data:`BOUNCE`); :mod:`coincli.reports.bounce` parses them and runs the
tosses (:mod:`coincli.core.bounce.engine`, MuJoCo, an optional extra).  Nothing here imports
numpy, scipy, rich or mujoco at import time; ``--landing catch`` (the default) never loads them.
"""

from __future__ import annotations

from typing import Annotated

import typer

from coincli.cli._options import Group

LandingOpt = Annotated[
    str, typer.Option("--landing", help="catch (the paper's: caught at first contact, the "
                      "exact model) or bounce (lands on a surface, bounces and settles; "
                      "simulated with MuJoCo, pip install 'thickcoin[physics]').",
                      metavar="catch|bounce")
]
SurfaceOpt = Annotated[
    str | None, typer.Option("--surface", help="With --landing bounce: wood (default), "
                             "hard-floor, felt or rice (the paper's catch surface); "
                             "--restitution and the friction options change one number.",
                             metavar="NAME")
]
RestitutionOpt = Annotated[
    str | None, typer.Option("--restitution", help="Coefficient of restitution of the surface "
                             "(the rebound speed ratio of a flat drop), 0.06 to 0.95.",
                             metavar="E")
]
FrictionOpt = Annotated[
    str | None, typer.Option("--friction", help="Sliding friction coefficient of the surface, "
                             "0 to 10.", metavar="MU")
]
TorsionalOpt = Annotated[
    str | None, typer.Option("--torsional", help="Torsional friction, a length (mm or with a "
                             "unit): resisting torque per unit normal force.", metavar="MM")
]
RollingOpt = Annotated[
    str | None, typer.Option("--rolling", help="Rolling resistance, a length (mm or with a "
                             "unit): c_rr times the radius.", metavar="MM")
]
ReleaseHeightOpt = Annotated[
    str | None, typer.Option("--release-height", help="With --landing bounce: the height of "
                             "the launch plane above the surface (mm or with a unit; or "
                             "normal:MEAN:SD, uniform:LOW:HIGH in mm).  Default 0: the surface "
                             "is the paper's catch plane.", metavar="SPEC")
]
VxOpt = Annotated[
    str | None, typer.Option("--vx", help="With --landing bounce: horizontal speed, m/s (or "
                             "normal:MEAN:SD, uniform:LOW:HIGH), in a random direction.",
                             metavar="SPEC")
]
JobsOpt = Annotated[
    str | None, typer.Option("--jobs", "-j", help="Worker processes for --landing bounce "
                             "(default: every core).  The results do not depend on it.",
                             metavar="N")
]
DtOpt = Annotated[
    str | None, typer.Option("--dt", help="MuJoCo's timestep, s (default 1e-4; see "
                             "docs/bounce.md for the convergence study), 1e-6 to 1e-3.",
                             metavar="S")
]
TMaxOpt = Annotated[
    str | None, typer.Option("--t-max", help="Simulated seconds after which a coin still "
                             "moving counts as unsettled (default 10).", metavar="S")
]


#: the table's options, in the order of ``--help``; a command takes those it has
BOUNCE = Group(("landing", LandingOpt, "catch"), ("surface", SurfaceOpt, None),
               ("restitution", RestitutionOpt, None), ("friction", FrictionOpt, None),
               ("torsional", TorsionalOpt, None), ("rolling", RollingOpt, None),
               ("release_height", ReleaseHeightOpt, None), ("vx", VxOpt, None),
               ("jobs", JobsOpt, None), ("dt", DtOpt, None), ("t_max", TMaxOpt, None))
#: the surface a coin lands on
SURFACE = BOUNCE.only("landing", "surface", "restitution", "friction")
