"""Speed of the bounce engine (coincli.core.bounce.engine, MuJoCo): tosses per second, and where the time goes.

Goals of issue 16, on the project's 2-core machine with a quarter-sized coin (D = 24.26 mm):
at least 500 bounce tosses/s and 5000 catch tosses/s with every core (``jobs=2``).  Measured for
a real quarter (xi = 0.0725) and the paper's fair coin (xi = 0.577), the hand toss that ``coin
simulate`` draws (coincli.core.toss.launch.HAND_TOSS: u ~ normal:2.4:0.3 m/s, omega ~ normal:38:4 rev/s,
psi ~ normal(90, 10) deg) onto wood.
Wall-clock rates and CPU time per toss (the workers' and the parent's); the baseline is the
exact catch model without MuJoCo (``coincli.core.toss.simulate.simulate``, the default ``coin simulate``),
timed in the same run.  Then a profile of bounce tosses run in one process: the share of the
time in MuJoCo's steps, the exact flight solver, the energy checks and the rest, and how the
steps are spread over the tosses.

    python benchmarks/bench_bounce.py          # rewrites the bench_bounce section of
                                               # docs/performance.md
"""

from __future__ import annotations

import cProfile
import os
import pstats
import resource
import sys
import time

sys.path.insert(0, os.path.dirname(__file__))

from _report import fmt_rate, machine, median, table, write_section  # noqa: E402

from coincli.core.bounce import engine as B  # noqa: E402
from coincli.core.bounce import runs as R  # noqa: E402
from coincli.core.toss import flight as T  # noqa: E402
from coincli.core.toss import launch as TL  # noqa: E402
from coincli.core.toss import simulate as TS

LAUNCH = TL.HAND_TOSS
CASES = [  # landing, xi, tosses
    ("catch", 0.0725, 20000), ("catch", 0.577, 20000),
    ("bounce", 0.0725, 2000), ("bounce", 0.577, 600),
]
GOAL = {"catch": 5000, "bounce": 500}


def cpu():
    """CPU seconds of this process and of its finished children."""
    me = resource.getrusage(resource.RUSAGE_SELF)
    kids = resource.getrusage(resource.RUSAGE_CHILDREN)
    return me.ru_utime + me.ru_stime + kids.ru_utime + kids.ru_stime


def timed(fn):
    c0, t0 = cpu(), time.perf_counter()
    out = fn()
    return out, time.perf_counter() - t0, cpu() - c0


REPEATS = 3  #: runs of each case; the table quotes medians


def main():
    rows = []
    for landing, xi, n in CASES:
        B.calibrate(B.Coin(xi), B.SURFACES["wood"])  # once per run, not per toss
        walls, cpus, bwalls = [], [], []
        for _ in range(REPEATS):
            r, wall, c = timed(lambda n=n, xi=xi, landing=landing: R.simulate(
                n, 1, xi=xi, landing=landing, jobs=2, **LAUNCH))
            _, bwall, _ = timed(lambda n=n, xi=xi: TS.simulate(n, 1, xi=xi, contact="thick",
                                                                 **LAUNCH))
            walls.append(wall)
            cpus.append(c)
            bwalls.append(bwall)
        wall, c, bwall = median(walls), median(cpus), median(bwalls)
        rate = n / wall
        capacity = 2 * n / c  # two idle cores at this CPU cost per toss
        rows.append([landing, f"{xi:g}", str(n), fmt_rate(rate), f"{1e3 * c / n:.3g} ms",
                     fmt_rate(capacity), f"{r.steps / n:.0f}", fmt_rate(n / bwall),
                     f"{rate / (n / bwall):.2g}",
                     f"{GOAL[landing]}: wall {'met' if rate >= GOAL[landing] else 'missed'}, "
                     f"CPU {'met' if capacity >= GOAL[landing] else 'missed'}"])
        print(rows[-1], file=sys.stderr, flush=True)
    body = ["## The bounce engine (`benchmarks/bench_bounce.py`)", "",
            f"{machine()}.", "",
            "The hand toss of `coin simulate` onto wood (u ~ normal:2.4:0.3 m/s, omega ~ "
            "normal:38:4 rev/s, psi ~ normal(90, 10) deg), a quarter-sized coin (D = 24.26 "
            f"mm), seed 1, every core (`jobs=2`), dt = 1e-4 s; medians of {REPEATS} runs.  CPU "
            "per toss counts the workers and the parent; the wall-clock rate is what a user "
            "gets (the machine is shared: other work runs beside it, so the wall clock can be "
            "several times the CPU).  Baseline: the exact catch model without MuJoCo (the "
            "default `coin simulate`), same tosses, same run.",
            "",
            table(["landing", "xi", "tosses", "tosses/s (wall)", "CPU per toss",
                   "2 idle cores (2 / CPU per toss)", "MuJoCo steps per toss",
                   "baseline tosses/s (wall)", "ratio (wall)", "goal"], rows)]
    body += where_the_time_goes()
    write_section("bench_bounce", "\n".join(body))
    return 0


