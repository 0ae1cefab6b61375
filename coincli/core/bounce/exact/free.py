"""The exact free flight of the coin and its first contact with the plane z = 0.

Between contacts the coin is a torque-free symmetric top under gravity (as
:class:`coincli.core.bounce.engine._Flight`, here in terms of the axis ``n`` alone, which is all
the contact needs): the angular momentum ``L = I w`` is fixed, the axis precesses about it at
``Omega = |L| / I1`` (Rodrigues' rotation of ``n0`` about ``L/|L|`` by ``Omega s``) and the
angular velocity is ``w = L / I1 + (L.n)(1/I3 - 1/I1) n``; the centre follows a parabola.  The
height of the lowest point, ``F(s) = z(s) - a sqrt(1 - n_z^2) - hh |n_z|``, has ``n_z = A + B
cos(Omega s) + C sin(Omega s)``.

The first contact is found as :func:`coincli.core.bounce.engine._first_touch` finds it:
``F'' <= Kc = max(Omega^2 sin(beta) (a + hh) - g, 0)`` (``beta`` the angle between ``L`` and
``n``), so on a cell of width ``w`` ``F >= min(F(t1), F(t2)) - Kc w^2 / 8``; cells where this
is positive hold no contact, however thin a dip.  Doubtful cells are cut 32-fold down to the
width ``scan``; the first such cell whose right end is below the plane holds the first root,
located by Brent's method to ``t_tol``.  A doubtful cell of width ``scan`` whose both ends are
above the plane is a graze at most ``Kc scan^2 / 8`` deep (1e-10 m at ``scan = 1e-6 s`` and 240
rad/s): it is passed over, the one approximation of the search, refined with ``scan``.

A flight that starts at a contact (``F(0) = 0``) starts the search at ``s = scan`` when ``F >
0`` there (a dip below the plane and back within ``scan`` is not looked for); otherwise the
flight is shorter than ``scan`` and its end is bracketed by halving ``s`` to a point above the
plane.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .body import Cylinder

G = 9.80665
ZOOM = 32


@dataclass(frozen=True)
class Flight:
    """A free flight from ``t0``: centre ``x0``, velocity ``v0``, axis ``n0``, the unit
    angular momentum ``lhat``, the precession rate ``omega`` and ``lam = (L.n)(1/I3 - 1/I1)``."""

    t0: float
    x0: tuple
    v0: tuple
    n0: tuple
    lhat: tuple
    omega: float
    lam: float
    g: float = G

    @classmethod
    def from_state(cls, body: Cylinder, t0, x, v, n, w, g=G) -> Flight:
        n = np.asarray(n, float)
        n = n / np.linalg.norm(n)
        w = np.asarray(w, float)
        L = body.inertia(n) @ w
        norm = float(np.linalg.norm(L))
        if norm == 0.0:
            return cls(t0, tuple(map(float, x)), tuple(map(float, v)), tuple(n), (0.0, 0.0, 1.0),
                       0.0, 0.0, g)
        lhat = L / norm
        return cls(t0, tuple(map(float, x)), tuple(map(float, v)), tuple(n), tuple(lhat),
                   norm / body.i1, float(L @ n) * (1 / body.i3 - 1 / body.i1), g)

    def _axis_terms(self):
        lh, n0 = np.array(self.lhat), np.array(self.n0)
        par = float(lh @ n0) * lh
        return par, n0 - par, np.cross(lh, n0)

    def state(self, t):
        """``(x, v, n, w)`` at the absolute time ``t``."""
        s = t - self.t0
        par, perp, side = self._axis_terms()
        c, sn = math.cos(self.omega * s), math.sin(self.omega * s)
        n = par + perp * c + side * sn
        n = n / np.linalg.norm(n)
        x = np.array(self.x0) + np.array(self.v0) * s
        x[2] -= 0.5 * self.g * s * s
        v = np.array(self.v0, float)
        v[2] -= self.g * s
        w = self.omega * np.array(self.lhat) + self.lam * n
        return x, v, n, w

    def nz_coefficients(self):
        par, perp, side = self._axis_terms()
        return float(par[2]), float(perp[2]), float(side[2])

    def clearance(self, s, a, hh):
        """``F`` at the times ``s`` after ``t0`` (array or float)."""
        A, B, C = self.nz_coefficients()
        om = self.omega
        nz = np.clip(A + B * np.cos(om * s) + C * np.sin(om * s), -1.0, 1.0)
        z = self.x0[2] + self.v0[2] * s - 0.5 * self.g * s * s
        return z - a * np.sqrt(1.0 - nz * nz) - hh * np.abs(nz)

    def curvature_bound(self, a, hh):
        ln = float(np.dot(self.lhat, self.n0))
        sin_beta = math.sqrt(max(0.0, 1.0 - ln * ln))
        return max(self.omega ** 2 * sin_beta * (a + hh) - self.g, 0.0)


def next_contact(fl: Flight, a, hh, t_limit, *, scan=1e-6, t_tol=1e-13, from_contact=False):
    """The absolute time of the flight's first contact with the plane, or None if there is none
    before ``t_limit`` (absolute).  ``from_contact``: the flight starts touching (``F(0) = 0``)."""
    from scipy.optimize import brentq

    kc = fl.curvature_bound(a, hh)
    g, z0, vz = fl.g, fl.x0[2], fl.v0[2]
    z_top = z0 + max(vz, 0.0) ** 2 / (2 * g)
    s_end = (vz + math.sqrt(vz * vz + 2.0 * g * max(z0, 0.0))) / g  # centre at the plane
    s_end = min(s_end, t_limit - fl.t0)
    if s_end <= 0 or z_top <= 0:
        return None

    def F(s):
        return float(fl.clearance(s, a, hh))

    s0 = 0.0
    if from_contact:
        s0 = min(scan, s_end)
        if F(s0) <= 0.0:  # a flight shorter than scan: halve to a point above the plane
            for _ in range(80):
                s0 /= 2
                if F(s0) > 0.0:
                    return fl.t0 + brentq(F, s0, 2 * s0, xtol=t_tol,
                                          rtol=4 * np.finfo(float).eps, maxiter=500)
            return fl.t0
    elif F(0.0) <= 0.0:
        return fl.t0

    def scan_cells(t1, t2, cells):
        """The first cell of width <= scan in [t1, t2] whose right end is below the plane."""
        w = (t2 - t1) / cells
        s = t1 + w * np.arange(cells + 1)
        s[-1] = t2
        f = fl.clearance(s, a, hh)
        low = np.minimum(f[:-1], f[1:]) - kc * w * w / 8
        for j in np.flatnonzero(low <= 0.0):
            if f[j + 1] <= 0.0 and (w <= scan or f[j] > 0.0 and kc == 0.0):
                return float(s[j]), float(s[j + 1])
            if w <= scan:
                continue  # a graze shallower than kc scan^2 / 8
            hit = scan_cells(float(s[j]), float(s[j + 1]), ZOOM)
            if hit is not None:
                return hit
        return None

    step = min(2 * math.pi / (16 * fl.omega) if fl.omega > 0 else math.inf, (s_end - s0) / 8)
    step = max(step, 1e-300)
    cells = max(1, math.ceil((s_end - s0) / step))
    hit = scan_cells(s0, s_end, cells)
    if hit is None:
        return None
    lo, hi = hit
    if F(lo) <= 0.0:
        return fl.t0 + lo
    return fl.t0 + brentq(F, lo, hi, xtol=t_tol, rtol=4 * np.finfo(float).eps, maxiter=500)
