"""Whole tosses with the exact contact (issue 39, stage 2): event-driven, from a launch to rest.

The toss is a sequence of phases joined by events:

- **flight**: the exact torque-free flight (:mod:`.free`); its first contact is the certified
  root of the lowest point's height.
- **impact** at the lowest rim point (:func:`.impact.rim_impact`: Darboux-Keller, Coulomb,
  Stronge's energetic ``e``), or of the whole face when the coin lands exactly flat
  (:func:`.impact.face_impact`).  After it the contact point separates at ``v_n``; at ``v_n >=
  v_min`` a new flight starts, below it the contact is *sustained* (the end of chatter: the
  remaining ``v_n < v_min`` is removed, an inelastic loss below ``m v_min^2 / 2``).
- **rim**: one rim point rolling or slipping (:mod:`.rim`), integrated with an error-controlled
  ODE (DOP853, ``rtol``) with events: lift-off (``N`` falls through 0: a new flight), the
  friction leaving the cone (rolling -> slipping), the slip halting (slipping -> rolling, or
  slipping again the other way; the slipping phase runs in the rescaled time ``dt = |s| dtau``,
  so the halt is a smooth event), the face reaching the plane (``sin(tilt) = flat_tol``) and the
  axis reaching the horizontal (``n_z = 0``: the other end of the lowest generator touches).
- **two points**: at those two events two points touch at once.  No rigid impact law is unique
  for two simultaneous contacts; the one approximation here is *sequential impacts* (the point
  approaching faster is struck first, then the other, until neither approaches), each with
  :func:`.impact.point_impact`.  Afterwards: a flight if a point separates at ``v_min`` or more
  and none stays; otherwise the coin is set flat on its face (or on its side), the rocking that
  is left (``< v_min`` at the points) removed.
- **flat**: on a face.  The face contact (:mod:`.flat`) has ``N = m g`` and holds while ``mu hh
  < a``: nothing can lift or tip the coin, so its side up is final; the toss ends there.
- **side**: on the curved side (:mod:`.side`), sliding then rolling, to the rest rule.

The outcome is decided by the MuJoCo engine's rest rules (:class:`..engine.Engine`), so that
the two engines are comparable: the energy (kinetic + gravitational, here exact: no springs)
below ``m g (R - REST_MARGIN)``; for ``xi >= 0.3`` also the rolling rule (rolling on the side,
the energy of rolling left out) and the spin rule (the energy a spinning coin keeps at a corner
left out, :meth:`..engine.Engine._spin_locked`; applied while in sustained contact, where the
MuJoCo engine asks for two checks touching); the side is eq. (7) on the tilt then.  ``t_max``
of simulated time without that: unsettled.

Every tolerance is a field of :class:`Tolerances`; :meth:`Tolerances.refined` divides them all
by a factor, for the convergence study.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from coincli.core.bounce.engine import (
    DEFAULT_DENSITY,
    DEFAULT_T_MAX,
    REST_MARGIN,
    ROLLING_XI_MIN,
    SIDE_TILT,
    SLIP_TOL,
    UNSETTLED,
    Launch,
    Surface,
)
from coincli.core.toss.flight import DEFAULT_DIAMETER, NAMES, classify

from . import rim as R
from . import side as S
from .body import UP, Cylinder, contact_matrix, cross, rim_point
from .free import Flight, G, next_contact
from .impact import face_impact, point_impact
from .tossrim import RimMode


@dataclass(frozen=True)
class Tolerances:
    """Every numerical tolerance of a toss.

    ``t_tol`` (s): a flight's contact located to this; ``scan`` (s): the flight search's finest
    cell; ``rtol``: the sustained modes' ODE error control (DOP853; ``atol`` is ``rtol`` times
    the state's scales) and the impact's; ``v_min`` (m/s): an impact leaving the contact slower
    than this ends chatter (sustained contact); ``slip_tol`` (m/s): a slip halts below this;
    ``flat_tol``: ``sin(tilt)`` at which a face is on the plane; ``impact``: the impact law's
    error control and its slip halt (fraction of the contact's speed, :func:`.impact.impulse`,
    whose slip phase needs both tight: 1e-12 as stage 1's default)."""

    t_tol: float = 1e-12
    scan: float = 1e-5
    rtol: float = 1e-8
    v_min: float = 1e-3
    slip_tol: float = 1e-6
    flat_tol: float = 1e-5
    impact: float = 1e-12

    def refined(self, factor=10.0) -> Tolerances:
        return Tolerances(*(getattr(self, k) / factor for k in self.__dataclass_fields__))


@dataclass
class ExactToss:
    """One toss: the outcome code (0 heads, 1 sides, 2 tails, 3 unsettled) and name, the time
    of the first contact and of the decision, the tilt then, the catch's outcome (eq. 7 at the
    first contact), the flights of at least 3 ms after the first impact (``bounces``, as the
    MuJoCo engine counts them), the final pose ``(x, n)``, the mode at the end and the events
    ``(t, kind, energy)``; ``impacts``: ``(t, v_n before, v_n after)`` of each impact."""

    code: int
    outcome: str
    t_first: float
    t_settle: float
    alpha: float
    catch_code: int
    bounces: int
    x: tuple
    n: tuple
    mode: str
    events: list = field(default_factory=list)
    impacts: list = field(default_factory=list)


class ExactEngine:
    """The exact engine for one coin (a :class:`.body.Cylinder` of aspect ratio ``xi``) on one
    surface (restitution, friction, torsional and rolling lengths)."""

    MAX_EVENTS = 20000  #: a toss with more events than this raises (a Zeno loop would)

    def __init__(self, xi, surf: Surface, *, diameter=DEFAULT_DIAMETER,
                 density=DEFAULT_DENSITY, g=G, t_max=DEFAULT_T_MAX,
                 tol: Tolerances | None = None, rest_rule=True):
        self.xi, self.surface, self.g, self.t_max = float(xi), surf, g, t_max
        self.body = Cylinder.solid(diameter, xi, density)
        self.tol = tol or Tolerances()
        #: False: no rest rule; the toss ends when a flat or side contact comes to rest
        self.rest_rule = rest_rule
        b = self.body
        self.R = math.hypot(b.a, b.hh)
        self.barrier = b.m * g * (self.R - REST_MARGIN)
        self.rules = self.xi >= ROLLING_XI_MIN
        self.corner_nz = b.hh / self.R
        self.mu, self.e = surf.friction, surf.restitution
        self.c, self.tau = surf.rolling, surf.torsional

    # -- energies and rules

    def energy(self, x, v, n, w):
        b = self.body
        return 0.5 * b.m * float(v @ v) + 0.5 * float(w @ b.inertia(n) @ w) + b.m * self.g * x[2]

    def spin_locked(self, n, w):
        """The kinetic energy kept at a corner balance without friction (the MuJoCo engine's
        :meth:`~coincli.core.bounce.engine.Engine._spin_locked`, in the world frame)."""
        b = self.body
        w3 = float(w @ n)
        s = b.i3 * w3
        lz = float((b.inertia(n) @ w)[2])
        c = self.corner_nz
        return 0.5 * s * w3 + 0.5 * min((lz - s * c) ** 2, (lz + s * c) ** 2) / (
            b.i1 * (1 - c * c))

    def rolled(self, v, n, w):
        """The energy of rolling on the side (the MuJoCo engine's
        :meth:`~coincli.core.bounce.engine.Engine._rolling`, its thresholds): when the axis is
        within SIDE_TILT of horizontal and the lowest point slips slower than SLIP_TOL, ``(I3
        w3^2 + m v_perp^2) / 2``; else 0."""
        if abs(n[2]) > SIDE_TILT:
            return 0.0
        b = self.body
        r = -b.hh * n * (1.0 if n[2] >= 0 else -1.0) - b.a * UP
        s = v + cross(w, r)
        if math.hypot(s[0], s[1]) > SLIP_TOL:
            return 0.0
        nh = math.hypot(n[0], n[1])
        along = (v[0] * n[0] + v[1] * n[1]) / nh
        w3 = float(w @ n)
        return 0.5 * (b.i3 * w3 * w3 + b.m * (v[0] ** 2 + v[1] ** 2 - along * along))

    def decided(self, x, v, n, w, touching):
        if not self.rest_rule:
            return False
        E = self.energy(x, v, n, w)
        return E < self.barrier or (self.rules and touching and (
            E - self.spin_locked(n, w) < self.barrier or
            E - self.rolled(v, n, w) < self.barrier))

    # -- one toss

    def run(self, launch: Launch) -> ExactToss:
        """The toss of a :class:`..engine.Launch` (heads up at t = 0, the surface at z = 0)."""
        b = self.body
        sp, cp = math.sin(launch.psi), math.cos(launch.psi)
        lam = launch.omega * cp * (b.i1 / b.i3 - 1.0)
        n0 = UP.copy()
        w0 = launch.omega * np.array([sp, 0.0, cp]) + lam * n0
        v0 = np.array([launch.vx * math.cos(launch.azimuth), launch.vx * math.sin(launch.azimuth),
                       launch.u])
        x0 = np.array([0.0, 0.0, launch.z0 + launch.height])
        return self.run_state(x0, v0, n0, w0)

    def run_state(self, x, v, n, w, t=0.0) -> ExactToss:
        """The toss from the state ``(x, v, n, w)`` (world frame) at ``t``, in the air or
        touching."""
        st = _State(self, float(t), *(np.array(q, float) for q in (x, v, n, w)))
        return st.run()


@dataclass
class _State(RimMode):
    eng: ExactEngine
    t: float
    x: np.ndarray
    v: np.ndarray
    n: np.ndarray
    w: np.ndarray
    events: list = field(default_factory=list)
    impacts: list = field(default_factory=list)
    t_first: float = math.nan
    catch_code: int = UNSETTLED
    bounces: int = 0
    t_lift: float = math.nan

    # -- bookkeeping

    def log(self, kind):
        self.events.append((self.t, kind, self.eng.energy(self.x, self.v, self.n, self.w)))
        if len(self.events) > self.eng.MAX_EVENTS:
            raise ArithmeticError(f"more than {self.eng.MAX_EVENTS} events in one toss")

    def finish(self, mode, code=None):
        mode = {"rim-slip": "rim", "contact": "rim", "decided": "rim"}.get(mode, mode)
        alpha = math.acos(max(-1.0, min(1.0, float(self.n[2]))))
        if code is None:
            code = int(classify(alpha, self.eng.xi))
        self.log(f"end:{mode}")
        return ExactToss(code, NAMES[code] if code < 3 else "unsettled", self.t_first,
                         self.t if code < 3 else math.nan, alpha, self.catch_code,
                         self.bounces, tuple(self.x), tuple(self.n), mode, self.events,
                         self.impacts)

    def sin_tilt(self):
        return math.hypot(self.n[0], self.n[1])

    def touch_down(self):
        """Note a landing: the first contact (the catch), and a bounce if airborne 3 ms."""
        if math.isnan(self.t_first):
            self.t_first = self.t
            alpha = math.acos(max(-1.0, min(1.0, float(self.n[2]))))
            self.catch_code = int(classify(alpha, self.eng.xi))
        elif self.t - self.t_lift >= 3e-3:
            self.bounces += 1
        self.t_lift = math.nan

    # -- the machine

    def run(self):
        eng = self.eng
        self.log("start")
        body = eng.body
        touching = R.height(body, self.x, self.n) <= 0.0 if self.sin_tilt() > 0 else (
            self.x[2] - body.hh <= 0.0)
        mode = "contact" if touching else "flight"
        while True:
            if eng.decided(self.x, self.v, self.n, self.w, mode not in ("flight", "contact")):
                return self.finish(mode)
            if self.t >= eng.t_max:
                return self.finish(mode, UNSETTLED)
            if mode == "flight":
                mode = self.flight()
            elif mode == "contact":
                mode = self.after_contact()
            elif mode == "rim":
                mode = self.rim()
            elif mode == "rim-slip":
                mode = self.rim(may_roll=False)
            elif mode == "flat":
                return self.finish("flat")
            elif mode == "side":
                return self.side()
            elif mode == "unsettled":
                return self.finish("flight", UNSETTLED)
            elif mode == "decided":  # a rule's event in the rim mode (located at its crossing)
                return self.finish("rim")

    def flight(self):
        eng, tol, body = self.eng, self.eng.tol, self.eng.body
        if math.isnan(self.t_lift):
            self.t_lift = self.t
        fl = Flight.from_state(body, self.t, self.x, self.v, self.n, self.w, eng.g)
        touching = float(fl.clearance(0.0, body.a, body.hh)) <= 1e-9 * body.a
        t_hit = next_contact(fl, body.a, body.hh, eng.t_max, scan=tol.scan, t_tol=tol.t_tol,
                             from_contact=touching)
        if t_hit is None:
            self.t = eng.t_max
            self.x, self.v, self.n, self.w = fl.state(self.t)
            return "unsettled"
        self.t = t_hit
        self.x, self.v, self.n, self.w = fl.state(t_hit)
        self.touch_down()
        self.log("landing")
        return self.impact()

    def lowest(self):
        return rim_point(self.eng.body, self.n)

    def impact(self):
        """An impact at the lowest point (or the face), then a flight or a sustained contact."""
        eng, tol, body = self.eng, self.eng.tol, self.eng.body
        if self.sin_tilt() <= tol.flat_tol:
            if self.v[2] >= 0:
                return self.after_contact()
            wz = float(self.w @ self.n) * float(np.sign(self.n[2]))
            imp = face_impact(body, self.v, wz, eng.mu, eng.e, eng.tau, rtol=tol.impact)
            self.impacts.append((self.t, float(self.v[2]), imp.v[2]))
            self.v = np.array(imp.v)
            self.w = np.array([self.w[0], self.w[1], 0.0]) + imp.wz * UP
            self.log("face impact")
            if imp.v[2] >= tol.v_min:
                return "flight"
            return self.set_flat()
        r = self.lowest()
        vn = float(self.v[2] + cross(self.w, r)[2])
        if vn >= 0:
            return self.after_contact()
        imp = point_impact(body, self.n, self.v, self.w, r, eng.mu, eng.e,
                               rtol=tol.impact, slip_tol=tol.impact)
        self.v, self.w = np.array(imp.v), np.array(imp.w)
        self.impacts.append((self.t, vn, imp.contact_velocity_after[2]))
        self.log("rim impact")
        if imp.contact_velocity_after[2] >= tol.v_min:
            return "flight"
        return self.after_contact()

    def after_contact(self):
        """Sustained contact at the lowest point: face, side or rim."""
        tol = self.eng.tol
        if self.sin_tilt() <= tol.flat_tol:
            return self.set_flat()
        if abs(self.n[2]) <= tol.flat_tol:
            return self.two_points()
        self.settle_on_rim()
        return "rim"

    def settle_on_rim(self):
        """Put the lowest rim point on the plane and remove its normal velocity (< v_min)."""
        body = self.eng.body
        self.x[2] -= R.height(body, self.x, self.n)
        r = self.lowest()
        vn = float(self.v[2] + cross(self.w, r)[2])
        self.contact_impulse(r, np.array([0.0, 0.0, -vn / contact_matrix(body, self.n, r)[2, 2]]))

    def contact_impulse(self, r, P):
        """Apply the impulse ``P`` at ``r``: the small corrections at a change of mode are
        impulses at the contact, so that they dissipate (a normal impulse that stops ``v_n``
        loses ``v_n^2 / (2 K_zz)``, one that stops the whole contact velocity ``v.K^-1 v / 2``)."""
        body = self.eng.body
        self.v = self.v + P / body.m
        self.w = self.w + body.inverse_inertia(self.n) @ cross(r, P)

    def set_contact_velocity(self, target):
        """Change the lowest point's velocity to ``target`` by an impulse there."""
        body = self.eng.body
        r = self.lowest()
        vc = self.v + cross(self.w, r)
        self.contact_impulse(r, np.linalg.solve(contact_matrix(body, self.n, r), target - vc))

    def set_flat(self):
        body = self.eng.body
        sign = 1.0 if self.n[2] >= 0 else -1.0
        self.n = sign * UP
        self.x[2] = body.hh
        self.v[2] = 0.0
        self.w = float(self.w @ UP) * UP
        self.log("flat")
        if self.eng.mu * body.hh >= body.a:
            raise ArithmeticError("mu hh >= a: the face contact tips, a regime not modelled")
        return "flat"

    def set_side(self):
        body = self.eng.body
        h = np.array([self.n[0], self.n[1], 0.0])
        self.n = h / np.linalg.norm(h)
        self.x[2] = body.a
        self.v[2] = 0.0
        e = cross(UP, self.n)
        self.w = self.w - float(self.w @ e) * e
        self.log("side")
        return "side"

    def two_points(self):
        """Two points on the plane at once (the face flat, or the side): sequential impacts."""
        eng, tol, body = self.eng, self.eng.tol, self.eng.body
        flat = self.sin_tilt() <= 0.5
        if flat:
            d = -(UP - self.n[2] * self.n)
            d /= np.linalg.norm(d)
            sigma = 1.0 if self.n[2] >= 0 else -1.0
            pts = [-sigma * body.hh * self.n + body.a * d, -sigma * body.hh * self.n - body.a * d]
        else:
            pts = [-body.hh * self.n - body.a * UP, body.hh * self.n - body.a * UP]
        for _ in range(200):
            vns = [float(self.v[2] + cross(self.w, r)[2]) for r in pts]
            j = int(np.argmin(vns))
            if vns[j] > -tol.v_min or eng.decided(self.x, self.v, self.n, self.w, True):
                break  # (a rest rule decides now: the loop ends the toss)
            imp = point_impact(body, self.n, self.v, self.w, pts[j], eng.mu, eng.e,
                               rtol=tol.rtol)
            self.v, self.w = np.array(imp.v), np.array(imp.w)
            self.impacts.append((self.t, vns[j], imp.contact_velocity_after[2]))
            self.log("two-point impact")
        vns = [float(self.v[2] + cross(self.w, r)[2]) for r in pts]
        if eng.decided(self.x, self.v, self.n, self.w, True):
            return "decided"
        if min(vns) >= tol.v_min:
            return "flight"
        if max(vns) >= tol.v_min and not flat:
            # one end stays, the other lifts: on the staying end's rim, tilted off the side
            j = int(np.argmin(vns))
            axis = cross(UP, self.n)
            tip = 1e-4 * tol.flat_tol * (-1 if j == 0 else 1)  # n_z = -sin(tip): lifts m g hh tip
            self.n = self.n * math.cos(tip) + cross(axis, self.n) * math.sin(tip)
            self.n /= np.linalg.norm(self.n)
            self.settle_on_rim()
            return "rim"
        return self.set_flat() if flat else self.set_side()

    # -- the side mode

    def side(self):
        """On the side: slide, then roll, to the rest rule (or ``t_max``)."""
        eng, tol, body = self.eng, self.eng.tol, self.eng.body
        psi = math.atan2(self.n[1], self.n[0])
        wn, wz = float(self.w @ self.n), float(self.w[2])
        y = (self.x[0], self.x[1], psi, self.v[0], self.v[1], wn, wz)
        chunk = 0.01
        while True:
            rolling = S.slip_measure(body, y) <= tol.slip_tol
            ne = np.array([math.cos(y[2]), math.sin(y[2]), 0.0])
            v = np.array([y[3], y[4], 0.0])
            along = float(v @ ne)
            E = self.eng.energy(self.x, v, ne, y[5] * ne + y[6] * UP)
            rolled = 0.5 * (body.i3 * y[5] ** 2 + body.m * (float(v @ v) - along ** 2))
            self.x = np.array([y[0], y[1], body.a])
            self.v, self.n, self.w = v, ne, y[5] * ne + y[6] * UP
            if eng.rest_rule and (E < eng.barrier or eng.rules and rolling and
                                  E - rolled < eng.barrier):
                return self.finish("side")
            if not eng.rest_rule and rolling and eng.c > 0:  # roll to a stop (constant decel.)
                t_stop = abs(y[5]) * (body.i3 + body.m * body.a ** 2) / (eng.c * body.m * eng.g)
                run = S.run(body, y, eng.mu, eng.c, eng.tau, t_stop, eng.g, rtol=tol.rtol)
                y = run.state[:3] + (0.0, 0.0, 0.0, 0.0)
                self.t += t_stop
                self.x, self.v, self.w = np.array([y[0], y[1], body.a]), np.zeros(3), np.zeros(3)
                return self.finish("side")
            if self.t >= eng.t_max:
                return self.finish("side", UNSETTLED)
            run = S.run(body, y, eng.mu, eng.c, eng.tau, chunk, eng.g, rtol=tol.rtol,
                        stop_tol=max(tol.slip_tol / (S.slip_measure(body, y) + 1e-300), 1e-14))
            y = run.state
            self.t += chunk



__all__ = ["ExactEngine", "ExactToss", "Tolerances"]
