r"""mpmath references for the root-found inverses, ``conditional_inverse`` and ``marginal_inverse``.

- Table I at a fixed psi: ``reference.ref_conditional_inverse``, root finding on the textbook
  forms of Table I (eqs. 9-10) in mpmath at 70+ digits, independent of the code under test
  (which starts from a closed-form inverse and finishes with a different root finder).
- psi averaged over a density: ``marginal_reference.ref_marginal`` (tanh-sinh quadrature at 40
  digits) evaluated at the computed xi gives the residual of the equation the code solves
  (``P(sides) - p``, or ``(1 - p) - P(heads) - P(tails)`` for p > 1/2); one Newton step with
  the slope taken from the double-precision ``marginal`` (a relative error of 1e-6 in the slope
  changes the step by 1e-6 of itself, far below a double's rounding) gives the exact root.

Each case stores ``kappa``, the condition number of xi with respect to the target the code
solves for (p for p <= 1/2, 1 - p above): the relative change of xi per relative change of the
target.  The bar (issue 17) is ``max(1e-12, 4 ulp(target)/target * kappa)`` relative in xi, or
an ulp of xi where xi is subnormal.

Run ``python tests/inverse_reference.py --write`` to regenerate
``tests/data/inverse_reference.json`` (about half an hour: the extreme cases need hundreds of
digits or hundreds of quadrature subintervals); the tests read that file and recompute a few
cases live.
"""

from __future__ import annotations

import json
import math
import sys
import time
from pathlib import Path

import mpmath
from mpmath import mp, mpf

sys.path.insert(0, str(Path(__file__).resolve().parent))

import marginal_reference as MR  # noqa: E402
import reference as R  # noqa: E402

DATA = Path(__file__).resolve().parent / "data" / "inverse_reference.json"

#: the targets of the grid: the issue's (1 - 2^-53, 1 - 1e-15, 1 - 1e-9, 1e-300, 2^-1074) and a
#: spread between
P_GRID = (2.0**-1074, 1e-300, 1e-100, 1e-60, 1e-20, 1e-8, 1e-3, 0.1, 1 / 3, 0.5,
          math.nextafter(0.5, 1.0), 0.7, 0.9, 1 - 1e-6, 1 - 1e-9, 1 - 1e-12, 1 - 1e-15,
          1 - 2.6e-15, 1 - 2.0**-52, 1 - 2.0**-53)
#: fixed angles (radians): near 0 and pi, on either side of pi/4 (where the all-three region
#: begins), the doubles nearest pi/4 and pi/2, the fair coin's boundaries, and the issue's 80 deg
PSI_GRID = (1e-300, 1e-12, 1e-4, 0.3, math.pi / 6, math.nextafter(math.pi / 4, 0.0), math.pi / 4,
            math.nextafter(math.pi / 4, 4.0), 0.8, 1.0, 1.2, math.pi / 3, math.radians(80),
            1.5, math.pi / 2 - 1e-9, math.pi / 2, 2.0, math.pi - 1e-4, math.pi)
#: densities (label -> spec), the paper's and the stress cases: narrow normals whose regime
#: boundaries cross their far tails, means at 0 and outside [0, 180], a table
DENSITIES = {
    "uniform": "uniform",
    "cosine": "cosine",
    "normal": "normal",
    "normal:90:18.12": ("normal", math.pi / 2, math.sqrt(0.1)),
    "normal:30:0.05": ("normal", math.radians(30), math.radians(0.05)),
    "normal:40:0.01": ("normal", math.radians(40), math.radians(0.01)),
    "normal:60:0.1": ("normal", math.radians(60), math.radians(0.1)),
    "normal:0:6": ("normal", 0.0, math.radians(6)),
    "normal:-20:10": ("normal", math.radians(-20), math.radians(10)),
    "table": ("table", [0.0, 0.3, 0.9, 1.6, 2.2, math.pi], [0.0, 1.0, 0.5, 2.0, 0.25, 0.0]),
}
MARGINAL_P = (2.0**-1074, 1e-300, 1e-60, 1e-20, 1e-8, 0.01, 1 / 3, 0.5, 0.9, 1 - 1e-6,
              1 - 1e-9, 1 - 1e-12, 1 - 1e-15, 1 - 2.0**-53)


