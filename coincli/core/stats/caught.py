r"""Caught coins, faces only: the same-side bias and each tosser's spread of psi.

A coin caught in the hand lands on a face.  Data sets of such flips (Bartos et al. 2023; the
prediction of Diaconis, Holmes and Montgomery 2007) record the side each coin started on and the
side it landed on: ``same`` and ``different`` out of ``n``.  Under every model of this project
the coin starts heads up, so the chance of landing on the starting side, *given that it lands on
a face*, is

.. math:: q = \frac{P(H)}{P(H) + P(T)},

and the observation is binomial: ``same ~ Binomial(n, q)``.  At ``xi -> 0`` and a fixed psi this
is DHM's ``1/2 + asin(cot^2 psi)/pi`` (for ``|cot psi| <= 1``, else 1).

The spread of psi (psi ~ Normal(pi/2, sigma) truncated to [0, pi], as :mod:`.fit`) enters
through ``q(xi, sigma)``, which rises monotonically from 1/2 (sigma = 0, the Keller flip) to the
uniform-psi value (sigma = inf).  :class:`SameChance` tabulates it per coin as a Chebyshev
interpolant in ``u = sigma / (1 + sigma)`` on 161 Chebyshev-Lobatto nodes, each node one call of
:func:`coincli.core.averages.marginal` (the psi-average every other fit uses): the interpolant
agrees with ``marginal`` to about 1e-15 (tests/core/test_caught.py).

Each row (one tosser) is fitted alone (:func:`fit_rows`): because ``q`` is monotone in sigma,
the maximum-likelihood ``q`` is ``same / n`` clipped to ``[1/2, q(inf)]``, and the profile
likelihood interval of sigma is the likelihood-ratio set of ``q`` within that range mapped back
through ``q``.  Its critical value is boundary-aware (:func:`boundary_cut`, Feldman and
Cousins' ordering in the normal approximation): ``chi2_1(conf)`` (3.84) for a ``q`` far from the
ends of its range, falling to ``ndtri(conf)^2`` (2.71) at ``q = 1/2``, so that the coverage
stays at ``conf`` near sigma = 0 too (a plain chi2_1 cut gives 97.5% there).  Estimates at a
bound (``same/n <= 1/2``: sigma = 0; ``same/n >= q(inf)``: sigma = inf) are flagged.

Across rows (:func:`heterogeneity`): the common sigma (one spread for all tossers), the
likelihood-ratio test of one spread against one spread per tosser (chi2 with ``k - 1``
degrees of freedom), and a random-effects model ``log sigma_i ~ Normal(mu, tau)`` fitted by
maximum marginal likelihood on a grid of log sigma (``tau`` is the between-tosser sd of log
sigma; ``exp(mu)`` the median tosser's sigma).

numpy and scipy.special are imported inside the functions that need them.
"""

from __future__ import annotations

import math
from collections import namedtuple

from coincli.core._numerics.roots import brent_minimize
from coincli.core._numerics.wilson import CONFIDENCE, check_level
from coincli.core.models import HALF_PI

__all__ = [
    "CAUGHT_XI_LIMIT",
    "same_chance",
    "SameChance",
    "RowFits",
    "boundary_cut",
    "fit_rows",
    "Heterogeneity",
    "heterogeneity",
    "fair_xi",
]

#: Above this xi a faces-only row is warned about: the models give a side more than 18% of the
#: time (dynamic: 2/pi atan 0.3 = 0.186), so a coin caught on a face is no longer the paper's
#: thin coin; the chances are validated against Table I up to here.
CAUGHT_XI_LIMIT = 0.3

_NODES = 160  #: Chebyshev-Lobatto nodes in u (161 points): the interpolant is within ~1e-15


def _sigma_of(u):
    """sigma = u / (1 - u) (inf at u = 1), arrays or floats."""
    import numpy as np

    u = np.asarray(u, dtype=float)
    with np.errstate(divide="ignore"):
        return np.where(u >= 1.0, np.inf, u / np.where(u >= 1.0, 1.0, 1.0 - u))


