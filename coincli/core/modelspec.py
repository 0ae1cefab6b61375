"""A choice of model: the map from a coin's aspect ratio to its chances, and back.

One :class:`ModelSpec` is what ``coin design``, ``coin table``, ``coin stack``, ``coin fair``
and ``coin plot sides`` mean by "a model": the geometric one (eq. 11), the dynamic one
(eq. 12), Table I at a fixed angle psi, or psi averaged over a density (eq. 15), with the
quadrature order to average with when a tolerance asks for one.  It is pure: it prints
nothing and knows no command line; the commands build it (and word its errors) themselves.

The closed forms stay on :mod:`coincli.core.models` (Python floats for one value); numpy and
:mod:`coincli.core.averages` load only when a psi density or a fixed-psi inverse is evaluated (at
90 deg that is eq. 12's own inverse), so a closed-form run imports neither.
"""

from __future__ import annotations

import math
from typing import NamedTuple

from coincli.core import models

__all__ = ["ModelSpec", "GEOMETRIC", "DYNAMIC"]

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
