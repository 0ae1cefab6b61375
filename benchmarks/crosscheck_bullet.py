"""coin's table against a second engine's contact: Bullet (pybullet), as a cross-check.

    pip install -e '.[crosscheck]'      # pybullet 3.2.7
    python benchmarks/crosscheck_bullet.py table --xi 0.354,0.5,0.577,0.7 --n 2000 [--surface wood]
    python benchmarks/crosscheck_bullet.py known     # the known-answer contact scenarios in Bullet

``table`` tosses the same launches (coin's hand toss, u ~ normal:2.4:0.3 m/s, omega ~
normal:38:4 rev/s, psi ~ normal:90:10 deg, drawn block by block from the seed exactly as
:func:`coincli.core.bounce.runs.simulate` draws them) onto the same surface in both engines:

- coin: :func:`coincli.core.bounce.runs.simulate` (MuJoCo's soft contact, the product);
- Bullet: only the contact is Bullet's.  The first contact is the same exact root
  (:meth:`Engine.first_contacts`), every later flight is solved exactly as coin solves it
  (:func:`coincli.core.bounce.engine._first_touch`), and the toss ends by the same rest rule (the
  energy below ``m g (R - 1 um)``, rolling on the side left out for xi >= 0.3).

It prints, per xi and engine, P(heads), P(sides), P(tails) among settled tosses with 95% Wilson
intervals, heads : tails, the fraction of tosses that end on the face the catch (first contact)
gives ("as caught": how much the table remembers of the landing), and the fair xi of each engine
by linear interpolation (markdown, for docs/contact-models.md).

Bullet's set-up (issue 29 lists why each is needed):

- a multibody with a free base (a plain pybullet rigid body has no gyroscopic term), no
  damping, no sleeping, its speed limit raised from Bullet's 100 rad/s (a hand toss spins at
  240 rad/s: at the default Bullet silently clamps it); mass and inertia the cylinder's
  (:func:`coincli.core.bounce.engine.inertia`);
- Bullet multiplies the two bodies' restitution and sliding friction: the table has 1, the coin
  the surface's values.  Spinning and rolling friction (lengths, as in MuJoCo: a torque per unit
  normal force) it combines as ``s_coin f_table + s_table f_coin``: the table has 0 and the coin
  the surface's torsional and rolling values (a table of 1 there, as for the others, would give
  a rolling friction of 0.3 m that stops all rotation at the first contact);
- ``contactBreakingThreshold`` 1e-5 m (at the default the bounce is applied before the coin
  touches), restitution velocity threshold 0.01 m/s, collision margin 10 um;
- the same timestep as coin (1e-4 s), 50 solver iterations.
"""

from __future__ import annotations

import argparse
import importlib.util
import math
import pathlib
import sys
import time

from coincli.core._numerics.quaternion import qconj, qrot
from coincli.core.bounce import engine as E
from coincli.core.bounce import runs as R
from coincli.core.toss.flight import classify, default_z0
from coincli.core.toss.launch import HAND_TOSS, as_dist
from coincli.core.toss.simulate import wilson_interval

DT = E.DEFAULT_DT
BREAKING = 1e-5  #: m, contactBreakingThreshold
REST_VEL = 0.01  #: m/s, restitution velocity threshold
MARGIN = 1e-5  #: m, the coin's collision margin
ITERATIONS = 50


