"""Pick ``math`` for Python scalars and ``numpy`` for arrays, so that each formula is written once.

numpy 2 carries the ``math`` module's names (``atan``, ``atan2``, ``hypot``, ``sqrt``, ...), so an
expression written against ``xp`` runs on either.  ``math`` lacks ``where``, ``minimum`` and
``maximum``; :data:`M` adds them.  numpy is imported only when an argument is not a plain number.

:func:`numpy_random` imports ``numpy.random`` without the ``secrets`` module (and the ``hashlib``,
``hmac``, ``base64`` and ``random`` it pulls in), about 7 ms of the 13 ms that ``numpy.random``
costs a seeded run's start-up; :func:`randbits` is the operating system's entropy that both coin
and numpy draw from ``secrets`` for.
"""

from __future__ import annotations

import math
import os
import sys
import types

__all__ = ["M", "namespace", "is_scalar", "long_double_64", "numpy_random", "randbits"]


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


def long_double_64(xp) -> bool:
    """Whether numpy's long double (``xp`` is numpy) has a 64-bit significand, as on x86: the
    numpy paths of Table I and of the averages then finish in it and round once."""
    return xp.finfo(xp.longdouble).nmant + 1 >= 64


def namespace(*args):
    """``M`` (the math module) if every argument is a scalar, else ``numpy``."""
    if is_scalar(*args):
        return M
    import numpy as np

    return np


def randbits(k: int) -> int:
    """An int of ``k`` random bits from the operating system's entropy (``os.urandom``): what
    ``secrets.randbits`` is (``random.SystemRandom.getrandbits``), without importing it."""
    if not isinstance(k, int) or isinstance(k, bool) or k < 0:
        raise ValueError(f"the number of bits must be a whole number >= 0, got {k!r}")
    nbytes = (k + 7) // 8
    return int.from_bytes(os.urandom(nbytes), "big") >> (8 * nbytes - k)


def numpy_random():
    """``numpy.random``, imported without ``secrets``.

    numpy's ``bit_generator`` runs ``from secrets import randbits`` when it is first imported,
    for the entropy of an unseeded ``SeedSequence``; ``secrets`` brings ``hashlib`` (OpenSSL),
    ``hmac``, ``base64`` and ``random``, about 7 ms of a 120 ms run that draws from a seed.  Here
    a module named ``secrets`` holding only :func:`randbits` (the same entropy) stands in while
    ``numpy.random`` is imported, and is removed at once: an ``import secrets`` afterwards gets
    the real module.  When ``numpy.random`` or ``secrets`` is already imported, nothing is done.
    """
    if "numpy.random" in sys.modules or "secrets" in sys.modules:
        import numpy.random

        return numpy.random
    stand_in = types.ModuleType("secrets", "coincli.core._numerics.backend's stand-in while numpy.random "
                                           "is imported (randbits only)")
    stand_in.randbits = randbits
    sys.modules["secrets"] = stand_in
    try:
        import numpy.random
    finally:
        if sys.modules.get("secrets") is stand_in:
            del sys.modules["secrets"]
    return numpy.random
