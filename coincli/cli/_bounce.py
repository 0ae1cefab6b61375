"""``--landing bounce``: the options shared by ``coin simulate``, ``coin toss``, ``coin design``
and ``coin plot sides`` for tosses that land on a surface (issue 16), and the progress bar of a
bounce design.  Where the tosses run (``--jobs``, ``--scheduler``, ``--checkpoint``,
``--timeout``: issue 26) is part of the group, so a command that runs bouncing tosses takes
them all (``BOUNCE``, or ``BOUNCE.only(*RUNS)``); ``coin toss`` (one toss) takes none.

These are the typer declarations, and their :class:`~coincli.cli._options.Group`
(:data:`BOUNCE`); :mod:`coincli.reports.bounce` parses them and runs the
tosses (:mod:`coincli.core.bounce.engine`, MuJoCo, an optional extra).  Nothing here imports
numpy, scipy, rich or mujoco at import time; ``--landing catch`` (the default) never loads them.
"""

from __future__ import annotations

from coincli.cli._options import Group, option
from coincli.limits import BOUNCE_OMEGA_MAX

LandingOpt = option("--landing", "catch|bounce", "catch (the paper's: caught at first contact, "
                    "the exact model) or bounce (lands on a surface, bounces and settles; "
                    "simulated with MuJoCo, pip install 'thickcoin[physics]').", kind=str)
SurfaceOpt = option("--surface", "NAME", "With --landing bounce: wood (default), hard-floor, felt "
                    "or rice (the paper's catch surface); --restitution and the friction options "
                    "change one number.")
RestitutionOpt = option("--restitution", "E", "Coefficient of restitution of the surface (the "
                        "rebound speed ratio of a flat drop), 0.06 to 0.95.")
FrictionOpt = option("--friction", "MU", "Sliding friction coefficient of the surface, 0 to 10.")
TorsionalOpt = option("--torsional", "MM", "Torsional friction, a length (mm or with a unit): "
                      "resisting torque per unit normal force.")
RollingOpt = option("--rolling", "MM", "Rolling resistance, a length (mm or with a unit): c_rr "
                    "times the radius.")
ReleaseHeightOpt = option("--release-height", "SPEC", "With --landing bounce: the height of the "
                          "launch plane above the surface (mm or with a unit; or normal:MEAN:SD, "
                          "uniform:LOW:HIGH in mm).  Default 0: the surface is the paper's catch "
                          "plane.")
VxOpt = option("--vx", "SPEC", "With --landing bounce: horizontal speed, m/s (or normal:MEAN:SD, "
               "uniform:LOW:HIGH), in a random direction.")
JobsOpt = option("--jobs -j", "N", "Worker processes for --landing bounce, 1 to 1024 (default: "
                 "every core; more than the cores is capped at the cores, with a note).  The "
                 "results do not depend on it.")
SchedulerOpt = option("--scheduler", "ADDRESS", "Run the tosses on a Dask cluster: the "
                      "scheduler's tcp://HOST:PORT, or local for a LocalCluster here (default: "
                      "$DASK_SCHEDULER_ADDRESS, else --jobs processes; pip install "
                      "'thickcoin[cluster]').  The results do not depend on it.")
CheckpointOpt = option("--checkpoint", "FILE", "Record the tosses done in FILE as they complete; "
                       "the same command run again computes only what is missing.")
TimeoutOpt = option("--timeout", "S", "With --scheduler: seconds to wait for the scheduler, a "
                    "worker, or a scheduler lost mid-run (default 15).")
DtOpt = option("--dt", "S", "MuJoCo's timestep, s (default 1e-4; see docs/bounce.md for the "
               "convergence study), 1e-6 to 1e-3.")
CalibrationOpt = option("--calibration", "CAL.json", "With --landing bounce: your table, "
                        "calibrated from tosses (coin fit --landing bounce FILE --save "
                        "CAL.json); it replaces --surface and the friction options.")
TMaxOpt = option("--t-max", "S", "Simulated seconds after which a coin still moving counts as "
                 "unsettled (default 10).")


#: where the tosses of a run are computed: the local pool, a Dask cluster, a checkpoint
RUNS = ("jobs", "scheduler", "checkpoint", "timeout")
#: the table's options, in the order of ``--help``; a command takes those it has
BOUNCE = Group(("landing", LandingOpt, "catch"), ("surface", SurfaceOpt, None),
               ("restitution", RestitutionOpt, None), ("friction", FrictionOpt, None),
               ("torsional", TorsionalOpt, None), ("rolling", RollingOpt, None),
               ("release_height", ReleaseHeightOpt, None), ("vx", VxOpt, None),
               ("jobs", JobsOpt, None), ("scheduler", SchedulerOpt, None),
               ("checkpoint", CheckpointOpt, None), ("timeout", TimeoutOpt, None),
               ("dt", DtOpt, None), ("t_max", TMaxOpt, None),
               ("calibration", CalibrationOpt, None))

#: the launch of the tosses a command simulates on a table when it also has a catch meaning
#: for ``--psi`` (``coin design``, ``coin table``, ``coin check``, ``coin fit``): speed, spin,
#: a fixed psi (``coin check``, ``coin fit``: their ``--psi-dist`` is a list of catch models
#: without ``--landing bounce``, the launch's with it) and the seed
LAUNCH = Group(
    ("u", option("--u", "SPEC", "With --landing bounce: launch speed, m/s, a value or "
                 "normal:MEAN:SD / uniform:LOW:HIGH (default the hand toss of coin simulate, "
                 "normal:2.4:0.3)."), None),
    ("omega", option("--omega", "SPEC", "With --landing bounce: precession rate, rad/s or with "
                     "a unit (default the hand toss, normal:38:4rev/s), at most "
                     f"{BOUNCE_OMEGA_MAX:.0f} rad/s."), None),
    ("psi", option("--psi", "DEG", "With --landing bounce: a fixed launch angle psi (degrees) "
                   "instead of the hand toss's spread (or --psi-dist)."), None),
    ("seed", option("--seed", "SEED", "With --landing bounce: the seed of the simulated tosses, "
                    "a whole number >= 0 (default: drawn, and reported)."), None),
)