def density(label):
    from coincli.core.densities import Cosine, Normal, Table, Uniform

    spec = DENSITIES[label]
    if spec == "uniform":
        return Uniform()
    if spec == "cosine":
        return Cosine()
    if spec == "normal":
        return Normal()
    if spec[0] == "normal":
        return Normal(spec[1], spec[2])
    return Table(spec[1], spec[2], "stress")


def target(p):
    """The target the code solves for: p, or 1 - p (exact) above 1/2."""
    return p if p <= 0.5 else 1 - p


def bar(xi_ref, p, kappa):
    """The allowed |xi - xi_ref| (issue 17): 1e-12 relative, or 4 ulps of the target times the
    condition number, whichever is larger; at least an ulp of xi."""
    r = target(p)
    with mp.workdps(60):
        rel = max(mpf("1e-12"), 4 * R.ulp(r) / mpf(r) * mpf(kappa))
        return max(rel * mpf(xi_ref), R.ulp(xi_ref))


# --------------------------------------------------------------------------- marginal


_SLOPE_AT_0: dict = {}  #: P(sides)/xi of each density as xi -> 0, once per density


def ref_marginal_inverse(p, d, xi_computed, dps=MR.DPS):
    """(xi_ref, kappa): Newton's method in log xi from ``xi_computed`` on the mpmath residual
    of ``log F = log r`` (F = P(sides), or P(heads) + P(tails) for p > 1/2; r the target), with
    the slope from doubles; for a subnormal target, whose doubles cannot show a slope, from
    mpmath.  For a thin coin (xi below 1e-150) P(sides) = C xi to 1e-100 relative, C measured
    at 1e-100 and 1e-110 (which must agree): xi = p/C, kappa = 1."""
    from coincli.core.averages import marginal

    r = target(p)

    def log_f(vals):
        h, s, t = vals
        return mpmath.log(s if p <= 0.5 else h + t)

    with mp.workdps(dps + 20):
        lr = mpmath.log(mpf(r))
        if p <= 0.5 and xi_computed < 1e-150:
            key = (d.spec, dps)
            if key not in _SLOPE_AT_0:
                c = [MR.ref_marginal(mpf(x), d, dps=dps)[0][1] / mpf(x) for x in (1e-100, 1e-110)]
                if abs(c[0] - c[1]) > mpf(10) ** -30 * c[0]:
                    raise ArithmeticError(f"P(sides) is not linear in xi for {d.spec}")
                _SLOPE_AT_0[key] = c[1]
            return mpf(p) / _SLOPE_AT_0[key], mpf(1)
        if r >= 2.2250738585072014e-308:
            hstep = 1e-6
            lo, hi = marginal(xi_computed * math.exp(-hstep), d), marginal(
                xi_computed * math.exp(hstep), d)
            slope = (math.log(hi.sides if p <= 0.5 else hi.heads + hi.tails)
                     - math.log(lo.sides if p <= 0.5 else lo.heads + lo.tails)) / (2 * hstep)
        xi_ref = mpf(xi_computed)
        for _ in range(12):  # until the step is far below a double's rounding
            vals, _ = MR.ref_marginal(xi_ref, d, dps=dps)
            if r < 2.2250738585072014e-308:
                hstep = mpf(10) ** -10
                up, down = (MR.ref_marginal(xi_ref * mpmath.exp(k * hstep), d, dps=dps)[0]
                            for k in (1, -1))
                slope = (log_f(up) - log_f(down)) / (2 * hstep)
            step = (log_f(vals) - lr) / slope
            xi_ref = xi_ref * mpmath.exp(-step)
            if abs(step) < mpf(10) ** -20:
                break
        else:
            raise ArithmeticError(f"reference Newton did not settle: {d.spec}, p = {p!r}")
        kappa = abs(1 / mpf(slope))  # d ln xi / d ln r
    return xi_ref, kappa


# --------------------------------------------------------------------------- the stored cases


