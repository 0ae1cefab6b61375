"""Known answers of the spinning contact (issue 29): the product's MuJoCo contact
(:func:`coincli.core.bounce.engine._model`, the same model builder ``--landing bounce`` uses)
against the mechanics of a disc on a rough plane.

Each scenario is a plain function of a *contact* (an object with ``set``, ``step``, ``state``,
``contacts``; :class:`MujocoContact` here, ``benchmarks/crosscheck_bullet.py`` gives Bullet's and
runs the same scenarios: ``python benchmarks/crosscheck_bullet.py known``).  Each states what
mechanics expects, its source, and the tolerance.

1. **A coin lying flat, spinning about its axis** (Coulomb friction on a flat contact; e.g.
   Farkas, Bartels, Unger & Wolf, PRL 90, 248302, 2003, "Frictional coupling between sliding
   and spinning motion"): the contact exerts a torque about the vertical only, so the coin does
   not tip (tilt stays 0); the torque is ``mu N r_eff + tau N`` with ``r_eff`` between ``2a/3``
   (uniform pressure over the face) and ``a`` (all the load on the rim), ``tau`` the torsional
   length; a constant torque, so the spin falls linearly: ``dw/dt = -(mu r_eff + tau) m g / I3``.
2. **A coin rolling upright on its rim** (the rolling disc, e.g. O'Reilly 1996, Nonlinear
   Dynamics 10, 287, "The dynamics of rolling disks and sliding disks"): it rolls straight
   without slipping, ``v = a w``, and rolling resistance (a torque ``c N`` about the contact,
   ``c`` the rolling length) slows it at ``dv/dt = -c g / (1 + I3/(m a^2)) / a = -2 c g / (3 a)``.
   Set down spinning in place on its rim, it slips, its centre speeding up at ``mu g``, until it
   rolls at ``v = a w0 I3 / (I3 + m a^2) = a w0 / 3`` (the angular momentum about the contact
   line is kept: the bowling-ball problem, e.g. Routh's *Rigid Dynamics*).
3. **Euler's disk** (Moffatt 2000, Nature 404, 833, "Euler's disk and its finite-time
   singularity"; Kessler & O'Reilly 2002, Regul. Chaotic Dyn. 7, 49, "The ups and downs of
   Euler's disks"): the steady motion with its centre at rest rolls without slip and precesses
   at ``Omega^2 sin(alpha) = 4 g / a`` for a thin disc (``alpha`` the angle between disc and
   table), so ``Omega`` grows as ``alpha^(-1/2)`` as the tilt falls: the finite-time
   singularity.  For a coin of half-thickness ``hh`` (the lower rim touching), the same balance
   of the gravity torque about the centre with ``dH/dt = Omega z x H`` gives (derived in
   :func:`euler_omega`) ``Omega^2 sin(alpha) (I1 cos(alpha) - I3 (hh/a) sin(alpha)) =
   m g (a cos(alpha) - hh sin(alpha))``.
4. **An oblique flat impact** (Routh's impact with friction; Stronge, *Impact Mechanics*, 2000,
   ch. 4): a coin falling flat at 1 m/s while sliding at 1 m/s slides throughout the impact, so
   the tangential impulse is ``mu`` times the normal one, ``dv_t = mu dv_n``; hit squarely on its
   face, it gains no spin.
5. **A spinning coin dropped** (mirror symmetry): reflecting the world in the vertical plane
   through the coin's axis keeps the pose and the face up and reverses the spin about the axis
   (angular velocity is a pseudovector).  So a coin dropped with spin ``+s`` and one dropped with
   ``-s`` have the same tilt at every instant and end on the same face: axial spin *by itself*
   cannot favour a face.  Dropped nearly flat (tilt 10 deg) it stays on its face (heads).

Each scenario ``X`` is a function ``X(contact_factory)`` returning its measured and expected
figures; :func:`report` prints them.  CPU: about 5 s of one core.
"""

from __future__ import annotations

import math

import pytest

from coincli.core._numerics.quaternion import qconj, qrot

G = 9.80665
D = 0.02426  #: m, the default diameter (a US quarter)


# --------------------------------------------------------------------------- the contacts


