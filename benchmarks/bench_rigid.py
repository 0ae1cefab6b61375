"""Speed of the free rigid body (``coin book``): the exact solution against DOP853.

Run from the repository root (a few minutes):

    python benchmarks/bench_rigid.py            # writes its section of docs/performance.md
    python benchmarks/bench_rigid.py --no-write # print only

A 235 x 155 x 30 mm book spun near its middle axis (0.4, 40, 0.3 rad/s: it flips every
0.54 s), sampled at 10^6 times over 20 s (37 periods of omega).  The exact solution
(``coincli.core.rigid.omega_at``, and ``attitude_at`` for the quaternion too) against scipy's DOP853
(``solve_ivp`` with ``t_eval`` at the same times, Euler's equations alone, and with the quaternion
kinematics) at two tolerances, each timed interleaved with the others (medians of the repeats),
each with its largest error against the exact solution (relative to |omega|; for the attitude the
largest quaternion difference).  Then the tosses of ``coin book --toss``: 10^6 boxes with random
spins and flight times, per second, and the scalar summary (the motion table) per call.
"""

from __future__ import annotations

import argparse
import sys
import time
import timeit
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import _report  # noqa: E402

SIZE = (0.235, 0.155, 0.030)
SPIN = (0.4, 40.0, 0.3)
T_END = 20.0


def _rhs_omega(I):
    I1, I2, I3 = I
    a, b, c = (I2 - I3) / I1, (I3 - I1) / I2, (I1 - I2) / I3

    def f(t, w):
        return [a * w[1] * w[2], b * w[2] * w[0], c * w[0] * w[1]]

    return f


def _rhs_full(I):
    import numpy as np

    I1, I2, I3 = I
    a, b, c = (I2 - I3) / I1, (I3 - I1) / I2, (I1 - I2) / I3

    def f(t, y):
        w1, w2, w3, qw, qx, qy, qz = y
        return np.array([a * w2 * w3, b * w3 * w1, c * w1 * w2,
                         0.5 * (-qx * w1 - qy * w2 - qz * w3), 0.5 * (qw * w1 + qy * w3 - qz * w2),
                         0.5 * (qw * w2 - qx * w3 + qz * w1), 0.5 * (qw * w3 + qx * w2 - qy * w1)])

    return f


