"""Pick ``math`` for Python scalars and ``numpy`` for arrays, so that each formula is written once.

numpy 2 carries the ``math`` module's names (``atan``, ``atan2``, ``hypot``, ``sqrt``, ...), so an
expression written against ``xp`` runs on either.  ``math`` lacks ``where``, ``minimum`` and
``maximum``; :data:`M` adds them.  numpy is imported only when an argument is not a plain number.
"""

from __future__ import annotations

import math
import types

__all__ = ["M", "namespace", "is_scalar"]


def _where(cond, a, b):
    return a if cond else b


M = types.SimpleNamespace(
    **{name: getattr(math, name) for name in (
        "atan", "atan2", "hypot", "sqrt", "sin", "cos", "tan", "asin", "acos", "exp", "log",
        "log1p", "expm1", "isnan", "isinf", "isfinite", "erf", "erfc", "pi", "inf", "nan",
    )},
    where=_where,
    minimum=min,
    maximum=max,
    abs=abs,
)


def is_scalar(*args) -> bool:
    """True when every argument is a plain ``int`` or ``float`` (``numpy.float64`` is a ``float``)."""
    return all(isinstance(a, (int, float)) for a in args)


def namespace(*args):
    """``M`` (the math module) if every argument is a scalar, else ``numpy``."""
    if is_scalar(*args):
        return M
    import numpy as np

    return np
