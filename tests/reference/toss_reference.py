r"""The first contact time of a toss in mpmath, written independently of ``coincli/toss.py``.

Eq. (3) as printed, ``cos alpha = cos^2 psi + sin^2 psi cos(omega t)``, ``sin alpha =
sqrt(1 - cos^2 alpha)`` at 40 significant digits (so the half-angle care of the module is not
needed: the digits lost near ``alpha = 0`` are far below a double's), ``L = a sin alpha (+
(h/2)|cos alpha|)``, ``F = z0 + u t - g t^2/2 - L``.

The first root is found by a certified scan in exact-enough arithmetic: ``F'' <= K = omega^2
sin psi (a + (h/2) sin psi) - g`` (``|N''| = omega^2 sin psi`` bounds the curvature of the
normal's horizontal projection), so on a cell ``[t1, t2]`` with ``F1, F2 > 0``,
``F >= min(F1, F2) - max(K, 0) (t2 - t1)^2 / 8``; a cell where that is positive holds no root,
any other is halved.  The leftmost cell where F changes sign is then bisected to 1e-30 of t.
Contact is only possible while ``z(t) <= a + h/2`` (``L`` never exceeds ``hypot(a, h/2)``), so
only those one or two windows of the flight are scanned.  Every double input is converted
exactly (``mpf(float)``).
"""

from __future__ import annotations

import math

from mpmath import mp, mpf

DPS = 40


def _setup(xi, psi, u, om, diameter, g, contact, z0):
    a = mpf(diameter) / 2
    hh = mpf(xi) * mpf(diameter) / 2 if contact == "thick" else mpf(0)
    z0 = (mp.sqrt(3) / 2 * a + hh) if z0 is None else mpf(z0)
    return a, hh, z0, mpf(psi), mpf(u), mpf(om), mpf(g)


def ref_f(t, xi, psi, u, om, *, diameter=0.02426, g=9.81, contact="rim", z0=None):
    """F(t) at mp precision (t an mpf or a float)."""
    with mp.workdps(DPS):
        a, hh, z0, psi, u, om, g = _setup(xi, psi, u, om, diameter, g, contact, z0)
        t = mpf(t)
        c = mp.cos(psi) ** 2 + mp.sin(psi) ** 2 * mp.cos(om * t)
        s = mp.sqrt(max(1 - c * c, mpf(0)))
        return z0 + u * t - g * t * t / 2 - (a * s + hh * abs(c))


def ref_first_root(xi, psi, u, om, *, diameter=0.02426, g=9.81, contact="rim", z0=None,
                   cells_per_turn=16, max_evals=400_000):
    """The smallest positive root of F (an mpf), by the certified scan of the module docstring.

    Raises RuntimeError if the scan would need more than ``max_evals`` evaluations.
    """
    with mp.workdps(DPS):
        a, hh, z0m, psim, um, omm, gm = _setup(xi, psi, u, om, diameter, g, contact, z0)
        sp = mp.sin(psim)
        k2 = max(omm ** 2 * sp * (a + hh * sp) - gm, mpf(0))
        t_end = (um + mp.sqrt(um * um + 2 * gm * z0m)) / gm

        def f(t):
            c = mp.cos(psim) ** 2 + sp ** 2 * mp.cos(omm * t)
            s = mp.sqrt(max(1 - c * c, mpf(0)))
            return z0m + um * t - gm * t * t / 2 - (a * s + hh * abs(c))

        top = mp.sqrt(a * a + hh * hh)
        # the windows where z(t) <= top
        disc = um * um - 2 * gm * (top - z0m)
        if disc <= 0:
            windows = [(mpf(0), t_end)]
        else:
            r = mp.sqrt(disc)
            t_up, t_down = (um - r) / gm, (um + r) / gm
            windows = []
            if t_up > 0:
                windows.append((mpf(0), t_up))
            if t_down < t_end:
                windows.append((max(t_down, mpf(0)), t_end))
        base = (2 * mp.pi / omm / cells_per_turn) if omm > 0 else t_end
        evals = 0
        for w0, w1 in windows:
            f0 = f(w0)
            if f0 <= 0:
                return w0
            # Cells of any width are certified by the same bound: start at 1/16 of a turn,
            # double after a free cell (a tilt that hardly changes lets them grow).
            t1, f1, d = w0, f0, min(base, w1 - w0)
            while t1 < w1:
                t2 = min(t1 + d, w1)
                f2 = f(t2)
                evals += 1
                root = _leftmost(f, t1, t2, f1, f2, k2, 0)
                if root is not None:
                    return root
                t1, f1, d = t2, f2, 2 * d
                if evals > max_evals:
                    raise RuntimeError("the reference scan took too many evaluations")
        return t_end


def _leftmost(f, t1, t2, f1, f2, k2, depth):
    """The first root in [t1, t2] (F(t1) > 0), or None when the cell is certified free."""
    d = t2 - t1
    if f1 > 0 and f2 > 0 and min(f1, f2) - k2 * d * d / 8 > 0:
        return None
    if f2 <= 0 and depth > 200:  # bisected to far below a double's resolution
        return t2
    if d <= abs(t2) * mpf(10) ** (-30):
        return t2 if f2 <= 0 else None  # a tangency below 1e-30 of t
    tm = t1 + d / 2
    fm = f(tm)
    left = _leftmost(f, t1, tm, f1, fm, k2, depth + 1)
    if left is not None:
        return left
    return _leftmost(f, tm, t2, fm, f2, k2, depth + 1)


def band(t, xi, psi, u, om, *, diameter=0.02426, g=9.81, contact="rim", z0=None):
    """The rounding band of a double evaluation of F at t, as coincli.core.toss.flight documents it: 16
    eps of the height scale and of the contact depth, and of the phase omega t."""
    eps = 2.0 ** -52
    a = diameter / 2
    hh = xi * diameter / 2 if contact == "thick" else 0.0
    zz = (math.sqrt(3) / 2 * a + hh) if z0 is None else z0
    lmax = math.hypot(a, hh)
    return 16 * eps * (zz + u * u / (2 * g) + 2 * lmax) + 16 * eps * lmax * om * float(t)


def allowed_error(t_ref, xi, psi, u, om, *, diameter=0.02426, g=9.81, contact="rim", z0=None):
    """How far a double-precision t_f may be from the exact root: 4 ulps of t, plus the time F
    takes to cross the rounding band of its evaluation (16 eps of the height scale and of the
    contact depth, and the phase omega t to 16 eps), as the module documents."""
    t = float(t_ref)
    width = band(t, xi, psi, u, om, diameter=diameter, g=g, contact=contact, z0=z0)
    with mp.workdps(DPS):
        h = mpf(t) * mpf(10) ** -20 + mpf(10) ** -40
        slope = abs(float((ref_f(mpf(t) + h, xi, psi, u, om, diameter=diameter, g=g,
                                 contact=contact, z0=z0)
                           - ref_f(mpf(t) - h, xi, psi, u, om, diameter=diameter, g=g,
                                   contact=contact, z0=z0)) / (2 * h)))
    return 4 * math.ulp(t) + (width / slope if slope > 0 else math.inf)
