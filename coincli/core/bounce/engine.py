r"""Tosses that land on a surface: a rigid-body engine for bouncing coins (MuJoCo).

Every closed form of :mod:`coincli.core.models` and the deterministic tosses of :mod:`coincli.core.toss.flight`
assume the paper's landing: the coin is *caught* at its first contact.  This module answers the
other question, what a coin does on a table: it bounces, rolls and settles.  It is an optional
engine, ``pip install 'thickcoin[physics]'`` (MuJoCo's ``mujoco-core`` bindings); nothing else in
``coincli`` imports MuJoCo.

The set-up
    The coin is MuJoCo's native cylinder (radius ``a = D/2``, half-length ``h/2 = xi a``) on a
    plane; its plane-cylinder collider is analytic (3 contacts lying flat, 2 on the side, 1 on
    the rim).  Mass and inertia come from the geometry and a density: MuJoCo's cylinder gives
    ``I1 = m (a^2/4 + h^2/12)`` and ``I3 = m a^2/2``, the paper's (tests/test_bounce.py checks
    it against :func:`inertia`).

    The launch is the paper's (Sec. II), as ``coin toss`` uses it: heads up, the centre at ``z0``
    above the launch plane, thrown up at ``u``, angular momentum ``M = I1 omega`` (``omega`` the
    precession rate ``omega_N`` of eq. 2) at the angle ``psi`` from the normal.  Added here: the
    surface lies ``height`` below the launch plane (0: the paper's catch plane), and the coin may
    move sideways at ``vx`` in a random horizontal direction.

Free flight is exact, not simulated
    Between contacts the coin is a torque-free symmetric top under gravity: the normal precesses
    about the fixed angular momentum ``L`` at ``Omega = |L| / I1`` and the body spins about its
    axis at ``lambda = (L.n)(1/I3 - 1/I1)``; the centre follows a parabola.  The first contact is
    the certified root of :func:`coincli.core.toss.batch.toss_many` (``contact="thick"``: the cylinder's
    lowest corner); later flights use the same certified scan, generalised to any tilt
    (:func:`_first_touch`).  MuJoCo starts :data:`LEAD_STEPS` steps before a contact and stops
    when the coin is airborne again.  (A precessing flight integrated by MuJoCo needs RK4 to keep
    its energy; ``flight="mujoco"`` does that, for the validation tests.)

Landings
    ``catch``: the toss ends at MuJoCo's first contact; the side up is eq. (7) on the tilt then
    (:func:`coincli.core.toss.flight.classify`).  ``bounce``: the coin bounces until its outcome can no
    longer change: when its energy (kinetic, gravitational and the contact springs' stored
    energy) is below ``m g (R - 1 um)``, ``R = sqrt(a^2 + h^2/4)`` the half-diagonal, it cannot
    lift its centre over a corner, so it can never cross ``alpha = theta0`` or
    ``pi - theta0``: the side is eq. (7) on its tilt at that moment.  A coin (``xi >= 0.3``)
    rolling on its curved side without slipping is compared with the barrier without the energy
    of its rolling (:meth:`Engine._rolling`, which says why).  A coin still above the barrier at
    ``t_max`` is *unsettled*, counted on its own.

The surface
    Users know a coefficient of restitution (the rebound speed ratio of a flat drop) and friction
    coefficients; MuJoCo has neither restitution nor a material.  Its soft contact pulls the
    contact's normal distance ``r`` toward ``r'' = -b r' - k r`` (``solref = (-k, -b)``, MuJoCo's
    direct stiffness and damping, "Modeling: contact parameters"), a damped oscillator in
    acceleration units, so the rebound ratio is the same for any effective mass (face or rim).
    ``k`` is fixed by the timestep (:data:`OMEGA_DT`), and ``b`` is found by a calibration
    (:func:`calibrate`): bisection on simulated drops until the mean restitution of a flat drop
    and an edge drop is the one asked for (both then within ~0.02 of it).
    ``solimp = (0.99, 0.99, ...)``: a constant impedance, so the oscillator is linear (MuJoCo's
    default impedance varies with penetration and would make ``e`` depend on the impact speed).
    ``condim = 6``: sliding, torsional and rolling friction (with the default ``condim = 3`` a
    coin rolling on its rim keeps its energy and circles for ever), on an elliptic friction cone.

Many tosses with seeded random launches, across worker processes, are
:mod:`coincli.core.bounce.runs` (:func:`~coincli.core.bounce.runs.simulate`); the aspect ratio
that lands on a side with a given chance is :mod:`coincli.core.bounce.design`.

Everything is SI; nothing here prints, parses text or exits.  Bad input raises ``ValueError``
naming the argument; a missing MuJoCo raises :class:`PhysicsMissing`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

from coincli import limits as L
from coincli.core._numerics.quaternion import qaxis, qconj, qmul, qrot
from coincli.core._numerics.roots import bisect
from coincli.core.toss.flight import (
    DEFAULT_DIAMETER,
    NAMES,
    STANDARD_G,
    check_number,
    classify,
)
from coincli.errors import PhysicsMissing, install_hint
from coincli.limits import BOUNCE_G_MAX, BOUNCE_XI_MAX, LANDINGS, SURFACE_NAMES

__all__ = [
    "PhysicsMissing",
    "require_mujoco",
    "INSTALL_HINT",
    "Surface",
    "SURFACES",
    "surface",
    "Coin",
    "inertia",
    "Launch",
    "launch_state",
    "Engine",
    "TossResult",
    "calibrate",
    "drop_restitution",
    "DEFAULT_DT",
    "DEFAULT_DENSITY",
    "DEFAULT_T_MAX",
    "LANDINGS",
    "UNSETTLED",
]

INSTALL_HINT = install_hint("physics")
UNSETTLED = 3  #: outcome code of a toss still moving at t_max
DEFAULT_DENSITY = 8920.0  #: kg/m^3, cupronickel (the US quarter's cladding, 75 Cu / 25 Ni)
#: s.  The step sets the contact's stiffness too (:data:`OMEGA_DT`).  2e-4 halves the steps, but
#: its contact, a quarter as stiff, moved P(sides) on wood from 0.61 to 0.70 at xi = 0.7, where
#: 1e-4 and 5e-5 agree within their intervals: the stiffness, not the step (docs/bounce.md, "The
#: step and the contact's stiffness"; benchmarks/bounce_vs_tables.py).
DEFAULT_DT = 1e-4
DEFAULT_T_MAX = 10.0  #: s of simulated time after launch before a toss counts as unsettled
#: Contact stiffness: omega_n dt = 0.3, so an impact (half a period, pi / omega_n) spans about
#: ten steps; stiffer contacts lose their restitution to the integrator, softer ones sink
#: further (0.7 mm at 2.5 m/s and dt = 1e-4, about twice that at 2e-4).
OMEGA_DT = 0.3
#: The impedance d of solimp, constant: the fraction of the reference acceleration the contact
#: achieves.  0.99 (MuJoCo's default ramps 0.9 to 0.95) keeps the contact nearly hard and linear.
IMPEDANCE = 0.99
EDGE_TILT = 0.6  #: rad, the tilt of the edge drop of the calibration
LEAD_STEPS = 5  #: MuJoCo starts this many steps before an exactly computed contact
CHECK_STEPS = 20  #: steps between the checks of energy and flight (4 ms at the default dt)
JUMP_MIN_STEPS = 30  #: a flight shorter than this many steps is stepped, not solved
#: s: a flight counts as a bounce from this long (shorter ones are chatter); a time, not a number
#: of steps, so that the count does not depend on the timestep (3 ms: 15 steps at the default)
BOUNCE_MIN = 3e-3
REST_MARGIN = 1e-6  #: m: rest when the energy is below m g (R - REST_MARGIN)
#: |n_z| below which a coin lies on its curved side (0.57 degrees of tilt from 90): both ends of
#: its lowest generator touch, as far as the contact's millimetre of give lets the tilt differ
SIDE_TILT = 0.01
SLIP_TOL = 2e-3  #: m/s: a contact point moving slower than this does not slip (rolls)
#: The rolling and spin rules apply from this aspect ratio up, where they were checked (xi =
#: 0.3 to 1.5).  A thinner coin's side is its rim, a basin a few degrees wide (4 for a
#: quarter), and a coin rolling upright there is not shown to keep its side (rolling on its rim,
#: friction turns its spin into standing up: the spin rule decided a quarter wrongly in a test):
#: it keeps the whole-energy rule.
ROLLING_XI_MIN = 0.3
_ZOOM = 32  #: cells a cell of the flight scan is cut into when it may hold a contact



#: MuJoCo's warnings in this process, the last few (:func:`require_mujoco` installs the handler
#: that keeps them here): never printed, never logged to a file
MUJOCO_WARNINGS: list = []


def _keep_warning(message: str) -> None:
    """MuJoCo's warning handler (``mju_user_warning``): keep the message, print nothing.  Without
    a handler MuJoCo prints each warning on the terminal and appends it to ``MUJOCO_LOG.TXT`` in
    the current directory (issue 28); a warning is a symptom the commands check for themselves
    (an unsettled toss, a refused input), not the user's business."""
    del MUJOCO_WARNINGS[:-9]
    MUJOCO_WARNINGS.append(message)


