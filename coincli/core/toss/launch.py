"""Launch distributions: the initial conditions ``u``, ``omega``, ``psi`` of seeded tosses.

:class:`Dist` is a fixed value, a normal truncated to the quantity's allowed range, a uniform
interval or (``psi``) a :mod:`coincli.core.densities` density; :func:`parse_dist` reads one from
``"2.4"``, ``"normal:MEAN:SD"`` or ``"uniform:LOW:HIGH"`` and :func:`as_dist` takes any of these
forms; :func:`sample_conditions` draws them from a numpy Generator (the truncated normal exactly,
by rejection); :data:`HAND_TOSS` is a natural hand toss, what ``coin toss`` and ``coin simulate``
draw by default.  A spec out of its quantity's range raises :class:`ValueError` naming it.

:func:`parse_dist` is text grammar, yet it lives here, not in :mod:`coincli.io.grammar`: the core's
API takes spec strings (:func:`as_dist`, so :func:`sample_conditions`, the simulate functions and
the bounce engine), and the core imports nothing from :mod:`coincli.io`.
"""

from __future__ import annotations

import math
import re

from coincli.core._numerics.records import record
from coincli.core.toss.flight import EPS, U_MAX, check_count

__all__ = [
    "Dist",
    "HAND_TOSS",
    "HAND_TOSS_TEXT",
    "parse_dist",
    "check_normal_mass",
    "as_dist",
    "sample_conditions",
]


_NUM = r"[+-]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][+-]?\d+)?"
_NUM_RE = re.compile(_NUM, re.ASCII)


@record(frozen=True, skip_compare=("density",))
class Dist:
    """A fixed value or a distribution of one initial condition.

    ``kind`` is 'fixed' (``p1``), 'normal' (mean ``p1``, sd ``p2``, truncated to the quantity's
    allowed range ``[lo, hi]``) or 'uniform' (``[p1, p2]``).
    """

    kind: str
    p1: float
    p2: float = 0.0
    lo: float = -math.inf
    hi: float = math.inf
    density: object = None  #: for kind 'density' (psi only; not compared)

    @classmethod
    def from_density(cls, density):
        """A psi distribution from a :mod:`coincli.core.densities` density (radians on [0, pi]).

        A normal or uniform density samples exactly; any other (cosine, table) by inverting its
        CDF tabulated on 2^16 + 1 points (plus the table's own points), accurate to ~1e-9 rad.
        """
        return cls("density", math.nan, math.nan, 0.0, math.pi, density)

    def __str__(self):
        if self.kind == "fixed":
            return f"{self.p1:g}"
        if self.kind == "density":
            return str(getattr(self.density, "spec", "density"))
        return f"{self.kind}:{self.p1:g}:{self.p2:g}"

    @property
    def is_fixed(self):
        if self.kind == "density":
            return False
        return self.kind == "fixed" or (self.kind == "normal" and self.p2 == 0) or (
            self.kind == "uniform" and self.p1 == self.p2)

    def scaled(self, factor):
        """The same distribution in other units (e.g. degrees to radians): all values times
        ``factor > 0``."""
        if self.kind == "density":
            raise ValueError("a psi density is already in radians; it cannot be rescaled")
        f = float(factor)
        return Dist(self.kind, self.p1 * f, self.p2 * f, self.lo * f, self.hi * f)

    def sample(self, rng, n):
        """``n`` draws (a float for a fixed value) from a numpy Generator."""
        import numpy as np

        if self.kind == "fixed":
            return self.p1
        if self.kind == "density":
            return _sample_density(np, rng, self.density, n)
        if self.kind == "uniform":
            if self.p1 == self.p2:
                return self.p1
            return rng.uniform(self.p1, self.p2, n)
        mu, sd = self.p1, self.p2
        if sd == 0:
            return mu
        return _truncnorm(np, rng, mu, sd, self.lo, self.hi, n)

    def pdf_interval(self):
        """The support ``(low, high)`` of the distribution."""
        if self.kind == "uniform":
            return self.p1, self.p2
        if self.kind == "fixed":
            return self.p1, self.p1
        return self.lo, self.hi


