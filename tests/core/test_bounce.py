"""Validation of the bounce engine (coincli.core.bounce.engine, MuJoCo): issue 16.

1. The set-up is the paper's: MuJoCo's mass and inertia are the cylinder's; the exact free
   flight agrees with MuJoCo integrating the same launch (RK4), which checks the free-joint
   conventions and the inertia (a wrong I1 or I3 turns the coin at the wrong rate); ``catch``
   reproduces eq. (12) and Table I within 95% intervals.
2. The restitution calibration: flat and edge drops rebound at the requested coefficient.
3. Energy: none gained in free flight.
4. Determinism: the same seed gives the same counts for any number of workers.

The timestep convergence study (halving dt) is ``test_timestep_halving`` (slow) and
benchmarks/bounce_convergence.py (docs/bounce.md).  Seeds are fixed, so every statistical test
is deterministic; they were not picked.
"""

from __future__ import annotations

import math

import pytest

B = pytest.importorskip("coincli.core.bounce.engine")
mujoco = pytest.importorskip("mujoco")

from coincli.core._numerics.quaternion import qconj, qrot  # noqa: E402
from coincli.core.bounce import design as D  # noqa: E402
from coincli.core.bounce import runs as R  # noqa: E402
from coincli.core.models import conditional, dynamic  # noqa: E402
from coincli.core.toss import flight as T  # noqa: E402
from coincli.core.toss import launch as TL  # noqa: E402

HAND = {"u": "normal:2.4:0.3", "omega": "normal:38:4"}


def inside(freq, p):
    return freq.lo <= p <= freq.hi


# --------------------------------------------------------------------------- the set-up


@pytest.mark.parametrize("xi", [0.0725, 0.577, 1.5])
def test_mass_and_inertia_are_the_papers(xi):
    coin = B.Coin(xi, 0.02426, 8920.0)
    _, m, d = B._model(coin, B.SURFACES["wood"], 1e-4, 1000.0, 9.81)
    mass, i1, i3 = B.inertia(coin)
    a, h = 0.02426 / 2, xi * 0.02426
    assert mass == pytest.approx(8920.0 * math.pi * a * a * h, rel=1e-12)
    assert i1 == pytest.approx(mass * (a * a / 4 + h * h / 12), rel=1e-12)
    assert i3 == pytest.approx(mass * a * a / 2, rel=1e-12)
    assert float(m.body_mass[1]) == pytest.approx(mass, rel=1e-9)
    assert list(m.body_inertia[1]) == pytest.approx([i1, i1, i3], rel=1e-9)


def test_launch_state_is_eq_3():
    """The exact flight: heads up at t = 0, cos alpha = cos^2 psi + sin^2 psi cos(omega t)."""
    coin = B.Coin(0.577)
    launch = B.Launch(2.4, 38.0, math.radians(70), 0.02)
    for t in (0.0, 0.013, 0.1, 0.37):
        p, q, v, _ = B.launch_state(launch, coin, t)
        nz = 1 - 2 * (q[1] ** 2 + q[2] ** 2)
        psi = launch.psi
        assert nz == pytest.approx(math.cos(psi) ** 2 + math.sin(psi) ** 2 * math.cos(38 * t),
                                   abs=1e-13)
        assert p[2] == pytest.approx(0.02 + 2.4 * t - 9.81 * t * t / 2, abs=1e-15)
        assert v[2] == pytest.approx(2.4 - 9.81 * t, abs=1e-15)


