"""Tables precomputed for the surface presets: the hand toss simulated at a fine grid of
aspect ratios, which ``coin design --landing bounce`` starts from instead of its first sweep.

``tables.json`` beside this module holds, per preset, the counts of :data:`GRID`'s points,
simulated by ``benchmarks/precompute_bounce_tables.py`` with :func:`launch_kw` (what a design
on the preset simulates with the default launch, coin, dt, t_max and g), seed
:data:`TABLE_SEED`.  The file records :func:`signature`, the engine's settings; a table is used
only while they are the engine's (:func:`for_design`), and ``tests/core/test_tables.py``
checks the table against fresh tosses.  A design that starts from a table adds its own rounds
of tosses, from the user's seed, where the table's points do not yet give the interval asked
for (:func:`coincli.core.bounce.design.design`).
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

__all__ = ["Table", "TABLE_SEED", "GRID", "TABLES_FILE", "signature", "launch_kw", "load",
           "for_design"]

TABLES_FILE = Path(__file__).with_name("tables.json")
TABLE_SEED = 25  #: the seed of every table (issue 25); its streams are (1000 + preset, point)
#: The grid: aspect ratios 5% apart from 0.25 to 1.6 (2000 tosses each), where P(sides) of the
#: presets rises, and the first sweep's thinnest and thickest coins beyond (200 each,
#: :data:`coincli.core.bounce.design.DESIGN_GRID`), so the fit over every point is anchored as
#: a first sweep's is.  2000: the design's narrowest window (a factor 1.12 either side) then
#: holds about 10,000 tosses, enough for the default --tol of 0.01 at P(sides) = 1/3 on wood
#: (1000 gave a half-width of 0.0102).
GRID = tuple(sorted([(round(0.25 * 1.05**k, 4), 2000) for k in range(39)]
                    + [(0.1, 200), (0.15, 200), (0.22, 200), (2.4, 200)]))


def signature() -> dict:
    """The settings that decide a table's tosses: the engine's constants and defaults, the
    presets, the hand toss and the default coin.  (MuJoCo's version is recorded beside it, not
    in it: another version gives other tosses, not another chance.)"""
    from coincli.core.bounce import engine as B
    from coincli.core.toss import flight as F
    from coincli.core.toss.launch import HAND_TOSS_TEXT

    names = ("DEFAULT_DT", "DEFAULT_T_MAX", "OMEGA_DT", "IMPEDANCE", "EDGE_TILT", "LEAD_STEPS",
             "CHECK_STEPS", "JUMP_MIN_STEPS", "BOUNCE_MIN", "REST_MARGIN", "SIDE_TILT",
             "SLIP_TOL", "ROLLING_XI_MIN", "DEFAULT_DENSITY")
    return {"engine": {n: getattr(B, n) for n in names},
            "surfaces": {k: [s.restitution, s.friction, s.torsional, s.rolling]
                         for k, s in B.SURFACES.items()},
            "launch": dict(HAND_TOSS_TEXT), "diameter": F.DEFAULT_DIAMETER,
            "g": F.STANDARD_G, "grid": [list(p) for p in GRID]}


def launch_kw(surf) -> dict:
    """The arguments of :func:`coincli.core.bounce.runs.simulate` (but ``n``, ``seed``, ``xi``,
    ``stream``) of a design on ``surf`` with every default: the hand toss, a quarter's
    diameter and density, the engine's dt and t_max, standard gravity."""
    from coincli.core.bounce.engine import DEFAULT_DT, DEFAULT_T_MAX
    from coincli.core.toss.flight import DEFAULT_DIAMETER, STANDARD_G
    from coincli.core.toss.launch import HAND_TOSS

    return {"u": HAND_TOSS["u"], "omega": HAND_TOSS["omega"], "psi": HAND_TOSS["psi"],
            "surf": surf, "landing": "bounce", "height": 0.0, "vx": 0.0,
            "diameter": DEFAULT_DIAMETER, "g": STANDARD_G, "dt": DEFAULT_DT,
            "t_max": DEFAULT_T_MAX}


@dataclass(frozen=True)
class Table:
    """One preset's table: ``points``, rows ``(xi, tosses, heads, sides, tails, unsettled,
    never_landed)``; ``generated``: the coincli and MuJoCo versions, the date, the time it
    took."""

    surface: str
    seed: int
    stream: int
    points: tuple
    generated: dict

    @property
    def tosses(self) -> int:
        return sum(p[1] for p in self.points)

    @property
    def unsettled(self) -> int:
        return sum(p[5] for p in self.points)

    @property
    def never_landed(self) -> int:
        return sum(p[6] for p in self.points)

    def design_points(self) -> dict:
        """``{xi: (settled tosses, sides)}``, as a design keeps its points."""
        return {p[0]: (p[1] - p[5], p[3]) for p in self.points}


_LOADED: dict = {}


def load(name: str) -> Table | None:
    """The table of the preset ``name``, or None: no file, no table for it, or a table of
    other settings than the engine's (:func:`signature`)."""
    if "doc" not in _LOADED:
        try:
            doc = json.loads(TABLES_FILE.read_text())
        except (OSError, ValueError):
            doc = {}
        _LOADED["doc"] = doc if doc.get("signature") == signature() else {}
    entry = _LOADED["doc"].get("surfaces", {}).get(name)
    if entry is None:
        return None
    points = tuple((float(p[0]), *map(int, p[1:])) for p in entry["points"])
    return Table(name, int(entry["seed"]), int(entry["stream"]), points,
                 dict(entry["generated"]))


def for_design(kw: dict) -> Table | None:
    """The table a design with the simulation arguments ``kw`` may start from: that of a
    preset whose tosses ``kw`` describes exactly (:func:`launch_kw`), or None."""
    from coincli.core.bounce.engine import DEFAULT_DENSITY, SURFACES

    surf = kw.get("surf")
    name = next((k for k, s in SURFACES.items() if s == surf), None)
    if name is None:
        return None
    want = launch_kw(SURFACES[name])
    if any(kw.get(key) != value for key, value in want.items()):
        return None
    if kw.get("density", None) not in (None, DEFAULT_DENSITY) or kw.get("z0") is not None:
        return None
    if kw.get("flight", "exact") != "exact":
        return None
    return load(name)
