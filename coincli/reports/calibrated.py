"""A calibration file under a bouncing run (``--calibration CAL.json``): the launch it records,
as data (:func:`dist_dict` writes it, :func:`launch_of` reads it back), the surface options it
replaces (:func:`refuse_surface_options`), the table and engine it puts under a run
(:func:`apply`), and the launch of a run on it (:func:`bounce_launch_for`, :func:`launch_on`).

The file is :mod:`coincli.io.calibration`; fitting one is :mod:`coincli.reports.calibrate`.
Nothing here imports numpy, scipy or mujoco at import time.
"""

from __future__ import annotations

import math

from coincli.errors import usage_error
from coincli.reports.launch import bounce_launch

__all__ = ["dist_dict", "check_launch", "launch_text", "refuse_surface_options", "apply",
           "launch_of", "bounce_launch_for", "launch_on"]


# --------------------------------------------------------------------------- the launch as data


def dist_dict(v):
    """A launch value (a float or a Dist) as JSON; a psi density as its spec, which
    :func:`coincli.io.grammar.parse_density` reads back."""
    if isinstance(v, (int, float)):
        return {"kind": "fixed", "p1": float(v), "p2": 0.0, "lo": None, "hi": None}
    if v.kind == "density":
        return {"kind": "density", "spec": str(v), "p1": None, "p2": None, "lo": None,
                "hi": None}
    return {"kind": v.kind, "p1": v.p1, "p2": v.p2, "lo": v.lo, "hi": v.hi}


def _dist_of(d):
    from coincli.core.toss.launch import Dist

    if d["kind"] == "density":
        from coincli.io.grammar import parse_density

        return Dist.from_density(parse_density(str(d["spec"])))
    lo = -math.inf if d.get("lo") is None else float(d["lo"])
    hi = math.inf if d.get("hi") is None else float(d["hi"])
    if d["kind"] == "fixed" and d.get("lo") is None:
        return float(d["p1"])
    return Dist(d["kind"], float(d["p1"]), float(d["p2"]), lo, hi)


def _key(v):
    """A launch value as (kind, numbers): a fixed value, a normal (mean, sd), a uniform (low,
    high); a psi density given as normal or uniform is that distribution, any other its spec."""
    if isinstance(v, (int, float)):
        return "fixed", (float(v),)
    if v.kind == "density":
        d = v.density
        if hasattr(d, "mean") and hasattr(d, "sd"):
            return "normal", (d.mean, d.sd)
        if str(v) == "uniform":
            return "uniform", (0.0, math.pi)
        return str(v), ()
    if v.is_fixed:
        return "fixed", (v.p1,)
    return v.kind, (v.p1, v.p2)


def _same(a, b) -> bool:
    """Two launch values (floats, Dists or psi densities) alike to a part in 10^9."""
    (ka, xa), (kb, xb) = _key(a), _key(b)
    return ka == kb and len(xa) == len(xb) and all(
        math.isclose(p, q, rel_tol=1e-9, abs_tol=1e-12) for p, q in zip(xa, xb, strict=True))


def _shown(v, unit: str, scale: float = 1.0) -> str:
    if isinstance(v, (int, float)):
        return f"{v * scale:g} {unit}"
    if v.kind == "density":
        return f"{v} deg"
    return f"{v.scaled(scale)} {unit}"


#: the launch options a calibration records: (key, option, unit shown, scale to it)
_LAUNCH_OPTS = (("u", "--u", "m/s", 1.0), ("omega", "--omega", "rad/s", 1.0),
                ("psi", "--psi/--psi-dist", "deg", 180.0 / math.pi))


def check_launch(path: str, cal: dict, given: dict) -> None:
    """Refuse a launch option typed with a calibration (``given``: the parsed u, omega, psi,
    None where not typed) that differs from the calibration's: the calibrated table holds for
    the launch it was fitted with (its parameters absorb it).  The same launch typed is
    accepted."""
    theirs = dict(zip(("u", "omega", "psi"), launch_of(cal), strict=True))
    for key, opt, unit, scale in _LAUNCH_OPTS:
        mine = given.get(key)
        if mine is not None and not _same(mine, theirs[key]):
            raise usage_error(f"{opt} {_shown(mine, unit, scale).strip()} differs from the "
                              f"calibration's {_shown(theirs[key], unit, scale).strip()} "
                              f"({path}): a calibrated table holds for the launch it was "
                              "fitted with; leave it out, or fit the table again with it")


def launch_text(cal: dict) -> str:
    """The calibration's launch in words (a file of coin 0.x before the launch options says
    nothing: it was the hand toss)."""
    text = cal["launch"].get("text")
    if not isinstance(text, str):
        from coincli.core.toss.launch import HAND_TOSS_TEXT as hand

        text = (f"u ~ {hand['u']}, omega ~ {hand['omega']}, psi ~ {hand['psi']} "
                "(the hand toss)")
    if "psi_sd_deg" in cal["fitted"]:
        text = text.split(", psi")[0] + (f", psi ~ normal(90, "
                                         f"{cal['parameters']['psi_sd_deg']['estimate']:.3g}) "
                                         "deg (its spread calibrated)")
    return text


# --------------------------------------------------------------------------- --calibration


def refuse_surface_options(path: str, **given) -> None:
    """The surface options cannot go with a calibration: it is the table."""
    named = [f"--{k}" for k, v in given.items() if v is not None]
    if named:
        raise usage_error(f"{', '.join(named)} cannot go with --calibration {path}: the "
                          "calibration is the table (fit again to change it)")