#: the costly corners (the textbook forms need 600+ digits there) at a few angles only
HEAVY_P, HEAVY_PSI = (2.0**-1074, 1e-300, 1e-100), (1e-4, 0.3, 1.0, math.pi / 2)


def conditional_cases():
    out = []
    for psi in PSI_GRID:
        for p in P_GRID:
            heavy = p in HEAVY_P or psi < 1e-100
            if not heavy or (psi in HEAVY_PSI and p in HEAVY_P) or (
                    psi < 1e-100 and p in (1e-8, 0.5, 1 - 1e-15)):
                out.append((p, psi))
    return [(p, psi) for p, psi in out if math.sin(psi) != 0]


#: the narrow normals' references cost minutes each: fewer targets, still the issue's
NARROW = ("normal:30:0.05", "normal:40:0.01", "normal:60:0.1")
NARROW_P = (2.0**-1074, 1e-300, 1e-60, 1e-8, 0.5, 1 - 1e-9, 1 - 1e-15, 1 - 2.0**-53)


def marginal_cases():
    return [(label, p) for label in DENSITIES
            for p in (NARROW_P if label in NARROW else MARGINAL_P)]


def write(path=DATA, which=("conditional", "marginal")):
    from coincli.core.averages import conditional_inverse, marginal_inverse

    data = json.loads(path.read_text()) if path.exists() else {}
    if "conditional" in which:
        rows = []
        for p, psi in conditional_cases():
            t0 = time.time()
            ref = R.ref_conditional_inverse(p, psi)
            kappa = R.inverse_condition(ref, p, psi) if 0 < ref < mpmath.inf else mpf(0)
            rows.append({"p": p.hex(), "psi": psi.hex(), "xi": mpmath.nstr(ref, 40),
                         "kappa": mpmath.nstr(kappa, 6)})
            try:
                got = repr(conditional_inverse(p, psi))
            except ValueError as exc:
                got = str(exc)
            print(f"conditional p={p:<10.4g} psi={psi:<10.4g} {time.time() - t0:6.1f}s "
                  f"xi={mpmath.nstr(ref, 17)} got={got}", file=sys.stderr, flush=True)
        data["conditional"] = rows
    if "marginal" in which:
        done = {(r["density"], r["p"]): r for r in data.get("marginal", [])}  # resumes
        rows = []
        for label, p in marginal_cases():
            if (label, p.hex()) in done:
                rows.append(done[(label, p.hex())])
                continue
            t0 = time.time()
            d = density(label)
            got = marginal_inverse(p, d)
            ref, kappa = ref_marginal_inverse(p, d, got, dps=25 if label in NARROW else MR.DPS)
            rows.append({"density": label, "p": p.hex(), "xi": mpmath.nstr(ref, 30),
                         "computed_at_write": got.hex(), "kappa": mpmath.nstr(kappa, 6)})
            print(f"marginal {label:16s} p={p:<10.4g} {time.time() - t0:6.1f}s "
                  f"xi={mpmath.nstr(ref, 17)} got={got!r}", file=sys.stderr, flush=True)
            data["marginal"] = rows
            path.write_text(json.dumps(data, indent=1) + "\n")  # as it goes: it takes long
    path.parent.mkdir(exist_ok=True)
    path.write_text(json.dumps(data, indent=1) + "\n")


def load(path=DATA):
    """{"conditional": [(p, psi, xi_ref, kappa)], "marginal": [(label, p, xi_ref, kappa)]}."""
    data = json.loads(path.read_text())
    with mp.workdps(50):
        cond = [(float.fromhex(r["p"]), float.fromhex(r["psi"]), mpf(r["xi"]), mpf(r["kappa"]))
                for r in data.get("conditional", [])]
        marg = [(r["density"], float.fromhex(r["p"]), mpf(r["xi"]), mpf(r["kappa"]))
                for r in data.get("marginal", [])]
    return {"conditional": cond, "marginal": marg}


if __name__ == "__main__":
    if "--write" in sys.argv:
        which = [w for w in ("conditional", "marginal") if w in sys.argv] or None
        write(which=which or ("conditional", "marginal"))
    else:
        print(__doc__)
