"""Regenerate docs/accuracy.md: errors of coincli.core.models' closed forms against 50-digit mpmath.

    python benchmarks/accuracy.py            # writes docs/accuracy.md (about a minute)
    python benchmarks/accuracy.py --stdout   # print instead

The reference values and input grids are those of tests/reference.py (denser here); errors are
in ulps of the reference value, on the scalar (math) path and on the numpy path.
"""

from __future__ import annotations

import argparse
import math
import platform
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests" / "reference"))

import numpy as np  # noqa: E402
import reference as R  # noqa: E402

from coincli.core import models  # noqa: E402

OUT = ROOT / "docs" / "accuracy.md"
OUTPUTS = ("heads", "sides", "tails")


def xi_region(xi):
    if xi < 1e-8:
        return "tiny xi < 1e-8 (incl. 0)"
    if xi > 1e8:
        return "huge xi > 1e8 (incl. inf)"
    return "moderate 1e-8 <= xi <= 1e8"


def p_region(p):
    if p < 1e-8:
        return "p near 0 (p < 1e-8, incl. 0)"
    if p > 1 - 1e-8:
        return "p near 1 (p > 1 - 1e-8, incl. 1)"
    return "moderate 1e-8 <= p <= 1 - 1e-8"


def _eval(name, inputs):
    """(scalar rows, numpy rows) of outputs for a list of argument tuples."""
    f = getattr(models, name)
    scalar = []
    for args in inputs:
        v = f(*args)
        scalar.append(tuple(v) if isinstance(v, tuple) else (v,))
    cols = [np.array(c, dtype=float) for c in zip(*inputs, strict=True)]
    v = f(*cols)
    v = tuple(v) if isinstance(v, tuple) else (v,)
    array = [tuple(float(c[i]) for c in v) for i in range(len(inputs))]
    return scalar, array


def _fmt_input(args):
    return ", ".join(repr(a) for a in args)


def measure(name, inputs, refs, regions, labels):
    """Rows of the table: one per (region, output)."""
    scalar, array = _eval(name, inputs)
    rows = []
    for region in dict.fromkeys(regions):  # first-seen order
        idx = [i for i, r in enumerate(regions) if r == region]
        for k, label in enumerate(labels):
            es = [R.ulp_error(scalar[i][k], refs[i][k]) for i in idx]
            ea = [R.ulp_error(array[i][k], refs[i][k]) for i in idx]
            j = max(range(len(idx)), key=lambda m: max(es[m], ea[m]))
            i = idx[j]
            rows.append((region, label, len(idx), max(es), max(ea), sum(es) / len(es),
                         _fmt_input(inputs[i]), scalar[i][k], float(refs[i][k])))
    differ = sum(1 for a, b in zip(scalar, array, strict=True) if a != b)
    return rows, differ, len(inputs)


# --------------------------------------------------------------------------- root-found inverses


def _relative(got, ref):
    with R.mp.workdps(60):
        return float(abs(R.mpf(got) - ref) / ref)


def inverse_rows(cases, solve, region_of):
    """Rows (region, cases, max relative error, max error/bar, bar used, worst input) of the
    root-found inverse ``solve`` against the stored references."""
    import inverse_reference as IR

    groups = {}
    for case in cases:
        *key, ref, kappa = case
        if not 0 < ref < 1.7976931348623157e308:
            continue
        p = key[-1] if isinstance(key[0], str) else key[0]
        got = solve(*key)
        with R.mp.workdps(60):
            err = abs(R.mpf(got) - ref)
            bar = IR.bar(ref, p, kappa)
            rel_bar = bar / ref
        groups.setdefault(region_of(*key), []).append(
            (float(err / bar), float(err / ref), "4 ulp x kappa" if rel_bar > 1.0000001e-12
             else "1e-12", key, got, float(ref), float(kappa)))
    rows = []
    for region, g in groups.items():
        w = max(g)
        bars = sorted({e[2] for e in g})
        rows.append((region, len(g), max(e[1] for e in g), w[0], " / ".join(bars), w[3], w[4],
                     w[5], w[6]))
    return rows


