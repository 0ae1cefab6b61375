"""The rim mode of a whole toss (:mod:`.toss`): one rim point rolling or slipping, integrated
with an error-controlled ODE (DOP853) until an event: lift-off (``N`` through 0), the friction
leaving the cone, the slip halting (the slipping phase in the rescaled time ``dt = |s| dtau``),
the face or the side reaching the plane, a rest rule.  A mixin of :class:`.toss._State`."""

from __future__ import annotations

import math

import numpy as np

from . import rim as R
from .body import cross, rim_point


class RimMode:
    """The rim mode's methods; the state (``t, x, v, n, w``, the engine ``eng``) is the
    toss's."""

    def rim(self, may_roll=True):
        """Roll or slip on the lowest rim point until an event.  ``may_roll`` False: the
        friction has just left the cone, slip starts."""
        eng, tol, body = self.eng, self.eng.tol, self.eng.body

        def solve(mode):
            return R.contact(body, self.n, self.v, self.w, eng.mu, eng.c, eng.tau, mode, eng.g)

        sol = solve("rolling")
        slip = math.hypot(*sol.slip)
        if slip <= 2 * tol.slip_tol:  # (a halt is located at slip_tol, to the ODE's error)
            if sol.N < 0:
                self.log("lift-off")
                return "flight"
            self.set_contact_velocity(np.zeros(3))
            if may_roll and solve("rolling").rolling_holds:
                return self.rolling()
            # static friction cannot hold: slip starts in the direction it is consistent with
            # (at the cone's edge, where rolling has just failed, that is -F_t: k = 0 there)
            ft = np.array(sol.force[:2])
            edge = math.hypot(*ft) <= eng.mu * sol.N * (1 + 1e-6)
            u = -ft / np.linalg.norm(ft) if edge else self.slip_onset()
            self.set_contact_velocity(4 * tol.slip_tol * np.array([u[0], u[1], 0.0]))
        if solve("slipping").N < 0:
            self.log("lift-off")
            return "flight"
        return self.slipping()

    def slip_onset(self):
        """The direction ``u`` (horizontal, unit) in which slip starts from rest when rolling
        needs more than ``mu N``: slipping along ``u`` under the friction ``-mu N u`` must
        accelerate the slip along ``u`` (``a_s(u) = k u``, ``k > 0``).  Found on a 72-point
        circle of directions and refined by Brent's method; none found (a Painleve-type
        inconsistency): ArithmeticError."""
        from scipy.optimize import brentq

        eng, body = self.eng, self.eng.body
        r, rdot = rim_point(body, self.n), R.rim_rate(body, self.n, self.w)
        delta = 1e-9

        def accel(phi):
            u = np.array([math.cos(phi), math.sin(phi), 0.0])
            c = R.contact(body, self.n, self.v + delta * u, self.w, eng.mu, eng.c, eng.tau,
                          "slipping", eng.g)
            a = np.array(c.a_centre) + cross(np.array(c.alpha), r) + cross(self.w, rdot)
            return u, a

        def across(phi):
            u, a = accel(phi)
            return u[0] * a[1] - u[1] * a[0]

        phis = np.linspace(0.0, 2 * math.pi, 73)
        vals = [across(p) for p in phis]
        best = None
        for j in range(72):
            if vals[j] == 0.0 or vals[j] * vals[j + 1] < 0:
                phi = phis[j] if vals[j] == 0.0 else brentq(across, phis[j], phis[j + 1],
                                                            xtol=1e-12)
                u, a = accel(phi)
                k = float(a @ u)
                if k > 0 and (best is None or k > best[0]):
                    best = (k, u)
        if best is None:
            raise ArithmeticError("rolling needs more than mu N and no slip direction is "
                                  "consistent (a Painleve-type case)")
        return best[1][:2]

    def _events(self, mode, rescaled):
        eng, tol, body = self.eng, self.eng.tol, self.eng.body
        k = 1 if rescaled else 0

        def split(y):
            n = y[k + 3:k + 6]
            return y[k:k + 3], n / np.linalg.norm(n), y[k + 6:k + 9], y[k + 9:k + 12]

        def sol(y):
            x, n, v, w = split(y)
            return R.contact(body, n, v, w, eng.mu, eng.c, eng.tau, mode, eng.g)

        evs = {
            "lift-off": (lambda _s, y: sol(y).N, -1),
            "flat": (lambda _s, y: math.hypot(y[k + 3], y[k + 4]) - tol.flat_tol, -1),
            "side": (lambda _s, y: y[k + 5], 0),
        }
        if eng.rest_rule:
            evs["rest"] = (lambda _s, y: eng.energy(*_xvnw(split(y))) - eng.barrier, -1)
        if eng.rules and eng.rest_rule:
            evs["spin rule"] = (lambda _s, y: eng.energy(*_xvnw(split(y))) - eng.spin_locked(
                split(y)[1], split(y)[3]) - eng.barrier, -1)
        if mode == "rolling":
            evs["cone"] = (lambda _s, y: eng.mu * sol(y).N - math.hypot(*sol(y).force[:2]), -1)
        else:
            evs["halt"] = (lambda _s, y: math.hypot(*sol(y).slip) - tol.slip_tol, -1)
            evs["t_max"] = (lambda _s, y: y[0] - eng.t_max, 1)
        funcs = []
        for _name, (f, direction) in evs.items():
            f.terminal, f.direction = True, direction
            funcs.append(f)
        return list(evs), funcs, split

    def _integrate(self, mode, rescaled):
        from scipy.integrate import solve_ivp

        eng, tol, body = self.eng, self.eng.tol, self.eng.body
        f = R.rhs(body, eng.mu, eng.c, eng.tau, mode, eng.g)
        names, funcs, split = self._events(mode, rescaled)
        y = np.concatenate([self.x, self.n, self.v, self.w])
        vs = float(np.linalg.norm(self.v)) + body.a * float(np.linalg.norm(self.w)) + 1e-3
        scales = np.array([body.a] * 6 + [vs] * 3 + [vs / body.a] * 3)
        if rescaled:
            def g(_s, yy):
                n = yy[4:7] / np.linalg.norm(yy[4:7])
                c = R.contact(body, n, yy[7:10], yy[10:13], eng.mu, eng.c, eng.tau, mode,
                              eng.g)
                sig = math.hypot(*c.slip)
                return np.concatenate([[sig], sig * yy[7:10], sig * cross(yy[10:13], n),
                                       sig * np.array(c.a_centre), sig * np.array(c.alpha)])
            y = np.concatenate([[self.t], y])
            scales = np.concatenate([[1.0], scales])
            rate = eng.mu * eng.g * (1 + body.m * (body.a + body.hh) ** 2 / body.i1)
            sig0 = math.hypot(*R.contact(body, self.n, self.v, self.w, eng.mu, eng.c, eng.tau,
                                         mode, eng.g).slip)
            span = (0.0, 10 * (eng.t_max - self.t) / sig0 + 200 * math.log(
                sig0 / tol.slip_tol + 2) / rate)
        else:
            g, span = f, (self.t, eng.t_max)
        with np.errstate(divide="ignore", invalid="ignore"):  # a wild trial step is rejected
            sol = solve_ivp(g, span, y, method="DOP853", rtol=tol.rtol,
                            atol=tol.rtol * scales, events=funcs)
        if sol.status < 0:
            raise ArithmeticError(f"the rim contact's ODE failed: {sol.message}")
        hits = [(te[0], j) for j, te in enumerate(sol.t_events) if len(te)]
        if hits:
            j = min(hits)[1]
            yy, name = np.array(sol.y_events[j][0]), names[j]
        else:
            yy, name = np.array(sol.y[:, -1]), "t_max"
        self.t = float(yy[0]) if rescaled else float(sol.t_events[j][0] if hits else sol.t[-1])
        self.x, self.n, self.v, self.w = (np.array(q) for q in split(yy))
        self.log(f"{mode}: {name}")
        return name

    def rolling(self):
        return self._after_rim_event(self._integrate("rolling", False))

    def slipping(self):
        return self._after_rim_event(self._integrate("slipping", True))

    def _after_rim_event(self, name):
        eng = self.eng
        stuck = [ev for ev in self.events[-20:] if abs(ev[0] - self.t) < 1e-12]
        if len(stuck) >= 20:
            raise ArithmeticError(f"the rim contact's {name} events make no progress")
        if name in ("rest", "spin rule"):
            return "decided"
        if name == "t_max":
            self.t = max(self.t, eng.t_max)
            return "rim"
        if name == "lift-off":
            return "flight"
        if name in ("flat", "side"):
            return self.two_points()
        # cone or halt: the rim mode starts again from this state
        self.settle_on_rim()
        return "rim-slip" if name == "cone" else "rim"


def _xvnw(parts):
    x, n, v, w = parts
    return x, v, n, w
