"""A table calibrated from tosses: its restitution and friction (and the spread of psi) estimated
by maximum likelihood from the counts of a few prototypes tossed on it.

Each evaluation of the likelihood would be a simulation, so the likelihood is read off a smooth
**response surface** fitted to simulations run once, on a designed set of table parameters:

1. **Design** (:func:`design_points`): a grid over the parameters' ranges (:data:`RANGES`), in
   coordinates where the chances vary smoothly (restitution, ln friction, psi spread in
   degrees), each scaled to [-1, 1].
2. **Common random numbers** (:func:`run_design`): prototype ``j`` is tossed at every design
   point with the same launches: :func:`coincli.core.bounce.runs.simulate` with the seed and
   the stream ``(j, g)`` for group ``g`` of :data:`GROUPS`; only the table changes from one
   point to the next, so the surface sees the table's effect, not the launches' noise.
3. **Surface** (:func:`fit_surface`): per prototype, a multinomial logit of (heads, sides,
   tails) with the terms of a cubic (:func:`default_degree`) in the scaled parameters, by
   maximum likelihood.
4. **Data** (:func:`fit_table`): the counts' multinomial log-likelihood on the surface,
   maximized over a fine grid then polished; 95% profile-likelihood intervals.
5. **The surface's own error**: a delete-one-group jackknife.  The groups of launches are
   independent (the design points within a group are not: they share launches), so the
   surface is refitted without each group in turn and the estimate recomputed; the spread of
   those estimates (times ``(G - 1) / G``, its quantile from Student's t with ``G - 1`` df) is
   added in quadrature to each side of the profile interval.
6. **Goodness of fit**: Pearson's statistic of the counts against the fitted chances, each
   prototype's cells weighted by the multinomial covariance plus the surface's (jackknife),
   chi-square on (cells - parameters) degrees of freedom; the deviance too.
7. **Identifiability**: a parameter whose interval runs from one end of its range to the
   other is not pinned by the data; two whose joint region is a thin curve are not told apart:
   the tables along that curve (the profile path) fit equally well (:attr:`TableFit.ridge`).

Numbers in, records out; numpy and scipy only inside the functions.  The simulator is a
parameter (:func:`run_design` ``simulate``), so the statistics are tested on known surfaces
without the engine.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

__all__ = ["PARAMS", "RANGES", "GROUPS", "METHOD", "design_points", "run_design",
           "fit_surface", "Surface", "fit_table", "TableFit", "to_coords", "from_coords"]

#: the parameters a table calibration may fit, in their order
PARAMS = ("restitution", "friction", "psi_sd_deg")
#: the designed range of each, in its natural unit: restitution (the engine allows 0.06 to
#: 0.95; at 0.9 a third to nine tenths of the tosses were still moving at 10 s, a biased
#: remainder that pulled the round trip's estimates into that corner), sliding friction (wood
#: 0.3, felt 0.6, rice 0.8), the sd of psi about 90 deg (the hand toss: 10; a caught coin's
#: same-side bias, 0.508, is about 8)
RANGES = {"restitution": (0.06, 0.8), "friction": (0.05, 1.0), "psi_sd_deg": (2.0, 30.0)}
#: friction is designed and fitted in ln: its effect is about even per factor, not per unit
_LOG = {"friction"}
#: independent groups of launches at every design point (the jackknife's groups)
GROUPS = 16
#: the method, as the output names it
METHOD = ("response surface (cubic multinomial logit; quadratic with psi-spread; common random "
          "numbers) + minimum chi-square with the surface's jackknife variance and its lack of "
          "fit + profile intervals")


def to_coords(name: str, value: float) -> float:
    """``value`` of parameter ``name`` in its scaled coordinate (its range is [-1, 1])."""
    lo, hi = RANGES[name]
    f = math.log if name in _LOG else float
    return 2.0 * (f(value) - f(lo)) / (f(hi) - f(lo)) - 1.0


def from_coords(name: str, u: float) -> float:
    """The natural value of parameter ``name`` at scaled coordinate ``u``."""
    lo, hi = RANGES[name]
    if name in _LOG:
        return math.exp(math.log(lo) + (u + 1.0) / 2.0 * (math.log(hi) - math.log(lo)))
    return lo + (u + 1.0) / 2.0 * (hi - lo)


def design_points(k: int, levels: int | None = None) -> list[tuple]:
    """A full grid of ``levels`` evenly spaced values on [-1, 1] in each of ``k`` scaled
    coordinates (default 5 levels for one or two parameters, 3 for three)."""
    import itertools

    levels = levels or (5 if k <= 2 else 3)
    axis = [-1.0 + 2.0 * i / (levels - 1) for i in range(levels)]
    return [tuple(p) for p in itertools.product(axis, repeat=k)]


def _terms(u, degree=2):
    """The polynomial's terms of scaled coordinates ``u`` (rows, k columns): 1, u_i, u_i u_j
    (and u_i u_j u_l for ``degree`` 3)."""
    import itertools

    import numpy as np

    u = np.atleast_2d(np.asarray(u, dtype=float))
    k = u.shape[1]
    cols = [np.ones(u.shape[0])]
    for d in range(1, degree + 1):
        for combo in itertools.combinations_with_replacement(range(k), d):
            cols.append(np.prod(u[:, list(combo)], axis=1))
    return np.column_stack(cols)


def default_degree(k: int) -> int:
    """The surface's degree for ``k`` parameters: cubic on the 4 x 4 (or 5-level) design of one
    or two (the engine's round trip at 1000 tosses a prototype held the truth in 20 and 19 of
    20 intervals against 18 and 17 for a quadratic), quadratic on the 3-level design of
    three."""
    return 3 if k <= 2 else 2


def _degree(coef, k):
    """The degree of a surface's coefficients (2, terms) in ``k`` coordinates."""
    n = len(coef[0])
    for d in (1, 2, 3, 4):
        if math.comb(k + d, d) == n:
            return d
    raise ValueError(f"{n} coefficients are no polynomial in {k} coordinates")