def same_chance(xi, sigma):
    """``q = P(H) / (P(H) + P(T))`` for psi ~ Normal(pi/2, sigma) truncated to [0, pi], straight
    from :func:`coincli.core.averages.marginal` (one call per sigma; ``xi`` may be an array).
    ``sigma = 0`` is exactly 1/2 (the Keller flip), ``sigma = inf`` psi uniform."""
    import numpy as np

    from coincli.core.averages import marginal
    from coincli.core.densities import Normal, Uniform

    sigma = float(sigma)
    if not sigma >= 0:
        raise ValueError(f"sigma must be >= 0, got {sigma!r}")
    x = np.asarray(xi, dtype=float)
    if sigma == 0:
        return np.full(x.shape, 0.5) if x.ndim else 0.5
    dens = Uniform() if math.isinf(sigma) else Normal(HALF_PI, sigma)
    if x.ndim == 0:
        h, _, t = marginal(float(x), dens)
        return h / (h + t)
    if x.size <= 2:  # a float at a time: marginal's scalar path is cheaper for one or two
        out = np.empty(x.shape)
        for i, v in enumerate(x.reshape(-1).tolist()):
            h, _, t = marginal(v, dens)
            out.reshape(-1)[i] = h / (h + t)
        return out
    h, _, t = marginal(x, dens)
    return h / (h + t)


class SameChance:
    """``q(xi, sigma)`` for a few coins, as Chebyshev interpolants in ``u = sigma/(1+sigma)``.

    ``SameChance(xis)`` evaluates :func:`same_chance` at 161 nodes for every distinct coin at
    once (161 calls of ``marginal``); then :meth:`at` and :meth:`invert` take a coin index and
    ``u`` (or a target ``q``) per row, vectorized, without calling ``marginal`` again.
    """

    def __init__(self, xis):
        import numpy as np

        self.xi = np.asarray(xis, dtype=float).reshape(-1)
        k = np.arange(_NODES + 1)
        self.nodes = (1.0 - np.cos(np.pi * k / _NODES)) / 2.0  # 0 ... 1
        self.nodes[0], self.nodes[-1] = 0.0, 1.0
        w = (-1.0) ** k
        w[0] *= 0.5
        w[-1] *= 0.5
        self.weights = w
        sig = _sigma_of(self.nodes)
        self.table = np.stack([np.broadcast_to(same_chance(self.xi, s), self.xi.shape)
                               for s in sig.tolist()], axis=1)  # K x 161
        self.q_inf = self.table[:, -1].copy()
        # a dense, monotone table for the brackets of invert()
        self._dense_u = np.linspace(0.0, 1.0, 1025)
        self._dense = self._eval_all(self._dense_u)  # K x 1025

    def _eval_all(self, u):
        """Every coin at the same u's (K x len(u))."""
        import numpy as np

        u = np.asarray(u, dtype=float)
        d = u[:, None] - self.nodes[None, :]
        exact = d == 0
        with np.errstate(divide="ignore", invalid="ignore"):
            c = self.weights / d
        c = np.where(exact.any(axis=1, keepdims=True), exact.astype(float), c)
        return (self.table @ c.T) / c.sum(axis=1)[None, :]

    def at(self, k, u):
        """q at coin index ``k`` and ``u`` (arrays of one length)."""
        import numpy as np

        k = np.asarray(k, dtype=np.int64)
        u = np.asarray(u, dtype=float)
        out = np.empty(u.shape)
        step = 4096
        for a in range(0, u.size, step):
            uu, kk = u[a:a + step], k[a:a + step]
            d = uu[:, None] - self.nodes[None, :]
            exact = d == 0
            with np.errstate(divide="ignore", invalid="ignore"):
                c = self.weights / d
            c = np.where(exact.any(axis=1, keepdims=True), exact.astype(float), c)
            out[a:a + step] = np.einsum("ij,ij->i", c, self.table[kk]) / c.sum(axis=1)
        return np.clip(out, 0.5, self.q_inf[k])

    def invert(self, k, q):
        """The ``u`` with ``q(xi_k, u) = q`` (``q`` within ``[1/2, q(inf)]``), vectorized:
        a bracket from the dense table, then Illinois steps on the interpolant (to 1e-14)."""
        import numpy as np

        k = np.asarray(k, dtype=np.int64)
        q = np.asarray(q, dtype=float)
        j = np.empty(q.shape, np.int64)
        for kk in np.unique(k).tolist():
            sel = k == kk
            j[sel] = np.searchsorted(self._dense[kk], q[sel], side="left")
        j = np.clip(j, 1, len(self._dense_u) - 1)
        a, b = self._dense_u[j - 1], self._dense_u[j]
        fa, fb = self._dense[k, j - 1] - q, self._dense[k, j] - q
        side = np.zeros(q.shape)
        for _ in range(60):
            live = (b - a > 1e-14) & (np.minimum(np.abs(fa), np.abs(fb)) > 1e-16)
            if not live.any():
                break
            with np.errstate(divide="ignore", invalid="ignore"):
                c = np.where(fb != fa, b - fb * (b - a) / (fb - fa), (a + b) / 2)
            c = np.where((c > a) & (c < b), c, (a + b) / 2)
            fc = np.where(live, self.at(k, c) - q, 0.0)
            left = live & (np.sign(fc) == np.sign(fa))
            right = live & ~left
            a = np.where(left, c, a)
            fa = np.where(left, fc, np.where(right & (side == -1), fa / 2, fa))
            b = np.where(right, c, b)
            fb = np.where(right, fc, np.where(left & (side == 1), fb / 2, fb))
            side = np.where(left, 1, np.where(right, -1, side))
        return np.where(np.abs(fa) <= np.abs(fb), a, b)


