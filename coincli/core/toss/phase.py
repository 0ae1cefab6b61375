"""Phase space (Fig. 3): the outcome of each toss on a grid of launch speeds ``u`` and spins
``omega`` (:func:`phase_map`, a :class:`PhaseMap`) and the boundary curves between outcomes
(:func:`hyperbolae`, eq. 10 or its exact form; :class:`Boundary`).

Nothing here prints or exits; bad input raises :class:`ValueError` naming the argument and its
allowed range.
"""

from __future__ import annotations

import math

from coincli.core._numerics.records import NEW_LIST, record
from coincli.core.models import Outcome
from coincli.core.toss.batch import toss_many
from coincli.core.toss.flight import (
    DEFAULT_DIAMETER,
    G_MAX,
    G_MIN,
    STANDARD_G,
    check_contact,
    check_number,
    default_z0,
)

__all__ = ["Boundary", "PhaseMap", "hyperbolae", "phase_map"]


@record(frozen=True)
class Boundary:
    """One boundary curve ``omega(u) = phase / t_star(u)`` in the (u, omega) plane."""

    kind: str  #: 'heads|sides' or 'sides|tails'
    phase: float  #: omega t_f at the boundary: 2 n pi +- theta1 or 2 n pi +- theta2
    omega: object  #: ndarray over the u grid (nan where undefined)

    @property
    def coefficient(self):
        """``c`` in eq. (10)'s ``omega = c pi g / (2 u)``: ``phase / pi``."""
        return self.phase / math.pi


def _boundary_phases(xi, psi):
    """Phases theta1 (heads|sides) and theta2 (sides|tails) in (0, pi), or None (Table I)."""
    c0 = math.cos(math.atan2(1.0, xi))
    A, B = math.cos(psi) ** 2, math.sin(psi) ** 2
    if B == 0:
        return None, None
    x1 = (c0 - A) / B
    x2 = (-c0 - A) / B
    th1 = math.acos(x1) if -1 < x1 < 1 else None
    th2 = math.acos(x2) if -1 < x2 < 1 else None
    return th1, th2


def hyperbolae(xi, psi, u, omega_max, *, g=STANDARD_G, exact=False, diameter=DEFAULT_DIAMETER,
               contact="rim", z0=None, max_curves=4000):
    r"""The outcome boundaries of Fig. 3 as curves over the ``u`` grid.

    The boundaries are where contact happens exactly at ``alpha_f = theta0`` (heads|sides) or
    ``pi - theta0`` (sides|tails): ``omega t_f = 2 n pi +- theta1`` or ``2 n pi +- theta2``
    (``theta1``, ``theta2`` of Table I; for ``psi = pi/2`` they are ``theta0`` and
    ``pi - theta0``).  With the vigorous ``t_f = 2u/g`` this is eq. (10):

    .. math:: \omega_N = \left(2n \pm \tfrac{\theta_0}{\pi}\right)\frac{\pi g}{2u},\qquad
              \omega_N = \left(2n + 1 \pm \tfrac{\theta_0}{\pi}\right)\frac{\pi g}{2u}

    (``theta0/pi = 1/3`` for ``xi = 1/sqrt 3``).  ``exact=True`` uses instead the time at which
    the descending centre is at the contact height ``L(theta0)`` (``a sin theta0``, or
    ``hypot(a, h/2)`` for a thick coin): ``t* = (u + sqrt(u^2 + 2 g (z0 - L)))/g``.  For the fair
    coin with the paper's ``z0 = a sin theta0`` this *is* ``2u/g``: eq. (10) is then exact
    wherever that contact is the first one, i.e. for ``omega a / u`` small.

    Returns a list of :class:`Boundary`, sorted by phase, with ``omega`` over ``u`` (an array;
    NaN where ``t*`` is undefined, and at ``u = 0`` for eq. 10).  Only curves reaching below
    ``omega_max`` somewhere on the grid are returned, at most ``max_curves``.
    """
    import numpy as np

    thick = check_contact(contact)
    xi = check_number("xi", xi, 0.0, allow_inf=not thick)
    psi = check_number("psi", psi, 0.0, math.pi, unit="rad")
    g = check_number("g", g, G_MIN, G_MAX, unit="m/s^2")
    u = np.atleast_1d(check_number("u", u, 0.0, unit="m/s"))
    omega_max = check_number("omega_max", omega_max, 0.0, unit="rad/s")
    th1, th2 = _boundary_phases(xi, psi)
    with np.errstate(divide="ignore", invalid="ignore"):
        if exact:
            a = diameter / 2
            hh = xi * diameter / 2 if thick else 0.0
            zz = default_z0(xi, diameter, contact) if z0 is None else z0
            low = math.hypot(a, hh) if thick else a * math.sin(math.atan2(1.0, xi))
            rad = u * u + 2 * g * (zz - low)
            tstar = np.where(rad >= 0, (u + np.sqrt(np.maximum(rad, 0))) / g, np.nan)
        else:
            tstar = np.where(u > 0, 2 * u / g, np.nan)
    tmax = np.nanmax(tstar) if np.any(np.isfinite(tstar)) else 0.0
    phase_max = omega_max * tmax
    out = []
    for kind, th in (("heads|sides", th1), ("sides|tails", th2)):
        if th is None:
            continue
        n = 0
        while 2 * n * math.pi - th <= phase_max and len(out) < 2 * max_curves:
            for ph in (2 * n * math.pi - th, 2 * n * math.pi + th):
                if 0 < ph <= phase_max:
                    with np.errstate(divide="ignore", invalid="ignore"):
                        out.append(Boundary(kind, ph, ph / tstar))
            n += 1
    out.sort(key=lambda b: b.phase)
    return out[:max_curves]