def test_mujoco_flight_matches_the_exact_flight():
    """MuJoCo integrating the whole flight (RK4, from the launch state) reaches the first contact
    with the tilt of the exact solution: within 0.5 deg (one step of precession at 40 rad/s is
    0.23 deg at dt = 1e-4; MuJoCo finds contact at a step boundary).  A wrong inertia, or the
    angular velocity in the wrong frame, turns the coin tens of degrees away within a flight."""
    coin = B.Coin(0.577)
    surf = B.SURFACES["wood"]
    exact = B.Engine(coin, surf, landing="catch", dt=1e-4)
    full = B.Engine(coin, surf, landing="catch", flight="mujoco", damping=exact.damping, dt=1e-4)
    z0 = T.default_z0(0.577, contact="thick")
    worst = 0.0
    for k in range(8):
        launch = B.Launch(1.0 + 0.1 * k, 30.0 + 7 * k, math.radians(50 + 5 * k), z0)
        a, b = exact.run(launch), full.run(launch)
        worst = max(worst, abs(a.alpha - b.alpha))
        assert a.t_first == pytest.approx(b.t_first, abs=2.5e-4)
    assert math.degrees(worst) < 0.5


def test_no_energy_gain_in_free_flight():
    """RK4 over a precessing flight keeps the energy to 1e-9 (relative); the engine integrates
    flights with MuJoCo only in this validation mode."""
    coin = B.Coin(0.3)
    eng = B.Engine(coin, B.SURFACES["wood"], landing="catch", flight="mujoco")
    launch = B.Launch(3.0, 200.0, math.radians(60), 0.05)
    eng.mujoco.mj_resetData(eng.m, eng.d)
    eng._set(B.launch_state(launch, coin, 0.0))
    eng.m.opt.integrator = eng._rk4
    eng.mujoco.mj_forward(eng.m, eng.d)
    e0 = eng._energy()
    highest = e0
    for _ in range(50):
        eng.mujoco.mj_step(eng.m, eng.d, nstep=100)
        assert eng.d.ncon == 0
        highest = max(highest, eng._energy())
    assert highest - e0 <= 1e-9 * e0


# --------------------------------------------------------------------------- catch = the paper


@pytest.mark.slow
@pytest.mark.parametrize("xi", [0.3, 0.577, 1.0, 1.5])
def test_catch_reproduces_eq_12(xi):
    """P(sides) of 3000 caught hand tosses (psi = 90) within its 95% Wilson interval of
    (2/pi) atan(xi).  With the rim instead of the cylinder's corner, or the tilt read after the
    step that found the contact, xi = 1 and 1.5 fall outside."""
    r = R.simulate(3000, 1, xi=xi, psi=math.pi / 2, landing="catch", jobs=1, **HAND)
    assert r.counts[3] == 0
    assert inside(r.frequencies[1], dynamic(xi).sides), (r.frequencies[1], dynamic(xi).sides)


@pytest.mark.parametrize("psi_deg", [60, 75])
def test_catch_reproduces_table_1(psi_deg):
    xi = 0.577
    r = R.simulate(3000, 1, xi=xi, psi=math.radians(psi_deg), landing="catch", jobs=1, **HAND)
    expected = conditional(xi, math.radians(psi_deg))
    for f, p in zip(r.frequencies, expected, strict=True):
        assert inside(f, p), (f, p)


# --------------------------------------------------------------------------- restitution


@pytest.mark.parametrize("name", list(B.SURFACES))
def test_flat_drop_gives_the_requested_restitution(name):
    surf = B.SURFACES[name]
    coin = B.Coin(0.577)
    b = B.calibrate(coin, surf)
    for speed in (1.0, 2.5):
        e = B.drop_restitution(coin, surf, B.DEFAULT_DT, b, speed=speed)
        assert abs(e - surf.restitution) <= 0.03, (name, speed, e)


@pytest.mark.parametrize("e", [0.3, 0.5, 0.7, 0.9])
@pytest.mark.parametrize("tilt", [0.3, 0.6, 0.9])
def test_edge_drop_gives_the_requested_restitution(e, tilt):
    """An edge drop at 1 m/s onto a frictionless surface (with friction, a sliding edge impact
    also loses energy to friction; rolling friction resists the turn about the corner), and the
    flat drop, both within 0.03 of the coefficient.  Below e ~ 0.3 the corner of a tilted coin
    stays on the surface while the coin pivots down (the contact lasts ~1 ms), so an edge drop
    has no rebound to measure; the flat drop is tested for every preset above."""
    coin = B.Coin(0.577)
    surf = B.Surface(e, 0.0, 0.0, 0.0)
    b = B.calibrate(coin, surf)
    got = B.drop_restitution(coin, surf, B.DEFAULT_DT, b, tilt=tilt)
    assert abs(got - e) <= 0.03, got
    assert abs(B.drop_restitution(coin, surf, B.DEFAULT_DT, b) - e) <= 0.03