class Bullet:
    """A coin on a plane in Bullet, with the same interface as the known-answer scenarios use for
    MuJoCo (:func:`tests.core.test_contact_known.MujocoContact`): ``set(p, q, v, w_body)``,
    ``step(n)``, ``state()``, ``contacts()``, ``energy()``."""

    def __init__(self, coin, surf, dt=DT, g=E.STANDARD_G):
        import pybullet as p

        self.p, self.coin, self.surf, self.dt, self.g = p, coin, surf, dt, g
        self.mass, self.i1, self.i3 = E.inertia(coin)
        self.cid = p.connect(p.DIRECT)
        c = self.cid
        p.setGravity(0, 0, -g, physicsClientId=c)
        p.setPhysicsEngineParameter(fixedTimeStep=dt, numSubSteps=1,
                                    numSolverIterations=ITERATIONS,
                                    contactBreakingThreshold=BREAKING,
                                    restitutionVelocityThreshold=REST_VEL,
                                    physicsClientId=c)
        plane = p.createCollisionShape(p.GEOM_PLANE, physicsClientId=c)
        self.plane = p.createMultiBody(0, plane, physicsClientId=c)
        cyl = p.createCollisionShape(p.GEOM_CYLINDER, radius=coin.a, height=2 * coin.hh,
                                     physicsClientId=c)
        self.body = p.createMultiBody(self.mass, cyl, basePosition=(0, 0, 1),
                                      useMaximalCoordinates=False, physicsClientId=c)
        # restitution and sliding friction: Bullet multiplies the two bodies' values.  Spinning
        # and rolling friction it combines as s0 f1 + s1 f0 (each body's times the other's
        # sliding friction): the table's must be 0, or a table of 1 gives the coin a rolling
        # friction of 0.3 m, which stops every rotation at the first contact.
        p.changeDynamics(self.plane, -1, restitution=1.0, lateralFriction=1.0,
                         spinningFriction=0.0, rollingFriction=0.0, physicsClientId=c)
        p.changeDynamics(self.body, -1, restitution=surf.restitution,
                         lateralFriction=surf.friction, spinningFriction=surf.torsional,
                         rollingFriction=surf.rolling, linearDamping=0.0, angularDamping=0.0,
                         localInertiaDiagonal=(self.i1, self.i1, self.i3),
                         collisionMargin=MARGIN, maxJointVelocity=1e4,
                         activationState=p.ACTIVATION_STATE_DISABLE_SLEEPING,
                         physicsClientId=c)
        self.time = 0.0

    def set(self, pos, q, v, w_body, t=0.0):
        """Centre, quaternion (w, x, y, z, body to world), velocity, body angular velocity."""
        p = self.p
        w = qrot(q, w_body)
        p.resetBasePositionAndOrientation(self.body, pos, (q[1], q[2], q[3], q[0]),
                                          physicsClientId=self.cid)
        p.resetBaseVelocity(self.body, v, w, physicsClientId=self.cid)
        # the contact points are those of the last collision pass: refresh them for this pose
        p.performCollisionDetection(physicsClientId=self.cid)
        self.time = t

    def step(self, n=1):
        for _ in range(n):
            self.p.stepSimulation(physicsClientId=self.cid)
        self.time += n * self.dt

    def state(self):
        """(centre, quaternion w,x,y,z, velocity, body angular velocity)."""
        p = self.p
        pos, o = p.getBasePositionAndOrientation(self.body, physicsClientId=self.cid)
        v, w = p.getBaseVelocity(self.body, physicsClientId=self.cid)
        q = (o[3], o[0], o[1], o[2])
        return tuple(pos), q, tuple(v), qrot(qconj(q), w)

    def contacts(self):
        """Contact points touching (distance <= 0) or within the breaking threshold: positions."""
        pts = self.p.getContactPoints(self.body, self.plane, physicsClientId=self.cid)
        return [c[5] for c in pts]

    def energy(self):
        pos, q, v, w = self.state()
        return (0.5 * self.mass * sum(x * x for x in v)
                + 0.5 * (self.i1 * (w[0] ** 2 + w[1] ** 2) + self.i3 * w[2] ** 2)
                + self.mass * self.g * pos[2])