def inverse_table(title, rows):
    lines = [f"### {title}", "",
             "| region | cases | max relative error | max error / bar | bar | worst input | "
             "computed there | reference there | kappa there |",
             "|---|---:|---:|---:|---|---|---:|---:|---:|"]
    for region, n, rel, ratio, bar, key, got, ref, kappa in rows:
        lines.append(f"| {region} | {n} | {rel:.2e} | {ratio:.3g} | {bar} | "
                     f"`{', '.join(repr(k) for k in key)}` | {got!r} | {ref!r} | {kappa:.3g} |")
    return lines + [""]


def _p_region(p):
    if p < 2.2250738585072014e-308:
        return "subnormal p (2^-1074)"
    return p_region(p)


def tail_rows():
    import test_inverses as TI

    rows = []
    for mean, sd, z, ref in TI.TAILS:
        xi, got, rel, kappa = TI.tail_error(mean, sd, z, ref)
        rows.append(f"| `normal:{mean:g}:{sd:g}` | {z:g} | {xi!r} | {ref} | {got!r} | {rel:.2e} "
                    f"| {kappa:.3g} | {4 * 2.0**-53 * max(1.0, kappa):.2e} |")
    return rows


def _consecutive(x0, n):
    b = np.array([x0]).view(np.int64)[0]
    return (b + np.arange(n, dtype=np.int64)).view(np.float64)


def _steps(v):
    """Largest decrease between neighbours, in ulps of the later value (0 if none)."""
    d = np.diff(np.asarray(v, dtype=float))
    bad = d < 0
    return float((-d[bad] / np.abs(np.spacing(np.asarray(v)[1:][bad]))).max()) \
        if bad.any() else 0.0


def step_rows():
    from coincli.core.averages import marginal
    from coincli.core.densities import Cosine, Normal, Table, Uniform

    rows = []
    starts = [1e-12, 1e-3, 0.1, 0.3535, 0.5773502691896, 1.0, 2.7, 30.0, 1e6, 1e15]
    psis = [0.1, 0.5, 1.0, 1.2, math.pi / 3, 1.5, math.pi / 2, 2.0, 3.0]
    down = up = 0.0
    count = 0
    for psi in psis:
        for x0 in starts:
            xs = _consecutive(x0, 20000)
            o = models.conditional(xs, psi)
            one = [models.conditional(float(x), psi) for x in xs[:2000]]
            down = max(down, _steps(o.sides), _steps([v.sides for v in one]))
            up = max(up, _steps(-o.heads), _steps([-v.heads for v in one]))
            count += xs.size + len(one)
    rows.append(f"| `conditional(xi, psi)`, psi at {len(psis)} angles, 0.1 to 3 rad | {count:,} "
                f"| {down:.0f} | {up:.0f} |")
    dens = {"uniform": Uniform(), "cosine": Cosine(), "normal": Normal(),
            "normal:90:18": Normal(math.pi / 2, math.radians(18)),
            "normal:0:6": Normal(0.0, math.radians(6)),
            "table (tests/marginal_reference.py)": Table([0.0, 0.3, 0.9, 1.6, 2.2, math.pi],
                                                         [0.0, 1.0, 0.5, 2.0, 0.25, 0.0]),
            "normal:30:0.05 (far tails)": Normal(math.radians(30), math.radians(0.05))}
    for name, d in dens.items():
        down = up = 0.0
        count = 0
        for x0 in [1e-8, 0.1, 0.5773502691896, 0.54, 3.0, 1e4]:
            o = marginal(_consecutive(x0, 3000), d)
            down, up = max(down, _steps(o.sides)), max(up, _steps(-o.heads))
            count += 3000
        rows.append(f"| `marginal(xi, {name})` | {count:,} | {down:.0f} | {up:.0f} |")
    return rows


def inverse_sections():
    import inverse_reference as IR

    from coincli.core.averages import conditional_inverse, marginal_inverse

    ref = IR.load()
    cond = inverse_rows(ref["conditional"], lambda p, psi: conditional_inverse(p, psi),
                        lambda p, psi: _p_region(p))
    marg = inverse_rows(ref["marginal"], lambda label, p: marginal_inverse(p, IR.density(label)),
                        lambda label, p: f"`{label}`" if p >= 2.2250738585072014e-308
                        else "subnormal p (2^-1074), every density")
    lines = inverse_table("`conditional_inverse(p, psi)`", cond)
    if marg:
        lines += inverse_table("`marginal_inverse(p, density)`", marg)
    return lines, cond, marg


