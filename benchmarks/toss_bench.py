"""Speed of real tosses: start-up of coin toss/simulate/phase, tosses per second, the engine.

Run from the repository root, in the environment where ``coin``'s dependencies are installed:

    python benchmarks/toss_bench.py            # writes its section of docs/performance.md
    python benchmarks/toss_bench.py --quick    # fewer repeats and tosses; print only

1. Start-up, as a user gets it: the package is copied out of the checkout into a temporary
   directory and byte-compiled there (a non-editable install with its bytecode cached; an
   editable checkout under PYTHONDONTWRITEBYTECODE recompiles on every run), and each command
   runs as ``python -c "from coincli._entry import main; main()" ARGS`` against ``python -c
   "import typer, numpy"``, the floor of anything that tosses (the aim: at most 1.2x),
   interleaved so that both see the same machine.  Output goes to a pipe.
2. Tosses per second of ``coin simulate`` (``coincli.toss.simulate``: draws, tosses, counts)
   against drawing its random numbers alone (``sample_conditions`` in the same chunks of
   65536, the same distributions), interleaved; the aim: at most 3x.  Two tosses: the issue's
   ordinary one (u ~ N(2.4, 0.3) m/s, omega ~ N(38, 4) rad/s, psi ~ N(90, 10) deg) and the
   hand toss of ``coincli.toss.HAND_TOSS`` (38 rev/s: more turns, so more cells before
   contact).  Raw ``numpy`` normals (three a toss) are shown for scale.
3. The engine on other inputs: toss_many on the stress mix (xi in {0, 1e6} or [0, 3], u in
   1e-6..30 m/s, omega in 1e-3..1e6 rad/s, log-uniform), one toss at a time, phase_map.

Times are medians of wall-clock seconds (CPU seconds beside them: for the children of part 1,
of this process in part 2; a loaded machine stretches wall time more than CPU time).
"""

from __future__ import annotations

import argparse
import compileall
import math
import os
import resource
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(ROOT))

import _report  # noqa: E402

AIM_STARTUP = 1.2
AIM_SIMULATE = 3.0
ENTRY = "from coincli._entry import main; main()"
STARTUP = {
    "coin toss --xi 0.577 --psi 90 --u 2 --omega 40": ["toss", "--xi", "0.577", "--psi", "90",
                                                       "--u", "2", "--omega", "40"],
    "coin toss --xi 0.577 (a hand toss drawn)": ["toss", "--xi", "0.577", "--seed", "1"],
    "coin simulate --xi 0.577 -n 1000": ["simulate", "--xi", "0.577", "-n", "1000", "--seed",
                                         "1"],
    "coin phase (80 x 24, a pipe)": ["phase"],
}


def installed_copy() -> Path:
    """The package copied to a temporary directory and byte-compiled: what ``pip install .``
    leaves in site-packages, without an editable finder."""
    tmp = Path(tempfile.mkdtemp(prefix="coin-bench-site-"))
    shutil.copytree(ROOT / "coincli", tmp / "coincli",
                    ignore=shutil.ignore_patterns("__pycache__", "*.pyc"))
    compileall.compile_dir(str(tmp / "coincli"), quiet=1)
    return tmp


