r"""An mpmath reference for the psi-averaged chances (eq. 15), to 40 digits.

Independent of :mod:`coincli.core.averages` in everything but the mathematics:

- the integral is mpmath's tanh-sinh quadrature (not Gauss-Legendre), in the offsets from each
  piece's left end (not the ``s^2`` variable), at ``DPS + 15`` working digits;
- the integrand is Table I through exact identities (``sin^2 psi - sin^2 t = sin(psi - t)
  sin(psi + t)``, ``cos(psi - t) = sin(2t - (psi - pi/2 + t))``), which ``check_identities``
  compares with the textbook ``acos`` forms of eqs. (9)-(10) at high precision;
- each density is written again in mpmath (the normal's normalizer from ``ncdf``; a table's
  interpolant renormalized exactly).

Run ``python tests/marginal_reference.py --write`` to regenerate
``tests/data/marginal_reference.json`` (a few minutes: the extreme aspect ratios need hundreds
of subintervals); the tests read that file and recompute a few cases live.
"""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path

import mpmath
from mpmath import mp, mpf

DPS = 40  #: digits the reference values are good to
DATA = Path(__file__).resolve().parent / "data" / "marginal_reference.json"

# --------------------------------------------------------------------------- densities in mpmath


def mp_density(spec):
    """(folded pdf on [0, pi/2] as an mpmath function, breakpoints in psi) for a density.

    ``spec`` is a :class:`coincli.core.densities.Density`; only its parameters are read.
    """
    from coincli.core.densities import Cosine, Normal, Table, Uniform

    pi = mp.pi
    if isinstance(spec, Uniform):
        return (lambda psi: 2 / pi), []
    if isinstance(spec, Cosine):
        return (lambda psi: 2 * (1 - mp.cos(2 * psi)) / pi), []
    if isinstance(spec, Normal):
        mu, sd = mpf(spec.mean), mpf(spec.sd)
        a, b = -mu / sd, (pi - mu) / sd
        if a > 0:
            z = mp.ncdf(-a) - mp.ncdf(-b)
        else:
            z = mp.ncdf(b) - mp.ncdf(a)
        k = 1 / (sd * mp.sqrt(2 * pi) * z)

        def fold(psi):
            return k * (mp.exp(-((psi - mu) / sd) ** 2 / 2)
                        + mp.exp(-((pi - psi - mu) / sd) ** 2 / 2))

        pts = []
        for m in (0, 0.5, 1, 2, 3, 4, 6, 8, 12, 16, 24, 40):
            for c in (mu, pi - mu):
                pts += [c - m * sd, c + m * sd]
        for end, d in ((mpf(0), -mu), (pi, mu - pi)):
            if d > sd:
                scale = sd * sd / d
                pts += [end + m * scale for m in (1, 4, 16, 64)]
                pts += [pi - end - m * scale for m in (1, 4, 16, 64)]
        return fold, pts
    if isinstance(spec, Table):
        xs = [mpf(float(v)) for v in spec.psi]
        ws = [mpf(float(v)) for v in spec.w]
        area = sum((xs[i + 1] - xs[i]) * (ws[i + 1] + ws[i]) / 2 for i in range(len(xs) - 1))

        def pdf(x):
            if x < xs[0] or x > xs[-1]:
                return mpf(0)
            lo, hi = 0, len(xs) - 1
            while hi - lo > 1:
                mid = (lo + hi) // 2
                if xs[mid] <= x:
                    lo = mid
                else:
                    hi = mid
            f = (x - xs[lo]) / (xs[hi] - xs[lo])
            return (ws[lo] + f * (ws[hi] - ws[lo])) / area

        return (lambda psi: pdf(psi) + pdf(pi - psi)), xs + [pi - x for x in xs]
    raise TypeError(f"no mpmath version of {spec!r}")


# --------------------------------------------------------------------------- Table I in mpmath


def _geometry(xi):
    t = mp.atan2(1, xi) / 2
    beta = mp.atan(xi)
    c = xi / mp.sqrt(1 + xi * xi)
    return t, beta, mp.sin(t), mp.cos(t), c


def cond_b(u1, t, s0):
    """(heads, sides) at psi = t + u1 in [t, pi/2 - t]."""
    q1 = mp.sqrt(mp.sin(u1) * mp.sin(2 * t + u1))
    return 2 * mp.atan2(s0, q1) / mp.pi, 2 * mp.atan2(q1, s0) / mp.pi


def cond_c(u2, t, beta, s0, c0, c):
    """(heads, sides, tails) at psi = pi/2 - t + u2 in [pi/2 - t, pi/2]."""
    d1 = mp.sin(beta + u2) * mp.cos(u2)
    d2 = mp.sin(u2) * mp.sin(2 * t - u2)
    q1, q2 = mp.sqrt(d1), mp.sqrt(d2)
    heads = 2 * mp.atan2(s0, q1) / mp.pi
    tails = 2 * mp.atan2(q2, c0) / mp.pi
    sides = 2 * mp.atan2((d1 + s0 * s0) * c, (q1 * q2 + c0 * s0) * (c0 * q1 + s0 * q2)) / mp.pi
    return heads, sides, tails