class RowFits(namedtuple("RowFits", "sigma low high q_hat at_bound confidence")):
    """Each row's own spread of psi (arrays, radians): the maximum-likelihood ``sigma`` with the
    ends of its profile-likelihood interval; ``q_hat`` the fitted chance of the same side;
    ``at_bound`` -1 (sigma = 0), +1 (sigma = inf) or 0."""

    __slots__ = ()


def _cut_half(conf: float) -> float:
    """chi2_1(conf) / 2 (scipy.stats.chi2.ppf's formula, from the upper tail near 1)."""
    from scipy.special import gammainccinv, gammaincinv

    return float(gammainccinv(0.5, 1.0 - conf) if conf >= 0.5 else gammaincinv(0.5, conf))


def _binom_ll(s, d, q):
    """s ln q + d ln(1 - q) (0 ln 0 = 0)."""
    import numpy as np
    from scipy.special import xlog1py, xlogy

    with np.errstate(divide="ignore", invalid="ignore"):
        return xlogy(s, q) + xlog1py(d, -q)


def boundary_cut(delta, conf: float):
    """Half the critical value of the likelihood-ratio statistic for a chance ``delta`` standard
    errors from the nearest end of its range (Feldman and Cousins' ordering, in the normal
    approximation): for ``x ~ N(delta, 1)`` constrained to ``x >= 0`` the statistic is
    ``(x - delta)^2`` for ``x >= 0`` and ``delta^2 - 2 x delta`` below, and the set it accepts
    has probability ``Phi(sqrt c) - Phi(-(delta^2 + c) / (2 delta))`` when ``delta < sqrt c``.
    ``c`` solves that = ``conf``: ``ndtri(conf)^2`` (2.71 at 95%) at the bound, rising to
    ``chi2_1(conf)`` (3.84) from ``delta = sqrt(chi2_1(conf))`` on.  Arrays, by bisection."""
    import numpy as np
    from scipy.special import ndtr, ndtri

    delta = np.maximum(np.asarray(delta, dtype=float), 0.0)
    full = 2.0 * _cut_half(conf)
    lo = np.full(delta.shape, float(ndtri(conf)) ** 2)
    hi = np.full(delta.shape, full)
    near = delta < math.sqrt(full)
    if not near.any():
        return hi / 2
    dn = np.maximum(delta[near], 1e-300)
    a, b = lo[near], hi[near]
    for _ in range(60):
        c = (a + b) / 2
        with np.errstate(over="ignore"):
            cover = ndtr(np.sqrt(c)) - ndtr(-(dn * dn + c) / (2 * dn))
        a = np.where(cover < conf, c, a)
        b = np.where(cover < conf, b, c)
    out = hi.copy()
    out[near] = (a + b) / 2
    return out / 2


def _lr_ends(s, d, q_hat, lo, hi, conf):
    """The likelihood-ratio confidence set of q within [lo, hi]: every q0 whose statistic
    ``2 (l(q_hat) - l(q0))`` is at most the critical value of :func:`boundary_cut` at q0's
    distance from the nearer end (in standard errors ``sqrt(q0 (1 - q0) / n)``).  Its ends by
    bisection from ``q_hat`` outward, vectorized; an end stays at the bound when the bound is
    accepted."""
    import numpy as np

    top = _binom_ll(s, d, q_hat)
    n = s + d

    def accepted(q):
        se = np.sqrt(np.maximum(q * (1 - q), 1e-300) / n)
        delta = np.minimum(q - lo, hi - q) / se
        return top - _binom_ll(s, d, q) <= boundary_cut(delta, conf)

    ends = []
    for bound in (lo, hi):
        inside = accepted(bound)
        a, b = (bound.copy(), q_hat.copy())  # a: rejected (or the bound), b: accepted
        for _ in range(200):
            m = (a + b) / 2
            if np.all((m == a) | (m == b) | inside):
                break
            ok = accepted(m)
            a = np.where(ok, a, m)
            b = np.where(ok, m, b)
        ends.append(np.where(inside, bound, b))
    return ends[0], ends[1]


