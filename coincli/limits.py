"""The constants and limits that the core and the command line share: one copy of each.

This module imports nothing, so that the command line can name a limit in a message, or check
it, without loading the core (and numpy) on a path that does not need it.  The core
(:mod:`coincli.core`) imports its limits from here too, so the two can never disagree.
"""

#: m, the diameter of a US quarter: the paper's coin, the default everywhere
DEFAULT_DIAMETER = 0.02426
#: m/s^2, standard gravity (the default ``--g``)
STANDARD_G = 9.81
#: the contacts of a toss: ``rim`` (the paper's) or ``thick`` (the cylinder's corner)
CONTACTS = ("rim", "thick")
#: the landings: ``catch`` (the paper's: caught at first contact) or ``bounce`` (on a table)
LANDINGS = ("catch", "bounce")
#: the surface presets of ``--landing bounce`` (their numbers are in coincli.core.bounce.engine)
SURFACE_NAMES = ("wood", "hard-floor", "felt", "rice")

#: m/s, the largest launch speed accepted
U_MAX = 1e8
#: rad/s, the top of a spin range in ``coin phase`` and ``coin plot phase``
OMEGA_TOP = 1e12
#: rad: a phase (omega * t) beyond this is refused: a double no longer resolves a turn in it
MAX_PHASE = 1e12
#: the most tosses of one catch run (``coin simulate -n``; about 20 s of hand tosses)
MAX_TOSSES = 10**8
#: the most tosses of one ``--landing bounce`` run (about 4 hours at 75 tosses/s on two cores)
MAX_BOUNCE_TOSSES = 10**6
#: the most tosses of one ``coin book --toss`` run (a box costs about ten coins)
MAX_BOOK_TOSSES = 10**7
#: a normal launch distribution is checked up to MEAN + NORMAL_REACH SD (P < 1e-23 a draw)
NORMAL_REACH = 10
#: m/s^2, the smallest and largest ``--g``.  Below G_MIN (a subnormal g has a digit or none)
#: ``g t^2 / 2`` loses its digits and the toss would be followed wrongly (issue 28)
G_MIN = 1e-300
G_MAX = 1e100

# --landing bounce: the limits of the MuJoCo engine (coincli.core.bounce.engine), checked and
# named by every bouncing command (toss, simulate, design, plot sides) before any simulation.
#: m/s^2, the largest --g of a bounce: a stronger gravity drives MuJoCo's soft contact past
#: what its time step resolves (the coin sinks through the surface; 'Nan, Inf or huge value')
BOUNCE_G_MAX = 1e3
#: rad/s, the fastest spin of a bounce (above it the contact cannot be resolved at --dt)
BOUNCE_OMEGA_MAX = 1e4
#: the thickest coin of a bounce, xi = h/D (MuJoCo's cylinder and inertia limits)
BOUNCE_XI_MAX = 100.0
#: the tosses of a bounce design (``coin design --landing bounce --max-tosses``): the default,
#: and the most (the least is the first sweep's, coincli.core.bounce.design)
BOUNCE_DESIGN_TOSSES = 200_000

# The launches and grids that help texts name (the reports use the same constants).
#: the hand toss that every launch option defaults to (after Diaconis, Holmes & Montgomery)
HAND = {"u": "normal:2.4:0.3", "omega": "normal:38:4rev/s", "psi": "normal:90:10"}
#: what --u and --omega of a run take
SPEC_FORM = "a value, normal:MEAN:SD or uniform:LOW:HIGH"
#: the ranges of ``coin phase`` and ``coin plot phase``: m/s and rad/s
PHASE_U_DEFAULT, PHASE_OMEGA_DEFAULT = "0:3", "0:60"
#: the grid of a phase figure file, and of its csv/json, along each axis
PHASE_FIGURE_CELLS, PHASE_DATA_CELLS = 400, 100

# The surface, launch-plane and step options of --landing bounce, and the same fields of a
# calibration file (coincli.io.calibration): one range each, checked by both.
#: the restitution a MuJoCo contact can give (coincli.core.bounce.engine.RESTITUTION_MIN/MAX)
BOUNCE_RESTITUTION_MIN = 0.06
BOUNCE_RESTITUTION_MAX = 0.95
#: the sliding friction coefficient of a surface
BOUNCE_FRICTION_MAX = 10.0
#: mm, the torsional and rolling friction lengths (from 0)
BOUNCE_FRICTION_LENGTH_MAX_MM = 100.0
#: mm, the surface below the launch plane (--release-height, from 0)
BOUNCE_HEIGHT_MAX_MM = 1e5
#: m/s, the sideways launch speed (--vx, from 0)
BOUNCE_VX_MAX = 100.0
#: s, MuJoCo's time step (--dt)
BOUNCE_DT_MIN = 1e-6
BOUNCE_DT_MAX = 1e-3
#: s, the time a toss may take to settle (--t-max)
BOUNCE_T_MAX_MIN = 0.01
BOUNCE_T_MAX_MAX = 1000.0
