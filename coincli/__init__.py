"""coin: design thick coins that land on heads, sides and tails with chances you choose.

The physics is Yong & Mahadevan, "Probability, geometry, and dynamics in the toss of a thick
coin".  The closed forms (:func:`geometric`, :func:`dynamic`, :func:`conditional` and their
inverses) need nothing beyond the standard library for Python floats; :func:`marginal` and the
root-found inverses import numpy when first called.
"""

from __future__ import annotations

__version__ = "0.2.0"

from coincli.core.models import (  # noqa: E402
    FAIR_XI_DYNAMIC,
    FAIR_XI_GEOMETRIC,
    Outcome,
    asymptotic_sides,
    conditional,
    dynamic,
    dynamic_inverse,
    geometric,
    geometric_inverse,
    psi_boundaries,
    theta0,
)

_LAZY = {
    "marginal": "coincli.core.averages",
    "marginal_inverse": "coincli.core.averages",
    "conditional_inverse": "coincli.core.averages",
    "Uniform": "coincli.core.densities",
    "Cosine": "coincli.core.densities",
    "Normal": "coincli.core.densities",
    "Table": "coincli.core.densities",
}

__all__ = [
    "FAIR_XI_DYNAMIC",
    "FAIR_XI_GEOMETRIC",
    "Outcome",
    "asymptotic_sides",
    "conditional",
    "dynamic",
    "dynamic_inverse",
    "geometric",
    "geometric_inverse",
    "psi_boundaries",
    "theta0",
    *_LAZY,
]


def __getattr__(name):  # PEP 562: numpy/scipy-backed names load on first use
    if name in _LAZY:
        import importlib

        return getattr(importlib.import_module(_LAZY[name]), name)
    raise AttributeError(f"module 'coincli' has no attribute {name!r}")