def test_restitution_out_of_range_is_refused():
    with pytest.raises(ValueError, match="restitution"):
        B.Surface(0.99, 0.3)
    with pytest.raises(ValueError, match="restitution"):
        B.Surface(0.0, 0.3)
    with pytest.raises(ValueError, match="surface"):
        B.surface("marble")


def test_surface_overrides():
    s = B.surface("felt", friction=0.9)
    assert (s.restitution, s.friction) == (0.2, 0.9) and "felt" in s.name
    assert B.surface(None, restitution=0.4, friction=0.3).name == "custom"


# --------------------------------------------------------------------------- bounce


def test_bounce_rest_is_final():
    """A coin declared at rest cannot change side: running on, it stays in its basin."""
    coin = B.Coin(0.577)
    eng = B.Engine(coin, B.SURFACES["wood"])
    z0 = T.default_z0(0.577, contact="thick")
    for k in range(6):
        launch = B.Launch(2.2 + 0.1 * k, 35.0 + 2 * k, math.radians(85), z0)
        r = eng.run(launch)
        assert r.code in (0, 1, 2)
        d, m = eng.d, eng.m
        for _ in range(300):  # 0.3 s more: the tilt stays in the basin of the outcome
            eng.mujoco.mj_step(m, d, nstep=10)
            assert T.classify(eng._tilt(), 0.577) == r.code
        assert float(d.energy[0] + d.energy[1]) < eng.barrier


def _on_side_rolling(eng, speed, spin):
    """The coin lying on its side (axis along -y), moving along x at ``speed`` and spinning
    about its axis so that the lowest generator moves at ``speed + a w_y`` (0: rolling)."""
    coin, d = eng.coin, eng.d
    eng.mujoco.mj_resetData(eng.m, d)
    q = (math.cos(math.pi / 4), math.sin(math.pi / 4), 0.0, 0.0)  # about x by 90 deg
    d.qpos[:3] = (0.0, 0.0, coin.a - 2e-5)  # 20 um into the surface: touching
    d.qpos[3:7] = q
    d.qvel[:3] = (speed, 0.0, 0.0)
    d.qvel[3:6] = qrot(qconj(q), (0.0, spin, 0.0))  # body frame
    eng.mujoco.mj_forward(eng.m, d)


def test_rolling_energy_is_left_out_only_when_rolling_on_the_side():
    coin = B.Coin(0.577)
    eng = B.Engine(coin, B.SURFACES["wood"])
    v = 0.4
    _on_side_rolling(eng, v, v / coin.a)  # rolls: the contact line is at rest
    assert eng.d.ncon >= 1
    want = 0.5 * (eng.i3 * (v / coin.a) ** 2 + eng.mass * v * v)
    assert eng._rolling() == pytest.approx(want, rel=1e-9)
    _on_side_rolling(eng, v, 0.0)  # slides on its side: all its energy stays counted
    assert eng._rolling() == 0.0
    _on_side_rolling(eng, 0.0, 20.0)  # spins in place (slips): likewise
    assert eng._rolling() == 0.0
    # only where it was checked: a quarter rolling upright on its rim keeps the whole energy
    assert eng.rolling_rest and not B.Engine(B.Coin(0.0725), B.SURFACES["wood"]).rolling_rest