# --------------------------------------------------------------------------- simulations


def _simulate_point(task):
    """One design point of one prototype, every group: a list of (heads, sides, tails,
    unsettled).  Module-level, so that a process pool pickles it by name."""
    simulate, xi, params, m, seed, j, groups, kw = task
    return [simulate(xi, params, m, seed, (j, g), kw) for g in range(groups)]


def _describe_point(task) -> str:
    """A design point's tosses, for a message (a cluster's task that killed every worker)."""
    _, xi, params, m, seed, j, groups, _ = task
    table = ", ".join(f"{k} {v:.4g}" for k, v in params.items())
    return (f"the {m * groups} tosses of prototype {j + 1} (xi {xi:g}) on the designed table "
            f"{table} (seed {seed})")


def _point_fits(task, result) -> bool:
    """Whether ``result`` (a checkpoint's counts) has the shape of this point's: a group of
    ``m`` tosses for each of its ``groups``."""
    _, _, _, m, _, _, groups, _ = task
    return len(result) == groups and all(sum(group) == m for group in result)


_simulate_point.describe = _describe_point
_simulate_point.fits = _point_fits


def engine_simulate(xi, params, n, seed, stream, kw):
    """The engine's counts (heads, sides, tails, unsettled) of ``n`` tosses of a coin of aspect
    ratio ``xi`` onto a table of ``params`` (restitution, friction, psi_sd_deg if fitted) and
    the fixed values of ``kw`` (``torsional``, ``rolling``, ``psi`` when not fitted, and the
    keyword arguments of :func:`coincli.core.bounce.runs.simulate`)."""
    from coincli.core.bounce.engine import surface
    from coincli.core.bounce.runs import simulate
    from coincli.core.toss.launch import Dist

    kw = dict(kw)
    surf = surface(None, restitution=params["restitution"], friction=params["friction"],
                   torsional=kw.pop("torsional"), rolling=kw.pop("rolling"))
    if "psi_sd_deg" in params:
        kw["psi"] = Dist("normal", math.pi / 2, math.radians(params["psi_sd_deg"]), 0.0,
                         math.pi)
    r = simulate(n, seed, xi=xi, surf=surf, jobs=1, stream=stream, **kw)
    return (*r.counts[:3], r.counts[3])