def fit_rows(xi, same, n, *, confidence: float = CONFIDENCE, chance: SameChance | None = None):
    """Each row's maximum-likelihood sigma of psi from ``same`` of ``n`` caught flips, with
    its profile-likelihood interval (see the module docstring).  Arrays in, :class:`RowFits`
    out (radians; inf where uniform psi is not excluded)."""
    import numpy as np

    conf = check_level(confidence, "confidence")
    xi = np.asarray(xi, dtype=float).reshape(-1)
    s = np.asarray(same, dtype=float).reshape(-1)
    m = np.asarray(n, dtype=float).reshape(-1)
    ux, k = np.unique(xi, return_inverse=True)
    k = k.ravel()
    if chance is None or not np.array_equal(chance.xi, ux):
        chance = SameChance(ux)
    # rows of one coin with the same counts share their fit: each distinct row once
    rows, inv = np.unique(np.stack([k.astype(float), s, m], axis=1), axis=0,
                          return_inverse=True)
    inv = inv.ravel()
    if len(rows) < len(s):
        f = _fit_distinct(rows[:, 0].astype(np.int64), rows[:, 1], rows[:, 2], conf, chance)
        return RowFits(*(v[inv] for v in f[:5]), conf)
    return _fit_distinct(k, s, m, conf, chance)


def _fit_distinct(k, s, m, conf, chance):
    import numpy as np

    d = m - s
    qinf = chance.q_inf[k]
    half = np.full(s.shape, 0.5)
    q_hat = np.clip(s / m, half, qinf)
    bound = np.where(s / m <= 0.5, -1, np.where(s / m >= qinf, 1, 0)).astype(np.int8)
    q_lo, q_hi = _lr_ends(s, d, q_hat, half, qinf.copy(), conf)

    def to_sigma(q, at_hi):
        u = np.where(q <= 0.5, 0.0, np.where(q >= qinf, 1.0, 0.5))
        mid = (q > 0.5) & (q < qinf)
        if mid.any():
            u[mid] = chance.invert(k[mid], q[mid])
        sig = _sigma_of(u)
        return np.where(at_hi & (q >= qinf), np.inf, sig)

    true = np.ones(s.shape, bool)
    return RowFits(to_sigma(q_hat, true), to_sigma(q_lo, ~true), to_sigma(q_hi, true),
                   q_hat, bound, conf)


class Heterogeneity(namedtuple("Heterogeneity", "sigma_common statistic df p_value mu tau "
                                                "method")):
    """Do the tossers differ?  ``sigma_common`` the one spread fitted to every caught row;
    ``statistic`` the likelihood-ratio statistic of one spread per row against it, with ``df``
    and its chi2 ``p_value``; ``mu``, ``tau`` the random-effects fit of ``log sigma_i ~
    Normal(mu, tau)`` (``exp(mu)`` the median tosser's sigma, radians; ``tau`` the sd of
    log sigma between tossers, 0 when they do not differ)."""

    __slots__ = ()


HETEROGENEITY_METHOD = ("likelihood-ratio test, one spread per tosser against one for all "
                        "(chi2, df = tossers - 1); random effects log sigma ~ normal(mu, tau), "
                        "maximum marginal likelihood")

_LOG_SIGMA_LO = math.log(math.radians(0.05))  #: the random-effects grid of log sigma ...
_LOG_SIGMA_HI = math.log(math.radians(400.0))
_GRID = 241  #: ... and its points