@pytest.mark.slow
def test_rolling_rule_changes_no_outcome():
    """The rest rule without the rolling energy decides the same side as the rule on the whole
    energy, for every toss the latter settles (and settles tosses the latter leaves rolling at
    t_max): 48 hand tosses of the fair coin, 8 of which end rolling on the side."""
    coin = B.Coin(0.577)
    eng = B.Engine(coin, B.SURFACES["wood"])
    dists = {**TL.HAND_TOSS, "height": TL.as_dist(0.0, "height", 0, 1),
             "vx": TL.as_dist(0.0, "vx", 0, 1),
             "z0": TL.as_dist(T.default_z0(0.577, contact="thick"), "z0", 0, 1)}
    launches = R._block_launches(5, 0, 48, dists, coin)
    fired = 0
    for launch in launches:
        eng.rolling_rest = True
        new = eng.run(launch)
        eng.rolling_rest = False
        old = eng.run(launch)
        fired += new.steps < old.steps
        assert new.code != B.UNSETTLED
        assert old.code in (new.code, B.UNSETTLED), (launch, new, old)
        assert new.steps <= old.steps
    assert fired >= 4


def _wobbling(eng, tilt, spin_z, w3, vx=0.0):
    """The coin on its rim at ``tilt`` (about x), turning about the vertical at ``spin_z`` and
    about its own axis at ``w3`` (rad/s), its centre moving along x at ``vx``."""
    coin, d = eng.coin, eng.d
    eng.mujoco.mj_resetData(eng.m, d)
    q = (math.cos(tilt / 2), math.sin(tilt / 2), 0.0, 0.0)
    d.qpos[:3] = (0.0, 0.0, coin.a * math.sin(tilt) + coin.hh * math.cos(tilt) - 1e-6)
    d.qpos[3:7] = q
    d.qvel[:3] = (vx, 0.0, 0.0)
    body = qrot(qconj(q), (0.0, 0.0, spin_z))
    d.qvel[3:6] = (body[0], body[1], body[2] + w3)
    eng.mujoco.mj_forward(eng.m, d)


@pytest.mark.parametrize("tilt,spin_z,w3", [(0.4, 60.0, 0.0), (0.4, 60.0, 25.0),
                                            (1.2, -30.0, 80.0), (0.05, 0.0, 0.0)])
def test_spin_locked_is_the_least_kinetic_energy_at_a_corner(tilt, spin_z, w3):
    """The closed form of _spin_locked against a direct minimisation: over every angular
    velocity at a corner balance (n_z = +-c) with the same spin w3 and the same L_z (computed
    from MuJoCo's own rotation matrix and inertia), the least kinetic energy."""
    import numpy as np
    from scipy.optimize import minimize_scalar

    coin = B.Coin(0.577)
    eng = B.Engine(coin, B.SURFACES["wood"])
    _wobbling(eng, tilt, spin_z, w3)
    d = eng.d
    rot = np.empty(9)
    mujoco.mju_quat2Mat(rot, d.qpos[3:7])
    inertia = np.diag(eng.m.body_inertia[1])
    w_body = np.array(d.qvel[3:6])
    lz = (rot.reshape(3, 3) @ inertia @ w_body)[2]
    c = coin.hh / coin.half_diagonal
    best = math.inf
    for nz in (c, -c):
        # the corner pose: the axis tilted so that n = (0, -sqrt(1 - nz^2), nz) (about x)
        t = math.acos(nz)
        r = np.array([[1, 0, 0], [0, math.cos(t), -math.sin(t)], [0, math.sin(t), math.cos(t)]])

        row = (r @ inertia)[2]  # L_z = row . w (body frame); w2 from it, given w1 and w3

        def ke(w1, r=r, row=row):
            w = np.array([w1, (lz - row[0] * w1 - row[2] * w_body[2]) / row[1], w_body[2]])
            return 0.5 * w @ inertia @ w

        best = min(best, minimize_scalar(ke, bracket=(-100.0, 100.0), tol=1e-12).fun)
    assert eng._spin_locked() == pytest.approx(best, rel=1e-5, abs=1e-12)