def where_the_time_goes():
    """Profile bounce tosses in this process: where the time goes, and which tosses cost."""
    import numpy as np

    out = ["### Where the time goes (bounce, one process, profiled)", ""]
    for xi, n in ((0.0725, 300), (0.577, 200)):
        coin = B.Coin(xi)
        eng = B.Engine(coin, B.SURFACES["wood"])
        dists = {"u": LAUNCH["u"], "omega": LAUNCH["omega"], "psi": LAUNCH["psi"],
                 "height": TL.as_dist(0.0, "height", 0, 1), "vx": TL.as_dist(0.0, "vx", 0, 1),
                 "z0": TL.as_dist(T.default_z0(xi, coin.diameter, "thick"), "z0", 0, 1)}
        launches = []
        for k in range(-(-n // R.BLOCK)):
            launches += R._block_launches(2, k, min(R.BLOCK, n - k * R.BLOCK), dists, coin)
        t_first = eng.first_contacts(launches)
        plain = {}  # CPU per toss without the profiler: the rolling rule on (default) and off
        for rolling in (True, False):
            eng.rolling_rest = rolling
            c0 = time.process_time()
            codes_plain = [eng.run(launch, t_contact=t).code
                           for launch, t in zip(launches, t_first, strict=True)]
            plain[rolling] = ((time.process_time() - c0) / n, codes_plain)
        eng.rolling_rest = True
        results = []
        prof = cProfile.Profile(time.process_time)  # CPU time: the machine is shared
        c0 = time.process_time()
        prof.enable()
        for launch, t in zip(launches, t_first, strict=True):
            results.append(eng.run(launch, t_contact=t))
        prof.disable()
        total = time.process_time() - c0
        st = pstats.Stats(prof)
        tott = {}
        for (_, _, func), (_, _, tt, _, _) in st.stats.items():
            key = next((k for k in ("mj_step", "_first_touch", "clearance", "scan", "_energy",
                                    "_rolling", "_flight_from_state", "_qrot", "_qmul",
                                    "mj_forward", "mj_resetData") if func == k or
                        func.endswith(f".{k}>")), "other")
            tott[key] = tott.get(key, 0.0) + tt
        prof_total = sum(tott.values())
        steps = np.array([r.steps for r in results])
        heavy = steps > 5000
        share = {k: v / prof_total for k, v in tott.items()}
        flight = sum(share.get(k, 0) for k in ("_first_touch", "clearance", "scan",
                                                "_flight_from_state", "_qrot", "_qmul"))
        codes = np.array([r.code for r in results])
        python = share.get("other", 0) + share.get("mj_forward", 0) + share.get(
            "mj_resetData", 0)
        out += [f"xi = {xi:g}, {n} tosses: {1e3 * total / n:.3g} ms CPU per toss "
                f"(with the profiler on); {steps.mean():.0f} MuJoCo steps per toss on average, "
                f"median {np.median(steps):.0f}, {1e6 * tott.get('mj_step', 0) / steps.sum():.1f}"
                f" us of CPU per step (profiled).  Time: MuJoCo steps "
                f"{share.get('mj_step', 0):.0%}, "
                f"exact flights {flight:.0%}, energy checks "
                f"{share.get('_energy', 0) + share.get('_rolling', 0):.0%}, "
                f"everything else (Python) {python:.0%}.  "
                f"{heavy.sum()} tosses ({heavy.mean():.1%}) took more than 5000 steps and "
                f"{steps[heavy].sum() / steps.sum():.0%} of all steps; "
                f"{np.sum(heavy & (codes == 1))} of them ended on a side.  Without the "
                f"profiler: {1e3 * plain[True][0]:.3g} ms CPU per toss; the same tosses "
                f"without the rolling rule (the rest rule on the whole energy): "
                f"{1e3 * plain[False][0]:.3g} ms, {plain[False][0] / plain[True][0]:.2g}x "
                f"as long; outcomes that differ: "
                f"{sum(a != b for a, b in zip(*(plain[k][1] for k in plain), strict=True))} "
                f"(unsettled at 10 s without the rule: {plain[False][1].count(B.UNSETTLED)}).",
                ""]
    return out


if __name__ == "__main__":
    sys.exit(main())