def textbook(xi, psi):
    """Table I with the acos forms of eqs. (9)-(10), for ``check_identities``."""
    t = mp.acos(xi / mp.sqrt(1 + xi * xi)) / 2
    c = xi / mp.sqrt(1 + xi * xi)
    a, b = mp.cos(psi) ** 2, mp.sin(psi) ** 2
    if psi < t:
        return mpf(1), mpf(0), mpf(0)
    th1 = mp.acos((c - a) / b)
    if psi < mp.pi / 2 - t:
        return th1 / mp.pi, 1 - th1 / mp.pi, mpf(0)
    th2 = mp.acos((-c - a) / b)
    return th1 / mp.pi, (th2 - th1) / mp.pi, 1 - th2 / mp.pi


def check_identities(points, dps=80):
    """Largest difference between the forms used here and the textbook ones, over (xi, psi)."""
    worst = mpf(0)
    with mp.workdps(dps):
        for xi, psi in points:
            xi, psi = mpf(xi), mpf(psi)
            t, beta, s0, c0, c = _geometry(xi)
            ref = textbook(xi, psi)
            if psi < t:
                got = (mpf(1), mpf(0), mpf(0))
            elif psi < mp.pi / 2 - t:
                got = (*cond_b(psi - t, t, s0), mpf(0))
            else:
                got = cond_c(psi - (mp.pi / 2 - t), t, beta, s0, c0, c)
            worst = max(worst, *(abs(g - r) for g, r in zip(got, ref, strict=True)))
    return worst


# --------------------------------------------------------------------------- the integral


def _points(lo, hi, extra):
    pts = sorted({lo, hi, *(p for p in extra if lo < p < hi)})
    return pts


def _graded(lo, hi, start, ratio=16):
    """lo + start * ratio**k inside (lo, hi)."""
    out, d = [], start
    while lo + d < hi:
        out.append(lo + d)
        d *= ratio
    return out


def ref_marginal(xi: float, density, dps: int = DPS):
    """(heads, sides, tails) as mpf, good to ``dps`` digits, with the estimated error."""
    if xi == math.inf:
        return (mpf(0), mpf(1), mpf(0)), mpf(0)
    with mp.workdps(dps + 15):
        x = mpf(xi)
        t, beta, s0, c0, c = _geometry(x)
        half = mp.pi / 2
        fold, breaks = mp_density(density)
        fb = [min(p, mp.pi - p) for p in breaks if 0 < p < mp.pi]
        tol = mpf(10) ** (-dps - 5)
        # a narrow normal's far tail cut by a regime boundary (a chance of 1e-60 or 1e-300):
        # offsets sd 2^k from each boundary, k = -20 .. 3, resolve any decay length in that range
        from coincli.core.densities import Normal

        edge = ([mpf(density.sd) * mpf(2) ** k for k in range(-20, 4)]
                if isinstance(density, Normal) and density.sd < 0.5 else [])

        def quad(f, pts):
            # mpmath's quad stops on an absolute error under eps: each subinterval is mapped to
            # [0, 1] and its integrand scaled to about 1 first, so tiny pieces converge too
            val = err = mpf(0)
            for a, b in zip(pts[:-1], pts[1:], strict=True):
                if b <= a:
                    continue
                h = b - a
                scale = max(abs(f(a + h * v)) for v in (mpf(1) / 8, mpf(3) / 8, mpf(5) / 8,
                                                        mpf(7) / 8)) or mpf(1)
                v, e = mp.quad(lambda y, a=a, h=h, scale=scale: f(a + h * y) / scale, [0, 1],
                               error=True, maxdegree=10)
                val += v * h * scale
                err += e * h * scale
            return val, err

        total = [mpf(0), mpf(0), mpf(0)]
        err = mpf(0)
        # A: [0, t]
        v, e = quad(fold, _points(mpf(0), t, fb + [t - d for d in edge]))
        total[0] += v
        err += e
        mass = v
        # B: u1 in [0, beta]
        if beta > 0:
            pts = _points(mpf(0), beta, [p - t for p in fb] + _graded(0, beta, 2 * t)
                          + edge + [beta - d for d in edge])
            cache = {}

            def fb_(u1, k):
                if u1 not in cache:
                    cache[u1] = (fold(t + u1), cond_b(u1, t, s0))
                f, hs = cache[u1]
                return f * hs[k] if k < 2 else f

            for k in range(3):
                v, e = quad(lambda u, k=k: fb_(u, k), pts)
                if k < 2:
                    total[k] += v
                else:
                    mass += v
                err += e
        # C: u2 in [0, t]
        pts = _points(mpf(0), t, [p - (half - t) for p in fb] + (
            _graded(0, t, beta) if beta > 0 else []) + edge)
        cache = {}

        def fc_(u2, k):
            if u2 not in cache:
                cache[u2] = (fold(half - t + u2), cond_c(u2, t, beta, s0, c0, c))
            f, hst = cache[u2]
            return f * hst[k] if k < 3 else f

        for k in range(4):
            v, e = quad(lambda u, k=k: fc_(u, k), pts)
            if k < 3:
                total[k] += v
            else:
                mass += v
            err += e
        # the density is normalized on [0, pi]; its folded mass on [0, pi/2] is 1 to the
        # working precision (a check, not a correction)
        if abs(mass - 1) > mpf(10) ** (-dps):
            raise ArithmeticError(f"reference mass {mass} for {density.spec} at xi = {xi}")
        del tol
        return tuple(+v for v in total), err