def run(n: int, repeat: int):
    import numpy as np
    from scipy.integrate import solve_ivp

    from coincli.core import rigid as R

    I = R.box_moments(SIZE)
    w0 = np.array(SPIN)
    ts = np.linspace(0.0, T_END, n)
    o = R.orbit(I, w0)
    exact_w = R.omega_at(o, ts)
    exact_q = R.attitude_at(o, ts)
    norm = float(np.linalg.norm(w0))

    def exact_omega():
        return R.omega_at(R.orbit(I, w0), ts)

    def exact_attitude():
        oo = R.orbit(I, w0)
        return R.omega_at(oo, ts), R.attitude_at(oo, ts)

    def dop(rtol, full):
        f = _rhs_full(I) if full else _rhs_omega(I)
        y0 = list(w0) + ([1.0, 0.0, 0.0, 0.0] if full else [])

        def go():
            return solve_ivp(f, (0.0, T_END), y0, method="DOP853", rtol=rtol,
                             atol=rtol * 1e-2 * norm, t_eval=ts)

        return go

    cases = [
        ("exact omega (`omega_at`)", exact_omega, "omega"),
        ("DOP853 omega, rtol 1e-10", dop(1e-10, False), "omega"),
        ("DOP853 omega, rtol 1e-13", dop(1e-13, False), "omega"),
        ("exact omega + attitude", exact_attitude, "both"),
        ("DOP853 omega + quaternion, rtol 1e-10", dop(1e-10, True), "both"),
        ("DOP853 omega + quaternion, rtol 1e-13", dop(1e-13, True), "both"),
    ]
    times = {name: [] for name, _, _ in cases}
    results = {}
    for _ in range(repeat):
        for name, fn, _ in cases:
            t0 = time.perf_counter()
            results[name] = fn()
            times[name].append(time.perf_counter() - t0)
    rows = []
    base = {"omega": _report.median(times[cases[0][0]]),
            "both": _report.median(times[cases[3][0]])}
    for name, _, kind in cases:
        res = results[name]
        if name.startswith("exact"):
            werr = float(np.abs((res if kind == "omega" else res[0]) - exact_w).max()) / norm
            qerr = 0.0 if kind == "both" else None
            steps = "-"
        else:
            y = res.y.T
            werr = float(np.abs(y[:, :3] - exact_w).max()) / norm
            qerr = None
            if kind == "both":
                q = y[:, 3:] / np.linalg.norm(y[:, 3:], axis=1, keepdims=True)
                qerr = float(np.minimum(np.abs(q - exact_q).max(1),
                                        np.abs(q + exact_q).max(1)).max())
            steps = f"{res.nfev:,} evaluations"
        m = _report.median(times[name])
        rows.append((name, m, m / base[kind], werr, qerr, steps))

    # tosses: 10^6 boxes caught, random spins and flight times (coin book --toss)
    class Normal:
        def __init__(self, mu, sd):
            self.mu, self.sd = mu, sd

        def sample(self, rng, k):
            return rng.normal(self.mu, self.sd, k)

    sides = tuple(v / max(SIZE) for v in SIZE)

    def tosses():
        c = np.zeros(6, dtype=np.int64)
        for codes in R.toss_chunks(n, 1, moments=I, sides=sides, spin=[Normal(0, 20)] * 3,
                                   flight=Normal(0.5, 0.05)):
            c += np.bincount(codes, minlength=6)
        return c

    arctan_x = np.random.default_rng(0).uniform(0, 3, n)
    toss_t, arctan_t = [], []
    for _ in range(max(3, repeat)):
        t0 = time.perf_counter()
        tosses()
        toss_t.append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        np.arctan(arctan_x)
        arctan_t.append(time.perf_counter() - t0)
    summary = timeit.repeat(lambda: R.motion(I, SPIN), number=200, repeat=5)

    # where the closed form wins: one time far out, and many motions at one time each
    t_far = 10 * T_END
    far = []
    for _ in range(max(2, repeat - 1)):
        t0 = time.perf_counter()
        oo = R.orbit(I, w0)
        wf, qf = R.omega_at(oo, t_far), R.attitude_at(oo, t_far)
        t1 = time.perf_counter()
        sol = solve_ivp(_rhs_full(I), (0.0, t_far), list(w0) + [1.0, 0.0, 0.0, 0.0],
                        method="DOP853", rtol=1e-13, atol=1e-15 * norm, t_eval=[t_far])
        t2 = time.perf_counter()
        far.append((t1 - t0, t2 - t1))
    yq = sol.y[3:, -1] / np.linalg.norm(sol.y[3:, -1])
    far_err = (float(np.abs(sol.y[:3, -1] - wf).max()) / norm,
               float(min(np.abs(yq - qf).max(), np.abs(yq + qf).max())))
    many, looped = 20000, 100
    spins = w0 + np.random.default_rng(1).normal(0.0, 0.3, (many, 3))
    t0 = time.perf_counter()
    om = R.orbit(I, spins)
    R.omega_at(om, 1.0), R.attitude_at(om, 1.0)
    t_many = time.perf_counter() - t0
    t0 = time.perf_counter()
    for k in range(looped):
        solve_ivp(_rhs_full(I), (0.0, 1.0), list(spins[k]) + [1.0, 0.0, 0.0, 0.0],
                  method="DOP853", rtol=1e-13, atol=1e-15 * norm, t_eval=[1.0])
    t_loop = (time.perf_counter() - t0) / looped
    extra = {"far": (t_far, _report.median([a for a, _ in far]), _report.median([b for _, b in far]),
                     far_err), "many": (many, t_many / many, t_loop)}
    return rows, _report.median(toss_t), _report.median(arctan_t), min(summary) / 200, extra


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("-n", type=int, default=10**6, help="times and tosses (default 10^6)")
    ap.add_argument("--repeat", type=int, default=5, help="repeats per figure (default 5)")
    ap.add_argument("--no-write", action="store_true", help="do not touch docs/performance.md")
    args = ap.parse_args(argv)
    where = _report.machine()
    rows, toss, arctan, summary, extra = run(args.n, args.repeat)
    t_far, ex_far, dop_far, (werr_far, qerr_far) = extra["far"]
    many, ex_many, dop_many = extra["many"]

    def err(v):
        return "-" if v is None else ("0 (the reference)" if v == 0 else f"{v:.1e}")

    body = [
        "## The free rigid body (`benchmarks/bench_rigid.py`)", "",
        "Command: `python benchmarks/bench_rigid.py` (a few minutes).  " + where + ".", "",
        f"A 235 x 155 x 30 mm book spun near its middle axis (0.4, 40, 0.3 rad/s; it flips every "
        f"0.54 s) at {args.n:,} times over {T_END:g} s (37 periods of omega): the exact solution "
        "against scipy's DOP853 (`solve_ivp`, `t_eval` at the same times), medians of "
        f"{args.repeat} interleaved runs.  Errors are against the exact solution, relative to "
        "|omega| (the attitude: the largest quaternion difference).", "",
        _report.table(["method", "time", "vs exact", "omega error", "attitude error", "work"],
                      [[n, _report.fmt_time(m), f"{r:.1f}x", f"{w:.1e}", err(q), s]
                       for n, m, r, w, q, s in rows]),
        f"Tosses (`coin book --toss`: orbit constants, attitude at the catch, face up; spins "
        f"normal(0, 20) rad/s per axis, flight normal(0.5, 0.05) s): {args.n:,} in "
        f"{_report.fmt_time(toss)}, {_report.fmt_rate(args.n / toss)} tosses/s "
        f"({1e9 * toss / args.n / (1e9 * arctan / args.n):.0f}x `np.arctan` over as many "
        f"doubles, {_report.fmt_time(arctan)}).  The motion table's summary (`rigid.motion`, "
        f"pure Python, no numpy): {1e6 * summary:.0f} µs a call.", "",
        "Where the closed form wins: one time far out, the cost of the exact solution does not "
        f"grow with it (t = {t_far:g} s, omega and the attitude: exact "
        f"{_report.fmt_time(ex_far)}, DOP853 at rtol 1e-13 {_report.fmt_time(dop_far)}, "
        f"{dop_far / ex_far:,.0f}x, off by {werr_far:.1e} of |omega| and {qerr_far:.1e} in the "
        f"quaternion); many motions at one time each (the tosses: {many:,} spins at t = 1 s, "
        f"exact {_report.fmt_time(ex_many)} a motion vectorized, DOP853 "
        f"{_report.fmt_time(dop_many)} a motion, {dop_many / ex_many:,.0f}x).  On one motion "
        "sampled densely the integrator's dense output is as fast as the closed form (its "
        "steps are set by the dynamics, not by the number of times asked), and faster for the "
        "attitude, whose elliptic integral of the third kind (Carlson's R_J) costs about a "
        "microsecond a time; it is the closed form's errors (eps-level, none accumulated) and "
        "the two cases above that it is for.", "",
    ]
    text = "\n".join(body)
    print(text)
    if not args.no_write:
        _report.write_section("bench_rigid", text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