def test_spin_rule_is_exact_without_friction():
    """On a frictionless plane L_z and w3 are kept, so a coin the spin rule decides cannot reach
    a corner: wobbling on its rim at 0.4 rad with 60 rad/s about the vertical, above the
    barrier, it stays in its basin for 0.5 s (and the whole-energy rule alone would not have
    decided it)."""
    coin = B.Coin(0.577)
    eng = B.Engine(coin, B.Surface(0.5, 0.0, 0.0, 0.0))
    _wobbling(eng, 0.4, 60.0, 0.0)
    e = eng._energy()
    assert e > eng.barrier and e - eng._spin_locked() < eng.barrier
    for _ in range(250):
        eng.mujoco.mj_step(eng.m, eng.d, nstep=10)
        assert T.classify(eng._tilt(), 0.577) == T.HEADS


@pytest.mark.slow
def test_spin_rule_changes_no_outcome():
    """The rest rule with the spin rule decides the same side as without it, for every toss the
    latter settles: 48 hand tosses at xi = 0.3 and 48 of the fair coin (docs/bounce.md gives
    the check on thousands), a good part of them decided earlier.  A quarter keeps the rules
    without it: it decided one of 48 quarters wrongly."""
    assert not B.Engine(B.Coin(0.0725), B.SURFACES["wood"]).spin_rest
    for xi in (0.3, 0.577):
        coin = B.Coin(xi)
        eng = B.Engine(coin, B.SURFACES["wood"])
        dists = {**TL.HAND_TOSS, "height": TL.as_dist(0.0, "height", 0, 1),
                 "vx": TL.as_dist(0.0, "vx", 0, 1),
                 "z0": TL.as_dist(T.default_z0(xi, contact="thick"), "z0", 0, 1)}
        fired = 0
        for launch in R._block_launches(6, 0, 48, dists, coin):
            eng.spin_rest = True
            new = eng.run(launch)
            eng.spin_rest = False
            old = eng.run(launch)
            fired += new.steps < old.steps
            assert new.code != B.UNSETTLED
            assert old.code in (new.code, B.UNSETTLED), (launch, new, old)
            assert new.steps <= old.steps
        assert fired >= 10, (xi, fired)


def test_determinism_across_workers():
    kw = dict(xi=0.577, psi=math.pi / 2, surf=B.SURFACES["wood"], **HAND)
    one = R.simulate(300, 5, jobs=1, chunk=R.BLOCK, **kw)
    ticks = []
    two = R.simulate(300, 5, jobs=2, chunk=7, progress=ticks.append, **kw)
    assert one.counts == two.counts and one.steps == two.steps
    assert one.mean_bounces == two.mean_bounces and one.mean_t_settle == two.mean_t_settle
    # the bar advances chunk by chunk (37 + 7 chunks of at most 7 tosses), not block by block
    assert len(ticks) == 37 + 7 and ticks == sorted(set(ticks)) and ticks[-1] == 300
    assert all(0 < b - a <= 7 for a, b in zip([0, *ticks], ticks))
    with pytest.raises(ValueError, match="chunk must be from 1 to 256"):
        R.simulate(10, 5, chunk=0, **kw)


def test_runs_sharing_workers_give_each_run_alone():
    """simulate_many (a design's round: several coins' runs on one pool, their calibrations
    side by side, their chunks in one queue; the pool kept for the next round) gives each run
    the result simulate gives it alone, field for field; and another coin's cached engine in a
    worker never leaks into a run (two surfaces, interleaved chunks)."""
    import dataclasses

    kw = dict(psi=math.pi / 2, **HAND)
    specs = [dict(n=40, seed=9, xi=x, surf=B.SURFACES[s], stream=(1, j), chunk=8, **kw)
             for j, (x, s) in enumerate(((0.4, "wood"), (0.9, "felt"), (0.4, "felt")))]
    alone = [R.simulate(jobs=1, **spec) for spec in specs]
    ticks = []
    with R.Workers(2) as workers:
        shared = R.simulate_many(specs, workers=workers, progress=ticks.append)
        again = R.simulate_many(specs[:1], workers=workers)  # the same pool, a second round
    for a, b in zip(alone, [*shared, *again], strict=False):
        assert dataclasses.asdict(a) == dataclasses.asdict(b)
    assert again[0] == shared[0] and ticks[-1] == 120 and len(ticks) == 15


