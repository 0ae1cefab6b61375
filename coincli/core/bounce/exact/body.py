"""The rigid cylinder: its mass and inertia, and where its lowest point is.

A solid cylinder of radius ``a`` (diameter ``D = 2a``), half-thickness ``hh = h/2`` and density
``rho``: ``m = rho pi a^2 h``, ``I1 = m (3 a^2 + h^2) / 12`` about a diameter through the
centre, ``I3 = m a^2 / 2`` about the axis (as :func:`coincli.core.bounce.engine.inertia`).  The
orientation enters only through the unit axis ``n`` (the body's z, the heads normal, in the world
frame): the inertia tensor of a symmetric top is ``I1 E + (I3 - I1) n n^T``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

UP = np.array([0.0, 0.0, 1.0])
DENSITY = 8920.0  #: kg/m^3, cupronickel: :data:`coincli.core.bounce.engine.DEFAULT_DENSITY`


@dataclass(frozen=True)
class Cylinder:
    """A solid cylinder: radius ``a`` (m), half-thickness ``hh`` (m), mass ``m`` (kg),
    moments of inertia ``i1`` (about a diameter) and ``i3`` (about the axis), kg m^2."""

    a: float
    hh: float
    m: float
    i1: float
    i3: float

    @classmethod
    def solid(cls, diameter: float, xi: float, density: float = DENSITY) -> Cylinder:
        """The solid cylinder of ``diameter`` (m), aspect ratio ``xi = h / D`` and ``density``
        (kg/m^3; cupronickel by default, as the bounce engine's coin)."""
        if not (diameter > 0 and xi > 0 and density > 0):
            raise ValueError("diameter, xi and density must be positive")
        a = diameter / 2
        h = xi * diameter
        m = density * math.pi * a * a * h
        return cls(a, h / 2, m, m * (3 * a * a + h * h) / 12, m * a * a / 2)

    def inertia(self, n):
        """The inertia tensor (3 x 3) in the world frame for the axis ``n``."""
        n = np.asarray(n, float)
        return self.i1 * np.eye(3) + (self.i3 - self.i1) * np.outer(n, n)

    def inverse_inertia(self, n):
        n = np.asarray(n, float)
        return np.eye(3) / self.i1 + (1 / self.i3 - 1 / self.i1) * np.outer(n, n)


def unit(v):
    v = np.asarray(v, float)
    return v / np.linalg.norm(v)


def cross(p, q):
    """``p x q`` for two 3-vectors (numpy's ``cross`` costs some 50 us a call, this 2)."""
    return np.array([p[1] * q[2] - p[2] * q[1], p[2] * q[0] - p[0] * q[2],
                     p[0] * q[1] - p[1] * q[0]])


def cross_matrix(r):
    """``[r]x``: ``cross_matrix(r) @ u == np.cross(r, u)``."""
    x, y, z = r
    return np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])


def rim_point(body: Cylinder, n):
    """The lowest point of the rim, from the centre (world frame), for a tilted axis ``n``
    (``|n_z| < 1``): ``r = -sign(n_z) hh n + a e`` with ``e`` the unit vector of the face's plane
    that points most steeply down.  A flat coin (``n_z = +-1``) has no lowest rim point: its
    face is the contact (:mod:`.flat`)."""
    n = unit(n)
    down = -(UP - n[2] * n)
    norm = np.linalg.norm(down)
    if norm < 1e-14:
        raise ValueError("the axis is vertical: the coin is flat, no single rim point is lowest")
    sigma = 1.0 if n[2] >= 0 else -1.0
    return -sigma * body.hh * n + body.a * down / norm


def contact_matrix(body: Cylinder, n, r):
    """``K`` (3 x 3, symmetric positive definite): the velocity of the body's point at ``r``
    changes by ``K P`` when the impulse ``P`` acts there: ``K = E/m - [r]x I^-1 [r]x``."""
    rx = cross_matrix(r)
    return np.eye(3) / body.m - rx @ body.inverse_inertia(n) @ rx