class MujocoContact:
    """The product's contact: the MJCF of :func:`coincli.core.bounce.engine._model`, the damping
    :func:`~coincli.core.bounce.engine.calibrate` finds for the surface."""

    def __init__(self, coin, surf):
        from coincli.core.bounce import engine as E

        self.coin, self.dt, self.g = coin, E.DEFAULT_DT, G
        b = E.calibrate(coin, surf, self.dt, G)
        self.mj, self.m, self.d = E._model(coin, surf, self.dt, b, G)
        self.mass, self.i1, self.i3 = E.inertia(coin)
        self.time = 0.0

    def set(self, pos, q, v, w_body, t=0.0):
        d = self.d
        self.mj.mj_resetData(self.m, d)
        d.qpos[:3], d.qpos[3:7], d.qvel[:3], d.qvel[3:6] = pos, q, v, w_body
        self.mj.mj_forward(self.m, d)
        self.time = t

    def step(self, n=1):
        self.mj.mj_step(self.m, self.d, nstep=n)
        self.time += n * self.dt

    def state(self):
        d = self.d
        q = tuple(float(x) for x in d.qpos[3:7])
        nq = math.sqrt(sum(x * x for x in q))
        return (tuple(float(x) for x in d.qpos[:3]), tuple(x / nq for x in q),
                tuple(float(x) for x in d.qvel[:3]), tuple(float(x) for x in d.qvel[3:6]))

    def contacts(self):
        return [tuple(float(x) for x in self.d.contact[i].pos) for i in range(self.d.ncon)]


# --------------------------------------------------------------------------- helpers


def _axis(q):
    return qrot(q, (0.0, 0.0, 1.0))


def _tilt(q):
    return math.acos(max(-1.0, min(1.0, _axis(q)[2])))


def _qx(angle):
    """Rotation by ``angle`` about the world x axis (w, x, y, z)."""
    return (math.cos(angle / 2), math.sin(angle / 2), 0.0, 0.0)


def _qy(angle):
    return (math.cos(angle / 2), 0.0, math.sin(angle / 2), 0.0)


def _world_w(state):
    return qrot(state[1], state[3])


def _coin(xi):
    from coincli.core.bounce import engine as E

    return E.Coin(xi, D)


def _wood():
    from coincli.core.bounce import engine as E

    return E.SURFACES["wood"]


# --------------------------------------------------------------------------- 1. flat spin


FLAT_XI, FLAT_SPIN = 0.1, 2 * math.pi * 5  # rad/s


def flat_spin(contact_factory):
    """A coin resting flat, spun at 5 rev/s about its axis: the spin deceleration, its
    linearity (the mid-run rate against the whole-run rate) and the largest tilt."""
    coin, surf = _coin(FLAT_XI), _wood()
    c = contact_factory(coin, surf)
    c.set((0.0, 0.0, coin.hh), (1.0, 0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, FLAT_SPIN))
    samples, tilt, lift = [], 0.0, 0.0
    for _ in range(40):  # 40 x 1 ms
        c.step(round(1e-3 / c.dt))
        st = c.state()
        tilt = max(tilt, _tilt(st[1]))
        lift = max(lift, st[0][2] - coin.hh)
        samples.append((c.time, _world_w(st)[2]))
    (t1, w1), (t2, w2), (t3, w3) = samples[4], samples[14], samples[24]
    a, mu, tau = coin.a, surf.friction, surf.torsional
    m, _, i3 = _inertia(coin)
    lo = (mu * 2 * a / 3 + tau) * m * G / i3
    hi = (mu * a + tau) * m * G / i3
    rate = (w1 - w3) / (t3 - t1)
    return {"decel": rate, "decel_lo": lo, "decel_hi": hi,
            "r_eff/a": (rate * i3 / (m * G) - tau) / (mu * a),
            "linearity": ((w1 - w2) / (t2 - t1)) / ((w2 - w3) / (t3 - t2)),
            "tilt_max": tilt, "lift_max": lift, "drift": math.hypot(*c.state()[0][:2])}


SLIDE_V = 0.5  # m/s


def flat_slide(contact_factory):
    """A coin lying flat, sliding at 0.5 m/s without spin: its deceleration (Coulomb: ``mu g``,
    the normal force staying ``m g``), how far it lifts off (nothing pushes it up), its tilt."""
    coin, surf = _coin(FLAT_XI), _wood()
    c = contact_factory(coin, surf)
    c.set((0.0, 0.0, coin.hh), (1.0, 0.0, 0.0, 0.0), (SLIDE_V, 0.0, 0.0), (0.0, 0.0, 0.0))
    vs, lift, tilt = [], 0.0, 0.0
    for _ in range(40):  # 40 x 1 ms
        c.step(round(1e-3 / c.dt))
        st = c.state()
        lift = max(lift, st[0][2] - coin.hh)
        tilt = max(tilt, _tilt(st[1]))
        vs.append((c.time, st[2][0]))
    (t1, v1), (t2, v2) = vs[4], vs[34]
    return {"decel": (v1 - v2) / (t2 - t1), "decel_expected": surf.friction * G,
            "lift_max": lift, "tilt_max": tilt}


