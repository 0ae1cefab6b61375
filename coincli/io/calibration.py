"""The calibration file: a table fitted by ``coin fit --landing bounce --save CAL.json`` and read
back by every bouncing command's ``--calibration CAL.json``.

A JSON object: ``format`` (:data:`FORMAT`), ``version`` (:data:`VERSION`), the coin version that
wrote it, the seed, the parameters fitted with their estimates and intervals, their covariance
(scaled coordinates, :mod:`coincli.core.bounce.calibrate`), the profiles, the response surface
(design points, coefficients per prototype), the launch, the surface's fixed values and the
data.  :func:`save` writes it atomically; :func:`load` reads and checks it, raising
:class:`CalibrationError` (one line) for a file that is not one, is of another version, or has
a field a command uses of the wrong type, kind or range (a hand edit: :func:`check`, with the
ranges of the options that set the same values, :mod:`coincli.limits`).
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
    """The calibration in ``path``, checked: its format, version, and every field a command
    uses (type, kind, range; :func:`check`)."""
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
    except (ValueError, RecursionError):  # not JSON, or nested deeper than the reader goes
        cal = None
    if not isinstance(cal, dict) or cal.get("format") != FORMAT:
        raise CalibrationError(f"--calibration {path} is not a table calibration (expected the "
                               "JSON that coin fit --landing bounce --save writes)")
    if cal.get("version") != VERSION or isinstance(cal.get("version"), bool):
        raise CalibrationError(f"--calibration {path} is a calibration of format version "
                               f"{_got(cal.get('version'))}; this coin reads version {VERSION} "
                               "(fit the table again with coin fit --landing bounce --save)")
    for key, kind in _REQUIRED.items():
        v = cal.get(key)
        if kind is float and isinstance(v, int) and not isinstance(v, bool):
            v = cal[key] = float(v)
        if not isinstance(v, kind) or isinstance(v, bool):
            raise CalibrationError(f"--calibration {path}: a calibration's {key!r} is missing "
                                   f"or malformed (expected {_KIND_NAMES[kind]}, got "
                                   f"{_got(v, key in cal)})")
    check(path, cal)
    return cal


_KIND_NAMES = {str: "a text", int: "a whole number", list: "a list", dict: "an object",
               float: "a number"}


def _got(v, present: bool = True) -> str:
    """A value of the file as JSON, short, for a message."""
    if not present:
        return "nothing (it is missing)"
    try:
        text = json.dumps(v, allow_nan=True)
    except (ValueError, TypeError, RecursionError):
        text = repr(type(v).__name__)
    return text if len(text) <= 40 else text[:37] + "..."


def _number(v) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)


class _Checker:
    """The checks of one file: each failure is one line naming the field and what is
    allowed."""

    def __init__(self, path: str):
        self.path = path

    def fail(self, field: str, allowed: str, v, present: bool = True):
        raise CalibrationError(f"--calibration {self.path}: {field} must be {allowed}, got "
                               f"{_got(v, present)}")

    def number(self, obj: dict, key: str, field: str, lo: float, hi: float, allowed: str,
               ) -> float:
        """``obj[key]``, a finite number in ``[lo, hi]``, as a float."""
        v = obj.get(key)
        if not _number(v) or not lo <= v <= hi:
            self.fail(field, allowed, v, key in obj)
        return float(v)

    def dist(self, launch: dict, key: str, lo: float, hi: float, unit: str, option: str,
             *, density: bool = False, top: float | None = None, keep_bounds: bool = True):
        """``launch[key]``, a launch value as the file writes it (``kind`` fixed, normal,
        uniform, or with ``density`` a psi density's ``spec``), its values in ``[lo, hi]``
        (``unit``, the range of ``option``), a normal's sd >= 0 and putting some of its
        probability there; the largest value drawn at most ``top``.  Numbers are made floats
        and a fixed value's bounds filled in: ``[lo, hi]`` with ``keep_bounds`` (a launch's u,
        omega, psi: a distribution), none without (a fixed number)."""
        from coincli.core.toss.launch import check_normal_mass
        from coincli.limits import NORMAL_REACH

        field = f"launch.{key}"
        d = launch.get(key)
        kinds = ("fixed", "normal", "uniform", *(("density",) if density else ()))
        rng = f"[{lo:g}, {hi:g}] {unit}" if math.isfinite(hi) else f">= {lo:g} {unit}"
        if not isinstance(d, dict):
            self.fail(field, f"an object with a kind ({', '.join(kinds)}), as coin fit "
                      "writes it", d, key in launch)
        kind = d.get("kind")
        if kind not in kinds:
            self.fail(f"{field}.kind", f"one of {', '.join(kinds)}", kind, "kind" in d)
        if kind == "density":
            from coincli.io.grammar import parse_density

            spec = d.get("spec")
            if not isinstance(spec, str):
                self.fail(f"{field}.spec", "a psi density's spec (uniform, cosine, "
                          "normal:MEAN:SD)", spec, "spec" in d)
            try:
                parse_density(spec)
            except (ValueError, OSError) as exc:
                self.fail(f"{field}.spec", f"a psi density --psi-dist reads ({exc})",
                          spec)
            return
        for b in ("lo", "hi"):
            if d.get(b) is not None and not (_number(d[b]) or
                                               (b == "hi" and d[b] == math.inf)):
                self.fail(f"{field}.{b}", "a number or null", d[b])
        slack = 1e-9 * max(abs(lo), abs(hi) if math.isfinite(hi) else 0.0, 1.0)
        t_lo = lo if d.get("lo") is None else float(d["lo"])
        t_hi = hi if d.get("hi") is None else float(d["hi"])
        if not lo - slack <= t_lo <= t_hi <= hi + slack:
            self.fail(f"{field}.lo and .hi", f"null or LO <= HI within {rng} (the range "
                      f"of {option})", [d.get("lo"), d.get("hi")])
        p1 = self.number(d, "p1", f"{field}.p1", -math.inf, math.inf, "a finite number")
        if kind == "fixed":
            if not lo <= p1 <= hi:
                self.fail(f"{field}.p1", f"in {rng} (the range of {option})", d["p1"])
            d["p1"], d["p2"] = p1, 0.0
            d["lo"], d["hi"] = ((lo, hi if math.isfinite(hi) else None) if keep_bounds
                                else (None, None))
            reach = p1
        elif kind == "uniform":
            p2 = self.number(d, "p2", f"{field}.p2", -math.inf, math.inf, "a finite number")
            if not lo <= p1 <= p2 <= hi:
                self.fail(f"{field}.p1 and .p2", f"LOW <= HIGH of a uniform, both in {rng} "
                          f"(the range of {option})", [d["p1"], d["p2"]])
            d["p1"], d["p2"] = p1, p2
            reach = p2
        else:
            p2 = self.number(d, "p2", f"{field}.p2 (a normal's sd)", 0.0, math.inf,
                             "a finite number >= 0")
            a, b = max(t_lo, lo), min(t_hi, hi)
            if p2 == 0:
                if not a <= p1 <= b:
                    self.fail(f"{field}.p1", f"in {rng} (the range of {option})", d["p1"])
            else:
                try:
                    check_normal_mass(field, f"normal:{p1:g}:{p2:g}", p1, p2, a, b, rng)
                except ValueError as exc:
                    raise CalibrationError(f"--calibration {self.path}: {exc}") from None
            d["p1"], d["p2"] = p1, p2
            reach = p1 if p2 == 0 else min(max(p1 + NORMAL_REACH * p2, 0.0), b)
        if top is not None and not reach <= top:
            self.fail(field, f"at most {top:g} {unit} at its largest (the limit of {option} "
                      f"with --landing bounce)", d)


def check(path: str, cal: dict) -> None:
    """Check every field of ``cal`` that a command uses (in place: numbers made floats, a
    missing interval end null made NaN, a fixed launch value's bounds filled in), raising
    :class:`CalibrationError` naming the first bad field and what is allowed: the ranges of
    the options that set the same values (:mod:`coincli.limits`)."""
    from coincli import limits as L
    from coincli.core.bounce.calibrate import PARAMS, RANGES

    c = _Checker(path)
    seed = cal["seed"]
    if not 0 <= seed < 10 ** 40:
        c.fail("seed", "a whole number >= 0 (at most 40 digits)", seed)
    fitted = cal["fitted"]
    if not (1 <= len(fitted) <= len(PARAMS) and all(isinstance(n, str) and n in PARAMS
                                                   for n in fitted)
            and len(set(fitted)) == len(fitted)):
        c.fail("fitted", f"a list of one to three distinct names from {', '.join(PARAMS)}", fitted)
    params = cal["parameters"]
    for n in fitted:
        par = params.get(n)
        if not isinstance(par, dict):
            c.fail(f"parameters.{n}", "an object (estimate, low, high)", par, n in params)
        lo, hi = RANGES[n]
        par["estimate"] = c.number(par, "estimate", f"parameters.{n}.estimate", lo, hi,
                                   f"a number from {lo:g} to {hi:g} (the designed range)")
        for end in ("low", "high"):
            v = par.get(end)
            if v is None:
                par[end] = math.nan  # JSON has no NaN: an interval's open end was saved null
            elif not _number(v):
                c.fail(f"parameters.{n}.{end}", "a number or null", v)
            else:
                par[end] = float(v)
    cov = cal["covariance"]
    k = len(fitted)
    if not (len(cov) == k and all(isinstance(r, list) and len(r) == k and
                                  all(_number(x) for x in r) for r in cov)):
        c.fail("covariance", f"a {k} x {k} list of lists of finite numbers (one row and "
               "column a fitted parameter)", cov)
    cal["covariance"] = [[float(x) for x in r] for r in cov]
    if any(cal["covariance"][i][i] < 0 for i in range(k)):
        c.fail("covariance", "a matrix whose diagonal (the variances) is >= 0", cov)
    fixed = cal["fixed"]
    length = L.BOUNCE_FRICTION_LENGTH_MAX_MM / 1000
    for key, lo, hi, option, unit in (
            ("torsional", 0.0, length, "--torsional", "m"),
            ("rolling", 0.0, length, "--rolling", "m"),
            ("restitution", L.BOUNCE_RESTITUTION_MIN, L.BOUNCE_RESTITUTION_MAX, "--restitution",
             ""),
            ("friction", 0.0, L.BOUNCE_FRICTION_MAX, "--friction", "")):
        if key in fitted:
            continue
        shown = f"{lo:g} to {hi:g}{' ' + unit if unit else ''}"
        fixed[key] = c.number(fixed, key, f"fixed.{key}", lo, hi,
                              f"a number from {shown} (the range of {option})")
    launch = cal["launch"]
    from coincli.limits import BOUNCE_OMEGA_MAX, U_MAX

    c.dist(launch, "u", 0.0, U_MAX, "m/s", "--u")
    c.dist(launch, "omega", 0.0, math.inf, "rad/s", "--omega", top=BOUNCE_OMEGA_MAX)
    c.dist(launch, "psi", 0.0, math.pi, "rad", "--psi", density=True)
    c.dist(launch, "release_height_m", 0.0, L.BOUNCE_HEIGHT_MAX_MM / 1000, "m",
           "--release-height", keep_bounds=False)
    c.dist(launch, "vx_ms", 0.0, L.BOUNCE_VX_MAX, "m/s", "--vx", keep_bounds=False)
    launch["dt"] = c.number(launch, "dt", "launch.dt", L.BOUNCE_DT_MIN, L.BOUNCE_DT_MAX,
                            f"a number from {L.BOUNCE_DT_MIN:g} to {L.BOUNCE_DT_MAX:g} s "
                            "(the range of --dt)")
    launch["t_max"] = c.number(launch, "t_max", "launch.t_max", L.BOUNCE_T_MAX_MIN,
                               L.BOUNCE_T_MAX_MAX, f"a number from {L.BOUNCE_T_MAX_MIN:g} to "
                               f"{L.BOUNCE_T_MAX_MAX:g} s (the range of --t-max)")
    if "text" in launch and not isinstance(launch["text"], str):
        c.fail("launch.text", "a text (the launch in words)", launch["text"])
    dia = cal["diameter_mm"]
    if not (math.isfinite(dia) and dia > 0):
        c.fail("diameter_mm", "a finite number > 0 (the prototypes' diameter in mm)", dia)