def issue17_sections():
    """The doc's sections on the root-found inverses, far tails and consecutive doubles."""
    import inverse_reference as IR

    inv, cond, marg = inverse_sections()
    worst_c = max(r[2] for r in cond if "subnormal" not in r[0])
    worst_m = max((r[2] for r in marg if "subnormal" not in r[0]), default=float("nan"))
    kappa = max(float(k) for p, _, r, k in IR.load()["conditional"]
                if p >= 2.2250738585072014e-308 and 0 < r < 1.7976931348623157e308)
    return [
        "## Root-found inverses",
        "",
        "`conditional_inverse` (Table I at a fixed psi) and `marginal_inverse` (psi averaged "
        "over a density) solve `P(sides) = p` for xi.  The solver "
        "(`coincli.core._numerics.roots.positive_roots`) "
        "brackets the root from a start (Table I inverted in closed form for a fixed psi; the "
        "dynamic model's xi, or Table I at the mean of a narrow normal, for a density), then "
        "runs Chandrupatla's method (inverse quadratic interpolation safeguarded by bisection, "
        "in log xi while the bracket spans more than a factor 2) until the bracket is two "
        "adjacent doubles, and returns the one with the smaller residual: the tolerance is the "
        "answer's own rounding, whatever its size (at p = 1e-300 too, where a tolerance on "
        "log xi would allow 1e-13).  For p > 1/2 it solves the complement, `P(heads) + "
        "P(tails) = 1 - p`: 1 - p is exact there and the forward functions give heads and "
        "tails to full relative accuracy, while a double P(sides) near 1 moves in steps of "
        "1.1e-16 (the old solver's 2e-9 median, 3e-2 worst error near p = 1).",
        "",
        "The references are in `tests/data/inverse_reference.json`, written by "
        "`tests/inverse_reference.py`: for Table I, root finding on the textbook forms in "
        "mpmath at 70 digits and more (independent of the code's closed-form start and of its "
        "solver); for the averages, Newton's method on the 40-digit tanh-sinh quadrature of "
        "`tests/marginal_reference.py`.  The bar (issue 17) is relative in xi: "
        "`max(1e-12, 4 ulp(r)/r * kappa)`, where r is the target the code solves for (p, or "
        "1 - p above 1/2) and kappa = |d ln xi / d ln r| is the condition number of xi with "
        "respect to it (stored with each case); at least an ulp of xi.  The column *bar* says "
        "which of the two applies in each region: 1e-12 wherever the target is a normal double "
        f"(kappa is at most a few there: {kappa:.3g} for Table I); the 4-ulp term only for a "
        "subnormal target, whose own ulp is 100% of it.",
        "",
        f"Worst relative error where p is a normal double: `conditional_inverse` "
        f"{worst_c:.2e}, `marginal_inverse` {worst_m:.2e} (within 1e-12 everywhere).  "
        "`tests/test_inverses.py` holds every stored case to the bar.",
        "",
        *inv,
        "One model reached by two paths gives one xi: `--psi 90` is the Keller flip itself "
        "(the double nearest pi/2 stands for pi/2 in `ModelSpec.fixed_psi`; the 6e-17 rad "
        "between them shifted P(heads) + P(tails) by (6e-17/theta0)^2 relative: 1e-13 at "
        "xi = 6e9, and removed tails past xi = 1e16), and a normal too narrow for any "
        "quadrature inverts through Table I at its mean (`dynamic_inverse` at 90 deg), so "
        "`coin design -p P --psi 90`, `--psi-dist normal:90:1e-20` and the default dynamic "
        "model print the same digits, as do `--psi 60` and `--psi-dist normal:60:1e-30`.",
        "",
        "## Far tails of narrow normals",
        "",
        "Where a regime boundary cuts a normal density more than 4 sd from its centre (or as "
        "far down the tail of a mean beyond 0 or 180 deg), the chance of the outcome that "
        "starts there is a tail of the density: 1e-60, 1e-300.  Breakpoints placed about the "
        "mean (out to 16 sd) left it unresolved (38% off for `normal:30:0.05` at 1e-60, a "
        "factor 2 for `normal:40:0.01` at 1e-300).  The quadrature now also places breakpoints "
        "at `b -+ w 2^k` (k = -2 .. 6) beyond each such boundary `b`, with `w = sd^2/|b - mean|` "
        "the tail's decay length there (`coincli.core.averages._tail_points`); past 40 sd the tail "
        "is below 1e-340 of the mass and rounds to 0.  The reference is "
        "`tests/marginal_reference.py` with breakpoints graded from every boundary.  What is left "
        "is the rounding of theta0/2 (half an ulp), which a tail exp(-z^2/2) feels z/sd times "
        "over: the relative error stays within 4 ulps times kappa = |d ln P / d ln xi|, the "
        "chance's own condition number.",
        "",
        "| density | boundary at (sd) | xi | P(sides), mpmath | computed | relative error | kappa "
        "| 4 ulp x kappa |",
        "|---|---:|---:|---:|---:|---:|---:|---:|",
        *tail_rows(),
        "",
        "## Steps between consecutive doubles",
        "",
        "`geometric` and `dynamic` never decrease P(sides) (or increase P(heads)) from one "
        "double of xi to the next.  `conditional` and `marginal` are not monotone at that "
        "scale: each output is within a few ulps of the exact value, and the errors of "
        "neighbouring doubles are independent, so P(sides) can step down by a few ulps.  "
        "Measured over runs of consecutive doubles (numpy and scalar paths for "
        "`conditional`): `tests/test_inverses.py` holds `conditional` to 6 ulps and the "
        "averages to 10.  The root finder does not need monotonicity: it stops at a sign "
        "change between adjacent doubles, which lies within those few ulps (divided by the "
        "slope) of the exact root.  In the far tail of a narrow normal a step is bounded by "
        "the relative error above (4 ulps times kappa), hundreds of ulps of a chance of 1e-60.",
        "",
        "| function | doubles | largest step down of P(sides), ulps | largest step up of "
        "P(heads), ulps |",
        "|---|---:|---:|---:|",
        *step_rows(),
        "",
    ]


