r"""Distributions of the angle psi on [0, pi] (Sec. V, Table II of the paper).

Each density is normalized exactly on ``[0, pi]`` and evaluates on numpy arrays (radians):

- :class:`Uniform`: ``1/pi``;
- :class:`Cosine`: ``(1 - cos 2 psi)/pi``;
- :class:`Normal`: a normal of any mean and standard deviation truncated to ``[0, pi]``; the
  paper's "normal" ``0.58 exp(-(psi - pi/2)^2)`` is ``Normal(pi/2, 1/sqrt 2)`` (its 0.58 is the
  normalizing constant ``1/(sqrt(pi) erf(pi/2)) = 0.5795...`` rounded);
- :class:`Table`: points ``(psi, weight)`` joined linearly and renormalized; ``uniform:LOW:HIGH``
  is the table of two equal weights at LOW and HIGH.

``features()`` tells the quadrature where a density changes quickly (a narrow normal) or has
kinks (a table), so that it can place breakpoints there.  :func:`parse_density` reads the
command-line syntax (``uniform``, ``uniform:LOW:HIGH``, ``cosine``, ``normal``,
``normal:MEAN:SD`` in degrees, ``table:FILE``): the one parser of ``--psi-dist`` for every
command.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

__all__ = ["Density", "Uniform", "Cosine", "Normal", "Table", "parse_density", "PAPER_DENSITIES"]

MAX_TABLE_BYTES = 10_000_000
MAX_TABLE_POINTS = 100_000


class Density:
    """A probability density of psi on [0, pi]."""

    name = "density"

    def pdf(self, psi):
        raise NotImplementedError

    def features(self) -> list[tuple[float, float]]:
        """(centre, scale) pairs where the density varies on a scale much below pi."""
        return []

    def kinks(self) -> list[float]:
        """Points where the density's derivative jumps."""
        return []

    @property
    def spec(self) -> str:
        """The text that :func:`parse_density` reads back to this density (machine output)."""
        return self.name

    @property
    def title(self) -> str:
        """A human name for tables and legends (the paper's normal is ``normal (paper)``)."""
        return self.spec


class Uniform(Density):
    """``P(psi) = 1/pi``."""

    name = "uniform"

    def pdf(self, psi):
        import numpy as np

        return np.full(np.shape(psi), 1 / math.pi)


class Cosine(Density):
    """``P(psi) = (1 - cos 2 psi)/pi = 2 sin^2(psi)/pi``."""

    name = "cosine"

    def pdf(self, psi):
        import numpy as np

        s = np.sin(psi)
        return 2 * s * s / math.pi


@dataclass(frozen=True)
class _NormalParams:
    mean: float
    sd: float


class Normal(Density):
    """A normal density of ``mean`` and ``sd`` (radians) truncated to [0, pi], normalized exactly.

    The normalizer ``Z = Phi((pi - mean)/sd) - Phi(-mean/sd)`` is formed from ``erfc`` on the
    side where it does not cancel.
    """

    def __init__(self, mean: float = math.pi / 2, sd: float = 1 / math.sqrt(2)):
        for label, v in (("mean", mean), ("sd", sd)):
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
                raise ValueError(f"normal {label} must be a finite number, got {v!r}")
        if not sd > 0:
            raise ValueError(f"normal sd must be > 0, got {sd!r}")
        self.mean, self.sd = float(mean), float(sd)
        a, b = -self.mean / self.sd, (math.pi - self.mean) / self.sd
        r2 = math.sqrt(2)
        if a >= 0:
            z = 0.5 * (math.erfc(a / r2) - math.erfc(b / r2))
        elif b <= 0:
            z = 0.5 * (math.erfc(-b / r2) - math.erfc(-a / r2))
        else:
            z = 1 - 0.5 * (math.erfc(b / r2) + math.erfc(-a / r2))
        if not z > 0:
            raise ValueError(
                f"normal:{math.degrees(mean):g}:{math.degrees(sd):g} puts no measurable mass "
                "on [0, 180] degrees; move the mean into the range or widen it"
            )
        # a sum of logs: z * sd underflows for a subnormal sd
        self._log_norm = -(math.log(z) + math.log(self.sd) + 0.5 * math.log(2 * math.pi))

    name = "normal"

    @property
    def is_paper(self) -> bool:
        """The paper's normal, 0.58 exp(-(psi - pi/2)^2): mean pi/2, sd 1/sqrt 2."""
        return self.mean == math.pi / 2 and self.sd == 1 / math.sqrt(2)

    @property
    def spec(self) -> str:
        if self.is_paper:
            return "normal"
        return f"normal:{math.degrees(self.mean):.10g}:{math.degrees(self.sd):.10g}"

    @property
    def title(self) -> str:
        return "normal (paper)" if self.is_paper else self.spec

    def pdf(self, psi):
        import numpy as np

        x = (np.asarray(psi, dtype=float) - self.mean) / self.sd
        return np.exp(self._log_norm - 0.5 * x * x)

    def features(self):
        return [(self.mean, self.sd)] if self.sd < 0.5 else []


