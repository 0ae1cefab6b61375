"""A choice of model: the map from a coin's aspect ratio to its chances, and back.

One :class:`ModelSpec` is what ``coin design``, ``coin table``, ``coin stack``, ``coin fair``
and ``coin plot sides`` mean by "a model": the geometric one (eq. 11), the dynamic one
(eq. 12), Table I at a fixed angle psi, or psi averaged over a density (eq. 15), with the
quadrature order to average with when a tolerance asks for one.  It is pure: it prints
nothing and knows no command line; the commands build it (and word its errors) themselves.

Table I at an angle in degrees, as every command takes one, is here too: :func:`table_i_radians`
(the angle it is evaluated at, mirrored exactly past 90 deg), :func:`table_i_model` (its
:class:`ModelSpec`) and :func:`table_i_deg` (its chances over arrays, for the figures).

The closed forms stay on :mod:`coincli.core.models` (Python floats for one value); numpy and
:mod:`coincli.core.averages` load only when a psi density or a fixed-psi inverse is evaluated (at
90 deg that is eq. 12's own inverse), so a closed-form run imports neither.
"""

from __future__ import annotations

import math
from typing import NamedTuple

from coincli.core import models

__all__ = ["ModelSpec", "GEOMETRIC", "DYNAMIC", "table_i_radians", "table_i_model", "table_i_deg"]

GEOMETRIC_LABEL = "geometric (uniform orientations, eq. 11)"
DYNAMIC_LABEL = "dynamic (Keller flip, psi = 90 deg, eq. 12)"


class ModelSpec(NamedTuple):
    """A model: ``forward`` (xi -> :class:`coincli.core.models.Outcome`) and ``inverse``
    (P(sides) -> xi), for a float or an array.

    A NamedTuple: a dataclass costs ~1 ms of import (dataclasses itself and the class), paid
    by every closed-form run.  Build one with :meth:`geometric`, :meth:`dynamic`,
    :meth:`fixed_psi` or :meth:`psi_density`.
    """

    key: str  #: geometric | dynamic | psi | dist
    label: str  #: a human description, for notes and legends
    psi: float | None = None  #: radians, for key "psi"
    density: object = None  #: a :class:`coincli.core.densities.Density`, for key "dist"
    order: int | None = None  #: quadrature nodes per subinterval (key "dist"); None: default

    # ----------------------------------------------------------------------- constructors

    @classmethod
    def geometric(cls, label: str = GEOMETRIC_LABEL) -> ModelSpec:
        """Every orientation equally likely (von Neumann, eq. 11)."""
        return cls("geometric", label)

    @classmethod
    def dynamic(cls, label: str = DYNAMIC_LABEL) -> ModelSpec:
        """Angular momentum conserved, the Keller flip psi = 90 deg (eq. 12)."""
        return cls("dynamic", label)

    @classmethod
    def fixed_psi(cls, psi: float, label: str | None = None) -> ModelSpec:
        """Table I at the fixed angle ``psi`` (radians; checked when evaluated).

        ``psi`` is the double it is, except that the double nearest pi/2 stands for pi/2: the
        Keller flip, eq. (12), so that ``--psi 90`` and the dynamic model give the same chances
        and the same xi to the last bit.  (The 6e-17 rad between them decides, for a coin thicker
        than 1e16, whether it can land tails at all, and shifts heads + tails by (6e-17/theta0)^2
        relative before that: 1e-13 at xi = 6e9.)"""
        if label is None:
            label = f"psi = {math.degrees(psi):.6g} deg (Table I)"
        return cls("psi", label, psi=psi)

    @classmethod
    def psi_density(cls, density, label: str | None = None) -> ModelSpec:
        """psi averaged over a :class:`coincli.core.densities.Density` (eq. 15)."""
        if label is None:
            unit = " deg" if ":" in density.spec and not density.spec.startswith("table:") \
                else ""
            label = f"psi ~ {density.title}{unit}, averaged (eq. 15)"
        return cls("dist", label, density=density)

    def with_order(self, order: int) -> ModelSpec:
        """The same psi-density model, averaged with ``order`` quadrature nodes."""
        return self._replace(order=order)

    # ----------------------------------------------------------------------- what it is

    @property
    def name(self) -> str:
        """The short name in tables and figure ids: ``geometric``, ``dynamic``, ``psi=60``,
        or the density's spec (``normal:90:18``)."""
        if self.key == "psi":
            return f"psi={math.degrees(self.psi):.10g}"
        if self.key == "dist":
            return self.density.spec
        return self.key

    @property
    def title(self) -> str:
        """:attr:`name` for people: the paper's normal is ``normal (paper)``."""
        return self.density.title if self.key == "dist" else self.name

    @property
    def gid(self) -> str:
        """:attr:`name`, as the figures' artist ids (``curve:dynamic``) spell it."""
        return self.name

    @property
    def closed_form(self) -> bool:
        return self.key in ("geometric", "dynamic", "psi")

    # ----------------------------------------------------------------------- the maps

    def forward(self, xi):
        """The chances of heads, sides and tails at ``xi`` (a float or an array)."""
        if self.key == "geometric":
            return models.geometric(xi)
        if self.key == "dynamic":
            return models.dynamic(xi)
        if self.key == "psi":
            if self.psi == models.HALF_PI:
                return models.dynamic(xi)
            return models.conditional(xi, self.psi)
        from coincli.core.averages import marginal

        return marginal(xi, self.density, **self._quadrature())

    def inverse(self, p):
        """The xi at which this model's P(sides) is ``p`` (a float or an array)."""
        if self.key == "geometric":
            return models.geometric_inverse(p)
        if self.key == "dynamic" or (self.key == "psi" and self.psi == models.HALF_PI):
            return models.dynamic_inverse(p)
        from coincli.core import averages as mg

        if self.key == "psi":
            return mg.conditional_inverse(p, self.psi)
        return mg.marginal_inverse(p, self.density, **self._quadrature())

    def _quadrature(self) -> dict:
        return {} if self.order is None else {"order": self.order}