def run_design(prototypes, names, points, *, seed, per_group, groups=GROUPS, fixed=None,
               jobs=1, simulate: Callable | None = None, progress=None, executor=None):
    """The counts of every prototype at every design point: an int array of shape
    (prototypes, points, groups, 4) (heads, sides, tails, unsettled).

    ``prototypes``: aspect ratios; ``names``: the parameters designed (of :data:`PARAMS`);
    ``points``: scaled coordinates (:func:`design_points`); ``per_group`` tosses in each of
    ``groups`` groups, group ``g`` of prototype ``j`` seeded ``(seed, j, g)`` at every point
    (common random numbers); ``fixed``: the values passed through to ``simulate`` (default
    :func:`engine_simulate`); ``jobs`` worker processes (the counts do not depend on it);
    ``progress(done, total)`` after each point.  ``executor`` (a checkpoint,
    :mod:`coincli.io.checkpoint`, or a Dask cluster, :mod:`coincli.core.bounce.cluster`)
    supplies points first (``executor.tasks(fn, items)``, or a cluster's ``run``); the rest run
    here and are handed to ``executor.keep(k, counts)``."""
    import numpy as np

    simulate = simulate or engine_simulate
    fixed = dict(fixed or {})
    tasks = []
    for j, xi in enumerate(prototypes):
        for p in points:
            params = {n: from_coords(n, u) for n, u in zip(names, p, strict=True)}
            tasks.append((simulate, float(xi), params, int(per_group), seed, j, groups, fixed))
    out = [None] * len(tasks)
    done, keep = 0, None
    if executor is not None:  # points from a checkpoint or a cluster; the rest run here
        supply = getattr(executor, "tasks", None) or executor.run
        for i, res in supply(_simulate_point, list(enumerate(tasks))):
            out[i] = res
            done += 1
            if progress is not None:
                progress(done, len(tasks))
        keep = getattr(executor, "keep", None)
    todo = [i for i in range(len(tasks)) if out[i] is None]
    if not todo:
        pass
    elif jobs <= 1 or len(todo) == 1:
        for i in todo:
            out[i] = _simulate_point(tasks[i])
            done += 1
            if keep is not None:
                keep(i, out[i])
            if progress is not None:
                progress(done, len(tasks))
    else:
        import multiprocessing as mp

        from coincli.core.bounce.runs import worker_init  # noqa: F401  (the engine imports)

        ctx = mp.get_context("fork" if "fork" in mp.get_all_start_methods() else "spawn")
        pool = ctx.Pool(min(jobs, len(todo)), initializer=_quiet_worker)
        try:
            for i, res in zip(todo, pool.imap(_simulate_point, [tasks[i] for i in todo]),
                              strict=True):
                out[i] = res
                done += 1
                if keep is not None:
                    keep(i, res)
                if progress is not None:
                    progress(done, len(tasks))
        except BaseException:
            pool.terminate()
            pool.join()
            raise
        pool.close()
        pool.join()
    arr = np.array(out, dtype=np.int64).reshape(len(prototypes), len(points), groups, 4)
    return arr


def _quiet_worker():
    import signal

    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C is the parent's, which ends the pool


# --------------------------------------------------------------------------- the surface


@dataclass
class Surface:
    """One prototype's fitted chances across the table's parameters: ``log(p_sides/p_heads)``
    and ``log(p_tails/p_heads)`` quadratic in the scaled coordinates (:func:`_terms`)."""

    coef: object  #: array (2, terms)
    deviance: float  #: of the surface against its design counts
    df: int
    p_value: float  #: of that lack of fit (chi-square)

    def probs(self, u):
        """(heads, sides, tails) chances at scaled coordinates ``u`` (rows): an (n, 3) array."""
        import numpy as np

        u = np.atleast_2d(u)
        return _probs(self.coef, _terms(u, _degree(self.coef, u.shape[1])))


