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
kinks (a table), so that it can place breakpoints there.  The command-line syntax (``uniform``,
``uniform:LOW:HIGH``, ``cosine``, ``normal``, ``normal:MEAN:SD`` in degrees, ``table:FILE``)
is read by :func:`coincli.io.grammar.parse_density`; a table's text by :meth:`Table.from_text`
(this module reads no files).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from coincli.core._numerics.quadrature import gauss_legendre
from coincli.errors import shown

__all__ = ["Density", "Uniform", "Cosine", "Normal", "Table", "PAPER_DENSITIES", "check_density"]

MAX_TABLE_POINTS = 100_000
#: the least area (radians times the largest weight) a table may enclose: a density of at most
#: 2**1000 per radian, well inside the doubles (the quadrature and the samplers then need no
#: scaling)
MIN_TABLE_SPAN = 2.0**-1000


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
        """The text that :func:`coincli.io.grammar.parse_density` reads back to this density
        (machine output)."""
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

    Any finite mean and any sd > 0 (subnormal to 1e308): the normalizer is formed relative to
    the density's value at :attr:`peak`, the point of [0, pi] nearest the mean, so that nothing
    cancels, underflows or overflows on the way (:func:`_relative_mass`).  Where the density
    itself exceeds the doubles (a peak 1/sd above 1.8e308), :meth:`pdf` gives inf there; the
    averages never need its scale (they divide by their own mass).
    """

    def __init__(self, mean: float = math.pi / 2, sd: float = 1 / math.sqrt(2)):
        for label, v in (("mean", mean), ("sd", sd)):
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
                raise ValueError(f"normal {label} must be a finite number, got {v!r}")
        if not sd > 0:
            raise ValueError(f"normal sd must be > 0, got {sd!r}")
        self.mean, self.sd = float(mean), float(sd)
        #: ``180 deg - mean`` in radians when the mean was given in degrees past 90 (set by
        #: :func:`coincli.io.grammar.parse_density`): a normal too narrow to average is Table I
        #: there, the angle ``coin ... --psi MEAN`` takes
        self.mirror: float | None = None
        #: the point of [0, pi] nearest the mean: the density's largest value is there
        self.peak = min(max(self.mean, 0.0), math.pi)
        # pdf(peak) = 1/(sd * rel) with rel = int_0^pi exp(-((x - m)^2 - (peak - m)^2)/(2 sd^2)) dx/sd
        rel = _relative_mass(self.mean, self.sd)
        self._log_peak = -(math.log(self.sd) + math.log(rel)) if rel > 0 else math.inf

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

    def log_shape(self, psi):
        """``log(pdf(psi)/pdf(peak))`` (numpy): ``-((psi - m)^2 - (peak - m)^2)/(2 sd^2)``,
        factored as ``-(psi - peak)(psi + peak - 2m)/(2 sd^2)`` in units of sd (never sd^2, which
        underflows); 0 at the peak, -inf where it underflows."""
        import numpy as np

        psi = np.asarray(psi, dtype=float)
        with np.errstate(over="ignore", invalid="ignore"):
            x = (psi - self.peak) / self.sd
            y = (psi - self.mean) / self.sd + (self.peak - self.mean) / self.sd
            out = -0.5 * (x * y)
        return np.where(x == 0, 0.0, np.where(np.isnan(out), -np.inf, out))

    def pdf(self, psi):
        import numpy as np

        with np.errstate(over="ignore"):
            return np.exp(min(self._log_peak, 1e300) + self.log_shape(psi))

    def features(self):
        return [(self.mean, self.sd)] if self.sd < 0.5 else []


def _relative_mass(mean: float, sd: float) -> float:
    """``int_0^pi exp(-((x - mean)^2 - (peak - mean)^2)/(2 sd^2)) dx / sd``, the mass of the
    normal on [0, pi] in units of sd relative to its value at ``peak`` (the point of [0, pi]
    nearest the mean); positive unless the density is narrower than the doubles (then 0).

    Mean inside: ``sqrt(pi/2) (erf(a/sqrt 2) + erf(b/sqrt 2))`` with ``a, b`` the distances to
    the ends in sd, a sum of positive terms.  Mean a distance ``a`` sd beyond an end, over
    ``L = pi/sd``: ``int_0^L exp(-a y - y^2/2) dy``, by Gauss-Legendre where the integrand
    changes by less than e^4 over the range (a wide, flat density: erfc would cancel), else
    ``sqrt(pi/2) (erfcx(a/sqrt 2) - exp(-L (a + L/2)) erfcx((a + L)/sqrt 2))``, whose second term is
    below e^-4 of the first.
    """
    r2 = math.sqrt(2.0)
    big = 1.7976931348623157e308
    lo = max(-mean, mean - math.pi)  # > 0: the mean lies beyond an end, by lo
    if lo <= 0:
        a, b = min(mean / sd, big), min((math.pi - mean) / sd, big)
        return math.sqrt(math.pi / 2) * (math.erf(a / r2) + math.erf(b / r2))
    a, span = min(lo / sd, big), min(math.pi / sd, big)
    if span <= 4.0 and a * span <= 4.0:
        x, w = gauss_legendre(24)
        return float(span * sum(wk * math.exp(-a * (span * xk) - 0.5 * (span * xk) ** 2)
                                for xk, wk in zip(x, w, strict=True)))
    far = min(a + span, big)
    return math.sqrt(math.pi / 2) * (_erfcx(a / r2) - math.exp(-span * (a + 0.5 * span))
                                     * _erfcx(far / r2))


def _erfcx(x: float) -> float:
    """``exp(x^2) erfc(x)`` for x >= 0 without overflow: ``x^2`` split exactly (Dekker) below 26,
    the continued fraction ``1/(sqrt(pi) (x + 1/(2x + 2/(x + 3/(2x + ...)))))`` above."""
    if x < 26.0:
        split = 134217729.0 * x  # x^2 = hi + lo exactly
        xh = split - (split - x)
        xl = x - xh
        hi = x * x
        lo = ((xh * xh - hi) + 2 * xh * xl) + xl * xl
        return math.exp(hi) * math.erfc(x) * (1.0 + lo)
    if x == math.inf:
        return 0.0
    f = x  # Lentz-free: 60 terms of the continued fraction are ample for x >= 26
    for k in range(60, 0, -1):
        f = x + (k / 2) / f
    return 1.0 / (math.sqrt(math.pi) * f)


class Table(Density):
    """Points ``(psi_k, w_k)`` (radians, weights >= 0) joined linearly; zero outside them.

    The weights may be of any size a double holds (1e-320 to 1e308): they are divided by the
    largest before the area is summed, so nothing overflows.  Refused, with what is allowed:
    fewer than two points, psi outside [0, pi] or not strictly increasing, a negative, NaN or
    infinite weight, all weights zero, and weight spread over less than ``MIN_TABLE_SPAN``
    radians (its density, 1/span, would leave the doubles; such a table is a fixed angle).
    """

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
            k = int(np.flatnonzero(np.diff(psi) <= 0)[0])
            raise ValueError(f"table psi values must be strictly increasing; point {k + 2} "
                             f"({math.degrees(psi[k + 1]):.17g} deg) does not exceed point "
                             f"{k + 1} ({math.degrees(psi[k]):.17g} deg)")
        if np.any(w < 0):
            raise ValueError("table weights must be >= 0")
        top = float(w.max())
        if not top > 0:
            raise ValueError("table weights must not all be zero")
        rel = w / top  # in [0, 1]: the area below cannot overflow
        area = float(np.sum(np.diff(psi) * (rel[1:] + rel[:-1]) / 2))  # exact for the interpolant
        if not area >= MIN_TABLE_SPAN:
            live = np.flatnonzero(rel > 0)
            lo, hi = psi[max(live[0] - 1, 0)], psi[min(live[-1] + 1, len(psi) - 1)]
            raise ValueError(
                f"table weight lies within {math.degrees(hi - lo):.3g} deg (from "
                f"{math.degrees(lo):.6g} to {math.degrees(hi):.6g}): a density must spread over "
                f"at least {math.degrees(MIN_TABLE_SPAN):.0e} deg; for a fixed angle use --psi")
        self.psi, self.w = np.minimum(psi, math.pi), rel / area
        with np.errstate(over="ignore"):  # a slope np.interp would overflow on
            self._steep = not bool(np.all(np.abs(np.diff(self.w)) / np.diff(self.psi) < 1e300))
        self.label = label
        self._spec = spec

    @property
    def spec(self) -> str:
        return self._spec if self._spec is not None else f"table:{self.label}"

    def pdf(self, psi):
        import numpy as np

        if not self._steep:
            return np.interp(psi, self.psi, self.w, left=0.0, right=0.0)
        # the weights joined linearly, as w0 + f (w1 - w0) with f in [0, 1]: np.interp forms the
        # slope (w1 - w0)/(x1 - x0) first, which overflows for points 1e-300 apart
        x = np.asarray(psi, dtype=float)
        k = np.clip(np.searchsorted(self.psi, x, side="right") - 1, 0, self.psi.size - 2)
        x0, x1 = self.psi[k], self.psi[k + 1]
        f = np.clip((x - x0) / (x1 - x0), 0.0, 1.0)
        w0 = self.w[k]
        out = w0 + f * (self.w[k + 1] - w0)
        return np.where((x < self.psi[0]) | (x > self.psi[-1]), 0.0, out)

    def kinks(self):
        return [float(v) for v in self.psi]

    @classmethod
    def from_text(cls, text: str, label: str = "table", degrees: bool = True) -> Table:
        """Parse lines ``psi,weight`` (or whitespace-separated); ``#`` comments; psi in degrees."""
        pts = []
        prev, last = "", 0.0
        where = shown(label)[1:-1]  # error messages repeat at most 60 characters of user text
        for n, raw in enumerate(text.splitlines(), start=1):
            line = raw.split("#", 1)[0].strip()
            if not line:
                continue
            parts = [p for p in line.replace(",", " ").replace(";", " ").split() if p]
            if len(parts) != 2:
                raise ValueError(f"{where} line {n}: expected 'psi,weight', got "
                                 f"{shown(raw.strip())}")
            try:
                if not (parts[0].isascii() and parts[1].isascii()):  # float() reads '٢' as 2
                    raise ValueError("digits 0-9 only")
                a, b = float(parts[0]), float(parts[1])
            except ValueError:
                if not pts:  # a header line
                    continue
                raise ValueError(f"{where} line {n}: not two numbers: "
                                 f"{shown(raw.strip())}") from None
            x = math.radians(a) if degrees else a
            top = 180.0 if degrees else math.pi
            if not 0.0 <= a <= top:
                raise ValueError(f"{where} line {n}: psi {shown(parts[0])} is outside [0, "
                                 f"{top:g}]{' degrees' if degrees else ' radians'}")
            if not b >= 0.0 or b == math.inf:
                raise ValueError(f"{where} line {n}: weight {shown(parts[1])} is not a finite "
                                 "number >= 0")
            if pts and not x > pts[-1][0]:
                raise ValueError(f"{where} line {n}: psi {shown(parts[0])} does not exceed the "
                                 f"previous point's {shown(prev)}; psi values must be strictly "
                                 "increasing" + (" (as doubles, in radians)" if a > last else ""))
            pts.append((x, b))
            prev, last = parts[0], a
            if len(pts) > MAX_TABLE_POINTS:
                raise ValueError(f"{where}: more than {MAX_TABLE_POINTS} points")
        if not pts:
            raise ValueError(f"{where}: no (psi, weight) points found")
        psi, w = zip(*pts, strict=True)
        return cls(psi, w, label)


PAPER_DENSITIES = {"uniform": Uniform, "cosine": Cosine, "normal": Normal}


def check_density(density):
    """``density`` itself if it is a :class:`Density`; the paper's normal for None; else a
    ValueError (the averages and the estimators take their density through this)."""
    density = Normal() if density is None else density
    if not isinstance(density, Density):
        raise ValueError(f"density must be a coincli.core.densities.Density, got {density!r}")
    return density
