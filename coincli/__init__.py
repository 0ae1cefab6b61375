"""coin: design thick coins that land on heads, sides and tails with chances you choose.

The physics is Yong & Mahadevan, "Probability, geometry, and dynamics in the toss of a thick
coin".  The closed forms (:func:`geometric`, :func:`dynamic`, :func:`conditional` and their
inverses) need nothing beyond the standard library for Python floats; :func:`marginal` and the
root-found inverses import numpy when first called.
"""

from __future__ import annotations

__version__ = "0.1.0"

from coincli.models import (  # noqa: E402
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
    "marginal": "coincli.averages",
    "marginal_inverse": "coincli.averages",
    "conditional_inverse": "coincli.averages",
    "Uniform": "coincli.densities",
    "Cosine": "coincli.densities",
    "Normal": "coincli.densities",
    "Table": "coincli.densities",
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