def require_mujoco():
    """Import and return :mod:`mujoco` with its warnings kept quiet (:func:`_keep_warning`), or
    raise :class:`PhysicsMissing` with the one-line hint."""
    try:
        import mujoco
    except ImportError:
        raise PhysicsMissing("this needs the MuJoCo physics engine, an optional extra: "
                             f"{INSTALL_HINT}") from None
    if mujoco.get_mju_user_warning() is not _keep_warning:  # global: once a process (a spawned
        mujoco.set_mju_user_warning(_keep_warning)  # worker gets it by building its model)
    return mujoco


# --------------------------------------------------------------------------- surfaces


@dataclass(frozen=True)
class Surface:
    """What the coin lands on: a coefficient of restitution and three friction coefficients.

    ``restitution`` is the rebound speed ratio of a flat drop (0 to 0.95); ``friction`` the
    sliding (Coulomb) coefficient; ``torsional`` and ``rolling`` are lengths in metres (MuJoCo's
    units: the resisting torque per unit normal force about the normal and about a tangent).
    """

    restitution: float
    friction: float
    torsional: float = 1e-4
    rolling: float = 1e-4
    name: str = "custom"
    source: str = "given by the user"

    def __post_init__(self):
        check_number("restitution", self.restitution, RESTITUTION_MIN, RESTITUTION_MAX)
        check_number("friction", self.friction, 0.0, 10.0)
        check_number("torsional friction", self.torsional, 0.0, 0.1, unit="m")
        check_number("rolling friction", self.rolling, 0.0, 0.1, unit="m")

    def describe(self):
        return (f"{self.name}: restitution {self.restitution:g}, friction {self.friction:g}, "
                f"torsional {self.torsional:g} m, rolling {self.rolling:g} m")


#: Above this the calibrated contact is nearly undamped and MuJoCo's soft contact stops giving a
#: controllable restitution; no table is that bouncy for a coin.
RESTITUTION_MAX = L.BOUNCE_RESTITUTION_MAX
#: The deadest contact MuJoCo's explicit damping allows (b dt = 1, see :func:`calibrate`) still
#: rebounds at 0.053; 0.06 leaves a margin.
RESTITUTION_MIN = L.BOUNCE_RESTITUTION_MIN

# Per-contact torsional and rolling friction.  A flat coin's three rim contacts already resist
# twisting through their sliding friction, so the torsional term only stands for the size of
# each contact patch (~0.1 mm).  Rolling resistance is a length, c_rr a, with c_rr the rolling
# resistance coefficient: ~0.008 for a coin rolling on its rim on a wooden table (it stops
# within a metre or two from 0.5 m/s: v^2 / (2 c_rr g)), less on stone, more on cloth and rice,
# which deform.  They matter for a coin rolling on its rim, which without them never stops.
SURFACES = {
    "wood": Surface(0.5, 0.3, 1e-4, 1e-4, "wood", "a varnished wooden table: restitution 0.5 "
                    "(hard metal objects on wood rebound at 0.4-0.6), friction 0.3 (handbook "
                    "metal-on-wood 0.2-0.6), rolling resistance c_rr ~ 0.008; the figures of the "
                    "trial in issue 16"),
    "hard-floor": Surface(0.7, 0.2, 1e-4, 5e-5, "hard-floor", "stone, tile or a hard laminate "
                          "floor: restitution 0.7, friction 0.2 (Murray & Teare's 'flat hard "
                          "surface'; handbook metal-on-stone 0.15-0.3), c_rr ~ 0.004"),
    "felt": Surface(0.2, 0.6, 5e-4, 5e-4, "felt", "a felt or cloth-covered game table: "
                    "restitution 0.2 (cloth absorbs the impact), friction 0.6, c_rr ~ 0.04 (the "
                    "cloth deforms)"),
    "rice": Surface(0.06, 0.8, 1e-3, 1e-3, "rice", "the paper's catch surface (a pan of rice "
                    "under plastic film, Sec. IV): as dead as the contact model allows (0.06), "
                    "rough; with --landing bounce it shows how far a nearly inelastic landing is "
                    "from a catch"),
}
if tuple(SURFACES) != SURFACE_NAMES:  # the command line names them from coincli.limits
    raise AssertionError("coincli.limits.SURFACE_NAMES must list the surface presets in order")