def _sample_density(np, rng, density, n):
    """n draws of psi (radians) from a coincli.core.densities density."""
    name = type(density).__name__
    if name == "Uniform":
        return rng.uniform(0.0, math.pi, n)
    if name == "Normal":
        from coincli.core.estimators import normal_is_exponential, sample_psi

        if normal_is_exponential(density):  # beyond what Phi resolves: exact by its own inverse
            return sample_psi(density, rng.random(n))
        return _truncnorm(np, rng, density.mean, density.sd, 0.0, math.pi, n)
    grid = np.linspace(0.0, math.pi, (1 << 16) + 1)
    kinks = [k for k in density.kinks() if 0.0 < k < math.pi]
    if kinks:
        grid = np.union1d(grid, kinks)
    pdf = np.maximum(np.asarray(density.pdf(grid), dtype=float), 0.0)
    area = np.diff(grid) * (pdf[1:] + pdf[:-1]) / 2
    total = float(area.sum())
    if not total > 0:
        raise ValueError(f"psi density {density.spec!r} has no mass on [0, 180] degrees")
    pdf = pdf / total
    cdf = np.concatenate([[0.0], np.cumsum(area) / total])
    # The pdf is linear on each grid interval, its CDF a quadratic: invert it there exactly,
    # x = 2 r / (f0 + sqrt(f0^2 + 2 s r)) (the root that does not cancel; s = 0 gives r / f0).
    q = rng.random(n)
    k = np.clip(np.searchsorted(cdf, q, side="right") - 1, 0, grid.size - 2)
    h = grid[k + 1] - grid[k]
    with np.errstate(over="ignore", divide="ignore", invalid="ignore"):  # kinks 1e-300 apart
        f0, slope, r = pdf[k], (pdf[k + 1] - pdf[k]) / h, np.maximum(q - cdf[k], 0.0)
        den = f0 + np.sqrt(np.fmax(f0 * f0 + 2 * slope * r, 0.0))  # fmax: NaN (inf - inf) is 0
        x = np.where(den > 0, 2 * r / den, 0.5 * h)
    return np.clip(grid[k] + np.clip(x, 0.0, h), 0.0, math.pi)


def _normal_mass(a, b):
    """``Phi(b) - Phi(a)`` for the standard normal, from ``erfc`` on the side where it does not
    cancel (the statistics module would cost 3 ms of start-up)."""
    r2 = math.sqrt(2.0)
    if a >= 0:
        return 0.5 * (math.erfc(a / r2) - math.erfc(b / r2))
    if b <= 0:
        return 0.5 * (math.erfc(-b / r2) - math.erfc(-a / r2))
    return 1.0 - 0.5 * (math.erfc(b / r2) + math.erfc(-a / r2))


def _truncnorm(np, rng, mu, sd, lo, hi, n):
    """Normal(mu, sd) truncated to [lo, hi], exact, by rejection (numpy only).

    With a mass above 0.2 the normal itself is the proposal.  Otherwise (Robert, Statistics and
    Computing 5 (1995) 121), in standard units ``[a, b]`` reflected so that ``b > 0`` and
    ``a >= 0`` unless the window straddles the mean: a uniform proposal on a window where the
    density varies by less than a factor e, else the exponential proposal of rate
    ``(a + sqrt(a^2 + 4))/2`` above ``a``, both accepted at least a third of the time.
    """
    a, b = (lo - mu) / sd, (hi - mu) / sd
    mass = _normal_mass(a, b) if math.isfinite(hi) or math.isfinite(lo) else 1.0
    out = np.empty(n)
    filled = 0
    if mass > 0.2:
        while filled < n:
            draw = rng.normal(mu, sd, max(64, int((n - filled) / mass * 1.1) + 16))
            draw = draw[(draw >= lo) & (draw <= hi)][: n - filled]
            out[filled:filled + draw.size] = draw
            filled += draw.size
        return out
    flip = b <= 0  # the window is below the mean: reflect it above
    if flip:
        a, b = -b, -a
    lo_sq = 0.0 if a < 0 else a * a  # the density's largest value is exp(-lo_sq / 2)
    uniform = a < 0 or b * b - a * a <= 2.0  # (a < 0: a narrow window around the mean)
    lam = 0.5 * (a + math.sqrt(a * a + 4.0))
    while filled < n:
        m = max(64, 2 * (n - filled) + 16)
        if uniform:
            z = rng.uniform(a, b, m)
            keep = rng.random(m) <= np.exp(0.5 * (lo_sq - z * z))
        else:
            z = a + rng.standard_exponential(m) / lam
            keep = (z <= b) & (rng.random(m) <= np.exp(-0.5 * (z - lam) ** 2))
        z = z[keep][: n - filled]
        out[filled:filled + z.size] = z
        filled += z.size
    return mu + sd * (-out if flip else out)