def _probs(coef, X):
    import numpy as np

    eta = X @ np.asarray(coef).T  # (n, 2)
    m = np.maximum(eta.max(axis=1), 0.0)
    e0 = np.exp(-m)
    e1 = np.exp(eta[:, 0] - m)
    e2 = np.exp(eta[:, 1] - m)
    s = e0 + e1 + e2
    return np.column_stack([e0 / s, e1 / s, e2 / s])


def fit_surface(points, counts, ridge=1e-6, degree=2) -> Surface:
    """The multinomial logit of :class:`Surface` fitted by Newton's method to ``counts`` (an
    array (points, 3): heads, sides, tails) at ``points`` (scaled coordinates).  ``ridge``: a
    tiny penalty that keeps a cell never seen from sending its coefficients to infinity."""
    import numpy as np
    from scipy.stats import chi2

    X = _terms(points, degree)
    y = np.asarray(counts, dtype=float)[:, :3]
    n = y.sum(axis=1)
    k = X.shape[1]
    coef = np.zeros((2, k))
    f = (y + 0.5) / (n[:, None] + 1.5)
    coef[0] = np.linalg.lstsq(X, np.log(f[:, 1] / f[:, 0]), rcond=None)[0]
    coef[1] = np.linalg.lstsq(X, np.log(f[:, 2] / f[:, 0]), rcond=None)[0]
    pen = ridge * float(n.sum())

    def objective(c):
        p = np.clip(_probs(c, X), 1e-300, 1.0)
        return -float(np.sum(y * np.log(p))) + 0.5 * pen * float(np.sum(c * c))

    old = objective(coef)
    for _ in range(100):
        p = _probs(coef, X)
        r = y[:, 1:] - n[:, None] * p[:, 1:]  # (points, 2)
        grad = np.concatenate([X.T @ r[:, 0], X.T @ r[:, 1]]) - pen * coef.ravel()
        w11 = n * p[:, 1] * (1 - p[:, 1])
        w22 = n * p[:, 2] * (1 - p[:, 2])
        w12 = -n * p[:, 1] * p[:, 2]
        H = np.block([[X.T @ (w11[:, None] * X), X.T @ (w12[:, None] * X)],
                      [X.T @ (w12[:, None] * X), X.T @ (w22[:, None] * X)]])
        H += pen * np.eye(2 * k)
        step = np.linalg.solve(H, grad).reshape(2, k)
        t = 1.0
        while True:  # damped Newton: the objective never rises
            new = coef + t * step
            val = objective(new)
            if val <= old + 1e-12 or t < 1e-6:
                break
            t /= 2
        done = abs(old - val) < 1e-10 * max(1.0, abs(old))
        coef, old = new, val
        if done:
            break
    p = _probs(coef, X)
    with np.errstate(divide="ignore", invalid="ignore"):
        dev = 2 * float(np.sum(np.where(y > 0, y * np.log(y / (n[:, None] * p)), 0.0)))
    df = 2 * X.shape[0] - 2 * k
    return Surface(coef, dev, df, float(chi2.sf(dev, df)) if df > 0 else math.nan)


# --------------------------------------------------------------------------- the data


@dataclass
class TableFit:
    """Result of :func:`fit_table`: per parameter (``names``), the estimate and its interval
    in natural units, and what they are made of."""

    names: tuple
    estimate: dict  #: name -> value
    low: dict  #: the interval: profile of Q, the surface's error included
    high: dict
    data_low: dict  #: the same profile with the surface taken as exact (its error left out)
    data_high: dict
    at_edge: dict  #: name -> "low", "high", "both" or "": the interval reaches the range's end
    covariance: list  #: of the scaled coordinates at the estimate (inverse of half Q's Hessian)
    statistic: float  #: Q at the estimate: the goodness of fit
    deviance: float  #: the multinomial deviance of the data against the fitted chances
    df: int
    p_value: float
    pinned: list  #: the parameters the data pin (their interval does not span the range)
    ridge: list  #: when not all pinned: natural parameters along the curve of equal fit
    predicted: list  #: per prototype: (p_heads, p_sides, p_tails) at the estimate
    surfaces: list  #: the :class:`Surface` of every prototype (all groups)
    surface_share: dict  #: name -> the share of the interval's width due to the surface's error
    profile: dict = field(default_factory=dict)  #: name -> (natural values, profile of Q)
    level: float = 0.95
    tau2: list = field(default_factory=list)  #: per prototype: the surface's lack of fit
    #: P(chi-square on every free cell > Q at the estimate): at the true table Q is that
    #: chi-square and the estimate's Q is no larger, so this bounds the chance that a table in
    #: the range gives counts this far off; it tests the fit even with no df left
    reach_p: float = math.nan


