"""The calibration file: a table fitted by ``coin fit --landing bounce --save CAL.json`` and read
back by every bouncing command's ``--calibration CAL.json``.

A JSON object: ``format`` (:data:`FORMAT`), ``version`` (:data:`VERSION`), the coin version that
wrote it, the seed, the parameters fitted with their estimates and intervals, their covariance
(scaled coordinates, :mod:`coincli.core.bounce.calibrate`), the profiles, the response surface
(design points, coefficients per prototype), the launch, the surface's fixed values and the
data.  :func:`save` writes it atomically; :func:`load` reads and checks it, raising
:class:`CalibrationError` (one line) for a file that is not one or is of another version.
"""

from __future__ import annotations

import json
import math

__all__ = ["FORMAT", "VERSION", "CalibrationError", "save", "load", "MAX_BYTES"]

FORMAT = "coin-calibration"
VERSION = 1
MAX_BYTES = 20_000_000  #: a calibration is a few kB; anything near this is not one

#: what a calibration must hold, with the type of each
_REQUIRED = {"format": str, "version": int, "coin_version": str, "seed": int, "fitted": list,
             "parameters": dict, "covariance": list, "launch": dict, "fixed": dict,
             "surface": dict, "data": list, "diameter_mm": float}


class CalibrationError(ValueError):
    """A file that is not a calibration this coin reads; the message is one line."""


def _clean(v):
    """JSON has no NaN: a missing number is null."""
    if isinstance(v, float) and not math.isfinite(v):
        return None
    if isinstance(v, dict):
        return {k: _clean(x) for k, x in v.items()}
    if isinstance(v, (list, tuple)):
        return [_clean(x) for x in v]
    return v


def save(path: str, calibration: dict) -> None:
    """Write ``calibration`` (a dict as :func:`load` returns it) to ``path``, atomically."""
    from coincli.io.files import write_text_atomic

    text = json.dumps(_clean(calibration), indent=1, sort_keys=True) + "\n"
    write_text_atomic(path, lambda fh: fh.write(text))


def load(path: str) -> dict:
    """The calibration in ``path``, checked: its format, version and keys."""
    from coincli.io.files import Unreadable, read_text

    try:
        text = read_text(path, MAX_BYTES)
    except Unreadable as exc:
        why = {"size": f"larger than {MAX_BYTES // 10**6} MB", "nul": "not text (a NUL byte)",
               "utf8": "not UTF-8 text", "kind": f"{exc.detail}, not a regular file",
               "system": exc.detail}
        raise CalibrationError(f"--calibration {path}: {why.get(exc.reason, exc.reason)}; "
                               "expected a calibration (coin fit --landing bounce --save)"
                               ) from None
    try:
        cal = json.loads(text)
    except ValueError:
        cal = None
    if not isinstance(cal, dict) or cal.get("format") != FORMAT:
        raise CalibrationError(f"--calibration {path} is not a table calibration (expected the "
                               "JSON that coin fit --landing bounce --save writes)")
    if cal.get("version") != VERSION:
        raise CalibrationError(f"--calibration {path} is a calibration of format version "
                               f"{cal.get('version')!r}; this coin reads version {VERSION} "
                               "(fit the table again with coin fit --landing bounce --save)")
    for key, kind in _REQUIRED.items():
        v = cal.get(key)
        if kind is float and isinstance(v, int) and not isinstance(v, bool):
            v = cal[key] = float(v)
        if not isinstance(v, kind) or isinstance(v, bool):
            raise CalibrationError(f"--calibration {path}: a calibration's {key!r} is missing "
                                   "or malformed")
    for name in cal["fitted"]:
        par = cal["parameters"].get(name)
        if not (isinstance(par, dict) and isinstance(par.get("estimate"), (int, float))):
            raise CalibrationError(f"--calibration {path}: a calibration's parameter {name!r} "
                                   "is missing or malformed")
    return cal