_KINDS = {"normal": "normal", "norm": "normal", "gauss": "normal", "uniform": "uniform",
          "unif": "uniform", "fixed": "fixed"}


def parse_dist(spec, name, lo=-math.inf, hi=math.inf, unit=""):
    """Parse ``"2.4"``, ``"fixed:2.4"``, ``"normal:MEAN:SD"`` or ``"uniform:LOW:HIGH"``.

    ``[lo, hi]`` is the quantity's allowed range (e.g. ``u >= 0``): a fixed value and a uniform
    interval must lie in it, a normal is truncated to it and must put some mass there.  No
    ``eval``; numbers are plain decimals.  Raises ValueError naming ``name``.
    """
    u = f" {unit}" if unit else ""
    form = "a number, normal:MEAN:SD or uniform:LOW:HIGH"
    if isinstance(spec, (int, float)) and not isinstance(spec, bool):
        parts = [repr(float(spec))]
        kind = "fixed"
    else:
        if not isinstance(spec, str):
            raise ValueError(f"{name} must be {form}, got {spec!r}")
        text = spec.strip()
        parts = [p.strip() for p in text.split(":")]
        if len(parts) == 1:
            kind = "fixed"
        else:
            kind = _KINDS.get(parts[0].lower())
            parts = parts[1:]
            if kind is None:
                raise ValueError(f"{name}: unknown distribution {spec!r}; expected {form}")
        want = 1 if kind == "fixed" else 2
        if len(parts) != want or not all(_NUM_RE.fullmatch(p) for p in parts):
            raise ValueError(f"{name}: cannot read {spec!r}; expected {form} "
                             "(plain decimal numbers)")
    vals = [float(p) for p in parts]
    if not all(math.isfinite(v) for v in vals):
        raise ValueError(f"{name}: numbers must be finite, got {spec!r}")
    rng = (f"[{lo:g}, {hi:g}]{u}" if math.isfinite(hi) else f">= {lo:g}{u}"
           if math.isfinite(lo) else f"finite{u}")
    if kind == "fixed":
        v = vals[0]
        if not lo <= v <= hi:
            raise ValueError(f"{name} must be {'in ' if math.isfinite(hi) else ''}{rng}, got "
                             f"{v:g}")
        return Dist("fixed", v, 0.0, lo, hi)
    if kind == "uniform":
        a, b = vals
        if not (lo <= a <= b <= hi):
            raise ValueError(f"{name}: uniform:LOW:HIGH needs LOW <= HIGH, both "
                             f"{'in ' if math.isfinite(hi) else ''}{rng}; got {spec!r}")
        return Dist("uniform", a, b, lo, hi)
    mu, sd = vals
    if sd < 0:
        raise ValueError(f"{name}: normal:MEAN:SD needs SD >= 0, got {spec!r}")
    if sd == 0:
        if not lo <= mu <= hi:
            raise ValueError(f"{name} must be {'in ' if math.isfinite(hi) else ''}{rng}, got "
                             f"{mu:g}")
        return Dist("normal", mu, 0.0, lo, hi)
    check_normal_mass(name, spec, mu, sd, lo, hi, rng)
    return Dist("normal", mu, sd, lo, hi)


def check_normal_mass(name, spec, mu, sd, lo, hi, rng):
    """Refuse a normal(mu, sd > 0) that puts at most 1e-9 of its probability in ``[lo, hi]``
    (``rng``, that range as text): a ValueError saying how much it puts there."""
    mass = _normal_mass((lo - mu) / sd, (hi - mu) / sd)
    if not mass > 1e-9:
        share = "no probability" if not mass > 0 else f"only {mass:.2g} of its probability"
        raise ValueError(f"{name}: {spec!r} puts {share} in the allowed range {rng}; at least "
                         "1e-9 is needed")


