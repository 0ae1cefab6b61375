"""The options that several commands take, declared once: the coin, tosses, seeds, psi, the
output, the accuracy of an average over psi, the table of ``--landing bounce`` and where its
tosses run, the launch, and the phase grid.

Each is an :class:`~coincli.requests.fields.Opt` (names, metavar, help); options that travel
together are a :class:`~coincli.requests.fields.Group`.  What a value *means* is parsed in
:mod:`coincli.io.options` and :mod:`coincli.io.grammar`.  Imports nothing heavy.
"""

from __future__ import annotations

from coincli.limits import (
    BOUNCE_G_MAX,
    BOUNCE_OMEGA_MAX,
    CONTACTS,
    G_MAX,
    G_MIN,
    LANDINGS,
    PHASE_DATA_CELLS,
    PHASE_FIGURE_CELLS,
    PHASE_OMEGA_DEFAULT,
    PHASE_U_DEFAULT,
    SURFACE_NAMES,
)
from coincli.requests.fields import Group, Param
from coincli.requests.fields import Opt as option

# --------------------------------------------------------------------------- the coin group

XiOpt = option("--xi -x", "XI", "Aspect ratio h/D: 0.577 or 17/30.")
XisOpt = option("--xi -x", "XI", "Aspect ratio h/D: 0.577, 17/30, a list a,b, a range lo:hi:step, "
                "or - (stdin).")
CoinOpt = option("--coin -c", "NAME", "Catalog coin (see coin coins).")
CountOpt = option("--count", "N", "Stack N of the --coin (or --diameter) coins.")
CountsOpt = option("--count", "N", "Stack N coins: N, a list, a range or -.")
QuartersOpt = option("--quarters", "N", "N US quarters stacked (--coin quarter --count N).")
QuartersManyOpt = option("--quarters", "N", "N US quarters stacked: N, a list, a range or -.")
DiameterOpt = option("--diameter -d", "D", "Diameter: 24.26 (mm), 2.4cm or 0.955in.")
ThicknessOpt = option("--thickness -t", "H", "Thickness (mm or a unit), with --diameter.")

# --------------------------------------------------------------------------- tosses, seeds

TossesOpt = option("-n --n --tosses", "N", "Number of tosses.")
#: the retired ``-n`` (stacked coins) of ``coin table`` and ``coin stack``: hidden, it fails
#: naming ``--count`` (``-n`` is always a number of tosses)
OldCountOpt = option("-n", "N", hidden=True)
SeedOpt = option("--seed", "SEED", "Seed, a whole number >= 0 (default: drawn, and reported).")

# --------------------------------------------------------------------------- psi

PsiOpt = option("--psi", "DEG", "Angle psi of the angular momentum to the normal, degrees [0, "
                "180].")
PsisOpt = option("--psi", "DEG", "Angle psi, degrees [0, 180]: a value, a list a,b or a range "
                 "lo:hi:step.")
PsiDistOpt = option("--psi-dist", "SPEC", "psi density: uniform[:LOW:HIGH], cosine, "
                    "normal[:MEAN:SD] (deg), table:FILE.")
PsiDistsOpt = option("--psi-dist", "SPECS", "psi densities, comma-separated: uniform[:LOW:HIGH], "
                     "cosine, normal[:MEAN:SD], table:FILE.")

# --------------------------------------------------------------------------- output

FormatOpt = option("--format -f", "FORMAT", "Output format: table (default: aligned text, folded "
                   "to fit a terminal), csv, tsv, json, jsonl or markdown (a pipe table).",
                   kind=str)
QuietOpt = option("--quiet -q", None, "Print only the main number (for shell scripts).", kind=bool)

#: a coin: ``--xi``, ``--coin``, ``--count``, ``--quarters``, ``--diameter``, ``--thickness``
COIN = Group(("xi", XiOpt, None), ("coin", CoinOpt, None), ("count", CountOpt, None),
             ("quarters", QuartersOpt, None), ("diameter", DiameterOpt, None),
             ("thickness", ThicknessOpt, None))
#: one or more coins: lists, ranges or - for --xi, --count and --quarters
COINS = COIN.but(xi=XisOpt, count=CountsOpt, quarters=QuartersManyOpt)
#: what is printed, and how: ``--format`` and ``-q``
#: (a way of printing: the api returns the rows, and takes neither)
OUTPUT = Group(Param("fmt", FormatOpt, "table", api=False),
               Param("quiet", QuietOpt, False, api=False))


# --------------------------------------------------------------------------- accuracy

TolOpt = option("--tol", "TOL", "Absolute error wanted on each psi-averaged chance, e.g. 1e-6 "
                "(the error is shown).")
MethodOpt = option("--method", "METHOD", "Averaging over psi: auto, quad (Gauss-Legendre), mc or "
                   "qmc (simulated tosses).")
DesignMethodOpt = option("--method", "auto|quad", "How to average over psi: auto (the fewest "
                         "nodes that meet --tol) or quad (Gauss-Legendre).")
McSeedOpt = option("--seed", "SEED", "Seed of --method mc or qmc, a whole number >= 0 (default: "
                 "drawn, and reported).")


# --------------------------------------------------------------------------- --landing bounce

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


# --------------------------------------------------------------------------- the phase grid

PhasePsiOpt = option("--psi", "DEG", "Angle psi of the angular momentum to the normal, degrees "
                     "[0, 180].", kind=str)
URangeOpt = option(
    "--u", "LOW:HIGH", f"Launch speeds: {PHASE_U_DEFAULT} (m/s) or with a unit, "
    "0:300cm/s.")
OmegaRangeOpt = option(
    "--omega", "LOW:HIGH", f"Spins: {PHASE_OMEGA_DEFAULT} (rad/s) or with a unit, "
    "0:10rev/s.")
ColsOpt = option(
    "--cols", "N", f"Grid cells along u (default: fit the terminal; "
    f"{PHASE_FIGURE_CELLS} for a figure, {PHASE_DATA_CELLS} for csv/json).")
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
PHASE = Group(("psi", PhasePsiOpt, "90"), ("u", URangeOpt, None), ("omega", OmegaRangeOpt, None),
              ("cols", ColsOpt, None), ("rows", RowsOpt, None), ("exact", ExactOpt, False),
              ("no_curves", NoCurvesOpt, False), ("toss", TossMarkOpt, None), FLIGHT)
#: the old spellings of ``coin plot phase``
OLD = Group(("u_range", OldURangeOpt, None), ("omega_range", OldOmegaRangeOpt, None),
            ("exact_curves", OldExactOpt, False), ("resolution", OldResolutionOpt, None))


# --------------------------------------------------------------------------- completion


def completions(option: str) -> tuple[str, ...]:
    """The names an option's value completes to in a shell (``--surface``: the presets); files
    complete as files (:mod:`coincli.cli._help`), everything else to nothing."""
    if option == "--coin":
        from coincli.core.coins import CATALOG

        return tuple(CATALOG)
    if option == "--format":
        from coincli.io.table import FORMATS

        return FORMATS
    return {"--surface": SURFACE_NAMES, "--landing": LANDINGS,
            "--model": ("geometric", "dynamic", "psi"), "--contact": CONTACTS,
            "--method": ("auto", "quad", "mc", "qmc"), "--vs": ("psi",),
            "--psi-dist": ("uniform", "cosine", "normal", "table:")}.get(option, ())