class Table(Density):
    """Points ``(psi_k, w_k)`` (radians, weights >= 0) joined linearly; zero outside them."""

    name = "table"

    def __init__(self, psi, weight, label: str = "table", spec: str | None = None):
        import numpy as np

        psi = np.asarray(psi, dtype=float)
        w = np.asarray(weight, dtype=float)
        if psi.ndim != 1 or psi.shape != w.shape or len(psi) < 2:
            raise ValueError("a psi table needs at least two (psi, weight) points")
        if not (np.all(np.isfinite(psi)) and np.all(np.isfinite(w))):
            raise ValueError("a psi table must hold finite numbers only")
        if np.any(psi < 0) or np.any(psi > math.pi + 1e-12):
            raise ValueError("table psi values must lie in [0, 180] degrees")
        if np.any(np.diff(psi) <= 0):
            raise ValueError("table psi values must be strictly increasing")
        if np.any(w < 0):
            raise ValueError("table weights must be >= 0")
        area = float(np.sum(np.diff(psi) * (w[1:] + w[:-1]) / 2))  # exact for the interpolant
        if not area > 0:
            raise ValueError("table weights must not all be zero")
        self.psi, self.w = np.minimum(psi, math.pi), w / area
        self.label = label
        self._spec = spec

    @property
    def spec(self) -> str:
        return self._spec if self._spec is not None else f"table:{self.label}"

    def pdf(self, psi):
        import numpy as np

        return np.interp(psi, self.psi, self.w, left=0.0, right=0.0)

    def kinks(self):
        return [float(v) for v in self.psi]

    @classmethod
    def from_text(cls, text: str, label: str = "table", degrees: bool = True) -> Table:
        """Parse lines ``psi,weight`` (or whitespace-separated); ``#`` comments; psi in degrees."""
        pts = []
        where = _shown(label)[1:-1]  # error messages repeat at most 60 characters of user text
        for n, raw in enumerate(text.splitlines(), start=1):
            line = raw.split("#", 1)[0].strip()
            if not line:
                continue
            parts = [p for p in line.replace(",", " ").replace(";", " ").split() if p]
            if len(parts) != 2:
                raise ValueError(f"{where} line {n}: expected 'psi,weight', got "
                                 f"{_shown(raw.strip())}")
            try:
                a, b = float(parts[0]), float(parts[1])
            except ValueError:
                if not pts:  # a header line
                    continue
                raise ValueError(f"{where} line {n}: not two numbers: "
                                 f"{_shown(raw.strip())}") from None
            pts.append((math.radians(a) if degrees else a, b))
            if len(pts) > MAX_TABLE_POINTS:
                raise ValueError(f"{where}: more than {MAX_TABLE_POINTS} points")
        if not pts:
            raise ValueError(f"{where}: no (psi, weight) points found")
        psi, w = zip(*pts, strict=True)
        return cls(psi, w, label)


PAPER_DENSITIES = {"uniform": Uniform, "cosine": Cosine, "normal": Normal}


DENSITY_FORMS = ("uniform, uniform:LOW:HIGH, cosine, normal (the paper's), normal:MEAN:SD "
                 "(degrees) or table:FILE")