GEOMETRIC = ModelSpec.geometric()
DYNAMIC = ModelSpec.dynamic()


# --------------------------------------------------------------------------- Table I in degrees


class _Mirrored(ModelSpec):
    """Table I at psi > 90 deg, computed at its mirror image 180 deg - psi and named by psi."""

    __slots__ = ()

    @property
    def name(self) -> str:
        return f"psi={180.0 - math.degrees(self.psi):.10g}"


def table_i_radians(deg):
    """The angle (radians) to evaluate Table I at for ``deg`` degrees (a float, or an array).

    Table I is symmetric, P(i | psi) = P(i | 180 deg - psi), and past 90 deg the mirror angle is
    taken in degrees, where ``180 - deg`` is exact: ``--psi 179.5`` is ``--psi 0.5`` to the last
    bit (in radians pi - psi would carry pi's rounding, 1e-16 rad, 1e-14 relative at 0.5 deg),
    and 180 deg is exactly 0 deg: the coin never precesses (``math.pi``, 1.2e-16 rad short of
    pi, would precess, and land on a side once xi > 4e15).
    """
    if isinstance(deg, (float, int)):
        return math.radians(180.0 - deg if deg > 90.0 else deg)
    import numpy as np

    d = np.asarray(deg, dtype=float)
    return np.radians(np.where(d > 90.0, 180.0 - d, d))


def table_i_model(deg: float) -> ModelSpec:
    """Table I at ``deg`` degrees (in [0, 180]; checked by the caller) as a :class:`ModelSpec`,
    evaluated at :func:`table_i_radians` and named by ``deg`` (``psi=120``)."""
    label = f"psi = {deg:.10g} deg (Table I)"
    return (_Mirrored if deg > 90.0 else ModelSpec).fixed_psi(table_i_radians(deg), label)


def table_i_deg(xi, psi_deg):
    """Table I at ``psi_deg`` degrees (floats or arrays that broadcast), as every command takes
    an angle: at :func:`table_i_radians` (past 90 deg the mirror angle ``180 - psi``, exact),
    and 90 deg is the Keller flip exactly (eq. 12, :meth:`ModelSpec.fixed_psi`), so that a plot
    marks the chances `coin table --psi` prints (:func:`table_i_model`)."""
    import numpy as np

    d = np.asarray(psi_deg, dtype=float)
    o = models.conditional(xi, table_i_radians(d))
    at90 = d == 90.0
    if not at90.any():
        return o
    k = models.dynamic(xi)
    out = [np.where(at90, a, b) for a, b in zip(k, o, strict=True)]
    if not np.ndim(out[0]):
        out = [float(v) for v in out]
    return models.Outcome(*out)
