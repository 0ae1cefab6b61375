"""Accuracy of the free rigid body (``coin book``) against mpmath, in units of eps.

Run from the repository root (about a minute):

    python benchmarks/accuracy_rigid.py            # rewrites its section of docs/book.md
    python benchmarks/accuracy_rigid.py --no-write # print only

Each function of :mod:`coincli.core.rigid` on a grid that reaches the extremes (the parameter's
complement ``m1 = 1 - m`` from 1 down to 1e-300, arguments over whole periods), against mpmath
at enough digits to hold ``1 - m1`` exactly; and the motion against the frozen 20-digit
Taylor-series integration of ``tests/data/rigid_reference.json``.  Errors are relative, in
units of eps = 2.2e-16, per region; "max" and "mean" over the grid.
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import mpmath as mp
import numpy as np

ROOT = Path(__file__).resolve().parents[1]
DOC = ROOT / "docs" / "book.md"
EPS = 2.220446049250313e-16
sys.path.insert(0, str(ROOT / "tests" / "reference"))


def _dps(m1):
    return 40 + int(max(0.0, -math.log10(m1)))


def _stats(errs):
    e = np.asarray(errs) / EPS
    return f"{e.max():.1f}", f"{e.mean():.1f}"


def k_and_f(m1s):
    from coincli.core._numerics import elliptic

    ek, ef = [], []
    for m1 in m1s:
        mp.mp.dps = _dps(m1)
        m = 1 - mp.mpf(m1)
        K = elliptic.ellip_k(float(m), m1)
        ek.append(abs(K / float(mp.ellipk(m)) - 1))
        for phi in np.linspace(1e-3, math.pi / 2, 24):
            s, c = math.sin(phi), math.cos(phi)
            ref = mp.ellipf(mp.atan2(mp.mpf(s), mp.mpf(c)), m)
            ef.append(abs(elliptic.ellip_f(s, c, m1) / float(ref) - 1))
    return ek, ef


def jacobi(m1s, points=64):
    """Relative error of sn, cn, dn with u in [0, 4K) (the argument itself exact), split into
    values above and below 1e-3 (near a zero of sn or cn, or dn next to the separatrix)."""
    from coincli.core._numerics import elliptic

    big, small = [], []
    for m1 in m1s:
        mp.mp.dps = _dps(m1)
        m = 1 - mp.mpf(m1)
        K = float(mp.ellipk(m))
        us = np.linspace(0, 4 * K, points, endpoint=False)[1:]
        s, c, d, _, _ = elliptic.ellip_j(us, np.float64(float(m)), np.float64(m1))
        for u, vals in zip(us, zip(s, c, d, strict=True), strict=True):
            for name, got in zip(("sn", "cn", "dn"), vals, strict=True):
                ref = float(mp.ellipfun(name, mp.mpf(float(u)), m=m))
                # the part of the error that the rounding of K explains is not the functions'
                # own: reducing u by q quarter periods puts it off by up to ~q eps K
                q = math.floor(u / K)
                slope = abs(float(mp.diff(lambda x: mp.ellipfun(name, x, m=m), mp.mpf(u))))
                err = max(0.0, abs(got - ref) - 2 * EPS * q * K * slope) / abs(ref)
                (big if abs(ref) >= 1e-3 else small).append(err)
    return big, small


def motion_vs_odefun():
    import rigid_reference

    from coincli.core import rigid as R

    out = []
    for case in rigid_reference.load()["cases"]:
        I, w = tuple(case["moments"]), np.array(case["omega"])
        rows = np.array(case["rows"])
        o = R.orbit(I, w)
        werr = np.abs(R.omega_at(o, rows[:, 0]) - rows[:, 1:4]).max() / np.linalg.norm(w)
        q = rows[:, 4:] / np.linalg.norm(rows[:, 4:], axis=1, keepdims=True)
        qa = R.attitude_at(o, rows[:, 0])
        qerr = np.minimum(np.abs(qa - q).max(1), np.abs(qa + q).max(1)).max()
        mo = R.motion(I, w)
        out.append((I, tuple(w), mo.m1, float(rows[-1, 0]), werr, qerr))
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--no-write", action="store_true")
    args = ap.parse_args(argv)
    m1s = [1.0, 0.5, 0.1, 1e-2, 1e-4, 1e-6, 1e-9, 1e-12, 1e-16, 1e-24, 1e-40, 1e-100, 1e-300]
    ek, ef = k_and_f(m1s)
    big, small = jacobi([0.5, 1e-2, 1e-6, 1e-12, 1e-40, 1e-300])
    lines = [
        "| function | region | max (eps) | mean (eps) |", "|---|---|---|---|",
        f"| `ellip_k` (K by the AGM) | m1 = 1 ... 1e-300 | {_stats(ek)[0]} | {_stats(ek)[1]} |",
        f"| `ellip_f` (F by Carlson's R_F) | phi in (0, pi/2], m1 = 1 ... 1e-300 | "
        f"{_stats(ef)[0]} | {_stats(ef)[1]} |",
        f"| `ellip_j` sn, cn, dn | values >= 1e-3, u in [0, 4K), m1 = 0.5 ... 1e-300 | "
        f"{_stats(big)[0]} | {_stats(big)[1]} |",
        f"| `ellip_j` sn, cn, dn | values < 1e-3 (near a zero; dn next to the separatrix) | "
        f"{_stats(small)[0]} | {_stats(small)[1]} |",
    ]
    lines += ["", "The motion next to the separatrix against the 20-digit Taylor-series "
              "integration (`tests/data/rigid_reference.json`):", "",
              "| moments | omega at launch | m1 | t up to (s) | omega error / abs(omega) | "
              "quaternion error |", "|---|---|---|---|---|---|"]
    for I, w, m1, T, werr, qerr in motion_vs_odefun():
        lines.append(f"| {', '.join(f'{v:g}' for v in I)} | {', '.join(f'{v:g}' for v in w)} "
                     f"| {m1:.2g} | {T:g} | {werr:.1e} | {qerr:.1e} |")
    text = "\n".join(lines) + "\n"
    print(text)
    if not args.no_write:
        start, end = "<!-- accuracy_rigid -->", "<!-- /accuracy_rigid -->"
        doc = DOC.read_text()
        before, rest = doc.split(start, 1)
        _, after = rest.split(end, 1)
        DOC.write_text(before + start + "\n" + text + end + after)
        print(f"wrote the accuracy section of {DOC.relative_to(ROOT)}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