@record()
class PhaseMap:
    """Outcome codes on a grid of (u, omega), with the boundary curves."""

    u: object  #: (nu,) m/s, cell centres
    omega: object  #: (nw,) rad/s, cell centres
    codes: object  #: (nw, nu) int8: rows omega (ascending), columns u
    xi: float
    psi: float
    contact: str
    curves: list = NEW_LIST  #: eq. (10) boundaries (:func:`hyperbolae`)

    def fractions(self):
        """Fractions of the grid that land heads, sides, tails."""
        import numpy as np

        c = np.bincount(np.asarray(self.codes).ravel(), minlength=3) / self.codes.size
        return Outcome(float(c[0]), float(c[1]), float(c[2]))


def phase_map(xi, psi, u_range, omega_range, shape=(200, 200), *, diameter=DEFAULT_DIAMETER,
              g=STANDARD_G, contact="rim", z0=None, exact_curves=False):
    """The pre-images of heads, sides and tails (Fig. 3) on a ``shape = (nu, nomega)`` grid.

    ``u_range = (u_lo, u_hi)`` in m/s, ``omega_range`` in rad/s; the grid samples cell centres.
    Curves are :func:`hyperbolae` over the same u grid (eq. 10 unless ``exact_curves``).
    """
    import numpy as np

    nu, nw = (int(v) for v in shape)
    if nu < 1 or nw < 1 or nu * nw > 50_000_000:
        raise ValueError(f"shape must be two positive sizes with at most 5e7 cells, got {shape!r}")
    (u0, u1), (w0, w1) = _range("u", u_range, "m/s"), _range("omega", omega_range, "rad/s")
    u = u0 + (np.arange(nu) + 0.5) * (u1 - u0) / nu
    w = w0 + (np.arange(nw) + 0.5) * (w1 - w0) / nw
    res = toss_many(xi, psi, u[None, :], w[:, None], diameter=diameter, g=g, contact=contact,
                    z0=z0)
    curves = hyperbolae(xi, psi, u, w1, g=g, exact=exact_curves, diameter=diameter,
                        contact=contact, z0=z0)
    return PhaseMap(u, w, res.code, float(xi), float(psi), contact, curves)


def _range(name, r, unit):
    try:
        lo, hi = (float(v) for v in r)
    except (TypeError, ValueError):
        raise ValueError(f"{name} range must be two numbers (low, high), got {r!r}") from None
    if not (math.isfinite(lo) and math.isfinite(hi) and 0 <= lo < hi):
        raise ValueError(f"{name} range must satisfy 0 <= low < high (finite, {unit}), "
                         f"got ({lo:g}, {hi:g})")
    return lo, hi