def surface(name=None, *, restitution=None, friction=None, torsional=None, rolling=None):
    """A preset by name, a custom surface, or a preset with some coefficients replaced."""
    base = SURFACES.get("wood" if name is None else name)
    if base is None:
        raise ValueError(f"surface must be one of {', '.join(SURFACES)}, got {name!r}")
    changes = {k: v for k, v in (("restitution", restitution), ("friction", friction),
                                 ("torsional", torsional), ("rolling", rolling)) if v is not None}
    if not changes:
        return base
    label = name or "custom"
    return replace(base, **changes, name=label if name is None else f"{label} (modified)",
                   source="given by the user" if name is None else
                   f"{base.name} preset with {', '.join(changes)} given by the user")


# --------------------------------------------------------------------------- the coin


@dataclass(frozen=True)
class Coin:
    """A solid cylinder: diameter ``D`` (m), aspect ratio ``xi = h/D``, density (kg/m^3)."""

    xi: float
    diameter: float = DEFAULT_DIAMETER
    density: float = DEFAULT_DENSITY

    def __post_init__(self):
        check_number("xi", self.xi, 0.0, BOUNCE_XI_MAX, lo_open=True)
        check_number("diameter", self.diameter, 1e-4, 10.0, unit="m")
        check_number("density", self.density, 1.0, 1e5, unit="kg/m^3")

    @property
    def a(self):
        return self.diameter / 2

    @property
    def hh(self):
        """Half the thickness, ``h/2 = xi a``."""
        return self.xi * self.diameter / 2

    @property
    def half_diagonal(self):
        """``R = sqrt(a^2 + h^2/4)``: the height of the centre balanced on a corner."""
        return math.hypot(self.a, self.hh)


def inertia(coin: Coin):
    """``(m, I1, I3)`` of a solid cylinder: ``m = rho pi a^2 h``, ``I1 = m (a^2/4 + h^2/12)``
    about a diameter through the centre, ``I3 = m a^2 / 2`` about the axis (the paper's)."""
    a, h = coin.a, 2 * coin.hh
    m = coin.density * math.pi * a * a * h
    return m, m * (a * a / 4 + h * h / 12), m * a * a / 2


MJ_MINVAL = 1e-15  #: MuJoCo's mjMINVAL: a moving body's mass and inertia must be above it
ENGINE_SMALLEST = 10 * MJ_MINVAL  #: the smallest mass (kg) and inertia (kg m^2) simulated
TRIANGLE_MARGIN = 1e-12  #: (2 I1 - I3) / I3 at least this: MuJoCo's A + B >= C, with room


def smallest_xi(diameter: float, density: float = DEFAULT_DENSITY) -> float:
    """The smallest aspect ratio whose coin (``diameter`` m, ``density``) MuJoCo can simulate:
    mass and both moments of inertia at least :data:`ENGINE_SMALLEST` (ten times mjMINVAL), and
    the moments clear of MuJoCo's triangle inequality by :data:`TRIANGLE_MARGIN` (xi >= 8.7e-7).
    All three grow with xi; ``inf`` when even xi = 100 is too light (a tiny diameter)."""
    def light(xi):
        c = Coin(xi, diameter, density)
        h2, a2 = (2 * c.hh) ** 2, c.a * c.a
        # MuJoCo also refuses I1 + I1 < I3, which a thin disc meets only by I1 + I1 - I3 =
        # m h^2/6: keep that a relative TRIANGLE_MARGIN of I3 = m a^2/2 (not lost to rounding)
        return min(inertia(c)) < ENGINE_SMALLEST or h2 / 6 < TRIANGLE_MARGIN * a2 / 2

    if light(100.0):
        return math.inf
    if not light(1e-300):
        return 1e-300
    return bisect(light, 1e-300, 100.0, log=True, rtol=1e-12)[1]


def smallest_diameter(density: float = DEFAULT_DENSITY, xi: float = 100.0) -> float:
    """The smallest diameter (m) MuJoCo can simulate at aspect ratio ``xi`` (by default 100:
    the smallest at any aspect ratio)."""
    return bisect(lambda d: smallest_xi(d, density) > xi, 1e-4, 10.0, log=True,
                  rtol=1e-12)[1]


def round_up(v: float, digits: int = 3) -> float:
    """``v`` to ``digits`` significant digits, rounded up (a stated lower limit that is
    itself allowed)."""
    if not math.isfinite(v) or v <= 0:
        return v
    e = math.floor(math.log10(v)) - digits + 1
    r = math.ceil(v / 10.0**e) * 10.0**e
    return float(f"{r:.{digits}g}") if float(f"{r:.{digits}g}") >= v else r


# --------------------------------------------------------------------------- the launch


@dataclass(frozen=True)
class Launch:
    """One toss's initial conditions (SI; ``psi`` and ``azimuth`` in radians)."""

    u: float  #: m/s, upward speed of the centre
    omega: float  #: rad/s, the precession rate omega_N = M / I1 (eq. 2)
    psi: float  #: rad, angle between the angular momentum and the normal
    z0: float  #: m, centre above the launch plane
    height: float = 0.0  #: m, the surface below the launch plane
    vx: float = 0.0  #: m/s, horizontal speed
    azimuth: float = 0.0  #: rad, direction of the horizontal speed from the plane of L and n


