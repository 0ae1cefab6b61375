"""``--landing``: the catch (the paper's, the default) or a bounce on a surface (issue 16).

:func:`parse_physics` is what every command that takes ``--landing`` calls with its surface,
release and run options as typed: None for the catch (then none of them may be given), else the
:class:`coincli.reports.physics.Physics` of :func:`coincli.reports.physics.bounce_physics`.  The
catch never loads that module (nor numpy, scipy or mujoco).
"""

from __future__ import annotations

from coincli.errors import usage_error
from coincli.limits import LANDINGS

__all__ = ["landing_of", "parse_physics"]


def landing_of(text: str) -> str:
    t = text.strip().lower()
    if t not in LANDINGS:
        raise usage_error(f"--landing must be catch or bounce, got {text!r}")
    return t


def parse_physics(landing: str, *, surface=None, restitution=None, friction=None,
                  torsional=None, rolling=None, height=None, vx=None, jobs=None, dt=None,
                  t_max=None, calibration=None, scheduler=None, checkpoint=None,
                  timeout=None):
    """The bounce options, or None for ``--landing catch`` (then none may be given).
    ``calibration``: a calibration file (:func:`coincli.reports.calibrated.apply`), the table
    instead of the surface options."""
    if landing == "catch":
        extra = [name for name, v in (("--surface", surface), ("--restitution", restitution),
                                      ("--friction", friction), ("--torsional", torsional),
                                      ("--rolling", rolling), ("--release-height", height),
                                      ("--vx", vx),
                                      ("--jobs", jobs), ("--dt", dt), ("--t-max", t_max),
                                      ("--calibration", calibration),
                                      ("--scheduler", scheduler), ("--checkpoint", checkpoint),
                                      ("--timeout", timeout))
                 if v is not None]
        if extra:
            raise usage_error(f"{', '.join(extra)} go{'es' if len(extra) == 1 else ''} with "
                              "--landing bounce (the catch ends at first contact: no surface)")
        return None
    from coincli.reports.physics import bounce_physics

    return bounce_physics(surface=surface, restitution=restitution, friction=friction,
                          torsional=torsional, rolling=rolling, height=height, vx=vx, jobs=jobs,
                          dt=dt, t_max=t_max, calibration=calibration, scheduler=scheduler,
                          checkpoint=checkpoint, timeout=timeout)