IMPACT_VN, IMPACT_VT = 1.0, 1.0  # m/s


def oblique_impact(contact_factory):
    """A coin falling flat at 1 m/s and sliding at 1 m/s hits the table: Coulomb friction acts
    through the whole impact (it slides throughout, as ``v_t > mu (1 + e) v_n``), so the
    tangential impulse is ``mu`` times the normal one (Routh's impact with friction; Stronge,
    Impact Mechanics, 2000, ch. 4): ``dv_t = mu dv_n``; a flat face hit squarely gains no
    spin."""
    coin, surf = _coin(FLAT_XI), _wood()
    c = contact_factory(coin, surf)
    c.set((0.0, 0.0, coin.hh + 0.5 * IMPACT_VN * c.dt), (1.0, 0.0, 0.0, 0.0),
          (IMPACT_VT, 0.0, -IMPACT_VN), (0.0, 0.0, 0.0))
    touched = False
    for _ in range(2000):
        c.step()
        n = len(c.contacts())
        touched = touched or n > 0
        if touched and n == 0 and c.state()[2][2] > 0:
            break
    st = c.state()
    dvn, dvt = st[2][2] + IMPACT_VN, IMPACT_VT - st[2][0]
    return {"dvt/dvn": dvt / dvn, "expected": surf.friction, "rebound": st[2][2] / IMPACT_VN,
            "spin": math.hypot(*_world_w(st))}


def _inertia(coin):
    from coincli.core.bounce import engine as E

    return E.inertia(coin)


# --------------------------------------------------------------------------- 2. rolling upright


ROLL_XI, ROLL_V = 0.5, 0.5  # m/s


def rolling_upright(contact_factory):
    """A thick coin (xi 0.5: its side is a flat strip, statically stable) rolling upright along
    x at 0.5 m/s: its deceleration, slip, heading and tilt over 0.4 s."""
    coin, surf = _coin(ROLL_XI), _wood()
    c = contact_factory(coin, surf)
    a = coin.a
    q = _qx(-math.pi / 2)  # the axis along +y
    w = (0.0, ROLL_V / a, 0.0)
    c.set((0.0, 0.0, a), q, (ROLL_V, 0.0, 0.0), qrot(qconj(q), w))
    c.step(round(0.05 / c.dt))
    st = c.state()
    t1, v1 = c.time, st[2][0]
    slip, heading, tilt = 0.0, 0.0, 0.0
    for _ in range(30):
        c.step(round(0.01 / c.dt))
        st = c.state()
        ww = _world_w(st)
        slip = max(slip, abs(st[2][0] - a * ww[1]))
        heading = max(heading, abs(math.atan2(st[2][1], st[2][0])))
        tilt = max(tilt, abs(_tilt(st[1]) - math.pi / 2))
    t2, v2 = c.time, st[2][0]
    m, _, i3 = _inertia(coin)
    expected = surf.rolling * G / (a * (1 + i3 / (m * a * a)))
    return {"decel": (v1 - v2) / (t2 - t1), "decel_expected": expected, "slip_max": slip,
            "heading_max": heading, "tilt_dev_max": tilt}


WHEEL_SPIN = 60.0  # rad/s


def wheel_spin_up(contact_factory):
    """A thick coin (xi 0.5) set down upright on its side spinning at 60 rad/s about its axis,
    its centre at rest: the rim slides, sliding friction ``mu m g`` accelerates the centre at
    ``mu g`` and slows the spin until it rolls (the bowling-ball problem); the angular momentum
    about the contact line is kept, so it then rolls at ``v = a w0 I3 / (I3 + m a^2)``
    (``a w0 / 3``), less rolling resistance over the 0.1 s.  The normal force stays ``m g``: the
    coin does not lift."""
    coin, surf = _coin(ROLL_XI), _wood()
    c = contact_factory(coin, surf)
    a = coin.a
    q = _qx(-math.pi / 2)  # the axis along +y
    c.set((0.0, 0.0, a), q, (0.0, 0.0, 0.0), (0.0, 0.0, WHEEL_SPIN))
    lift, vs = 0.0, []
    for _ in range(100):
        c.step(round(1e-3 / c.dt))
        st = c.state()
        lift = max(lift, st[0][2] - a)
        vs.append((c.time, math.hypot(st[2][0], st[2][1])))
    m, _, i3 = _inertia(coin)
    v_roll = a * WHEEL_SPIN * i3 / (i3 + m * a * a)
    t_slip = v_roll / (surf.friction * G)
    k = max(1, int(0.5 * t_slip / 1e-3))
    accel = (vs[k][1] - vs[0][1]) / (vs[k][0] - vs[0][0])
    return {"accel": accel, "accel_expected": surf.friction * G, "v_final": vs[-1][1],
            "v_expected": v_roll - 2 * surf.rolling * G / (3 * a) * (vs[-1][0] - t_slip),
            "lift_max": lift}