@dataclass
class _Flight:
    """A free flight from time ``t0``: centre ``p``, velocity ``v``, orientation ``q``
    (body to world), angular momentum direction ``lhat``, precession rate ``big_omega`` and body
    spin ``lam`` (rad/s)."""

    t0: float
    p: tuple
    v: tuple
    q: tuple
    lhat: tuple
    big_omega: float
    lam: float

    def state(self, t, g):
        """(position, quaternion, linear velocity (world), angular velocity (body)) at ``t``."""
        s = t - self.t0
        p = (self.p[0] + self.v[0] * s, self.p[1] + self.v[1] * s,
             self.p[2] + self.v[2] * s - 0.5 * g * s * s)
        v = (self.v[0], self.v[1], self.v[2] - g * s)
        q = qmul(qaxis(self.lhat, self.big_omega * s),
                  qmul(self.q, (math.cos(0.5 * self.lam * s), 0.0, 0.0,
                                 math.sin(0.5 * self.lam * s))))
        n = qrot(q, (0.0, 0.0, 1.0))
        w = tuple(self.big_omega * self.lhat[i] + self.lam * n[i] for i in range(3))
        return p, q, v, qrot(qconj(q), w)

    def clearance(self, t, a, hh, g):
        """The height of the lowest point of the cylinder (radius ``a``, half-thickness ``hh``)
        above the plane z = 0 at ``t``: ``z - a sin(alpha) - hh |cos(alpha)|``."""
        s = t - self.t0
        q = qmul(qaxis(self.lhat, self.big_omega * s),
                  qmul(self.q, (math.cos(0.5 * self.lam * s), 0.0, 0.0,
                                 math.sin(0.5 * self.lam * s))))
        nz = 1.0 - 2.0 * (q[1] * q[1] + q[2] * q[2])
        z = self.p[2] + self.v[2] * s - 0.5 * g * s * s
        return z - a * math.sqrt(max(0.0, 1.0 - nz * nz)) - hh * abs(nz)


def _flight_from_launch(launch: Launch, i1, i3):
    """The launch as a :class:`_Flight` at t = 0, the surface at z = 0: heads up (body z up),
    ``L = I1 omega (sin psi, 0, cos psi)``, so ``cos alpha = cos^2 psi + sin^2 psi cos(omega t)``
    (eq. 3), and the body spin ``lambda = omega cos psi (I1/I3 - 1)``."""
    sp, cp = math.sin(launch.psi), math.cos(launch.psi)
    lam = launch.omega * cp * (i1 / i3 - 1.0)
    vx, vy = launch.vx * math.cos(launch.azimuth), launch.vx * math.sin(launch.azimuth)
    return _Flight(0.0, (0.0, 0.0, launch.z0 + launch.height), (vx, vy, launch.u),
                   (1.0, 0.0, 0.0, 0.0), (sp, 0.0, cp), launch.omega, lam)


def launch_state(launch: Launch, coin: Coin, t, g=STANDARD_G):
    """The exact state of a launched coin at time ``t`` of its first flight (the surface at
    z = 0): ``(position, quaternion w,x,y,z, velocity, body angular velocity)``."""
    _, i1, i3 = inertia(coin)
    return _flight_from_launch(launch, i1, i3).state(t, g)


def _flight_from_state(t0, qpos, qvel, i1, i3):
    """The free flight through a MuJoCo free-joint state (angular velocity in the body frame)."""
    x, y, z, qw, qx, qy, qz = qpos.tolist()
    vx, vy, vz, wx, wy, wz = qvel.tolist()
    nq = math.sqrt(qw * qw + qx * qx + qy * qy + qz * qz)
    q = (qw / nq, qx / nq, qy / nq, qz / nq)
    lw = qrot(q, (i1 * wx, i1 * wy, i3 * wz))  # L in the world frame
    lnorm = math.sqrt(lw[0] * lw[0] + lw[1] * lw[1] + lw[2] * lw[2])
    if lnorm == 0.0:
        return _Flight(t0, (x, y, z), (vx, vy, vz), q, (0.0, 0.0, 1.0), 0.0, 0.0)
    n = qrot(q, (0.0, 0.0, 1.0))
    lhat = (lw[0] / lnorm, lw[1] / lnorm, lw[2] / lnorm)
    ln = lw[0] * n[0] + lw[1] * n[1] + lw[2] * n[2]
    return _Flight(t0, (x, y, z), (vx, vy, vz), q, lhat, lnorm / i1, ln * (1.0 / i3 - 1.0 / i1))


def _first_touch(fl: _Flight, a, hh, g, resolution):
    """The time (s, absolute) up to which the flight certainly stays clear of the plane z = 0,
    to within ``resolution``: the start of the first cell, at that resolution, whose lower bound
    of the clearance is not positive.

    The clearance is ``F(t) = z(t) - a sin alpha - hh |cos alpha|`` with
    ``cos alpha = A + B cos(Omega s) + C sin(Omega s)``.  As in :mod:`coincli.core.toss.flight`, ``F`` is
    semi-concave, ``F'' <= K = Omega^2 sin(beta) (a + hh) - g`` (``beta`` the angle between L and
    the normal), so on a cell of width ``w``, ``F >= min(F(t1), F(t2)) - max(K, 0) w^2 / 8``:
    cells where this is positive hold no contact, however thin a dip could be.
    """
    import numpy as np

    n0 = qrot(fl.q, (0.0, 0.0, 1.0))
    ln = sum(fl.lhat[i] * n0[i] for i in range(3))
    big_a = ln * fl.lhat[2]
    big_b = n0[2] - big_a
    big_c = fl.lhat[0] * n0[1] - fl.lhat[1] * n0[0]  # (L x n)_z
    sin_beta = math.sqrt(max(0.0, 1.0 - ln * ln))
    om = fl.big_omega
    k = max(om * om * sin_beta * (a + hh) - g, 0.0)
    z0, vz = fl.p[2], fl.v[2]
    t_end = (vz + math.sqrt(vz * vz + 2.0 * g * max(z0, 0.0))) / g  # centre at the plane

    def clearance(s):
        c = np.clip(big_a + big_b * np.cos(om * s) + big_c * np.sin(om * s), -1.0, 1.0)
        return z0 + vz * s - 0.5 * g * s * s - a * np.sqrt(1.0 - c * c) - hh * np.abs(c)

    def scan(t1, t2, cells):
        w = (t2 - t1) / cells
        s = t1 + w * np.arange(cells + 1)
        f = clearance(s)
        low = np.minimum(f[:-1], f[1:]) - k * w * w / 8
        for j in np.flatnonzero(low <= 0.0):
            if w <= resolution:
                return float(s[j])
            hit = scan(float(s[j]), float(s[j + 1]), _ZOOM)
            if hit is not None:
                return hit
        return None

    step = min(2 * math.pi / (16 * om) if om > 0 else math.inf, max(t_end, 1e-9) / 8)
    cells = max(1, math.ceil(t_end / step))
    hit = scan(0.0, t_end, cells)
    return fl.t0 + (t_end if hit is None else hit)


# --------------------------------------------------------------------------- the model