def _cells(datum):
    """The free cells of one prototype's counts: sides and tails (faces told apart), or
    sides (out of n), their indices among (heads, sides, tails), and n."""
    import numpy as np

    h, s, t, n = datum
    if h is None:
        return np.array([s], dtype=float), [1], float(n)
    return np.array([s, t], dtype=float), [1, 2], float(n)


class _Objective:
    """Q(u) = sum over prototypes of r' V^-1 r, r = observed cells - n p(u) and V = n (1 + n
    tau2) (diag p - p p') + n^2 S(u), S the jackknife covariance of the surface's chances at u
    and tau2 the prototype's discrepancy (:func:`discrepancy`; both zero with
    ``surface_error=False``): a chi-square whose minimum is the estimate and whose rise is the
    profile."""

    def __init__(self, full, jack, data, surface_error=True, tau2=None):
        self.full, self.jack, self.data, self.err = full, jack, data, surface_error
        self.tau2 = list(tau2) if tau2 is not None else [0.0] * len(data)

    def __call__(self, u):
        import numpy as np

        X = _terms(u, _degree(self.full[0], np.atleast_2d(u).shape[1]))
        G = len(self.jack)
        q = np.zeros(X.shape[0])
        for j, datum in enumerate(self.data):
            obs, idx, n = _cells(datum)
            p = _probs(self.full[j], X)[:, idx]  # (m, c)
            V = n * (p[:, :, None] * np.eye(len(idx))[None] - p[:, :, None] * p[:, None, :])
            if self.err:
                V = V * (1.0 + n * self.tau2[j])  # the surface's lack of fit (discrepancy)
                pj = np.stack([_probs(c[j], X)[:, idx] for c in self.jack])  # (G, m, c)
                d = pj - pj.mean(axis=0)
                V = V + n * n * (G - 1) / G * np.einsum("gma,gmb->mab", d, d)
            V = V + 1e-9 * n * np.eye(len(idx))[None]
            r = obs[None, :] - n * p
            q += np.einsum("ma,ma->m", r, np.linalg.solve(V, r[:, :, None])[:, :, 0])
        return q


def _minimize(obj, k):
    """The minimum of ``obj`` over [-1, 1]^k: a grid (kept for the profiles), then a bounded
    polish.  Returns (u, Q(u), grid values, grid axis)."""
    import numpy as np
    from scipy.optimize import minimize

    axis, G = _grid(k)
    q = obj(G)
    best = G[int(np.argmin(q))]
    res = minimize(lambda u: float(obj(u[None, :])[0]), best, method="L-BFGS-B",
                   bounds=[(-1.0, 1.0)] * k)
    u = res.x if res.fun <= q.min() else best
    return np.asarray(u, dtype=float), float(min(res.fun, q.min())), q, axis


def _grid(k):
    import numpy as np

    m = {1: 1001, 2: 121, 3: 35}[k]
    axis = np.linspace(-1.0, 1.0, m)
    mesh = np.meshgrid(*([axis] * k), indexing="ij")
    return axis, np.column_stack([g.ravel() for g in mesh])


def _profile(q, axis, k, i, low):
    """The profile of Q along coordinate ``i``: its minimum over the others, less ``low``."""
    import numpy as np

    cube = q.reshape([axis.size] * k)
    other = tuple(a for a in range(k) if a != i)
    prof = cube.min(axis=other) if other else cube
    return np.maximum(prof - low, 0.0)