def as_dist(value, name, lo=-math.inf, hi=math.inf):
    """A :class:`Dist` from a Dist, a number, a spec string or (psi) a densities.Density."""
    if isinstance(value, Dist):
        return value
    if hasattr(value, "pdf") and hasattr(value, "kinks"):
        return Dist.from_density(value)
    return parse_dist(value, name, lo, hi)


DOMAINS = {"u": (0.0, U_MAX), "omega": (0.0, math.inf), "psi": (0.0, math.pi)}

#: A natural hand toss: the initial conditions ``coin toss`` and ``coin simulate`` draw when
#: ``--u``, ``--omega`` or ``--psi`` is not given (SI units; normals truncated to the domain).
#:
#: - ``omega ~ normal(38, 4) rev/s``: Diaconis, Holmes and Montgomery, "Dynamical bias in the
#:   coin toss", SIAM Review 49 (2007) 211, filmed natural flips at 1000 frames a second; their
#:   coins turned at about 38 revolutions a second (omega_N, the precession rate, is the
#:   turning rate of a coin flipped about a diameter).
#: - ``u ~ normal(2.4, 0.3) m/s``: a flight of 2u/g = 0.49 s, about half a second, the time a
#:   hand-caught flip spends in the air (some 19 turns at 38 rev/s).
#: - ``psi ~ normal(90, 10) degrees``: DHM's flips were close to the Keller flip (psi = 90)
#:   but not at it; with their p(psi) = 1/2 + asin(cot^2 psi)/pi (thin coin, same side up) a
#:   normal spread of 10 degrees gives the 0.51 same-side chance they report (8.9 degrees
#:   gives the 0.508 of Bartos et al.'s 350,757 hand flips, arXiv:2310.04153).
#:
#: The spreads of u and omega are this module's choice (the films give typical values, not
#: distributions); the vigorous limit does not depend on them.
HAND_TOSS = {
    "u": Dist("normal", 2.4, 0.3, 0.0, U_MAX),
    "omega": Dist("normal", 238.7610416728243, 25.132741228718345, 0.0, math.inf),  # 38, 4 rev/s
    "psi": Dist("normal", math.pi / 2, 0.17453292519943295, 0.0, math.pi),  # 90, 10 degrees
}
#: The same, as a person would type it.
HAND_TOSS_TEXT = {"u": "normal:2.4:0.3 m/s", "omega": "normal:38:4 rev/s",
                  "psi": "normal:90:10 deg"}


def sample_conditions(n, rng, *, u, omega, psi):
    """Draw ``n`` initial conditions from a numpy Generator (or an int seed).

    ``u`` (m/s), ``omega`` (rad/s) and ``psi`` (radians) are numbers, spec strings or
    :class:`Dist`.  Normals are truncated to the allowed range (``u, omega >= 0``,
    ``0 <= psi <= pi``).  Returns a dict of arrays (floats for fixed values).  The draws are made
    in the order u, omega, psi, so a seed gives the same stream on every run.
    """
    import numpy as np

    from coincli.core._numerics.backend import numpy_random

    n = check_count(n)
    npr = numpy_random()
    rng = npr.default_rng(rng) if not isinstance(rng, npr.Generator) else rng
    out = {}
    for name, val in (("u", u), ("omega", omega), ("psi", psi)):
        lo, hi = DOMAINS[name]
        dist = as_dist(val, name, lo, hi)
        if dist.kind != "density" and (dist.lo < lo or dist.hi > hi):
            dist = Dist(dist.kind, dist.p1, dist.p2, max(dist.lo, lo), min(dist.hi, hi))
        if dist.kind in ("fixed", "uniform"):
            a, b = dist.p1, (dist.p2 if dist.kind == "uniform" else dist.p1)
            slack = 4 * EPS * max(abs(lo), abs(hi) if math.isfinite(hi) else 0.0)
            if not (lo - slack <= a <= b <= hi + slack):
                raise ValueError(f"{name}: {dist} lies outside the allowed range "
                                 f"[{lo:g}, {hi:g}]")
        v = dist.sample(rng, n)
        # Degrees converted to radians may land an ulp beyond pi: clamp to the domain.
        out[name] = min(max(v, lo), hi) if isinstance(v, float) else np.clip(v, lo, hi)
    return out