def test_trajectory_is_recorded():
    coin = B.Coin(0.577)
    eng = B.Engine(coin, B.SURFACES["wood"])
    r = eng.run(B.Launch(2.4, 38.0, math.pi / 2, T.default_z0(0.577, contact="thick")),
                record=True)
    ts = [row[0] for row in r.trajectory]
    assert ts == sorted(ts) and ts[0] == 0.0 and len(r.trajectory[0]) == len(
        B.TRAJECTORY_COLUMNS)
    assert ts[-1] == pytest.approx(r.t_settle)


@pytest.mark.parametrize("psi_deg,omega", [(90, 194.8), (90, 201.1), (90, 207.3), (70, 238.8)])
def test_every_solved_flight_is_counted_as_a_bounce(psi_deg, omega):
    """Each flight the engine solves exactly lasts at least BOUNCE_MIN, so each is a bounce.
    A landing shorter than the checks' spacing (2 ms; an impact at e = 0.5 lasts about 1 ms)
    went unseen, and these tosses, which hop five to twelve times, reported 0 bounces."""
    coin = B.Coin(0.51)
    eng = B.Engine(coin, B.SURFACES["wood"])
    launch = B.Launch(2.4, omega, math.radians(psi_deg), T.default_z0(0.51, contact="thick"))
    r = eng.run(launch, record=True)
    phases = [row[-1] for row in r.trajectory if row[0] > r.t_first]
    solved = sum(1 for i, p in enumerate(phases) if p == "flight" and (i == 0 or
                                                                      phases[i - 1] != "flight"))
    assert r.bounces >= solved
    if psi_deg == 90:
        assert solved >= 3


@pytest.mark.slow
def test_timestep_halving():
    """Halving dt (and so hardening the contact, omega_n dt = 0.3, recalibrated) moves no
    frequency beyond its 95% interval (the intervals of the two runs overlap)."""
    kw = dict(xi=0.577, psi=math.pi / 2, jobs=2, **HAND)
    a = R.simulate(1000, 3, dt=B.DEFAULT_DT, **kw)
    b = R.simulate(1000, 3, dt=B.DEFAULT_DT / 2, **kw)
    for fa, fb in zip(a.frequencies, b.frequencies, strict=True):
        assert fa.lo <= fb.hi and fb.lo <= fa.hi, (fa, fb)


# --------------------------------------------------------------------------- design's fits


def _probit(alpha, beta, x):
    return 0.5 * math.erfc(-(alpha + beta * math.log(x)) / math.sqrt(2))


def test_fit_sides_computes_what_scipy_stats_would_to_the_bit():
    """fit_sides avoids importing scipy.stats (a second of start-up): its normal density,
    ndtri and chdtrc (of a deviance clamped at 0, as chi2.sf's support is) give the bits of
    norm.pdf, norm.ppf and chi2.sf, over grids that reach the tails and a deviance that
    rounding makes negative."""
    import numpy as np
    from scipy.special import chdtrc, ndtri
    from scipy.stats import chi2, norm

    x = np.linspace(-40.0, 40.0, 200_001)
    assert np.array_equal(D._norm_pdf(x), norm.pdf(x))
    q = np.concatenate([np.geomspace(1e-300, 0.5, 5000), 1 - np.geomspace(1e-16, 0.5, 5000)])
    assert np.array_equal(ndtri(q), norm.ppf(q))
    for df in (1, 2, 3, 7, 40):
        for dev in (-2.7e-9, 0.0, 1e-12, 0.3, 2.0, 17.5, 300.0):
            assert float(chdtrc(df, max(dev, 0.0))) == float(chi2.sf(dev, df)), (df, dev)