# --------------------------------------------------------------------------- the stored cases


def cases():
    """(label, xi, density) of the stored reference values."""
    from coincli.core.densities import Cosine, Normal, Table, Uniform

    xis = [0.0, 1e-300, 1e-100, 1e-20, 1e-8, 1e-3, 0.1, 1 / (2 * math.sqrt(2)),
           1 / math.sqrt(3), 1.0, 3.0, 10.0, 1e3, 1e8, 1e20, 1e100, 1e300]
    paper = {"uniform": Uniform(), "cosine": Cosine(), "normal": Normal(),
             "normal:90:18.12": Normal(math.pi / 2, math.sqrt(0.1))}
    out = [(k, x, d) for k, d in paper.items() for x in xis]
    xf = 1 / math.sqrt(3)  # boundaries at pi/6 and pi/3
    tab = Table([0.0, 0.3, 0.9, 1.6, 2.2, math.pi], [0.0, 1.0, 0.5, 2.0, 0.25, 0.0], "stress")
    stress = {
        "normal sd 1e-6 at 60 deg": Normal(math.pi / 3, 1e-6),
        "normal sd 1e-6 at 30 deg (boundary)": Normal(math.pi / 6, 1e-6),
        "normal sd 1e-4 at 60 deg (boundary)": Normal(math.pi / 3, 1e-4),
        "normal sd 1e-6 at 90 deg": Normal(math.pi / 2, 1e-6),
        "normal mean 0 sd 0.1": Normal(0.0, 0.1),
        "normal mean pi sd 0.3": Normal(math.pi, 0.3),
        "normal mean 0 sd 1e-6": Normal(0.0, 1e-6),
        "normal sd 1e3": Normal(1.0, 1e3),
        "normal mean -0.5 sd 0.2": Normal(-0.5, 0.2),
        "table": tab,
    }
    for k, d in stress.items():
        for x in (1e-8, 0.1, xf, 3.0, 1e8):
            out.append((k, x, d))
    return out


def write(path=DATA):
    import time

    rows = []
    for label, xi, d in cases():
        t0 = time.time()
        vals, err = ref_marginal(xi, d)
        rows.append({"density": label, "spec": _spec(d), "xi": xi.hex(),
                     "heads": mpmath.nstr(vals[0], DPS), "sides": mpmath.nstr(vals[1], DPS),
                     "tails": mpmath.nstr(vals[2], DPS), "quad_error": mpmath.nstr(err, 3)})
        print(f"{label:40s} xi={xi:<10.3g} {time.time() - t0:6.1f}s err={mpmath.nstr(err, 3)}",
              file=sys.stderr)
    path.parent.mkdir(exist_ok=True)
    path.write_text(json.dumps({"dps": DPS, "cases": rows}, indent=1) + "\n")


def _spec(d):
    from coincli.core.densities import Normal, Table

    if isinstance(d, Normal):
        return {"kind": "normal", "mean": d.mean.hex(), "sd": d.sd.hex()}
    if isinstance(d, Table):
        return {"kind": "table", "psi": [float(v).hex() for v in d.psi],
                "w": [float(v).hex() for v in d.w]}
    return {"kind": d.name}


def density_from_spec(spec):
    from coincli.core.densities import Cosine, Normal, Table, Uniform

    kind = spec["kind"]
    if kind == "normal":
        return Normal(float.fromhex(spec["mean"]), float.fromhex(spec["sd"]))
    if kind == "table":
        return Table([float.fromhex(v) for v in spec["psi"]],
                     [float.fromhex(v) for v in spec["w"]])
    return {"uniform": Uniform, "cosine": Cosine}[kind]()


def load(path=DATA):
    """[(label, xi, density, (heads, sides, tails) as mpf)] from the stored file."""
    data = json.loads(path.read_text())
    out = []
    with mp.workdps(DPS + 10):  # mpf keeps the precision it is made with
        for r in data["cases"]:
            out.append((r["density"], float.fromhex(r["xi"]), density_from_spec(r["spec"]),
                        tuple(mpf(r[k]) for k in ("heads", "sides", "tails"))))
    return out


if __name__ == "__main__":
    if "--write" in sys.argv:
        write()
    else:
        print(__doc__)