def heterogeneity(xi, same, n, fits: RowFits, *, chance: SameChance | None = None
                  ) -> Heterogeneity:
    """:class:`Heterogeneity` of caught rows (arrays) with their own fits ``fits``."""
    import numpy as np
    from scipy.special import chdtrc

    xi = np.asarray(xi, dtype=float)
    s = np.asarray(same, dtype=float)
    d = np.asarray(n, dtype=float) - s
    ux, k = np.unique(xi, return_inverse=True)
    k = k.ravel()
    if chance is None or not np.array_equal(chance.xi, ux):
        chance = SameChance(ux)
    # rows with the same coin and counts count once, with a weight
    key = np.stack([k.astype(float), s, d], axis=1)
    uniq, inv, wt = np.unique(key, axis=0, return_inverse=True, return_counts=True)
    kk, ss, dd, wt = uniq[:, 0].astype(np.int64), uniq[:, 1], uniq[:, 2], wt.astype(float)

    def total(u: float) -> float:
        q = chance.at(kk, np.full(len(kk), u))
        return float(np.sum(wt * _binom_ll(ss, dd, q)))

    us = np.linspace(0.0, 1.0, 41)
    ls = [total(u) for u in us]
    j = int(np.argmax(ls))
    a, b = float(us[max(j - 1, 0)]), float(us[min(j + 1, 40)])
    u_c, f_c = brent_minimize(lambda u: -total(u), a, b, xatol=1e-10)
    l_common = max(-f_c, ls[j])
    if -f_c < ls[j]:
        u_c = float(us[j])
    own = float(np.sum(_binom_ll(s, d, fits.q_hat)))
    stat = max(2.0 * (own - l_common), 0.0)
    df = len(s) - 1
    p = float(chdtrc(df, stat)) if df > 0 else 1.0
    # random effects on a grid of log sigma (Riemann weights of the normal density)
    g = np.linspace(_LOG_SIGMA_LO, _LOG_SIGMA_HI, _GRID)
    ug = np.exp(g) / (1.0 + np.exp(g))
    qg = np.stack([chance.at(np.full(len(ug), i), ug) for i in range(len(ux))])  # K x G
    ll = _binom_ll(ss[:, None], dd[:, None], qg[kk])  # U x G
    step = g[1] - g[0]
    top = ll.max(axis=1)
    lik = np.exp(ll - top[:, None])  # each row's likelihood on the grid, scaled to peak 1

    def marginal_ll(mu: float, tau: float) -> float:
        if tau <= step / 4:  # a point mass: the nearest grid point would jump; interpolate
            x = (mu - g[0]) / step
            i = int(min(max(math.floor(x), 0), _GRID - 2))
            f = min(max(x - i, 0.0), 1.0)
            row = (1 - f) * ll[:, i] + f * ll[:, i + 1]
            return float(np.sum(wt * row))
        w = np.exp(-0.5 * ((g - mu) / tau) ** 2)
        w /= w.sum()
        with np.errstate(divide="ignore"):  # a row no spread near mu can give: log 0 = -inf,
            return float(np.sum(wt * (np.log(lik @ w) + top)))  # the least likely, as it is

    def best_mu(tau: float) -> tuple[float, float]:
        mus = np.linspace(g[0], g[-1], 17)
        vals = [marginal_ll(mu, tau) for mu in mus]
        i = int(np.argmax(vals))
        lo, hi = float(mus[max(i - 1, 0)]), float(mus[min(i + 1, 16)])
        mu, f = brent_minimize(lambda x: -marginal_ll(x, tau), lo, hi, xatol=1e-6)
        return (mu, -f) if -f >= vals[i] else (float(mus[i]), vals[i])

    taus = [0.0, 0.05, 0.1, 0.2, 0.35, 0.5, 0.75, 1.0, 1.5, 2.0, 3.0]
    vals = [best_mu(t)[1] for t in taus]
    i = int(np.argmax(vals))
    lo, hi = taus[max(i - 1, 0)], taus[min(i + 1, len(taus) - 1)]
    tau, f = brent_minimize(lambda t: -best_mu(max(t, 0.0))[1], lo, hi, xatol=1e-4)
    if -f < vals[i]:
        tau = taus[i]
    tau = max(tau, 0.0)
    if tau <= step / 4 and vals[0] >= -f - 1e-9:
        tau = 0.0
    mu = best_mu(tau)[0]
    return Heterogeneity(float(_sigma_of(u_c)), stat, df, p, mu, tau, HETEROGENEITY_METHOD)


def fair_xi(sigma, p_sides: float = 1 / 3):
    """The aspect ratio whose chance of a side is ``p_sides`` under psi ~ Normal(pi/2, sigma)
    (per entry of ``sigma``; 0 is the Keller flip, inf uniform psi): each tosser's three-sided
    coin (:func:`coincli.core.averages.marginal_inverse`)."""
    import numpy as np

    from coincli.core.averages import marginal_inverse
    from coincli.core.densities import Normal, Uniform
    from coincli.core.models import dynamic_inverse

    sig = np.asarray(sigma, dtype=float).reshape(-1)
    out = np.empty(sig.shape)
    memo: dict[float, float] = {}
    for i, v in enumerate(sig.tolist()):
        if v not in memo:
            if v == 0:
                memo[v] = float(dynamic_inverse(p_sides))
            else:
                dens = Uniform() if math.isinf(v) else Normal(HALF_PI, v)
                memo[v] = float(marginal_inverse(p_sides, dens))
        out[i] = memo[v]
    return out
