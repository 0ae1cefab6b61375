"""The impact law: a rigid cylinder strikes the rigid plane z = 0 at one point, with Coulomb
friction ``mu`` and Stronge's energetic coefficient of restitution ``e``.

Darboux-Keller (Keller, J. Appl. Mech. 53, 1, 1986; Stronge, *Impact Mechanics*, 2000, ch. 5):
during an impact the forces are finite only at the contact, so the velocity of the body's point
at the contact is linear in the impulse ``P`` there, ``v_c = v_c0 + K P`` with ``K = E/m - [r]x
I^-1 [r]x`` (:func:`.body.contact_matrix`).  The normal impulse ``p = P_z`` is the independent
variable.  While the tangential velocity ``s`` (the slip) is not zero, Coulomb's law gives
``dP_t/dp = -mu s/|s|``, a nonlinear ODE in ``p``.  When the slip vanishes:

- *stick* if ``lam = -K_tt^-1 K_tz`` (the tangential impulse ratio that keeps ``s = 0``) has
  ``|lam| <= mu``: then ``dP_t/dp = lam`` to the end;
- otherwise *reversal*: slip restarts in the constant direction ``u`` with ``K_tz - mu K_tt u =
  k u``, ``k > 0`` (unique), and ``dP_t/dp = -mu u`` to the end.

Both are linear in ``p``, and are solved in closed form.  The slip phase is solved by an
error-controlled ODE (scipy's DOP853, ``rtol``) after the change of variable ``dp = |s| dtau``,
which makes the right-hand side smooth (``ds/dtau = |s| K_tz - mu K_tt s`` near a halt): slip
that halts decays exponentially in ``tau`` and is declared halted below ``slip_tol`` times the
initial speed of the contact point.

Compression ends where ``v_n = 0`` (``p = p_c``; the normal force's work ``W_c = int v_n dp <
0``).  Restitution ends where the work of restitution is ``-e^2 W_c`` (Stronge's energetic
coefficient: the impact never creates energy, with any friction).  ``e = 0``: the impact ends
at ``p_c``.  For a collinear impact without friction it is Newton's ``v_n' = -e v_n``.

:func:`face_impact` is the square impact of a whole face (a flat landing): the normal impulse is
``m (1 + e) |v_z|`` and the friction over the face is that of the flat contact
(:mod:`.flat`), integrated over the impulse.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np

from .body import Cylinder, contact_matrix, rim_point, unit

RTOL = 1e-12  #: the slip phase's ODE error control (relative)
SLIP_TOL = 1e-12  #: slip below this fraction of the contact point's initial speed is halted
#: The slip phase can be stiff (``mu K_tt`` far from isotropic, a rim point of a coin nearly
#: flat, high friction): after this many evaluations DOP853 gives way to LSODA (stiff-capable)
STIFF_EVALS = 20000


@dataclass(frozen=True)
class Impact:
    """The outcome of one impact: the centre's velocity ``v`` and the angular velocity ``w``
    after it; the impulse ``impulse`` (world frame) at the contact ``r`` (from the centre);
    ``p_compression`` and ``p_final``, the normal impulse at the end of compression and of the
    impact; the works of the normal force in compression (< 0) and restitution (>= 0); the
    phases in order (``"slip"``, ``"stick"``, ``"reversal"``); the contact point's velocity
    before and after; the kinetic energies before and after."""

    v: tuple
    w: tuple
    impulse: tuple
    r: tuple
    p_compression: float
    p_final: float
    work_compression: float
    work_restitution: float
    phases: tuple
    contact_velocity_before: tuple
    contact_velocity_after: tuple
    energy_before: float
    energy_after: float


class _Stiff(Exception):
    """DOP853 took more than STIFF_EVALS evaluations in a slip phase."""


def reversal_direction(ktt, ktz, mu):
    """The unit ``u`` with ``ktz - mu ktt u = k u``, ``k > 0``: the direction in which slip
    restarts when stick cannot hold (``|ktt^-1 ktz| > mu``).  ``|(k E + mu ktt)^-1 ktz|`` falls
    from above 1 at ``k = 0`` to ``|ktz| / k``; its crossing of 1 is the unique ``k``."""
    from scipy.optimize import brentq

    def excess(k):
        return np.linalg.norm(np.linalg.solve(k * np.eye(2) + mu * ktt, ktz)) - 1.0

    hi = float(np.linalg.norm(ktz))
    k = brentq(excess, 0.0, hi, xtol=1e-15 * hi, rtol=1e-15, maxiter=200)
    return unit(np.linalg.solve(k * np.eye(2) + mu * ktt, ktz))


def impulse(K, vc0, mu, e, *, rtol=RTOL, slip_tol=SLIP_TOL):
    """Darboux-Keller integration for the contact matrix ``K`` and the contact point's velocity
    ``vc0`` before the impact (``vc0[2] < 0``).  Returns ``(P, p_c, W_c, W_r, phases)``."""
    from scipy.integrate import solve_ivp

    K = np.asarray(K, float)
    vc0 = np.asarray(vc0, float)
    if not vc0[2] < 0:
        raise ValueError("the contact point must approach the plane (v_n < 0)")
    if mu < 0 or not 0 <= e <= 1:
        raise ValueError("need mu >= 0 and 0 <= e <= 1")
    ktt, ktz, kzz = K[:2, :2], K[:2, 2], K[2, 2]
    vscale = float(np.linalg.norm(vc0))
    pscale = vscale / kzz
    floor = slip_tol * vscale
    state = {"p": 0.0, "pt": np.zeros(2), "w": 0.0, "compressing": True, "pc": None,
             "wc": None, "target": None, "halted": False}
    phases = []

    def velocity(p, pt):
        return vc0 + K[:, :2] @ pt + K[:, 2] * p

    def end_compression(W, p):
        state.update(compressing=False, pc=p, wc=W, target=(1 - e * e) * W)

    while True:
        p, pt, W = state["p"], state["pt"], state["w"]
        vc = velocity(p, pt)
        if mu == 0 or state["halted"] or np.linalg.norm(vc[:2]) <= floor:
            if mu == 0:
                d, kind = np.zeros(2), "slip"
            else:
                lam = -np.linalg.solve(ktt, ktz)
                if np.linalg.norm(lam) <= mu * (1 + 1e-12):
                    d, kind = lam, "stick"
                else:
                    d, kind = -mu * reversal_direction(ktt, ktz, mu), "reversal"
            kappa = kzz + K[2, :2] @ d  # dv_n/dp, constant in this phase
            if not kappa > 0:
                raise ArithmeticError("v_n does not grow with the impulse (a jam): no rigid "
                                      "impact law with these parameters")
            vn = vc[2]
            if state["compressing"]:
                q = max(-vn / kappa, 0.0)
                W += vn * q + 0.5 * kappa * q * q
                p, pt, vn = p + q, pt + d * q, 0.0
                end_compression(W, p)
            rem = max(state["target"] - W, 0.0)
            q = 2 * rem / (vn + math.sqrt(vn * vn + 2 * kappa * rem)) if rem > 0 else 0.0
            state.update(p=p + q, pt=pt + d * q, w=state["target"])
            if not phases or phases[-1] != kind:
                phases.append(kind)
            break
        if not phases or phases[-1] != "slip":
            phases.append("slip")

        budget = {"evals": 0, "stiff": False}

        def rhs(_t, y, budget=budget):
            budget["evals"] += 1
            if budget["evals"] > STIFF_EVALS and not budget["stiff"]:
                raise _Stiff
            v = velocity(y[0], y[1:3])
            rho = math.hypot(v[0], v[1])
            return [rho, -mu * v[0], -mu * v[1], rho * v[2]]

        def ev_compression(_t, y):
            return velocity(y[0], y[1:3])[2] if state["compressing"] else -1.0

        def ev_restitution(_t, y):
            return -1.0 if state["compressing"] else y[3] - state["target"]

        def ev_halt(_t, y):
            v = velocity(y[0], y[1:3])
            return math.hypot(v[0], v[1]) - floor

        for ev, direction in ((ev_compression, 1), (ev_restitution, 1), (ev_halt, -1)):
            ev.terminal, ev.direction = True, direction
        rho0 = np.linalg.norm(vc[:2])
        lam_min = float(np.linalg.eigvalsh(ktt)[0])
        span = 10 * pscale / rho0 + 100 * math.log(rho0 / floor + 2) / (mu * lam_min)
        y0 = [p, pt[0], pt[1], W]
        atol = rtol * np.array([pscale, pscale, pscale, pscale * vscale])
        try:
            sol = solve_ivp(rhs, (0.0, span), y0, method="DOP853", rtol=rtol, atol=atol,
                            events=(ev_compression, ev_restitution, ev_halt))
        except _Stiff:
            budget["stiff"] = True
            for method in ("LSODA", "Radau"):
                with warnings.catch_warnings():  # LSODA's convergence notice: its status says
                    warnings.simplefilter("ignore", UserWarning)  # it, and Radau follows
                    sol = solve_ivp(rhs, (0.0, span), y0, method=method, rtol=rtol, atol=atol,
                                    events=(ev_compression, ev_restitution, ev_halt))
                if sol.status >= 0:
                    break
        if sol.status < 0:
            raise ArithmeticError(f"the slip phase failed: {sol.message}")
        hits = [(te[0], k, ye[0]) for k, (te, ye) in
                enumerate(zip(sol.t_events, sol.y_events, strict=True)) if len(te)]
        y = min(hits)[2] if hits else sol.y[:, -1]
        kind = min(hits)[1] if hits else None
        state.update(p=float(y[0]), pt=np.array(y[1:3]), w=float(y[3]))
        if kind == 0:
            end_compression(state["w"], state["p"])
            if e == 0:
                break
        elif kind == 1:
            state["w"] = state["target"]
            break
        elif kind == 2:
            state["halted"] = True
    P = np.array([state["pt"][0], state["pt"][1], state["p"]])
    return P, state["pc"], state["wc"], state["w"] - state["wc"], tuple(phases)


def point_impact(body: Cylinder, n, v, w, r, mu, e, *, rtol=RTOL, slip_tol=SLIP_TOL) -> Impact:
    """The impact at the point ``r`` (from the centre, world frame) of a body with axis ``n``
    moving at ``v`` and turning at ``w`` (world frame)."""
    n, v, w, r = (np.asarray(x, float) for x in (n, v, w, r))
    K = contact_matrix(body, n, r)
    vc0 = v + np.cross(w, r)
    P, pc, wc, wr, phases = impulse(K, vc0, mu, e, rtol=rtol, slip_tol=slip_tol)
    inv = body.inverse_inertia(n)
    v1 = v + P / body.m
    w1 = w + inv @ np.cross(r, P)
    inertia = body.inertia(n)

    def energy(vv, ww):
        return 0.5 * body.m * float(vv @ vv) + 0.5 * float(ww @ inertia @ ww)

    return Impact(tuple(v1), tuple(w1), tuple(P), tuple(r), pc, float(P[2]), wc, wr, phases,
                  tuple(vc0), tuple(v1 + np.cross(w1, r)), energy(v, w), energy(v1, w1))


def rim_impact(body: Cylinder, n, v, w, mu, e, *, rtol=RTOL, slip_tol=SLIP_TOL) -> Impact:
    """The impact of a tilted coin (axis ``n``, ``|n_z| < 1``) on its lowest rim point."""
    return point_impact(body, n, v, w, rim_point(body, n), mu, e, rtol=rtol, slip_tol=slip_tol)


@dataclass(frozen=True)
class FaceImpact:
    """A square face impact: the centre's velocity and the spin about the vertical after it,
    the normal and tangential impulses, and the kinetic energies before and after."""

    v: tuple
    wz: float
    normal_impulse: float
    tangential_impulse: tuple
    energy_before: float
    energy_after: float


def face_impact(body: Cylinder, v, wz, mu, e, tau=0.0, *, rtol=RTOL) -> FaceImpact:
    """A coin flat on a face (axis vertical, no tumbling) hits the plane at ``v`` (``v_z < 0``)
    spinning at ``wz`` about the vertical.  The whole face meets the plane at once: the normal
    impulse is ``m (1 + e) |v_z|`` (``v_n`` linear in the impulse, so Stronge's ``e`` is
    Newton's), the pressure over the face uniform, and the friction and the torsional
    resistance ``tau`` (m) act as in the flat contact, with the impulse in place of ``N dt``
    (:func:`.flat.integrate`).  The friction's moment about horizontal axes is carried by the
    pressure's first moment (the coin does not tumble) while ``mu hh < a``."""
    from .flat import integrate

    v = np.asarray(v, float)
    if not v[2] < 0:
        raise ValueError("the face must approach the plane (v_z < 0)")
    pn = body.m * (1 + e) * -v[2]
    run = integrate(body, v[:2], wz, mu, tau, pn, rtol=rtol)
    v1 = np.array([run.v[0], run.v[1], -e * v[2]])
    pt = body.m * (v1[:2] - v[:2])

    def energy(vv, ww):
        return 0.5 * body.m * float(vv @ vv) + 0.5 * body.i3 * ww * ww

    return FaceImpact(tuple(v1), run.wz, pn, tuple(pt), energy(v, wz), energy(v1, run.wz))