# --------------------------------------------------------------------------- 3. Euler's disk


EULER_XI = 0.1
EULER_TILTS = (0.4, 0.2, 0.1)  # rad between disc and table


def euler_omega(coin, alpha):
    """The steady precession rate (rad/s) of a coin rolling on its lower rim with its centre at
    rest, at tilt ``alpha`` (rad) between its faces and the table.

    Let ``u`` be the horizontal direction to the contact, ``e = cos(a) u - sin(a) z`` (centre
    to rim in the coin's plane), ``n = sin(a) u + cos(a) z`` the axis; the contact is at
    ``r = a e - hh n`` from the centre.  Centre and contact at rest: ``w`` is parallel to ``r``,
    and ``w = Omega z + s n`` (precession plus spin), so ``w = Omega sin(alpha) (-e + (hh/a) n)``.
    The contact force is ``m g z`` (the centre does not move), its torque about the centre
    ``r x m g z``; with ``H = I1 w_e e + I3 w_n n`` turning at ``Omega``, ``dH/dt = Omega z x H``
    gives the formula of the module's docstring (``hh = 0``: Moffatt's ``4 g / (a sin alpha)``).
    """
    m, i1, i3 = _inertia(coin)
    a, hh = coin.a, coin.hh
    s, c = math.sin(alpha), math.cos(alpha)
    return math.sqrt(m * G * (a * c - hh * s) / (s * (i1 * c - i3 * (hh / a) * s)))


def euler_disk(contact_factory, alpha, duration=0.02):
    """Start a coin in the steady motion at ``alpha``; the measured precession rate (the turning
    of the axis about the vertical, fitted over ``duration``) and mean tilt, and the expected
    rate at that mean tilt.  The surface is wood without rolling and torsional resistance (the
    steady motion is that of a disc on a rough plane, which loses no energy; MuJoCo keeps
    1e-5 m of each)."""
    from coincli.core.bounce import engine as E

    coin, surf = _coin(EULER_XI), E.surface("wood", torsional=0.0, rolling=0.0)
    c = contact_factory(coin, surf)
    a, hh = coin.a, coin.hh
    om = euler_omega(coin, alpha)
    s, co = math.sin(alpha), math.cos(alpha)
    e = (co, 0.0, -s)
    n = (s, 0.0, co)
    w = tuple(om * s * (-e[i] + hh / a * n[i]) for i in range(3))
    q = _qy(alpha)  # body z to n
    c.set((0.0, 0.0, a * s + hh * co), q, (0.0, 0.0, 0.0), qrot(qconj(q), w))
    ts, phis, tilts = [], [], []
    last = None
    for _ in range(100):
        c.step(max(1, round(duration / 100 / c.dt)))
        st = c.state()
        nv = _axis(st[1])
        phi = math.atan2(nv[1], nv[0])
        if last is not None:
            phi += round((last - phi) / (2 * math.pi)) * 2 * math.pi
        last = phi
        ts.append(c.time)
        phis.append(phi)
        tilts.append(_tilt(st[1]))
    k = len(ts)
    tm, pm = sum(ts) / k, sum(phis) / k
    rate = sum((t - tm) * (p - pm) for t, p in zip(ts, phis, strict=True)) / sum(
        (t - tm) ** 2 for t in ts)
    tilt = sum(tilts) / k
    return {"alpha0": alpha, "alpha_mean": tilt, "alpha_range": max(tilts) - min(tilts),
            "omega": rate, "omega_expected": euler_omega(coin, tilt)}


# --------------------------------------------------------------------------- 4. spinning drops


DROP_XI, DROP_SPIN = 0.1, 100.0  # rad/s about the axis