def _crossings(axis, dev, at, crit):
    """The smallest interval holding every u with dev(u) <= crit (a profile with two valleys
    gives one interval over both), its ends interpolated linearly on the grid; an end that
    does not cross stays at -1 or 1."""
    import numpy as np

    inside = np.nonzero(dev <= crit)[0]
    if inside.size == 0:
        return float(at), float(at)
    i, j = int(inside[0]), int(inside[-1])
    lo = -1.0 if i == 0 else float(axis[i - 1] + (crit - dev[i - 1]) / (dev[i] - dev[i - 1])
                                   * (axis[i] - axis[i - 1]))
    hi = 1.0 if j == axis.size - 1 else float(axis[j] + (crit - dev[j]) / (dev[j + 1] - dev[j])
                                              * (axis[j + 1] - axis[j]))
    return float(min(lo, at)), float(max(hi, at))


def discrepancy(surface: Surface, tosses_per_point: float) -> float:
    """The surface's lack of fit as a variance: tau2 such that the true chances at a table
    scatter about the surface's with covariance tau2 (diag p - p p').  A surface that follows
    the simulated chances leaves a deviance of about its df (the design points' counts are
    multinomial, common random numbers or not); a dispersion phi = deviance / df above 1 is
    read as 1 + m tau2 with m the tosses a design point (quasi-likelihood's dispersion), so
    tau2 = (phi - 1) / m, and 0 when phi <= 1.  Your n tosses then vary about the surface
    with n (1 + n tau2) (diag p - p p'): a bias the jackknife cannot see becomes a variance
    that grows with n as a bias's weight does."""
    if surface.df <= 0 or tosses_per_point <= 0:
        return 0.0
    return max(0.0, surface.deviance / surface.df - 1.0) / tosses_per_point


