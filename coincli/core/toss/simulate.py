"""Seeded runs of many tosses: :func:`simulate_chunks` (the outcome codes, chunk by chunk),
:func:`simulate` (their counts with Wilson intervals, a :class:`Simulation`) and
:func:`vigorous_limit`, the closed-form chances (Table I) they tend to.

The random stream is fixed by the seed and the chunk of :data:`_CHUNK` tosses drawn at once: a
shorter run is a prefix of a longer one.  Nothing here prints or exits; bad input raises
:class:`ValueError` naming the argument and its allowed range.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator

from coincli.core._numerics.records import record
from coincli.core.models import Outcome, conditional
from coincli.core.toss.batch import outcome_codes
from coincli.core.toss.flight import (
    DEFAULT_DIAMETER,
    NAMES,
    STANDARD_G,
    check_contact,
    check_count,
    check_number,
)
from coincli.core.toss.launch import DOMAINS, as_dist, sample_conditions

__all__ = [
    "Frequency",
    "Simulation",
    "simulate_chunks",
    "simulate",
    "wilson_interval",
    "vigorous_limit",
]

_CHUNK = 1 << 16  # tosses drawn at once by simulate (this fixes its random stream)


def simulate_chunks(n, seed, *, xi, u, omega, psi, diameter=DEFAULT_DIAMETER, g=STANDARD_G,
                    contact="rim") -> Iterator:
    """Yield the outcome codes (int8 arrays) of ``n`` seeded tosses, batch by batch.

    Each batch of 65536 tosses draws its initial conditions from one
    ``numpy.random.default_rng(seed)`` (a full batch even when fewer are needed), so a seed
    always gives the same sequence of outcomes, and a shorter run is a prefix of a longer one.
    Arguments as :func:`sample_conditions`; ``xi``, ``diameter``, ``g`` are fixed numbers.
    """
    import numpy as np

    n = check_count(n)
    thick = check_contact(contact)
    xi = check_number("xi", xi, 0.0, allow_inf=not thick)
    dists = {k: as_dist(v, k, *DOMAINS[k]) for k, v in (("u", u), ("omega", omega),
                                                          ("psi", psi))}
    from coincli.core._numerics.backend import numpy_random

    rng = numpy_random().default_rng(seed)
    done = 0
    while done < n:
        m = min(_CHUNK, n - done)
        # Always draw a full batch, so that the first m tosses of a run are those of any longer
        # run with the same seed.
        c = {k: (v if isinstance(v, float) else v[:m])
             for k, v in sample_conditions(_CHUNK, rng, **dists).items()}
        code = np.broadcast_to(outcome_codes(xi, c["psi"], c["u"], c["omega"],
                                             diameter=diameter, g=g, contact=contact), (m,))
        yield code
        done += m


@record(frozen=True)
class Frequency:
    """Observed frequency of one outcome with its Wilson score interval."""

    outcome: str
    count: int
    p: float
    lo: float
    hi: float


def wilson_interval(k, n, level=0.95):
    """Wilson score interval ``(low, high)`` (floats) for ``k`` successes in ``n`` trials:
    :func:`coincli.core.stats.tests.wilson_interval`, the one implementation (no scipy at the common
    levels 0.9, 0.95, 0.99; imported from its small module, not the whole of stats)."""
    if n <= 0:
        raise ValueError(f"n must be >= 1, got {n}")
    if not 0 < level < 1:
        raise ValueError(f"level must be in (0, 1), got {level}")
    from coincli.core._numerics.wilson import wilson_interval as _wilson

    lo, hi = _wilson(k, n, level)
    return float(lo), float(hi)


@record()
class Simulation:
    """Result of :func:`simulate`."""

    n: int
    counts: tuple
    frequencies: list  #: list of :class:`Frequency` (heads, sides, tails)
    vigorous: Outcome | None  #: closed-form prediction for the same psi distribution
    level: float = 0.95


def simulate(n, seed, *, xi, u, omega, psi, diameter=DEFAULT_DIAMETER, g=STANDARD_G,
             contact="rim", level=0.95, progress: Callable[[int], None] | None = None):
    """Toss ``n`` coins (at most :data:`MAX_TOSSES`, about 20 seconds of hand
    tosses) with seeded random initial conditions; count the outcomes.

    Returns a :class:`Simulation` with Wilson intervals and :func:`vigorous_limit` for the same
    psi distribution.  ``progress(done)`` is called after each batch.
    """
    counts = [0, 0, 0]
    import numpy as np

    done = 0
    for code in simulate_chunks(n, seed, xi=xi, u=u, omega=omega, psi=psi, diameter=diameter,
                                g=g, contact=contact):
        c = np.bincount(code, minlength=3)
        for i in range(3):
            counts[i] += int(c[i])
        done += code.size
        if progress is not None:
            progress(done)
    freqs = []
    for i in range(3):
        lo, hi = wilson_interval(counts[i], done, level)
        freqs.append(Frequency(NAMES[i], counts[i], counts[i] / done, lo, hi))
    return Simulation(done, tuple(counts), freqs, vigorous_limit(xi, psi), level)


def vigorous_limit(xi, psi):
    """The vigorous-toss chances (Table I) averaged over a psi distribution (radians).

    ``psi`` is a number, a spec string, a :class:`Dist` on [0, pi] or a density.  A fixed value
    gives :func:`coincli.core.models.conditional`; otherwise :func:`coincli.core.averages.marginal` (Gauss-
    Legendre between the regime boundaries, double precision): a normal is the density
    :class:`coincli.core.densities.Normal` truncated to [0, pi], as it is sampled, and
    ``uniform:LOW:HIGH`` the two-point table of equal weights.
    """
    dist = as_dist(psi, "psi", 0.0, math.pi)
    xi = check_number("xi", xi, 0.0, allow_inf=True)
    if dist.is_fixed:
        return conditional(xi, min(max(dist.p1, 0.0), math.pi))
    from coincli.core.averages import marginal

    if dist.kind == "density":
        density = dist.density
    elif dist.kind == "uniform":
        from coincli.core.densities import Table

        density = Table([max(dist.p1, 0.0), min(dist.p2, math.pi)], [1.0, 1.0], "uniform")
    else:
        from coincli.core.densities import Normal

        density = Normal(dist.p1, dist.p2)
    # The vectorized path of marginal (one element): its scalar path gives NaN for a narrow
    # normal and a thin coin (marginal(0.05, Normal(pi/2, 10 deg))), reported; never print one.
    import numpy as np

    out = marginal(np.array([float(xi)]), density)
    return Outcome(*(float(v[0]) for v in out))