def _cpu_children() -> float:
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def startup(repeat: int):
    site = installed_copy()
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONDONTWRITEBYTECODE",
                                                            "PYTHONPATH", "NO_COLOR")}
    env.update(PYTHONPATH=str(site), COLUMNS="80", LINES="24")
    cases = {"`import typer, numpy` (the floor)": [sys.executable, "-c", "import typer, numpy"],
             "`import typer, numpy, numpy.random` (what drawing needs)":
                 [sys.executable, "-c", "import typer, numpy, numpy.random"],
             "the same, numpy.random as coin imports it (without `secrets`)":
                 [sys.executable, "-c", "import typer, numpy; from coincli._backend import "
                  "numpy_random; numpy_random()"]}
    cases.update({k: [sys.executable, "-c", ENTRY, *v] for k, v in STARTUP.items()})
    walls = {k: [] for k in cases}
    cpus = {k: [] for k in cases}
    for argv in cases.values():  # warm the file cache
        subprocess.run(argv, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    for _ in range(repeat):
        for k, argv in cases.items():
            c0, t0 = _cpu_children(), time.perf_counter()
            p = subprocess.run(argv, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
            walls[k].append(time.perf_counter() - t0)
            cpus[k].append(_cpu_children() - c0)
            if p.returncode != 0:
                raise SystemExit(f"{k} failed: {p.stderr.decode()}")
    shutil.rmtree(site, ignore_errors=True)
    base = next(iter(cases))
    bw, bc = _report.median(walls[base]), _report.median(cpus[base])
    rows = []
    for k in cases:
        w, c = _report.median(walls[k]), _report.median(cpus[k])
        rows.append([k, _report.fmt_time(w), _report.fmt_time(c), f"{w / bw:.2f}x",
                     f"{c / bc:.2f}x"])
    return rows, {k: _report.median(walls[k]) / bw for k in STARTUP}


def throughput(n: int, repeat: int):
    import numpy as np

    from coincli import toss as T

    psi = T.Dist("normal", math.pi / 2, math.radians(10), 0.0, math.pi)
    configs = {
        "ordinary (u N(2.4, 0.3) m/s, omega N(38, 4) rad/s, psi N(90, 10) deg)":
            {"u": T.Dist("normal", 2.4, 0.3, 0.0, T.U_MAX),
             "omega": T.Dist("normal", 38.0, 4.0, 0.0, math.inf), "psi": psi},
        "hand toss (omega N(38, 4) rev/s, the default)": dict(T.HAND_TOSS),
    }
    rows, ratios = [], {}
    for name, kw in configs.items():
        def draw(kw=kw):
            rng = np.random.default_rng(7)
            for _ in range(n // T._CHUNK):
                T.sample_conditions(T._CHUNK, rng, **kw)

        def raw():
            rng = np.random.default_rng(7)
            for _ in range(n // T._CHUNK):
                rng.standard_normal(3 * T._CHUNK)

        def sim(kw=kw):
            return T.simulate(n, 7, xi=0.577, **kw)

        t = {"draw": [], "raw": [], "sim": []}
        c = {"draw": [], "raw": [], "sim": []}
        sim()  # warm up
        for _ in range(repeat):
            for key, fn in (("draw", draw), ("sim", sim), ("raw", raw)):
                c0, t0 = time.process_time(), time.perf_counter()
                fn()
                t[key].append(time.perf_counter() - t0)
                c[key].append(time.process_time() - c0)
        d, s, r = (_report.median(t[k]) for k in ("draw", "sim", "raw"))
        dc, sc = (_report.median(c[k]) for k in ("draw", "sim"))
        ratios[name] = (s / d, sc / dc)
        rows.append([name, f"{_report.fmt_rate(n / s)}/s", f"{1e9 * s / n:.0f} ns",
                     f"{1e9 * d / n:.0f} ns", f"{s / d:.2f}x", f"{sc / dc:.2f}x",
                     f"{1e9 * r / n:.0f} ns", f"{100 * window_share(kw):.0f}%"])
    return rows, ratios


def window_share(kw, xi=0.577):
    """The share of one chunk of tosses whose outcome the contact window alone decides."""
    import numpy as np

    from coincli import toss as T

    c = T.sample_conditions(T._CHUNK, np.random.default_rng(7), **kw)
    t0 = math.atan2(1.0, xi)
    k = T._window_outcomes(np, c["psi"], c["u"], c["omega"], xi, T.DEFAULT_DIAMETER,
                           T.STANDARD_G, False, (math.sin(t0 / 2), math.cos(t0 / 2)), T._CHUNK)
    return float(np.mean(k >= 0))


def engine(n: int, repeat: int):
    import numpy as np

    from coincli import toss as T

    rng = np.random.default_rng(7)
    rows = []

    def timed(fn):
        ts = []
        for _ in range(repeat):
            t0 = time.perf_counter()
            fn()
            ts.append(time.perf_counter() - t0)
        return _report.median(ts)

    m = n // 4
    xi = np.where(rng.random(m) < 0.1, rng.choice([0.0, 1e6], m), rng.uniform(0, 3, m))
    psi = rng.uniform(0, math.pi, m)
    u = 10 ** rng.uniform(-6, 1.5, m)
    om = 10 ** rng.uniform(-3, 6, m)
    for contact in T.CONTACTS:
        s = timed(lambda contact=contact: T.toss_many(xi, psi, u, om, contact=contact))
        rows.append([f"toss_many, stress mix, {contact}", f"{m:,}", f"{_report.fmt_rate(m / s)}/s"])
    k = 2000
    for label, a in (("ordinary", (0.577, math.pi / 2, 2.0, 40.0)),
                     ("omega 1e6 rad/s, u 1e-6 m/s", (0.577, math.pi / 2, 1e-6, 1e6)),
                     ("omega 1e6 rad/s, u 2 m/s (9e4 turns)", (0.577, 1.2, 2.0, 1e6))):
        s = timed(lambda a=a: [T.flight_time(*a) for _ in range(k)])
        rows.append([f"flight_time one at a time, {label}", f"{k:,}",
                     f"{_report.fmt_rate(k / s)}/s"])
    s = timed(lambda: T.phase_map(0.577, math.pi / 2, (0, 3), (0, 60), (200, 200)))
    rows.append(["phase_map 200 x 200 (Fig. 3)", "40,000", f"{_report.fmt_rate(4e4 / s)}/s"])
    return rows


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="fewer repeats and tosses; print only")
    args = ap.parse_args(argv)
    reps_start = 7 if args.quick else 31
    n = 1 << (18 if args.quick else 20)
    reps = 3 if args.quick else 9
    machine = _report.machine()
    s_rows, s_ratios = startup(reps_start)
    t_rows, t_ratios = throughput(n, reps)
    e_rows = engine(n, 3 if args.quick else 5)

    def verdict(ratios, aim):
        worst = max(ratios.values())
        return f"worst {worst:.2f}x, {'within' if worst <= aim else 'above'} the aim of {aim}x"

    def verdict2(ratios, aim):
        wall = verdict({k: v[0] for k, v in ratios.items()}, aim)
        cpu = verdict({k: v[1] for k, v in ratios.items()}, aim)
        return f"wall: {wall}; CPU: {cpu}"

    body = "\n".join([
        "## Real tosses (`benchmarks/toss_bench.py`)",
        "",
        f"Command: `python benchmarks/toss_bench.py` (a few minutes).  {machine}.",
        "",
        f"### Start-up of toss, simulate and phase ({reps_start} runs each, interleaved)",
        "",
        "The package copied out of the checkout and byte-compiled (a non-editable install with "
        "its bytecode cached), each command run as `python -c \"from coincli._entry import "
        "main; main()\" ...`, output to a pipe, against `python -c \"import typer, numpy\"`: "
        f"aim <= {AIM_STARTUP}x.  {verdict(s_ratios, AIM_STARTUP)} (wall).",
        "",
        _report.table(["command", "wall", "CPU", "wall / floor", "CPU / floor"], s_rows),
        "What a drawn toss or a simulate run adds to the floor: `numpy.random`, imported without "
        "the `secrets` module that numpy's `bit_generator` loads for unseeded entropy (with it "
        "come `hashlib` and OpenSSL, `hmac`, `base64` and `random`: some 7 ms; "
        "`coincli._backend.numpy_random` lets a stand-in holding only `randbits`, the same "
        "`os.urandom` entropy, serve that one import and removes it at once); `coincli.toss`; "
        "for simulate's vigorous limit `coincli.averages` with its own Gauss-Legendre rule "
        "(`numpy.polynomial` was 2 ms) and the Wilson interval's small module (all of "
        "`coincli.stats` was 2 ms); the top of the distributions is checked by "
        "`check_toss`, without tossing.  A command can read below 1.0x: `coin` pauses the "
        "garbage collector while it imports (coincli._entry), the floor does not.  "
        "tests/test_cli_subprocess.py forbids `scipy`, `rich`, `matplotlib`, `numpy.ma`, "
        "`secrets`, `hashlib`, `numpy.polynomial` and `coincli.stats` in these commands.",
        "",
        f"### Tosses per second of `coin simulate` ({n:,} tosses, {reps} runs each, "
        "interleaved)",
        "",
        "`coincli.toss.simulate` (draws, tosses, counts) against drawing its random numbers "
        "alone (`sample_conditions`, the same chunks and distributions): aim <= "
        f"{AIM_SIMULATE}x.  {verdict2(t_ratios, AIM_SIMULATE)}.  Both are single-threaded; "
        "on a shared machine the CPU seconds of this process are the steadier measure (the "
        "wall clock also counts the time other processes hold the CPU).",
        "",
        _report.table(["tosses", "simulate", "per toss", "draws alone, per toss",
                       "simulate / draws", "same, CPU", "3 numpy normals, per toss",
                       "decided by the window"], t_rows),
        "Where the time goes.  `simulate` wants outcomes, not times of flight, and reads each "
        "one off the first bound that settles it (`coincli.toss._outcomes`; the same codes as "
        "`toss_many`, compared toss by toss in tests/test_toss.py and on 4.6 million seeded "
        "tosses of six kinds).  (1) The contact window: first contact lies where the centre "
        "is below `Lmax`, on the descent `[w2s, t_end]`; where `sin(alpha/2)` over that whole "
        "window stays inside one outcome's band, the toss is decided in about 50 array "
        "operations, no root finding (the last column: most ordinary tosses, whose coin turns "
        "some 0.2 rad while it falls the last 12 mm; few hand tosses, which turn 1.2 rad "
        "there).  (2) The others run the scan of `toss_many` unchanged (its setup, about 130 "
        "operations; F and F' at the window's start, about 70, 45 of them the sine and cosine "
        "polynomials; one evaluation a round), gathered into full batches of 8192, and stop as "
        "soon as `[front, t_end]` lies in one band, or the certified cell holding the root "
        "does, or a bracket of a hundredth of that cell around its Hermite estimate (two "
        "evaluations) does: some 98% of the cells that straddle a boundary.  (3) The last "
        "half percent are refined by Newton, once a chunk of 65536.  The hand toss stays "
        "near 10x: most of its tosses take the setup and two to four rounds of the scan (its "
        "coin turns more than a radian over the window).  Its cells are those of `toss_many`, "
        "bit for bit, on purpose: a different sequence of cells could move a grazing contact "
        "(a dip within F's rounding band), so the outcome could change; fewer operations a "
        "round is what is left (numpy runs each over the whole batch: a toss costs every "
        "operation of every round it takes part in).  One toss at a time pays numpy's per-call "
        "overhead some 300 times (about 1.5 ms): nothing for `coin toss`, whose start-up is a "
        "hundred times that, but a loop over `flight_time` should pass arrays to `toss_many` "
        "instead.",
        "",
        "### The engine on other inputs",
        "",
        _report.table(["what", "tosses", "rate"], e_rows),
    ])
    print(body)
    if not args.quick:
        _report.write_section("toss_bench", body)
    return 0


if __name__ == "__main__":
    sys.exit(main())