def parse_density(text: str) -> Density:
    """``uniform``, ``uniform:LOW:HIGH``, ``cosine``, ``normal`` (the paper's),
    ``normal:MEAN:SD`` (degrees) or ``table:FILE`` (lines ``psi_degrees,weight``)."""
    s = str(text).strip()
    kind, _, rest = s.partition(":")
    kind = kind.lower()
    if kind in ("uniform", "cosine") and not rest:
        return PAPER_DENSITIES[kind]()
    if kind == "uniform":
        return _uniform_on(rest, text)
    if kind == "normal":
        if not rest:
            return Normal()
        parts = rest.split(":")
        if len(parts) != 2:
            raise ValueError(f"psi density must be normal:MEAN:SD in degrees, got {text!r}")
        from coincli.parse import parse_number

        mean = parse_number(parts[0], "normal mean (degrees)")
        sd = parse_number(parts[1], "normal sd (degrees)")
        if not sd > 0:
            raise ValueError(f"normal sd must be > 0 degrees, got {parts[1]!r}")
        return Normal(math.radians(mean), math.radians(sd))
    if kind == "table" and rest:
        return Table.from_text(_read_table_file(rest), label=rest)
    raise ValueError(f"psi density must be {DENSITY_FORMS}; got {_shown(str(text))}")


def _uniform_on(rest: str, text: str) -> Density:
    """``uniform:LOW:HIGH`` (degrees, 0 <= LOW < HIGH <= 180): the two-point table of equal
    weights, sampled and integrated exactly; ``uniform:0:180`` is :class:`Uniform` itself."""
    from coincli.parse import parse_number

    parts = rest.split(":")
    rule = "uniform:LOW:HIGH in degrees with 0 <= LOW < HIGH <= 180"
    if len(parts) != 2:
        raise ValueError(f"psi density must be {rule}, got {_shown(str(text))}")
    try:
        lo, hi = (parse_number(p, "uniform bound (degrees)") for p in parts)
    except ValueError:
        raise ValueError(f"psi density must be {rule}, got {_shown(str(text))}") from None
    if lo == hi and 0 <= lo <= 180:
        raise ValueError(f"psi density {_shown(str(text))} is a single angle; give it as "
                         f"--psi {parts[0].strip()}, or make LOW < HIGH")
    if not 0 <= lo < hi <= 180:
        raise ValueError(f"psi density must be {rule}, got {_shown(str(text))}")
    if lo == 0 and hi == 180:
        return Uniform()
    rad = [math.pi if v == 180 else math.radians(v) for v in (lo, hi)]
    return Table(rad, [1.0, 1.0], label=f"uniform {lo:g} to {hi:g} deg",
                 spec=f"uniform:{lo + 0.0:.10g}:{hi:.10g}")


def _shown(text: str, limit: int = 60) -> str:
    """``repr(text)`` for an error message, cut to about ``limit`` characters with '...'."""
    import re

    r = repr(text)
    if len(r) <= limit + 2:
        return r
    body = ""
    for tok in re.findall(r"\\(?:x..|u....|U........|.)|.", r[1:limit + 10], re.S):
        if len(body) + len(tok) > limit - 3:  # never end inside an escape such as \x00
            break
        body += tok
    return f"{r[0]}{body}...{r[0]}"


def _read_table_file(path: str) -> str:
    """The text of a psi table file, read in chunks and never more than ``MAX_TABLE_BYTES + 1``
    bytes (a device such as /dev/zero, or a pipe, has no size to check first); a NUL byte stops
    it at once.  UTF-8, a leading byte-order mark dropped."""
    name = _shown(path)
    parts, total = [], 0
    try:
        with open(path, "rb") as fh:
            while total <= MAX_TABLE_BYTES:
                chunk = fh.read(min(1 << 20, MAX_TABLE_BYTES + 1 - total))
                if not chunk:
                    break
                if b"\0" in chunk:
                    raise ValueError(f"psi table {name} contains a NUL byte; expected a text file "
                                     "of psi,weight lines")
                parts.append(chunk)
                total += len(chunk)
    except OSError as exc:
        raise ValueError(f"cannot read psi table {name}: {exc.strerror or exc}") from None
    if total > MAX_TABLE_BYTES:
        raise ValueError(f"psi table {name} is larger than {MAX_TABLE_BYTES} bytes; a table is at "
                         f"most {MAX_TABLE_BYTES // 10**6} MB and {MAX_TABLE_POINTS} points")
    try:
        return b"".join(parts).decode("utf-8-sig")
    except UnicodeDecodeError:
        raise ValueError(f"psi table {name} is not UTF-8 text") from None