def test_fit_sides_recovers_an_exact_probit():
    """Counts exactly on a probit (n large, k = n p rounded) give back its coefficients, a
    deviance near 0 and the inverse of the curve."""
    n = 10**8
    pts = [(x, n, round(n * _probit(0.3, 1.7, x))) for x in (0.2, 0.35, 0.5, 0.8, 1.3)]
    f = D.fit_sides(pts)
    assert f.alpha == pytest.approx(0.3, abs=1e-5) and f.beta == pytest.approx(1.7, abs=1e-5)
    assert f.deviance < 1e-3 and f.p_value > 0.99
    want = math.exp((-0.4307272992954576 - 0.3) / 1.7)  # Phi^-1(1/3) = -0.43072729929545756
    assert f.inverse(1 / 3) == pytest.approx(want, rel=1e-5)


@pytest.mark.parametrize("points", [
    [(0.1, 10, 0), (0.2, 10, 0)],  # no side anywhere
    [(0.1, 10, 10), (0.2, 10, 10)],  # all sides
    [(0.1, 10, 0), (0.2, 10, 10)],  # a jump between two aspect ratios
    [(0.1, 10, 0), (0.2, 10, 5), (0.3, 10, 10)],  # quasi-separated: the slope is unbounded
])
def test_fit_sides_refuses_separated_points_in_one_line(points):
    with pytest.raises(ValueError, match="do not determine a curve of P\\(sides\\)"):
        D.fit_sides(points)


def test_fit_sides_fits_points_that_overlap():
    f = D.fit_sides([(0.1, 10, 1), (0.2, 10, 5), (0.3, 10, 10)])
    assert f.beta > 0 and 0.1 < f.inverse(0.5) < 0.3


def test_fit_sides_widens_intervals_by_the_dispersion():
    """Points that scatter beyond binomial noise widen the interval: the covariance is
    multiplied by the dispersion deviance / df, so Fieller's interval is that of binomial
    noise at a z larger by sqrt(deviance / df)."""
    from statistics import NormalDist

    pts = [(0.2, 400, 40), (0.3, 400, 150), (0.45, 400, 110), (0.7, 400, 260), (1.0, 400, 250)]
    f = D.fit_sides(pts)
    phi = f.deviance / f.df
    assert phi > 5
    lo, hi = f.interval(1 / 3)
    g = D.SidesFit(f.alpha, f.beta, tuple(tuple(c / phi for c in row) for row in f.cov),
                   f.points, f.deviance, f.df, f.p_value)
    glo, ghi = g.interval(1 / 3)
    assert lo < glo < ghi < hi
    # at the 50% level (the 95% one's z, times sqrt(phi), is past what a double holds as a
    # level): the dispersed fit's interval is the binomial one's at z * sqrt(phi)
    z = NormalDist().inv_cdf(0.75) * math.sqrt(phi)
    wlo, whi = g.interval(1 / 3, 2 * NormalDist().cdf(z) - 1)
    assert (wlo, whi) == pytest.approx(f.interval(1 / 3, 0.5), rel=1e-7)


def test_fieller_interval_is_the_set_where_the_curve_is_within_its_error():
    """Fieller's interval: its ends are where (alpha + beta l - q)^2 = z^2 var(alpha + beta l),
    and the estimate lies inside; a slope not told from 0 gives no bound."""
    from statistics import NormalDist

    from scipy.special import ndtri

    f = D.fit_sides([(0.3, 500, 60), (0.4, 500, 130), (0.5, 500, 190), (0.6, 500, 260)])
    lo, hi = f.interval(1 / 3)
    assert lo < f.inverse(1 / 3) < hi
    (vaa, vab), (_, vbb) = f.cov
    z2 = NormalDist().inv_cdf(0.975) ** 2
    for x in (lo, hi):
        lx = math.log(x)
        lhs = (f.alpha + f.beta * lx - float(ndtri(1 / 3))) ** 2
        assert lhs == pytest.approx(z2 * (vaa + 2 * lx * vab + lx * lx * vbb), rel=1e-9)
    flat = D.SidesFit(0.0, 0.01, ((1.0, 0.0), (0.0, 1.0)), [], 0.0, 0, math.nan)
    assert flat.interval(1 / 3) == (0.0, math.inf)