def _mjcf(coin: Coin, surf: Surface, dt, k, b, g):
    """The MJCF model: a plane, a free cylinder, one explicit contact pair.

    Geoms have ``contype = conaffinity = 0`` so that only the ``<pair>`` collides, whose
    parameters are then exactly these (no mixing of two geoms' values).  ``margin = 0``: a
    contact exists only while the solids touch, so "no contact" means "airborne".  Constraint
    islands are off: one body is one island, and finding it each step cost 5% of a toss's CPU
    (1,200 tosses on four surfaces at xi 0.1 to 1 gave the same outcomes, steps, bounces, times
    and tilts to the bit either way; docs/bounce.md).
    """
    mu, tor, rol = surf.friction, surf.torsional, surf.rolling
    # MuJoCo clamps friction below mjMINMU (1e-5); a frictionless surface is that.
    mu, tor, rol = max(mu, 1e-5), max(tor, 1e-5), max(rol, 1e-5)
    d = IMPEDANCE
    return f"""<mujoco model="coin">
  <option timestep="{dt!r}" gravity="0 0 {-g!r}" integrator="implicitfast" cone="elliptic">
    <flag energy="enable" island="disable"/>
  </option>
  <worldbody>
    <geom name="surface" type="plane" size="0 0 1" contype="0" conaffinity="0"/>
    <body name="coin">
      <freejoint/>
      <geom name="coin" type="cylinder" size="{coin.a!r} {coin.hh!r}" density="{coin.density!r}"
            contype="0" conaffinity="0"/>
    </body>
  </worldbody>
  <contact>
    <pair geom1="surface" geom2="coin" condim="6" friction="{mu!r} {mu!r} {tor!r} {rol!r} {rol!r}"
          solref="{-k!r} {-b!r}" solimp="{d!r} {d!r} 0.001 0.5 2" margin="0"/>
  </contact>
</mujoco>"""


def _stiffness(dt):
    wn = OMEGA_DT / dt
    return wn * wn


def _model(coin, surf, dt, b, g):
    lo = smallest_xi(coin.diameter, coin.density)
    if not coin.xi >= lo:
        raise ValueError(f"xi must be at least {round_up(lo):g} for a {coin.diameter:g} m coin "
                         f"(MuJoCo's smallest mass and inertia), got {coin.xi:g}")
    mujoco = require_mujoco()
    m = mujoco.MjModel.from_xml_string(_mjcf(coin, surf, dt, _stiffness(dt), b, g))
    return mujoco, m, mujoco.MjData(m)


def drop_restitution(coin: Coin, surf: Surface, dt, b, *, tilt=0.0, speed=1.0, g=STANDARD_G):
    """The coefficient of restitution of one simulated drop: the coin tilted by ``tilt`` about a
    diameter, falling at ``speed`` onto the surface, with contact damping ``b``.

    Energetic (Stronge's) definition: ``e^2 = 1 - dE / (m_eff v^2 / 2)``, ``dE`` the mechanical
    energy the impact took (gravity's work during the contact accounted for) and ``m_eff`` the
    effective mass of the touching point at the first-contact pose (``m`` for a flat drop, where
    this is the rebound speed ratio).  For an edge drop it is the fraction of the compression
    energy given back; the ratio of the corner's normal speeds (Newton's) is not usable for a
    soft contact, as the coin turns by ~0.1 rad during the millisecond of contact, which moves
    the corner.  With friction, a sliding edge impact also loses energy to friction: calibrate and
    check edges on a frictionless surface.
    """
    mujoco, m, d = _model(coin, surf, dt, b, g)
    a, hh = coin.a, coin.hh
    depth = a * math.sin(tilt) + hh * abs(math.cos(tilt))
    d.qpos[:3] = (0.0, 0.0, depth + 0.5 * speed * dt)  # half a step above the surface
    d.qpos[3:7] = (math.cos(tilt / 2), math.sin(tilt / 2), 0.0, 0.0)
    d.qvel[:] = 0.0
    d.qvel[2] = -speed
    mujoco.mj_forward(m, d)
    mass, i1 = float(m.body_mass[1]), float(m.body_inertia[1][0])
    # the point that touches first: the low corner of a tilted coin (the tilt is about the x
    # axis, so the lever r x n lies along the body's x axis), the lower face of a flat one
    r = qrot(tuple(float(c) for c in d.qpos[3:7]), (0.0, -a if tilt > 0 else 0.0, -hh))
    m_eff = 1.0 / (1.0 / mass + (r[0] ** 2 + r[1] ** 2) / i1)
    e0 = float(d.energy[0]) + float(d.energy[1])
    touched = 0
    # An impact lasts about half a period, pi / omega_n (~10 steps); an overdamped contact never
    # lets go, and is read after five half periods (its rebound is then ~0).
    longest = 5 * math.ceil(math.pi / OMEGA_DT) + 2
    while touched < longest:
        mujoco.mj_step(m, d)
        if d.ncon:
            touched += 1
        if touched and (d.ncon == 0 or not any(d.efc_force[i] > 0 for i in range(0, d.nefc, 6))):
            break
    lost = e0 - float(d.energy[0]) - float(d.energy[1])
    return math.sqrt(max(0.0, 1.0 - lost / (0.5 * m_eff * speed * speed)))


CALIBRATION: dict = {}


def calibration_key(coin: Coin, surf: Surface, dt, g):
    """What decides :func:`calibrate`'s answer (its cache's key)."""
    return (coin, surf.restitution, surf.friction, surf.torsional, surf.rolling, dt, g)


def calibrate(coin: Coin, surf: Surface, dt=DEFAULT_DT, g=STANDARD_G):
    """The contact damping ``b`` (1/s) at which this coin's drops rebound at
    ``surf.restitution`` (:func:`drop_restitution`, the mean of a flat and an edge drop):
    bisection in ``log b`` on simulated drops at 1 m/s (the oscillator is linear, so the speed
    hardly matters).  Cached per (coin, surface, dt, g).

    The linear oscillator would rebound at ``e`` with ``b = 2 zeta omega_n``,
    ``zeta = -ln e / sqrt(pi^2 + ln^2 e)``; the unilateral contact (it lets go as soon as the
    force would pull) and the discrete steps shift that by up to 0.1 in ``e``, hence the
    bisection, bracketed by ``b = 0.003 omega_n`` and the explicit-damping limit ``b = 1/dt``.
    """
    key = calibration_key(coin, surf, dt, g)
    if key in CALIBRATION:
        return CALIBRATION[key]
    e = surf.restitution
    wn = OMEGA_DT / dt
    # A flat drop and an edge drop (tilted 0.6 rad, on the same surface without friction: a
    # sliding edge also loses energy to friction, which is not restitution) differ by ~0.03,
    # the edge rebounding less (the coin turns during the contact): calibrate on their mean, so
    # both are within ~0.02 of the coefficient asked for.
    edge = replace(surf, friction=0.0, torsional=0.0, rolling=0.0)

    def rebound(b):
        return 0.5 * (drop_restitution(coin, surf, dt, b, g=g)
                      + drop_restitution(coin, edge, dt, b, tilt=EDGE_TILT, g=g))

    # MuJoCo applies the damping explicitly (from the velocity at the start of a step), so it
    # is stable up to b dt ~ 1: the damping ratio reaches 1 / (2 OMEGA_DT) = 1.67, where a flat
    # drop still rebounds at RESTITUTION_MIN.
    lo, hi = 1e-3 * wn, 1.0 / dt
    e_lo, e_hi = rebound(lo), rebound(hi)
    if not e_hi <= e <= e_lo:
        raise ValueError(f"restitution {e:g} is beyond what the contact can give at dt = {dt:g} s "
                         f"({e_hi:.3f} to {e_lo:.3f})")
    for _ in range(40):
        mid = math.sqrt(lo * hi)
        if rebound(mid) > e:
            lo = mid
        else:
            hi = mid
        if hi / lo < 1 + 1e-4:
            break
    b = math.sqrt(lo * hi)
    CALIBRATION[key] = b
    return b