def apply(p, path: str, *, height_given: bool, vx_given: bool, dt_given: bool,
          t_max_given: bool):
    """The Physics ``p`` with the calibrated table of ``path`` under it: its surface, its launch
    plane, sideways speed, timestep and time limit (an option given that differs from the
    calibration's is refused, naming what changed); its ``calibration`` keeps the file."""
    from dataclasses import replace

    from coincli.io.calibration import CalibrationError, load

    try:
        cal = load(path)
    except CalibrationError as exc:
        raise usage_error(str(exc)) from None
    launch = cal["launch"]
    try:  # the whole launch is read here, once: a malformed one is one line, not a traceback
        checks = (("--release-height", height_given, "height",
                   _dist_of(launch["release_height_m"]), "mm", 1000.0),
                  ("--vx", vx_given, "vx", _dist_of(launch["vx_ms"]), "m/s", 1.0),
                  ("--dt", dt_given, "dt", float(launch["dt"]), "s", 1.0),
                  ("--t-max", t_max_given, "t_max", float(launch["t_max"]), "s", 1.0))
        launch_of(cal)
    except (KeyError, TypeError, ValueError, AttributeError) as exc:
        raise usage_error(f"--calibration {path}: its launch is malformed ({exc!s:.80})"
                          ) from None
    theirs_all = {}
    for opt, given, attr, theirs, unit, scale in checks:
        if given and not _same(getattr(p, attr), theirs):
            raise usage_error(f"{opt} {_shown(getattr(p, attr), unit, scale).strip()} differs "
                              f"from the calibration's {_shown(theirs, unit, scale).strip()} "
                              f"({path}): a calibrated table holds for the launch and engine "
                              "it was fitted with; leave it out, or fit the table again with it")
        theirs_all[attr] = theirs
    if not height_given:  # a message on the height names the calibration's, not 'None'
        theirs_all["height_text"] = (f"{_shown(theirs_all['height'], 'mm', 1000.0).strip()} "
                                     "(the calibration's)")
    est = {n: cal["parameters"][n]["estimate"] for n in cal["fitted"]}
    fixed = cal["fixed"]
    try:
        surface = replace(p.surface, restitution=est.get("restitution", fixed.get("restitution")),
                          friction=est.get("friction", fixed.get("friction")),
                          torsional=float(fixed["torsional"]), rolling=float(fixed["rolling"]),
                          name="calibrated", source=f"calibrated from tosses ({path})")
    except (TypeError, ValueError) as exc:
        raise usage_error(f"--calibration {path}: its table is malformed ({exc})") from None
    return replace(p, surface=surface, calibration=(path, cal), **theirs_all)


def launch_of(cal: dict):
    """The calibration's launch: u, omega, psi (a fitted spread as its estimate)."""
    from coincli.core.toss.launch import Dist

    launch = cal["launch"]
    psi = _dist_of(launch["psi"])
    if "psi_sd_deg" in cal["fitted"]:
        psi = Dist("normal", math.pi / 2,
                   math.radians(cal["parameters"]["psi_sd_deg"]["estimate"]), 0.0, math.pi)
    return _dist_of(launch["u"]), _dist_of(launch["omega"]), psi


def bounce_launch_for(p, psi, psi_dist, u, omega):
    """The launch of a bouncing run (:func:`coincli.reports.launch.bounce_launch`: the three
    specs and their description), or, on a calibrated table (``p.calibration``), the
    calibration's own launch: the table was fitted for it.  A launch option typed with a
    calibration must be the calibration's (:func:`check_launch`): another is refused."""
    if p.calibration is None:
        return bounce_launch(psi, psi_dist, u, omega)
    path, cal = p.calibration
    if any(v is not None for v in (psi, psi_dist, u, omega)):
        u_spec, w_spec, psi_spec, _ = bounce_launch(psi, psi_dist, u, omega)
        check_launch(path, cal, {"u": u_spec if u is not None else None,
                                 "omega": w_spec if omega is not None else None,
                                 "psi": psi_spec if (psi, psi_dist) != (None, None) else None})
    u_spec, w_spec, psi_spec = launch_of(cal)
    return u_spec, w_spec, psi_spec, f"the calibration's launch ({path}: {launch_text(cal)})"


def launch_on(p, psi, psi_dist, u, omega):
    """The launch of ``coin simulate --landing bounce`` on a calibrated table: the toss typed,
    what is not typed from the calibration's launch (not the hand toss); and a note when the
    toss typed is not the calibration's (it is tossed: "this toss on my table", but the table
    was fitted for another).  Returns the three specs, their description and the note (or
    None)."""
    path, cal = p.calibration
    mine = dict(zip(("u", "omega", "psi"), bounce_launch(psi, psi_dist, u, omega)[:3],
                    strict=True))
    theirs = dict(zip(("u", "omega", "psi"), launch_of(cal), strict=True))
    typed = {"u": ("--u", u), "omega": ("--omega", omega),
             "psi": ("--psi", psi) if psi is not None else ("--psi-dist", psi_dist)}
    out = {k: mine[k] if typed[k][1] is not None else theirs[k] for k in theirs}
    other = [f"{opt} {text.strip()}" for k, (opt, text) in typed.items()
             if text is not None and not _same(mine[k], theirs[k])]
    shown = [f"{opt} {text.strip()}" for opt, text in typed.values() if text is not None]
    text = (f"the calibration's launch ({path}: {launch_text(cal)})" if not shown else
            f"{', '.join(shown)}, the rest of the calibration's launch ({path})")
    note = None
    if other:
        note = (f"{', '.join(other)} is not the launch the table was calibrated with "
                f"({launch_text(cal)}): its parameters absorb that launch, so this run is "
                "your toss on a table fitted for another")
    return out["u"], out["omega"], out["psi"], text, note
