"""Regenerate ``coincli/core/bounce/tables.json``: the hand toss simulated onto each surface
preset, at a fine grid of aspect ratios, for ``coin design --landing bounce`` to start from
(issue 25, lever 4; as scipy keeps ``_precompute``).

    python benchmarks/precompute_bounce_tables.py            # every preset, every core
    python benchmarks/precompute_bounce_tables.py wood felt  # some presets (the others kept)

Each point is :func:`coincli.core.bounce.runs.simulate` of the tosses ``coin design --landing
bounce --surface NAME`` would simulate there with the default launch (the hand toss), coin
(a quarter's diameter and density), dt, t_max and g, seeded :data:`TABLE_SEED` on the stream
``(1000 + preset index, point index)`` (a design's own rounds use the streams ``(round,
point)`` of the user's seed).  The file records the engine's settings
(:func:`coincli.core.bounce.tables.signature`): a table whose settings are no longer the
engine's is not used, and ``tests/core/test_tables.py`` fails until it is regenerated; the same
test checks the table against fresh tosses.  Run it after any change to the engine's physics.
Written to a temporary file and renamed after each preset, so an interrupted run keeps the
presets it finished.
"""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))


class Progress:
    """Prints the tosses done on stderr every 2000 or so."""

    def __init__(self, name, total, w0):
        self.name, self.total, self.w0, self.shown = name, total, w0, 0

    def __call__(self, k):
        if k - self.shown >= 2000 or k == self.total:
            self.shown = k
            print(f"  {self.name}: {k}/{self.total} tosses, {time.monotonic() - self.w0:.0f} s",
                  file=sys.stderr, flush=True)


def main(names):
    import mujoco

    from coincli import __version__
    from coincli.core.bounce import runs as R
    from coincli.core.bounce import tables as TB
    from coincli.core.bounce.engine import SURFACES
    from coincli.io.files import write_text_atomic

    out = Path(TB.TABLES_FILE)
    doc = json.loads(out.read_text()) if out.exists() else {}
    if doc.get("signature") != TB.signature():
        doc = {}  # another engine's tables: none of them is kept
    doc["signature"] = TB.signature()
    doc.setdefault("surfaces", {})
    names = names or list(SURFACES)
    for name in names:
        if name not in SURFACES:
            raise SystemExit(f"no surface preset {name!r} (one of {', '.join(SURFACES)})")
    for name in names:
        index = list(SURFACES).index(name)
        specs = [dict(n=n, seed=TB.TABLE_SEED, xi=xi, stream=(1000 + index, j),
                      **TB.launch_kw(SURFACES[name]))
                 for j, (xi, n) in enumerate(TB.GRID)]
        c0, w0 = time.process_time(), time.monotonic()
        with R.Workers(None) as workers:
            sims = R.simulate_many(specs, workers=workers, progress=Progress(
                name, sum(s["n"] for s in specs), w0))
        wall = time.monotonic() - w0
        points = [[xi, s.n, *s.counts, s.n - sum(s.catch_counts)]
                  for (xi, _), s in zip(TB.GRID, sims, strict=True)]
        doc["surfaces"][name] = {
            "seed": TB.TABLE_SEED, "stream": 1000 + index, "points": points,
            "generated": {"coincli": __version__, "mujoco": mujoco.__version__,
                          "date": time.strftime("%Y-%m-%d"),
                          "wall_s": round(wall, 1), "parent_cpu_s": round(
                              time.process_time() - c0, 1)}}
        text = json.dumps(doc, indent=1, sort_keys=True) + "\n"
        write_text_atomic(str(out), lambda fh, text=text: fh.write(text))
        tosses = sum(p[1] for p in points)
        print(f"{name}: {tosses} tosses at {len(points)} aspect ratios in {wall:.0f} s of wall "
              f"time", flush=True)


if __name__ == "__main__":
    main(sys.argv[1:])