# --------------------------------------------------------------------------- one toss


@dataclass
class TossResult:
    """One toss on a surface."""

    code: int  #: 0 heads, 1 sides, 2 tails, 3 unsettled
    outcome: str  #: 'heads', 'sides', 'tails' or 'unsettled'
    t_first: float  #: s, first contact
    t_settle: float  #: s, when the outcome could no longer change (nan if unsettled)
    bounces: int  #: flights of at least BOUNCE_MIN after the first impact
    alpha: float  #: rad, tilt of the normal at the end (catch: at first contact)
    catch_code: int  #: the outcome the catch (first contact, eq. 7) would have given
    steps: int  #: MuJoCo steps taken
    trajectory: list | None = None  #: rows of :data:`TRAJECTORY_COLUMNS` when recorded


TRAJECTORY_COLUMNS = ("t", "x", "y", "z", "qw", "qx", "qy", "qz", "vx", "vy", "vz", "wx", "wy",
                      "wz", "tilt_deg", "energy", "contacts", "phase")


class Engine:
    """One MuJoCo model and data for a coin on a surface; runs tosses one after another.

    ``flight="exact"`` (default) solves free flights in closed form and simulates only near
    contacts; ``flight="mujoco"`` integrates the whole toss with MuJoCo (RK4 in the air,
    implicitfast in contact), for validation.  Each toss starts from a reset ``MjData``, so a
    toss's result does not depend on the tosses run before it.
    """

    def __init__(self, coin: Coin, surf: Surface, *, dt=DEFAULT_DT, g=STANDARD_G,
                 landing="bounce", t_max=DEFAULT_T_MAX, flight="exact", damping=None):
        if landing not in LANDINGS:
            raise ValueError(f"landing must be one of {', '.join(LANDINGS)}, got {landing!r}")
        if flight not in ("exact", "mujoco"):
            raise ValueError(f"flight must be 'exact' or 'mujoco', got {flight!r}")
        check_number("dt", dt, 1e-7, 1e-3, unit="s")
        check_number("g", g, 0.0, BOUNCE_G_MAX, lo_open=True, unit="m/s^2")
        check_number("t_max", t_max, 0.0, 1e3, lo_open=True, unit="s")
        self.coin, self.surface, self.dt, self.g = coin, surf, dt, g
        self.landing, self.t_max, self.flight = landing, t_max, flight
        self.damping = calibrate(coin, surf, dt, g) if damping is None else damping
        self.mujoco, self.m, self.d = _model(coin, surf, dt, self.damping, g)
        self.mass = float(self.m.body_mass[1])
        self.i1 = float(self.m.body_inertia[1][0])
        self.i3 = float(self.m.body_inertia[1][2])
        # MuJoCo's direct stiffness is k / dmax^2, achieved to the impedance d = dmax: k / d
        self.k_spring = _stiffness(dt) / IMPEDANCE
        self.barrier = self.mass * g * (coin.half_diagonal - REST_MARGIN)
        #: the rest rule leaves out the energy of rolling on the side (thick coins only)
        self.rolling_rest = coin.xi >= ROLLING_XI_MIN
        #: the rest rule leaves out the kinetic energy a spinning coin keeps at a corner
        #: (:meth:`_spin_locked`), thick coins only; False: the rules before it (comparisons)
        self.spin_rest = coin.xi >= ROLLING_XI_MIN
        self._corner_nz = coin.hh / coin.half_diagonal  # |n_z| balanced on a corner
        mj = self.mujoco
        self._rk4, self._implicit = mj.mjtIntegrator.mjINT_RK4, mj.mjtIntegrator.mjINT_IMPLICITFAST

    # -- helpers

    def _set(self, state):
        p, q, v, w = state
        d = self.d
        d.qpos[:3] = p
        d.qpos[3:7] = q
        d.qvel[:3] = v
        d.qvel[3:6] = w

    def _tilt(self):
        q = self.d.qpos[3:7]
        nz = 1.0 - 2.0 * (float(q[1]) ** 2 + float(q[2]) ** 2)  # (R e3)_z
        return math.acos(max(-1.0, min(1.0, nz)))

    def _energy(self):
        """Kinetic + gravitational (from the surface) + the contact springs' stored energy.

        The springs: the contact pulls each penetration ``r`` back with acceleration ``k r`` in
        its own effective mass, ``m_eff <= m``; ``m k r^2 / 2`` a contact bounds what each can
        give back (three contacts of a flat coin share the mass, so this over-counts: safe).
        """
        d = self.d
        e0, e1 = d.energy.tolist()
        e = e0 + e1
        spring = 0.0
        if d.ncon:  # the contacts' distances as one array (an MjContact each is slow to make)
            for dist in d.contact.dist.tolist():
                r = -dist
                if r > 0:
                    spring += r * r
        return e + 0.5 * self.mass * self.k_spring * spring

    def _rolling(self):
        """The energy of rolling on the side, when the coin rolls there: else 0.

        A coin lying on its curved side (tilt within :data:`SIDE_TILT` of 90 degrees) whose
        contacts do not slip (every contact point moves at under :data:`SLIP_TOL`) is rolling
        about its own axis.  Its spin about the axis, ``I3 w3^2 / 2``, and its speed across the
        axis, ``m v_perp^2 / 2``, cannot lift it onto a face: the contact forces that change them
        (the rolling friction across the axis, the normal forces) exert no torque about the
        horizontal diameter it would tip about, and the gyroscopic coupling of the spin only
        trades energy among the rotations about diameters, which stay counted.  Only friction
        along the axis tips the coin, and it is fed by the sliding along the axis, which stays
        counted too.  So the energy left, ``E - (I3 w3^2 + m v_perp^2) / 2``, is what can lift it,
        and the rest rule compares that with the barrier.  (Without the no-slip condition a
        sliding coin could turn spin into yaw through uneven normal forces; the rule then keeps
        the whole energy.)  This is exact for a symmetric line contact; when only one end
        touches, the rolling friction there also turns the coin about the vertical, a small
        flow into counted energy, so the rule is an argument checked by simulation (both rules
        on the same tosses, docs/bounce.md), not a proof.
        """
        d = self.d
        px, py, pz, qw, qx, qy, qz = d.qpos.tolist()
        # the axis n = R e3 (world)
        nx, ny = 2.0 * (qx * qz + qw * qy), 2.0 * (qy * qz - qw * qx)
        nz = 1.0 - 2.0 * (qx * qx + qy * qy)
        if abs(nz) > SIDE_TILT or d.ncon == 0:
            return 0.0
        vx, vy, _, w1, w2, w3 = d.qvel.tolist()
        ww = qrot((qw, qx, qy, qz), (w1, w2, w3))  # world angular velocity
        for cx, cy, cz in d.contact.pos.tolist():
            rx, ry, rz = cx - px, cy - py, cz - pz
            sx = vx + ww[1] * rz - ww[2] * ry
            sy = vy + ww[2] * rx - ww[0] * rz
            if sx * sx + sy * sy > SLIP_TOL * SLIP_TOL:
                return 0.0
        nh = math.hypot(nx, ny)
        along = (vx * nx + vy * ny) / nh
        v_perp2 = vx * vx + vy * vy - along * along
        return 0.5 * (self.i3 * w3 * w3 + self.mass * v_perp2)

    def _spin_locked(self):
        """The kinetic energy the coin would still have balanced on a corner, had it no friction.

        The coin can change its outcome only by passing a corner balance, its centre at ``R``
        and its axis at ``n_z = +-c``, ``c = (h/2) / R``.  On a frictionless plane two
        quantities never change: the contact force is vertical, so the angular momentum about
        the vertical through the centre, ``L_z``, is kept; and it passes through the axis (a
        symmetric body touches the plane in the vertical plane of its axis), so the spin about
        the axis, ``w3``, is kept (Euler's equation ``I3 w3' = 0``).  With ``L = I3 w3 n + I1
        w_perp``, ``L_z = I3 w3 n_z + I1 (w_perp)_z`` and ``|(w_perp)_z| <= |w_perp|
        sqrt(1 - n_z^2)``, so at the corner the kinetic energy is at least ``I3 w3^2 / 2 + (L_z
        - I3 w3 n_z)^2 / (2 I1 (1 - c^2))``: the heavy symmetric top's effective potential.  The
        smaller of the two corners' values is returned, and the rest rule compares ``E - that``
        with the barrier, at two checks in a row and touching at the second (in the air, the
        coin lands with a friction impulse that changes ``L_z`` and ``w3`` at once: read at one
        check, the rule decided two of 500 tosses on a lively surface wrongly, in the air).  A
        coin wobbling on its rim like Euler's disk (a steady one has no horizontal force, hence
        no friction) keeps most of its energy in ``L_z``, which it cannot spend on standing up.
        On a real table friction at the contact changes ``L_z`` and ``w3``, so this is an
        argument checked by simulation (both rules on thousands of tosses run to the end,
        docs/bounce.md), not a proof, as the rolling rule is; and only
        from ``xi = 0.3`` (:data:`ROLLING_XI_MIN`): a thin coin rolling on its rim stands up
        as friction turns its spin into tilt, and it decided a quarter wrongly.
        """
        _, _, _, qw, qx, qy, qz = self.d.qpos.tolist()
        _, _, _, w1, w2, w3 = self.d.qvel.tolist()
        i1 = self.i1
        s = self.i3 * w3  # I3 w3, the angular momentum along the axis
        # L_z: the third row of the rotation matrix times L in the body frame
        lz = (2.0 * (qx * qz - qw * qy) * i1 * w1
              + 2.0 * (qy * qz + qw * qx) * i1 * w2
              + (1.0 - 2.0 * (qx * qx + qy * qy)) * s)
        c = self._corner_nz
        return 0.5 * s * w3 + 0.5 * min((lz - s * c) ** 2, (lz + s * c) ** 2) / (
            i1 * (1.0 - c * c))

    def _touching(self):
        d = self.d
        return d.ncon > 0

    # -- a toss

    def first_contacts(self, launches):
        """The exact times of first contact of many launches (one vectorized call of
        :func:`coincli.core.toss.batch.toss_many` with the cylinder's corner as the contact)."""
        import numpy as np

        from coincli.core.toss.batch import toss_many

        arr = {k: np.array([getattr(x, k) for x in launches]) for k in
               ("u", "omega", "psi", "z0", "height")}
        return toss_many(self.coin.xi, arr["psi"], arr["u"], arr["omega"],
                         diameter=self.coin.diameter, g=self.g, contact="thick",
                         z0=arr["z0"] + arr["height"]).t_f.tolist()

    def run(self, launch: Launch, *, record=False, t_contact=None) -> TossResult:
        """One toss.  ``t_contact``: its exact first contact, if already known
        (:meth:`first_contacts`)."""
        mj, m, d = self.mujoco, self.m, self.d
        coin, g, dt = self.coin, self.g, self.dt
        a, hh = coin.a, coin.hh
        fl = _flight_from_launch(launch, self.i1, self.i3)
        traj = [] if record else None
        mj.mj_resetData(m, d)
        steps = 0
        if self.flight == "exact":
            t_f = self.first_contacts([launch])[0] if t_contact is None else t_contact
            t_start = max(0.0, t_f - LEAD_STEPS * dt)
            if record:
                self._record_flight(traj, fl, 0.0, t_start)
            self._set(fl.state(t_start, g))
            d.time = t_start
            m.opt.integrator = self._implicit
        else:
            self._set(fl.state(0.0, g))
            d.time = 0.0
            m.opt.integrator = self._rk4
        mj.mj_forward(m, d)
        # To the first contact, one step at a time.  mj_step detects contacts in the
        # configuration it starts from, then integrates: the first touching configuration is the
        # one before the step that found a contact (its tilt and time are kept).
        t_first, alpha = float(d.time), self._tilt()
        while not self._touching():
            if d.time > self.t_max:
                return self._result(UNSETTLED, math.nan, math.nan, 0, steps, UNSETTLED, traj)
            t_first, alpha = float(d.time), self._tilt()
            mj.mj_step(m, d)
            steps += 1
            if record:
                self._record(traj, "mujoco")
        catch_code = int(classify(alpha, coin.xi))
        if self.landing == "catch":
            return self._result(catch_code, t_first, t_first, 0, steps, catch_code, traj, alpha)
        m.opt.integrator = self._implicit
        bounces = 0
        airborne = None  # time the coin last left the surface, while it is in the air
        jump_min = JUMP_MIN_STEPS * dt
        no_jump_until = -math.inf  # a flight found too short to solve: step it out
        lift_lo, lift_state = None, None  # lift-off bracket and state, when seen at a check
        spin_held = False  # the spin rule held at the last check
        step, barrier, mujoco_flight = mj.mj_step, self.barrier, self.flight == "mujoco"
        while True:
            if airborne is None:
                step(m, d, nstep=CHECK_STEPS)
            else:
                # In the air at the last check (or just placed before a solved landing): step
                # one at a time, so that a landing shorter than the checks' spacing is seen and
                # the flight it ends is counted.  The same steps as nstep=CHECK_STEPS.
                for _ in range(CHECK_STEPS):
                    step(m, d)
                    if d.ncon > 0:
                        if airborne is not None:
                            # a bounce is a flight of at least BOUNCE_MIN; shorter is chatter
                            if self._is_bounce(d.time, airborne, lift_lo, lift_state):
                                bounces += 1
                            airborne = None
                    elif airborne is None:
                        airborne = lift_lo = float(d.time)
                        lift_state = None
            steps += CHECK_STEPS
            if record:
                self._record(traj, "mujoco")
            energy = self._energy()
            touching = d.ncon > 0
            # the spin rule: held at this check and the last, touching now (a coin in the air
            # lands with a friction impulse that can change L_z and w3 at once)
            spin, spin_held = spin_held, (self.spin_rest and energy - self._spin_locked()
                                          < barrier)
            if energy < barrier or (spin and spin_held and touching) or (
                    self.rolling_rest and energy - self._rolling() < barrier):
                alpha = self._tilt()
                code = int(classify(alpha, coin.xi))
                return self._result(code, t_first, float(d.time), bounces, steps, catch_code,
                                    traj, alpha)
            if d.time > self.t_max:
                return self._result(UNSETTLED, t_first, math.nan, bounces, steps, catch_code,
                                    traj, self._tilt())
            if touching:
                airborne = None  # (a landing in the air's steps was counted there)
                if mujoco_flight:  # (RK4 only in the air's steps)
                    m.opt.integrator = self._implicit
                continue
            if airborne is None:
                # it left the surface since the last check, at a time in (lift_lo, airborne]
                airborne, lift_lo = float(d.time), float(d.time) - CHECK_STEPS * dt
                lift_state = (d.qpos.copy(), d.qvel.copy())
            if mujoco_flight:
                m.opt.integrator = self._rk4
                continue
            if d.time < no_jump_until:
                continue
            t_now = float(d.time)
            free = _flight_from_state(t_now, d.qpos, d.qvel, self.i1, self.i3)
            if free.clearance(t_now + jump_min, a, hh, g) <= 0.0:
                # below the plane by then: this hop ends within jump_min (the clearance is
                # continuous and positive now), too short to solve; no scan needed to know it
                no_jump_until = t_now + jump_min
                continue
            t_hit = _first_touch(free, a, hh, g, 0.5 * LEAD_STEPS * dt)
            if t_hit - d.time < jump_min:
                no_jump_until = t_hit
                continue
            t_start = t_hit - LEAD_STEPS * dt
            if record:
                self._record_flight(traj, free, float(d.time), t_start)
            self._set(free.state(t_start, g))
            d.time = t_start
            mj.mj_forward(m, d)

    def _is_bounce(self, t_land, t_seen, t_lo, state):
        """Whether a flight that ended at ``t_land`` lasted at least BOUNCE_MIN.  Lift-off was
        seen at ``t_seen`` and happened after ``t_lo``; when the bracket leaves the answer open,
        lift-off is the last time in it that the exact free flight through the state at
        ``t_seen`` (``state``) meets the plane, so the flight is a bounce when that free flight
        is clear of the plane at ``t_land - BOUNCE_MIN`` (one evaluation: the bracket holds one
        crossing, as a bisection for the lift-off would assume)."""
        if t_land - t_seen >= BOUNCE_MIN:
            return True
        if t_land - t_lo < BOUNCE_MIN or state is None:
            return False
        fl = _flight_from_state(t_seen, state[0], state[1], self.i1, self.i3)
        a, hh, g = self.coin.a, self.coin.hh, self.g
        return (fl.clearance(t_lo, a, hh, g) > 0.0
                or fl.clearance(t_land - BOUNCE_MIN, a, hh, g) > 0.0)

    def _result(self, code, t_first, t_settle, bounces, steps, catch_code, traj, alpha=math.nan):
        name = NAMES[code] if code < 3 else "unsettled"
        return TossResult(code, name, t_first, t_settle, bounces, alpha, catch_code, steps, traj)

    def _record(self, traj, phase):
        d = self.d
        traj.append(self._row(float(d.time), tuple(d.qpos[:3]), tuple(d.qpos[3:7]),
                              tuple(d.qvel[:3]), tuple(d.qvel[3:6]), self._energy(), d.ncon,
                              phase))

    def _record_flight(self, traj, fl, t1, t2, every=1e-3):
        n = max(1, math.ceil((t2 - t1) / every))
        for i in range(n):
            t = t1 + (t2 - t1) * i / n
            p, q, v, w = fl.state(t, self.g)
            ke = 0.5 * self.mass * sum(c * c for c in v) + 0.5 * (
                self.i1 * (w[0] ** 2 + w[1] ** 2) + self.i3 * w[2] ** 2)
            traj.append(self._row(t, p, q, v, w, ke + self.mass * self.g * p[2], 0, "flight"))

    def _row(self, t, p, q, v, w, energy, ncon, phase):
        nz = 1.0 - 2.0 * (q[1] ** 2 + q[2] ** 2)
        tilt = math.degrees(math.acos(max(-1.0, min(1.0, nz))))
        return (t, *map(float, p), *map(float, q), *map(float, v), *map(float, w), tilt,
                float(energy), int(ncon), phase)