def spin_drop(contact_factory, tilt, spin, duration=2.0):
    """A coin tilted by ``tilt`` (rad) about x, its lowest point 1 mm up, falling at 0.3 m/s and
    spinning at ``spin`` about its axis: its tilt every 5 ms, and the face up at the end
    (the outcome of eq. (7) on the final tilt)."""
    from coincli.core.toss.flight import classify

    coin, surf = _coin(DROP_XI), _wood()
    c = contact_factory(coin, surf)
    a, hh = coin.a, coin.hh
    z = a * math.sin(tilt) + hh * abs(math.cos(tilt)) + 1e-3
    c.set((0.0, 0.0, z), _qx(tilt), (0.0, 0.0, -0.3), (0.0, 0.0, spin))
    tilts = []
    for _ in range(round(duration / 5e-3)):
        c.step(round(5e-3 / c.dt))
        tilts.append(_tilt(c.state()[1]))
    return tilts, int(classify(tilts[-1], coin.xi))


# --------------------------------------------------------------------------- the report


def report(contact_factory, name):
    """Print each scenario's expected and measured figures for one contact (the cross-check)."""
    f = flat_spin(contact_factory)
    print(f"\n{name}: known-answer contact scenarios")
    print(f"1 flat spin: decel {f['decel']:.1f} rad/s^2, expected {f['decel_lo']:.1f} to "
          f"{f['decel_hi']:.1f} (r_eff/a = {f['r_eff/a']:.3f}, 2/3 to 1); linearity "
          f"{f['linearity']:.3f} (1); max tilt {f['tilt_max']:.2e} rad (0); max lift "
          f"{f['lift_max']:.1e} m (0); drift {f['drift']:.1e} m")
    f = flat_slide(contact_factory)
    print(f"1b flat slide: decel {f['decel']:.3f} m/s^2, expected {f['decel_expected']:.3f} "
          f"(error {f['decel'] / f['decel_expected'] - 1:+.1%}); max lift {f['lift_max']:.1e} m "
          f"(0); max tilt {f['tilt_max']:.1e} rad (0)")
    o = oblique_impact(contact_factory)
    print(f"1c oblique flat impact: dv_t/dv_n {o['dvt/dvn']:.3f}, expected {o['expected']:.3f} "
          f"(error {o['dvt/dvn'] / o['expected'] - 1:+.1%}); rebound {o['rebound']:.3f}; spin "
          f"gained {o['spin']:.2f} rad/s (0)")
    r = rolling_upright(contact_factory)
    print(f"2 rolling upright: decel {r['decel']:.4f} m/s^2, expected {r['decel_expected']:.4f} "
          f"(error {r['decel'] / r['decel_expected'] - 1:+.1%}); max slip {r['slip_max']:.1e} "
          f"m/s; max heading {r['heading_max']:.1e} rad; max tilt off 90 deg "
          f"{r['tilt_dev_max']:.1e} rad")
    w = wheel_spin_up(contact_factory)
    print(f"2b wheel set down spinning: slip accel {w['accel']:.3f} m/s^2, expected "
          f"{w['accel_expected']:.3f} (error {w['accel'] / w['accel_expected'] - 1:+.1%}); "
          f"rolling speed {w['v_final']:.4f} m/s, expected {w['v_expected']:.4f} (error "
          f"{w['v_final'] / w['v_expected'] - 1:+.1%}); max lift {w['lift_max']:.1e} m (0)")
    for alpha in EULER_TILTS:
        e = euler_disk(contact_factory, alpha)
        print(f"3 Euler's disk at tilt {alpha:g}: Omega {e['omega']:.2f} rad/s, expected "
              f"{e['omega_expected']:.2f} at the mean tilt {e['alpha_mean']:.4f} (error "
              f"{e['omega'] / e['omega_expected'] - 1:+.2%}); tilt range "
              f"{e['alpha_range']:.1e} rad")
    for tilt in (math.radians(10), math.radians(80)):
        (tp, fp), (tm, fm) = (spin_drop(contact_factory, tilt, s) for s in
                              (DROP_SPIN, -DROP_SPIN))
        dev = max(abs(x - y) for x, y in zip(tp, tm, strict=True))
        print(f"4 drop at tilt {math.degrees(tilt):.0f} deg, spin +-{DROP_SPIN:g} rad/s: faces "
              f"{fp} and {fm} (0 heads, 1 side, 2 tails), final tilts "
              f"{math.degrees(tp[-1]):.2f} and {math.degrees(tm[-1]):.2f} deg; largest tilt "
              f"difference {dev:.1e} rad (mirror symmetry: 0)")


# --------------------------------------------------------------------------- the tests (MuJoCo)