def fit_table(names, points, counts, data, *, level=0.95, degree=None,
              lack_of_fit=True) -> TableFit:
    """Estimate the table's parameters ``names`` from ``data`` (per prototype (heads, sides,
    tails, n); heads and tails None when only sides out of n were counted) on the surfaces
    fitted to ``counts`` (:func:`run_design`'s array) at ``points``: the minimum of Q
    (:class:`_Objective`), each parameter's interval where Q's profile rises by the chi-square
    quantile (1 df), the goodness of fit Q at its minimum on (cells - parameters) df.
    ``lack_of_fit``: carry each surface's lack of fit (:func:`discrepancy`) with its jackknife
    variance (False: the jackknife only, for comparison)."""
    import numpy as np
    from scipy.stats import chi2

    names = tuple(names)
    k = len(names)
    if degree is None:
        degree = default_degree(k)
    counts = np.asarray(counts)
    P, _, G, _ = counts.shape
    if len(data) != P:
        raise ValueError("one count of tosses per prototype")
    # unsettled tosses are left out, as everywhere; leaving out the designed tables where many
    # are unsettled made the engine's round trip worse (the quadratic then extrapolates there)
    pooled = counts.sum(axis=2)  # (P, points, 4)
    surfaces = [fit_surface(points, pooled[j], degree=degree) for j in range(P)]
    full = [s.coef for s in surfaces]
    jack = []
    for g in range(G):
        keep = [h for h in range(G) if h != g]
        jack.append([fit_surface(points, counts[j][:, keep].sum(axis=1), degree=degree).coef
                     for j in range(P)])
    tau2 = [discrepancy(s, float(pooled[j][:, :3].sum(axis=1).mean())) if lack_of_fit else 0.0
            for j, s in enumerate(surfaces)]
    obj = _Objective(full, jack, data, tau2=tau2)
    u_hat, q_hat, q, axis = _minimize(obj, k)
    exact = _Objective(full, jack, data, surface_error=False)
    u_exact, q_exact, q0, _ = _minimize(exact, k)
    crit = float(chi2.ppf(level, 1))
    est, low, high, dlow, dhigh, edge, profile, share = {}, {}, {}, {}, {}, {}, {}, {}
    for i, name in enumerate(names):
        dev = _profile(q, axis, k, i, q_hat)
        lo, hi = _crossings(axis, dev, u_hat[i], crit)
        dev0 = _profile(q0, axis, k, i, q_exact)
        lo0, hi0 = _crossings(axis, dev0, u_exact[i], crit)
        est[name] = from_coords(name, float(u_hat[i]))
        low[name], high[name] = from_coords(name, lo), from_coords(name, hi)
        dlow[name], dhigh[name] = from_coords(name, lo0), from_coords(name, hi0)
        edge[name] = {(True, True): "both", (True, False): "low", (False, True): "high",
                      (False, False): ""}[(lo <= -0.999, hi >= 0.999)]
        w, w0 = hi - lo, hi0 - lo0
        share[name] = float(max(0.0, 1.0 - (w0 / w) ** 2)) if w > 0 else 0.0
        step = max(1, axis.size // 100)
        profile[name] = ([from_coords(name, float(a)) for a in axis[::step]],
                         [float(d) for d in dev[::step]])
    # half Q's Hessian at the estimate: the information, scaled coordinates
    h = 1e-3

    def f(u):
        return float(obj(np.clip(u, -1.0, 1.0)[None, :])[0])

    H = np.zeros((k, k))
    eye = np.eye(k) * h
    for a in range(k):
        for b in range(k):
            H[a, b] = (f(u_hat + eye[a] + eye[b]) - f(u_hat + eye[a] - eye[b])
                       - f(u_hat - eye[a] + eye[b]) + f(u_hat - eye[a] - eye[b])) / (8 * h * h)
    try:
        cov = np.linalg.inv(H)
        if not np.all(np.isfinite(cov)) or np.any(np.diag(cov) <= 0):
            raise np.linalg.LinAlgError
    except np.linalg.LinAlgError:  # flat in some direction: the interval's width instead
        cov = np.diag([((to_coords(n, high[n]) - to_coords(n, low[n])) / 3.92) ** 2
                       for n in names])
    pred = [_probs(c, _terms(u_hat[None, :], degree))[0] for c in full]
    cells = sum(len(_cells(d)[1]) for d in data)
    dev_total = 0.0
    for p, (hh, ss, tt, n) in zip(pred, data, strict=True):
        full_obs = np.array([hh, ss, tt] if hh is not None else [n - ss, ss], dtype=float)
        pf = p if hh is not None else np.array([1 - p[1], p[1]])
        with np.errstate(divide="ignore", invalid="ignore"):
            dev_total += 2 * float(np.sum(np.where(full_obs > 0,
                                                   full_obs * np.log(full_obs / (n * pf)), 0.0)))
    df = cells - k
    p_value = float(chi2.sf(q_hat, df)) if df > 0 else math.nan
    pinned = [n for n in names if edge[n] != "both"
              and to_coords(n, high[n]) - to_coords(n, low[n]) < 1.5]
    ridge = []
    if k >= 2 and len(pinned) < k:
        # the curve of equally good tables: along the first parameter, the best of the others
        flat = q.reshape(axis.size, -1)
        best = flat.argmin(axis=1)
        inside = np.nonzero(flat.min(axis=1) - q_hat <= crit)[0]
        if inside.size:
            picks = inside[np.linspace(0, inside.size - 1, min(5, inside.size)).astype(int)]
            rest = np.array(np.unravel_index(best[picks], [axis.size] * (k - 1))).T
            for a, r in zip(picks, rest, strict=True):
                u = [axis[a], *(axis[b] for b in r)]
                ridge.append(tuple(from_coords(n, float(v))
                                   for n, v in zip(names, u, strict=True)))
    return TableFit(names, est, low, high, dlow, dhigh, edge, cov.tolist(), q_hat, dev_total,
                    df, p_value, pinned, ridge, [tuple(float(x) for x in p) for p in pred],
                    surfaces, share, profile, level, tau2, float(chi2.sf(q_hat, cells)))