class BulletTosses:
    """coin's toss with Bullet's contact: exact flights, the same rest rule."""

    def __init__(self, coin, surf, t_max=E.DEFAULT_T_MAX):
        self.coin, self.surf, self.t_max = coin, surf, t_max
        self.b = Bullet(coin, surf)
        self.g = self.b.g
        self.barrier = self.b.mass * self.g * (coin.half_diagonal - E.REST_MARGIN)
        self.rolling_rest = coin.xi >= E.ROLLING_XI_MIN
        # coin's own engine only for the exact first contacts (no MuJoCo stepping)
        self._first = E.Engine.first_contacts.__get__(self)

    def _rolling(self, pts, state):
        """The energy of rolling on the side, as :meth:`Engine._rolling` (same rule)."""
        pos, q, v, wb = state
        nx, ny, nz = qrot(q, (0.0, 0.0, 1.0))
        if not pts or abs(nz) > E.SIDE_TILT:
            return 0.0
        ww = qrot(q, wb)
        for c in pts:
            rx, ry, rz = c[0] - pos[0], c[1] - pos[1], c[2] - pos[2]
            sx = v[0] + ww[1] * rz - ww[2] * ry
            sy = v[1] + ww[2] * rx - ww[0] * rz
            if sx * sx + sy * sy > E.SLIP_TOL ** 2:
                return 0.0
        nh = math.hypot(nx, ny)
        along = (v[0] * nx + v[1] * ny) / nh
        v_perp2 = v[0] ** 2 + v[1] ** 2 - along * along
        return 0.5 * (self.b.i3 * wb[2] ** 2 + self.b.mass * v_perp2)

    def _tilt(self, q):
        nz = 1.0 - 2.0 * (q[1] ** 2 + q[2] ** 2)
        return math.acos(max(-1.0, min(1.0, nz)))

    def run(self, launch, t_f):
        import numpy as np

        b, coin, g, dt = self.b, self.coin, self.g, self.b.dt
        a, hh = coin.a, coin.hh
        fl = E._flight_from_launch(launch, b.i1, b.i3)
        t = max(0.0, t_f - E.LEAD_STEPS * dt)
        b.set(*fl.state(t, g), t=t)
        alpha = self._tilt(fl.state(t, g)[1])
        while not b.contacts():
            if b.time > self.t_max:
                return E.UNSETTLED, E.UNSETTLED
            alpha = self._tilt(b.state()[1])
            b.step()
        catch = int(classify(alpha, coin.xi))
        jump_min = E.JUMP_MIN_STEPS * dt
        no_jump_until = -math.inf
        while True:
            b.step(E.CHECK_STEPS)
            st = b.state()
            pts = b.contacts()
            energy = b.energy()
            if energy < self.barrier or (self.rolling_rest and
                                         energy - self._rolling(pts, st) < self.barrier):
                return int(classify(self._tilt(st[1]), coin.xi)), catch
            if b.time > self.t_max:
                return E.UNSETTLED, catch
            if pts or b.time < no_jump_until:
                continue
            pos, q, v, w = st
            qpos = np.array([*pos, *q])
            qvel = np.array([*v, *w])
            free = E._flight_from_state(b.time, qpos, qvel, b.i1, b.i3)
            if free.clearance(b.time + jump_min, a, hh, g) <= 0.0:
                no_jump_until = b.time + jump_min
                continue
            t_hit = E._first_touch(free, a, hh, g, 0.5 * E.LEAD_STEPS * dt)
            if t_hit - b.time < jump_min:
                no_jump_until = t_hit
                continue
            t_start = t_hit - E.LEAD_STEPS * dt
            b.set(*free.state(t_start, g), t=t_start)