def _levels_off(x):
    """P(sides) that is not a probit in log xi: it levels off at 0.95."""
    return 0.95 * _probit(-0.2, 2.6, x / 0.4)


def _floor(x):
    """P(sides) with a floor of 0.06 (thin coins that stay on edge): not a probit either."""
    return 0.06 + 0.9 * _probit(0.0, 3.0, x / 0.5)


@pytest.mark.parametrize("curve, target", [(_floor, 0.2), (_levels_off, 1 / 3)])
def test_design_answers_from_the_points_near_the_target(monkeypatch, curve, target):
    """On a curve that a probit over the whole sweep misses, design's answer comes from the
    points near the target: within tol of the true xi, its interval covering it.  (On the
    floor, fitting every point with binomial intervals answered 0.336 [0.327, 0.345] for the
    true 0.357.)  The simulation is replaced by binomial draws from the curve, seeded as
    design seeds its simulations."""
    import numpy as np
    from scipy.optimize import brentq

    def fake(n, seed, *, xi, stream=(), **kw):
        k = int(np.random.default_rng([seed, *stream]).binomial(n, curve(xi)))
        return type("R", (), {"settled": n, "counts": (0, k, n - k, 0), "n": n,
                              "catch_counts": (n, 0, 0)})()

    monkeypatch.setattr(D, "simulate", fake)
    truth = brentq(lambda x: curve(x) - target, 0.05, 3.0)
    r = D.design([target], seed=4, tol=0.01, max_tosses=10**6)
    assert r.met and r.stopped_by == "tol"
    assert abs(r.xi[0] - truth) < 0.01, (r.xi, truth)
    assert r.low[0] <= truth <= r.high[0]
    assert D.fit_sides(r.fit.points).p_value < 1e-3  # the whole-sweep probit misses them


@pytest.mark.parametrize("cap", [180, 600, 1799, 1800, 2999, 3000, 5000])
def test_design_never_passes_max_tosses(monkeypatch, cap):
    """--max-tosses is a cap: below the first sweep's 9 x 200 tosses the sweep is cut (and
    design stops there, saying so); never a toss more than the cap."""
    import numpy as np

    sims = []

    def fake(n, seed, *, xi, stream=(), **kw):
        sims.append(n)
        k = int(np.random.default_rng([seed, *stream]).binomial(n, _floor(xi)))
        return type("R", (), {"settled": n, "counts": (0, k, n - k, 0), "n": n,
                              "catch_counts": (n, 0, 0)})()

    monkeypatch.setattr(D, "simulate", fake)
    r = D.design([1 / 3], seed=4, tol=1e-4, max_tosses=cap)
    assert sum(sims) == r.tosses <= cap
    assert r.first == min(200, cap // 9) and r.stopped_by == "max_tosses" and not r.met
    if cap < 1800:
        assert r.rounds == 0 and r.tosses == 9 * (cap // 9)
    with pytest.raises(ValueError, match="--max-tosses must be at least 180"):
        D.design([1 / 3], seed=4, max_tosses=179)


def test_smallest_xi_is_what_mujoco_builds():
    """Just above smallest_xi every coin builds (a sweep: the triangle inequality is a
    rounding matter on thin discs); just below, the engine refuses it in one ValueError."""
    import numpy as np

    for dia in (B.smallest_diameter(), 1e-3, 0.02426, 3.0):
        lo = B.smallest_xi(dia)
        for xi in np.minimum(np.geomspace(lo * (1 + 1e-9), lo * 1e4, 40), 100.0):
            B._model(B.Coin(float(xi), dia), B.SURFACES["wood"], 1e-4, 1.0, 9.81)
        with pytest.raises(ValueError, match="xi must be at least"):
            B._model(B.Coin(lo * 0.999, dia), B.SURFACES["wood"], 1e-4, 1.0, 9.81)
    assert B.smallest_xi(1e-4) == math.inf
    assert B.round_up(2.1103e-5) == 2.12e-5 and B.round_up(8.67e-7) == 8.67e-7