@pytest.fixture(scope="module")
def mujoco_contact():
    pytest.importorskip("mujoco")
    return MujocoContact


# MuJoCo's soft friction cone turns the friction a sliding contact asks for into normal force
# (docs/contact-models.md): these known answers fail with the product's contact today.  strict:
# a contact model that passes them makes these tests fail, so that the marks are removed.
SOFT_CONE = pytest.mark.xfail(strict=True, reason="MuJoCo's soft friction cone lifts a sliding "
                              "contact (issue 29, docs/contact-models.md)")


@SOFT_CONE
def test_flat_spin_does_not_tip_and_decays_by_coulomb_friction(mujoco_contact):
    f = flat_spin(mujoco_contact)
    # within the band of Coulomb friction on a flat contact, 3% on either side
    assert f["decel_lo"] * 0.97 <= f["decel"] <= f["decel_hi"] * 1.03
    assert f["linearity"] == pytest.approx(1.0, abs=0.05)  # a constant torque
    assert f["tilt_max"] < 1e-4  # rad: a torque about the vertical cannot tip it
    assert f["lift_max"] < 1e-6  # m: nor lift it (the contact's own give is ~1e-8 m)
    assert f["drift"] < 1e-5  # m: nor move its centre


def test_oblique_flat_impact_takes_mu_times_the_normal_impulse(mujoco_contact):
    o = oblique_impact(mujoco_contact)
    assert o["dvt/dvn"] == pytest.approx(o["expected"], rel=0.03)
    assert o["spin"] < 0.1  # rad/s: a square flat impact gives no turn


@SOFT_CONE
def test_flat_slide_decelerates_at_mu_g_without_lifting(mujoco_contact):
    f = flat_slide(mujoco_contact)
    assert f["decel"] == pytest.approx(f["decel_expected"], rel=0.02)
    assert f["lift_max"] < 1e-6  # m
    assert f["tilt_max"] < 1e-4  # rad


def test_rolling_upright_keeps_its_line_and_slows_by_rolling_resistance(mujoco_contact):
    r = rolling_upright(mujoco_contact)
    assert r["decel"] == pytest.approx(r["decel_expected"], rel=0.05)
    assert r["slip_max"] < 1e-3 * ROLL_V
    assert r["heading_max"] < 1e-3  # rad
    assert r["tilt_dev_max"] < 1e-3  # rad


@SOFT_CONE
def test_wheel_set_down_spinning_slips_then_rolls(mujoco_contact):
    w = wheel_spin_up(mujoco_contact)
    assert w["accel"] == pytest.approx(w["accel_expected"], rel=0.03)
    assert w["v_final"] == pytest.approx(w["v_expected"], rel=0.02)
    assert w["lift_max"] < 1e-6  # m


def test_wheel_set_down_spinning_ends_rolling_at_a_third(mujoco_contact):
    """The part MuJoCo gets right: the rolling speed the kept angular momentum gives."""
    w = wheel_spin_up(mujoco_contact)
    assert w["v_final"] == pytest.approx(w["v_expected"], rel=0.02)


@pytest.mark.parametrize("alpha", EULER_TILTS)
def test_euler_disk_precesses_at_the_steady_rate(mujoco_contact, alpha):
    e = euler_disk(mujoco_contact, alpha)
    assert e["omega"] == pytest.approx(e["omega_expected"], rel=0.02)
    assert e["alpha_range"] < 0.1 * alpha  # it stays near the steady motion


def test_euler_omega_is_moffatts_for_a_thin_disc():
    """The thick-coin formula reduces to Omega^2 sin(alpha) = 4 g / a as hh -> 0."""
    coin = _coin(1e-6)
    for alpha in (0.05, 0.3, 1.0):
        assert euler_omega(coin, alpha) ** 2 * math.sin(alpha) == pytest.approx(
            4 * G / coin.a, rel=1e-5)


@pytest.mark.parametrize("tilt_deg", [10, 80])
def test_axial_spin_alone_does_not_choose_the_face(mujoco_contact, tilt_deg):
    tilt = math.radians(tilt_deg)
    tp, fp = spin_drop(mujoco_contact, tilt, DROP_SPIN)
    tm, fm = spin_drop(mujoco_contact, tilt, -DROP_SPIN)
    assert fp == fm
    assert max(abs(x - y) for x, y in zip(tp, tm, strict=True)) < 1e-3
    if tilt_deg == 10:
        assert fp == 0  # dropped nearly flat, heads up: stays heads