def bullet_counts(n, seed, xi, surf, dists):
    """Outcome counts (heads, sides, tails, unsettled), the caught outcomes' counts, and how
    many tosses end on the face the catch (first contact) gives."""
    coin = E.Coin(xi)
    tosser = BulletTosses(coin, surf)
    counts = [0, 0, 0, 0]
    catch = [0, 0, 0, 0]
    agree = 0
    for blk in range(-(-n // R.BLOCK)):
        count = min(R.BLOCK, n - blk * R.BLOCK)
        launches = R._block_launches(seed, blk, count, dists, coin)
        t_first = tosser._first(launches)
        for launch, t_f in zip(launches, t_first, strict=True):
            code, c = tosser.run(launch, t_f)
            counts[code] += 1
            catch[c] += 1
            agree += code == c
    return counts, catch, agree


def dists_for(xi, psi=None):
    coin = E.Coin(xi)
    out = {"u": as_dist(HAND_TOSS["u"], "u", 0.0, 1e3),
           "omega": as_dist(HAND_TOSS["omega"], "omega", 0.0, 1e5),
           "psi": as_dist(HAND_TOSS["psi"] if psi is None else psi, "psi", 0.0, math.pi)}
    for name, val in (("height", 0.0), ("vx", 0.0),
                      ("z0", default_z0(coin.xi, coin.diameter, "thick"))):
        lo, hi = R._DOMAINS[name]
        out[name] = as_dist(val, name, lo, hi)
    return out


def fmt(counts):
    h, s, t = counts[:3]
    ns = h + s + t
    cells = []
    for k in (h, s, t):
        lo, hi = wilson_interval(k, ns)
        cells.append(f"{k / ns:.3f} [{lo:.3f}, {hi:.3f}]")
    ratio = f"{h / t:.2f}" if t else "inf"
    return cells, ratio


def table(args):
    surf = E.SURFACES[args.surface]
    psi = None if args.psi is None else math.radians(args.psi)
    print(f"surface {surf.describe()}; seed {args.seed}; {args.n} tosses per engine per xi; "
          f"psi {'normal:90:10 deg' if psi is None else f'{args.psi:g} deg'}", flush=True)
    print("\n| xi | engine | P(heads) | P(sides) | P(tails) | heads : tails | as caught | "
          "unsettled |")
    print("|---|---|---|---|---|---|---|---|", flush=True)
    sides = {}
    for xi in args.xi:
        rows = []
        if "coin" in args.engines:
            t0 = time.perf_counter()
            r = R.simulate(args.n, args.seed, xi=xi, surf=surf, jobs=1,
                           **{k: v for k, v in HAND_TOSS.items()
                              if psi is None or k != "psi"},
                           **({} if psi is None else {"psi": psi}))
            rows.append(("coin", r.counts, r.agree, time.perf_counter() - t0))
        if "bullet" in args.engines:
            t0 = time.perf_counter()
            c, _, agree = bullet_counts(args.n, args.seed, xi, surf, dists_for(xi, psi))
            rows.append(("Bullet", tuple(c), agree, time.perf_counter() - t0))
        for name, counts, agree, secs in rows:
            sides.setdefault(name, []).append((xi, counts))
            cells, ratio = fmt(counts)
            print(f"| {xi:g} | {name} | {' | '.join(cells)} | {ratio} | {agree / args.n:.3f} | "
                  f"{counts[3]} |", flush=True)
            print(f"  ({name} xi {xi:g}: {secs:.0f} s, {1e3 * secs / args.n:.0f} ms/toss)",
                  file=sys.stderr, flush=True)
    print()
    for name, pts in sides.items():
        if len(pts) > 1:
            print(f"fair xi (P(sides) = 1/3, linear interpolation), {name}: {fair_xi(pts)}")


def fair_xi(points):
    """Where P(sides) crosses 1/3, by linear interpolation between the xi that bracket it, with
    the crossings of the Wilson bounds as its interval: text."""
    pts = sorted(points)

    def cross(values):
        for (x1, p1), (x2, p2) in zip(values[:-1], values[1:], strict=True):
            if (p1 - 1 / 3) * (p2 - 1 / 3) <= 0 and p1 != p2:
                return x1 + (1 / 3 - p1) * (x2 - x1) / (p2 - p1)
        return math.nan

    mid, lo, hi = [], [], []
    for x, c in pts:
        ns = c[0] + c[1] + c[2]
        a, b = wilson_interval(c[1], ns)
        mid.append((x, c[1] / ns))
        lo.append((x, a))
        hi.append((x, b))
    return f"{cross(mid):.3f} [{cross(hi):.3f}, {cross(lo):.3f}]"


def known(args):
    """The known-answer scenarios of tests/core/test_contact_known.py, in Bullet and MuJoCo."""
    path = pathlib.Path(__file__).resolve().parents[1] / "tests" / "core" / "test_contact_known.py"
    spec = importlib.util.spec_from_file_location("contact_known", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    mod.report(lambda coin, surf: Bullet(coin, surf), "Bullet")
    mod.report(mod.MujocoContact, "MuJoCo")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    t = sub.add_parser("table")
    t.add_argument("--xi", type=lambda s: [float(x) for x in s.split(",")],
                   default=[0.354, 0.5, 0.577, 0.7])
    t.add_argument("--n", type=int, default=2000)
    t.add_argument("--seed", type=int, default=1)
    t.add_argument("--surface", default="wood", choices=list(E.SURFACES))
    t.add_argument("--psi", type=float, default=None, help="degrees, fixed (default the hand "
                   "toss's normal:90:10)")
    t.add_argument("--engines", default="coin,bullet")
    sub.add_parser("known")
    args = ap.parse_args(argv)
    if args.cmd == "table":
        args.engines = args.engines.lower().split(",")
        table(args)
    else:
        known(args)


if __name__ == "__main__":
    main()
