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
2. Tosses per second of ``coin simulate`` (``coincli.core.toss.simulate.simulate``: draws, tosses, counts)
   against drawing its random numbers alone (``sample_conditions`` in the same chunks of
   65536, the same distributions), interleaved; the aim: at most 3x.  Two tosses: the issue's
   ordinary one (u ~ N(2.4, 0.3) m/s, omega ~ N(38, 4) rad/s, psi ~ N(90, 10) deg) and the
   hand toss of ``coincli.core.toss.launch.HAND_TOSS`` (38 rev/s: more turns, so more cells before
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
                 [sys.executable, "-c", "import typer, numpy; from coincli.core._numerics.backend import "
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


THROUGHPUT_CHILD = r"""
import math, sys, time
import numpy as np
from coincli.core.toss import flight as T, launch as TL, simulate as TS
kind, cfg, n = sys.argv[1], sys.argv[2], int(sys.argv[3])
kw = dict(TL.HAND_TOSS) if cfg == "hand" else {
    "u": TL.Dist("normal", 2.4, 0.3, 0.0, T.U_MAX),
    "omega": TL.Dist("normal", 38.0, 4.0, 0.0, math.inf),
    "psi": TL.Dist("normal", math.pi / 2, math.radians(10), 0.0, math.pi)}
c0, t0 = time.process_time(), time.perf_counter()
if kind == "sim":
    TS.simulate(n, 7, xi=0.577, **kw)
else:
    rng = np.random.default_rng(7)
    for _ in range(n // TS._CHUNK):
        TL.sample_conditions(TS._CHUNK, rng, **kw)
print(time.perf_counter() - t0, time.process_time() - c0)
"""


def throughput(n: int, repeat: int):
    """Tosses per second of simulate against its draws alone: in a fresh process each (as a
    user gets it: ``coin simulate`` is one run), interleaved, and in this process once warm."""
    import numpy as np

    from coincli.core.toss import flight as T
    from coincli.core.toss import launch as TL
    from coincli.core.toss import simulate as TS

    psi = TL.Dist("normal", math.pi / 2, math.radians(10), 0.0, math.pi)
    configs = {
        "ordinary (u N(2.4, 0.3) m/s, omega N(38, 4) rad/s, psi N(90, 10) deg)":
            ("ordinary", {"u": TL.Dist("normal", 2.4, 0.3, 0.0, T.U_MAX),
                          "omega": TL.Dist("normal", 38.0, 4.0, 0.0, math.inf), "psi": psi}),
        "hand toss (omega N(38, 4) rev/s, the default)": ("hand", dict(TL.HAND_TOSS)),
    }
    env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
    rows, ratios, split = [], {}, []
    # Freed, a 16 MB block raises glibc's threshold for serving allocations by mmap, so that
    # numpy's chunk-sized temporaries are reused rather than mapped and faulted in afresh: the
    # warm in-process figures.  A fresh process starts without it.
    block = np.ones(2 << 20)
    del block
    for name, (cfg, kw) in configs.items():
        fresh = {"draw": [], "sim": []}
        for _ in range(repeat):
            for key in fresh:
                p = subprocess.run([sys.executable, "-c", THROUGHPUT_CHILD, key, cfg, str(n)],
                                   env=env, capture_output=True, text=True, check=True)
                fresh[key].append(tuple(float(v) for v in p.stdout.split()))

        def draw(kw=kw):
            rng = np.random.default_rng(7)
            for _ in range(n // TS._CHUNK):
                TL.sample_conditions(TS._CHUNK, rng, **kw)

        def raw():
            rng = np.random.default_rng(7)
            for _ in range(n // TS._CHUNK):
                rng.standard_normal(3 * TS._CHUNK)

        def sim(kw=kw):
            return TS.simulate(n, 7, xi=0.577, **kw)

        t = {"draw": [], "raw": [], "sim": []}
        c = {"draw": [], "raw": [], "sim": []}
        sim()  # warm up
        for _ in range(repeat):
            for key, fn in (("draw", draw), ("sim", sim), ("raw", raw)):
                c0, t0 = time.process_time(), time.perf_counter()
                fn()
                t[key].append(time.perf_counter() - t0)
                c[key].append(time.process_time() - c0)
        fd, fs = (_report.median([v[1] for v in fresh[k]]) for k in ("draw", "sim"))
        fdw, fsw = (_report.median([v[0] for v in fresh[k]]) for k in ("draw", "sim"))
        s, r = (_report.median(t[k]) for k in ("sim", "raw"))
        dc, sc = (_report.median(c[k]) for k in ("draw", "sim"))
        ratios[name] = (fsw / fdw, fs / fd, sc / dc)
        rows.append([name, f"{_report.fmt_rate(n / fs)}/s", f"{1e9 * fs / n:.0f} ns",
                     f"{1e9 * fd / n:.0f} ns", f"{fs / fd:.2f}x", f"{fsw / fdw:.2f}x",
                     f"{1e9 * sc / n:.0f} ns", f"{1e9 * dc / n:.0f} ns", f"{sc / dc:.2f}x",
                     f"{1e9 * r / n:.0f} ns",
                     "{:.1f}% / {:.2f}% / {:.4f}%".format(*(100 * s for s in path_shares(kw)))])
        b, e, o = stages(kw, n, repeat)
        split.append([name.split(" (")[0], f"{1e9 * b / n:.1f}", f"{1e9 * (e - b) / n:.1f}",
                      f"{1e9 * (o - e) / n:.1f}", f"{1e9 * o / n:.1f}", f"{1e9 * dc / n:.0f}",
                      f"{1e9 * sc / n:.0f}"])
    return rows, ratios, split


def _descent_constants(xi):
    """The rim coin's radius, launch height, band sines and descent limits, as ``outcome_codes``
    sets them up for a quarter-sized coin of aspect ratio ``xi`` under standard gravity."""
    from coincli.core.toss import batch as TB
    from coincli.core.toss import flight as T

    a = T.DEFAULT_DIAMETER / 2
    z0 = math.sqrt(3.0) / 2 * a
    t0 = math.atan2(1.0, xi)
    sb, cb = math.sin(t0 / 2), math.cos(t0 / 2)
    return a, z0, sb, cb, TB._descent_limits(a, z0, T.STANDARD_G, 2 * a * sb * cb, sb, cb)


def stages(kw, n, repeat, xi=0.577):
    """CPU seconds of simulate's outcome path over ``n`` drawn tosses, cumulatively: the bounds
    pass alone (``_descent_batch``), the rim path (``_descent_outcomes``: bounds and sampled
    passes) and all of ``outcome_codes`` (validation, then the scan for what is left): the least of
    ``2 repeat + 1`` interleaved runs each (the cost without interference: the differences of
    medians are noise at a few nanoseconds)."""
    import numpy as np

    from coincli.core.toss import batch as TB
    from coincli.core.toss import flight as T
    from coincli.core.toss import launch as TL
    from coincli.core.toss import simulate as TS

    rng = np.random.default_rng(7)
    chunks = [TL.sample_conditions(TS._CHUNK, rng, **kw) for _ in range(n // TS._CHUNK)]
    a, z0, sb, cb, lim = _descent_constants(xi)
    m = TS._CHUNK
    code = np.empty(m, dtype=np.int8)

    def bounds():
        work, flags = TB._descent_scratch(np)
        for c in chunks:
            for lo in range(0, m, TB._DBATCH):
                sl = slice(lo, lo + TB._DBATCH)
                k = sl.stop - sl.start
                TB._descent_batch(np, c["psi"][sl], c["u"][sl], c["omega"][sl], a, z0,
                                  T.STANDARD_G, lim, work[:, :k], flags[:, :k], code[sl])

    def descent():
        for c in chunks:
            TB._descent_outcomes(np, c["psi"], c["u"], c["omega"], xi, T.DEFAULT_DIAMETER,
                                 T.STANDARD_G, (sb, cb), m)

    def outcomes():
        for c in chunks:
            TB.outcome_codes(xi, c["psi"], c["u"], c["omega"])

    ts = {bounds: [], descent: [], outcomes: []}
    with np.errstate(all="ignore"):
        outcomes()  # warm up
        for _ in range(2 * repeat + 1):
            for fn in ts:
                c0 = time.process_time()
                fn()
                ts[fn].append(time.process_time() - c0)
    return tuple(min(v) for v in ts.values())


def path_shares(kw, xi=0.577, chunks=4):
    """The shares of ``chunks`` chunks of tosses whose outcome the bounds on the tilt settle,
    the sampled passes settle, and the scan must settle (simulate's rim path)."""
    import numpy as np

    from coincli.core.toss import batch as TB
    from coincli.core.toss import flight as T
    from coincli.core.toss import launch as TL
    from coincli.core.toss import simulate as TS

    rng = np.random.default_rng(7)
    a, z0, sb, cb, lim = _descent_constants(xi)
    m = TS._CHUNK
    first = left = 0
    for _ in range(chunks):
        c = TL.sample_conditions(m, rng, **kw)
        code = np.empty(m, dtype=np.int8)
        with np.errstate(all="ignore"):
            TB._descent_batch(np, c["psi"], c["u"], c["omega"], a, z0, T.STANDARD_G, lim,
                              np.empty((9, m)), np.empty((4, m), dtype=bool), code)
            full = TB._descent_outcomes(np, c["psi"], c["u"], c["omega"], xi,
                                        T.DEFAULT_DIAMETER, T.STANDARD_G, (sb, cb), m)
        first += int(np.count_nonzero(code >= 0))
        left += int(np.count_nonzero(full < 0))
    total = chunks * m
    return first / total, (total - first - left) / total, left / total


def engine(n: int, repeat: int):
    import numpy as np

    from coincli.core.toss import batch as TB
    from coincli.core.toss import flight as T
    from coincli.core.toss import phase as TP

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
        s = timed(lambda contact=contact: TB.toss_many(xi, psi, u, om, contact=contact))
        rows.append([f"toss_many, stress mix, {contact}", f"{m:,}", f"{_report.fmt_rate(m / s)}/s"])
    k = 2000
    for label, a in (("ordinary", (0.577, math.pi / 2, 2.0, 40.0)),
                     ("omega 1e6 rad/s, u 1e-6 m/s", (0.577, math.pi / 2, 1e-6, 1e6)),
                     ("omega 1e6 rad/s, u 2 m/s (9e4 turns)", (0.577, 1.2, 2.0, 1e6))):
        s = timed(lambda a=a: [TB.flight_time(*a) for _ in range(k)])
        rows.append([f"flight_time one at a time, {label}", f"{k:,}",
                     f"{_report.fmt_rate(k / s)}/s"])
    s = timed(lambda: TP.phase_map(0.577, math.pi / 2, (0, 3), (0, 60), (200, 200)))
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
    t_rows, t_ratios, t_split = throughput(n, reps)
    e_rows = engine(n, 3 if args.quick else 5)

    def verdict(ratios, aim):
        worst = max(ratios.values())
        return f"worst {worst:.2f}x, {'within' if worst <= aim else 'above'} the aim of {aim}x"

    def verdict2(ratios, aim):
        wall = verdict({k: v[0] for k, v in ratios.items()}, aim)
        cpu = verdict({k: v[1] for k, v in ratios.items()}, aim)
        warm = verdict({k: v[2] for k, v in ratios.items()}, aim)
        return f"fresh processes, wall: {wall}; CPU: {cpu}; warm, CPU: {warm}"

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
        "`coincli.core._numerics.backend.numpy_random` lets a stand-in holding only `randbits`, the same "
        "`os.urandom` entropy, serve that one import and removes it at once); the modules of `coincli.core.toss`; "
        "for simulate's vigorous limit `coincli.core.averages` with its own Gauss-Legendre rule "
        "(`numpy.polynomial` was 2 ms) and the Wilson interval's small module (all of "
        "`coincli.core.stats.tests` was 2 ms); the top of the distributions is checked by "
        "`check_toss`, without tossing.  A command can read below 1.0x: `coin` pauses the "
        "garbage collector while it imports (coincli._entry), the floor does not.  "
        "tests/test_cli_subprocess.py forbids `scipy`, `rich`, `matplotlib`, `numpy.ma`, "
        "`secrets`, `hashlib`, `numpy.polynomial` and `coincli.core.stats.tests` in these commands.",
        "",
        f"### Tosses per second of `coin simulate` ({n:,} tosses, {reps} runs each, "
        "interleaved)",
        "",
        "`coincli.core.toss.simulate.simulate` (draws, tosses, counts) against drawing its random numbers "
        "alone (`sample_conditions`, the same chunks and distributions): aim <= "
        f"{AIM_SIMULATE}x.  {verdict2(t_ratios, AIM_SIMULATE)}.  Both are single-threaded; "
        "on a shared machine CPU seconds are the steadier measure (the wall clock also counts "
        "the time other processes hold the CPU).  Fresh: each run in a fresh process, as "
        "`coin simulate` runs (the imports not counted), the two interleaved; per toss in CPU "
        "time.  Warm: in this process, after a 16 MB block has been freed.  The difference is "
        "glibc's allocator: until a large block is freed it serves every allocation over 128 kB "
        "(a numpy temporary of one chunk, 512 kB) by a fresh mmap, faulted in page by page, "
        "which doubles the cost of the draws (`_truncnorm`'s temporaries) and adds a third to "
        "simulate's; `outcome_codes` itself allocates no such block a batch.",
        "",
        _report.table(["tosses", "simulate, fresh", "per toss", "draws alone, per toss",
                       "simulate / draws (CPU)", "same, wall", "simulate, warm, per toss",
                       "draws alone, warm", "warm: simulate / draws", "3 numpy normals, warm",
                       "settled by bounds / samples / scan"], t_rows),
        "Where the time goes, warm (CPU nanoseconds a toss).  `outcome_codes` by stage, measured "
        "cumulatively on the same drawn tosses (each column a difference; the least of "
        f"{2 * reps + 1} interleaved runs, the cost without interference), beside the medians "
        "of the draws and of simulate above (the rest of simulate is its counting, `bincount` "
        "of each chunk, and the vigorous limit, a quadrature once a run):",
        "",
        _report.table(["tosses", "bounds pass", "sampled passes", "validation and the scan",
                       "`outcome_codes`", "draws", "simulate"], t_split),
        "`simulate` wants outcomes, not times of flight, and reads each one off the first "
        "proof that settles it (`coincli.core.toss.batch.outcome_codes`; the same codes as `toss_many`, "
        "compared toss by toss in tests/test_toss.py: seeded hand and ordinary tosses at six "
        "thicknesses, contacts tuned to the side boundary, other coins, planets and tilts, and "
        "simulate's counts end to end).  A rim touching at `t_f` has `a sin(alpha_f) = "
        "z(t_f)`, so it lands on its side exactly when it touches before its centre falls "
        "through `c = a sin(theta0)`, at `Tc`: the question is only whether `F = z - L` goes "
        "negative before `Tc`, and which face is down after.  (1) The bounds pass "
        "(`_descent_batch`, batches of 32768 on scratch kept from call to call): "
        "`sin(alpha/2) = sin(psi) |sin(omega t/2)|` at `Tc` inside the side band proves a "
        "contact (sides), and its range over `[w2s, Tc]` outside the band proves none (the "
        "face down then), each with a margin `M` a hundred times the scan's rounding band; "
        "about 90 array operations a toss (30 of them two sine polynomials), some 0.2 ns "
        "each: most tosses (the last column of the table above).  (2) The tosses whose coin "
        "tilted through its side band on the way down (5% of hand tosses, 1% of ordinary "
        "ones) have `F` sampled at four points with the semi-concave bound between them, then "
        "the few left at 46 points closing in on `Tc` (contacts within 1e-8 of `Tc`, a few a "
        "chunk); the first pass is most of this column (some 200 ns a toss it takes: 30 "
        "operations on its setup, 40 on each sample), the second about 2 ns a toss of "
        "numpy's per-call overhead.  (3) Validation of the drawn arrays, and the "
        "scan of `toss_many` for whatever is left: none of these tosses, so the scan costs "
        "nothing here; it still settles thick contact, very fast spins and throws, and tilts "
        "beyond 45 degrees from the Keller flip (the sampled passes take any tilt).  At 38 "
        "rev/s the coin turns 1.2 rad while its centre falls the last 12 mm, which no longer "
        "matters much: the hand toss costs little more than the ordinary one, and `outcome_codes` "
        "now costs about what the draws do.  "
        "One toss at a time pays numpy's per-call overhead some 300 times (about 1.5 ms): "
        "nothing for `coin toss`, whose start-up is a hundred times that, but a loop over "
        "`flight_time` should pass arrays to `toss_many` instead.",
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