def table(title, rows, differ, n):
    lines = [f"### {title}", "",
             "| region | output | inputs | max ulps (math) | max ulps (numpy) | mean ulps | "
             "worst input | computed there | reference there |",
             "|---|---|---:|---:|---:|---:|---|---:|---:|"]
    for region, label, count, ms, ma, mean, where, got, ref in rows:
        lines.append(f"| {region} | {label} | {count} | {ms:.2f} | {ma:.2f} | {mean:.3f} | "
                     f"`{where}` | {got!r} | {ref!r} |")
    lines += ["", f"Scalar and numpy paths differ on {differ} of {n} inputs.", ""]
    return lines


# Rows measured by their own reference checks (too slow to redo here), kept in this table so
# that regenerating the file keeps them.  Update them when the check is rerun.
MEASURED_ELSEWHERE = [
    # tests/test_intervals.py against tests/interval_reference.py (mpmath, 40 digits): 712
    # cases, n = 1, 2, 3, 10, 41, 100, 10^3, 10^4, 10^6, 10^9, 10^12, 10^15, 2^53; k = 0, 1, 2,
    # n/3, n/2, n - 2, n - 1, n; confidence 0.5, 0.9, 0.95, 0.99, 1 - 1e-6, 1 - 1e-10,
    # 1 - 1e-15, 1 - 2^-53 (worst: k = 2 of 10^4 at 1 - 1e-15; Wilson: k = 1 of 10^12 at
    # 1 - 2^-53)
    "| `stats.clopper_pearson_interval` (n 1 to 2^53, confidence 0.5 to 1 - 2^-53; "
    "`tests/test_intervals.py`) | 18.54 |",
    "| `stats.wilson_interval` (the same 712 cases) | 3.27 |",
]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--stdout", action="store_true", help="print instead of writing the doc")
    ap.add_argument("--inverses", action="store_true",
                    help="print only the root-found inverses, tails and steps (quick)")
    args = ap.parse_args(argv)
    issue17 = issue17_sections()
    if args.inverses:
        print("\n".join(issue17))
        return

    xis = R.xi_grid(n_log=601, n_random=2000, seed=1)
    ps = R.p_grid(n_log=301, n_random=1000, seed=1)
    cases = R.conditional_cases(n_xi_log=61, n_xi_random=40, n_psi_random=20, seed=1)

    kind_name = {"interior": "interior", "boundary": "boundary +-1e-12..1e-6",
                 "adjacent": "boundary-adjacent doubles"}
    sections = []
    worst = {}
    for name, ref in (("geometric", R.ref_geometric), ("dynamic", R.ref_dynamic)):
        inputs = [(x,) for x in xis]
        refs = [ref(x) for x in xis]
        rows, differ, n = measure(name, inputs, refs, [xi_region(x) for x in xis], OUTPUTS)
        sections += table(f"`{name}(xi)`", rows, differ, n)
        worst[name] = max(max(r[3], r[4]) for r in rows)
    inputs = [(x, p) for x, p, _ in cases]
    refs = [R.ref_conditional(x, p) for x, p, _ in cases]
    regions = [f"{xi_region(x)}; {kind_name[k]}" for x, _, k in cases]
    order = sorted(set(regions), key=lambda r: (r.split(";")[1], r))
    regions_sorted = sorted(range(len(cases)), key=lambda i: order.index(regions[i]))
    rows, differ, n = measure("conditional", [inputs[i] for i in regions_sorted],
                              [refs[i] for i in regions_sorted],
                              [regions[i] for i in regions_sorted], OUTPUTS)
    sections += table("`conditional(xi, psi)`", rows, differ, n)
    worst["conditional"] = max(max(r[3], r[4]) for r in rows if "adjacent" not in r[0])
    adjacent = max(max(r[3], r[4]) for r in rows if "adjacent" in r[0])
    for name, ref in (("geometric_inverse", R.ref_geometric_inverse),
                      ("dynamic_inverse", R.ref_dynamic_inverse)):
        inputs = [(p,) for p in ps]
        refs = [(ref(p),) for p in ps]
        rows, differ, n = measure(name, inputs, refs, [p_region(p) for p in ps], ("xi",))
        sections += table(f"`{name}(p)`", rows, differ, n)
        worst[name] = max(max(r[3], r[4]) for r in rows)

    summary = ["| function | worst error (ulps) |", "|---|---:|"]
    summary += [f"| `{k}` | {v:.2f} |" for k, v in worst.items()]
    summary += [f"| `conditional`, boundary-adjacent doubles | {adjacent:.2f} |"]
    summary += MEASURED_ELSEWHERE
    summary += ["", "The root-found inverses (`conditional_inverse`, `marginal_inverse`) are measured "
                "in relative error of xi against a bar of 1e-12 (or 4 ulps of the target times "
                "its condition number), and the far tails of narrow normals in relative error "
                "against their condition number: see the sections below."]
    doc = [
        "# Accuracy against mpmath: the closed forms, the root-found inverses, the far tails",
        "",
        "Regenerate with `python benchmarks/accuracy.py` (writes this file; about a minute).",
        "",
        "Every output of `coincli.core.models.geometric`, `dynamic`, `conditional`, "
        "`geometric_inverse` and `dynamic_inverse` is compared with the paper's textbook "
        "formulas (eqs. 9-12, Table I) evaluated in mpmath to 50 significant digits "
        "(`tests/reference.py`; working precision raised until two precisions agree, so the "
        "catastrophic cancellation of the textbook forms does not reach the reference). Each "
        "double input is converted exactly. The error is `|computed - reference| / ulp(reference)`"
        " (the ulp of a subnormal is 2**-1074); where the reference is exactly 0, 1 or inf the "
        "computed value is required to be exactly that, and is.",
        "",
        "The bar is 4 ulps on every output (issue 2), boundary-adjacent doubles included; "
        "`tests/test_accuracy.py` enforces it on a smaller grid of the same kind. Inputs: xi "
        "log-spaced and log-uniform random in [1e-300, 1e300], plus uniform on [0, 3] and "
        "log-uniform on [1e-3, 1e3] where real coins and stacks live, plus 0, inf and the fair "
        "coins; p log-spaced towards 0 and towards 1 in [1e-300, 1 - 2**-53], random, plus 0 and "
        "1; psi at 0, pi/2, pi, random, and at 1e-12, 1e-9, 1e-6 (relative and absolute) and "
        "1e-4 .. 0.49 theta0/2 from each regime boundary theta0/2, pi/2 -+ theta0/2, "
        "pi - theta0/2, plus the three doubles on either side of each boundary "
        "(\"boundary-adjacent\", closer than 1e-12).",
        "",
        "## Worst errors",
        "",
        *summary,
        "",
        "## How `conditional` stays accurate at the regime boundaries",
        "",
        "Near a boundary the chance of the rarer outcome goes like the square root of the "
        "distance `u` from psi to the boundary, so `u` must be known to full relative accuracy. "
        "`theta0/2` rounded to a double is off by up to half an ulp, which for `u` = 1e-12 "
        "`theta0/2` is a relative error of 1e-4 in `u`. Where `|u| < theta0/4`, `conditional` "
        "recomputes the offsets more precisely, in three tiers:",
        "",
        "1. **long double** (numpy path, where long double has a 64-bit significand, as on "
        "x86-64 Linux): for `2**-8 theta0/2 <= |u| < theta0/4` (almost every near input) the "
        "offsets are formed from long double's `arctan2` and pi to 160 bits; their relative "
        "error is below 2**-55. Where long double is a plain double (e.g. ARM macOS) this tier "
        "is skipped; `tests/test_accuracy.py` checks that path too "
        "(`numpy-without-long-double`).",
        "2. **double-double** (`_half_theta0_dd`: a double-double atan by one correction of "
        "libm's, sin and cos from a Taylor series; about 2**-104 relative; pi/2 and pi to 160 "
        "bits), once per distinct xi, for the closer offsets down to 2**-40 theta0/2. Past "
        "xi = 2**899 the angles are rescaled by 2**840 so that nothing underflows.",
        "3. **exact** (`_offsets_exact`: big-integer fixed point, atan by three half-angle steps "
        "and its series, pi by Machin's formula, 230 bits beyond the scale of theta0/2) below "
        "2**-40 theta0/2, where even the double-double's 2**-104 would show: in practice only "
        "the doubles adjacent to a boundary, which the grid places as close as 3e-19 theta0/2. "
        "Each costs some tens of microseconds in pure Python.",
        "",
        "Elsewhere the offsets of the plain path are accurate enough and nothing extra is "
        "computed. The bar therefore holds at every distance from every boundary, down to the "
        "adjacent doubles (worst in the summary above).",
        "",
        "## Scalar and numpy paths",
        "",
        "Both paths evaluate the same formulas. On this machine numpy's SIMD `arctan`, "
        "`arctan2`, `arcsin`, `tan`, `sin` and `cos` round differently from libm's by an ulp on "
        "a fraction of a percent of arguments, and the numpy path's long-double tier has no "
        "scalar twin, so the two paths can differ by an ulp or two (counts under each table; "
        "both are held to the bar). With numpy's elementary functions replaced by libm's and "
        "the long-double tier off, the numpy path reproduces the scalar path bit for bit "
        "(`test_paths_agree_bit_for_bit_given_the_same_libm`).",
        "",
        *issue17,
        "## Tables of the closed forms",
        "",
        f"Python {platform.python_version()}, numpy {np.__version__}, mpmath "
        f"{R.mpmath.__version__}, {platform.machine()}.",
        "",
        *sections,
    ]
    text = "\n".join(doc).rstrip() + "\n"
    if args.stdout:
        print(text)
    else:
        OUT.parent.mkdir(exist_ok=True)
        OUT.write_text(text)
        print(f"wrote {OUT.relative_to(ROOT)}")
        for k, v in worst.items():
            print(f"  {k:18s} worst {v:.2f} ulps")


if __name__ == "__main__":
    main()
