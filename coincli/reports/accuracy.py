"""``--tol``, ``--method`` and ``--seed``: how the psi-averaged rows are computed, and how well.

Shared by ``coin table`` and ``coin design`` (:mod:`coincli.reports.design`).  The numbers come
from :mod:`coincli.core.estimators` (loaded only when a psi density is used); this module parses
the options (:func:`parse`, with their one-line usage errors), shares the run's budget of
simulated tosses among the densities (:class:`Budget`, :func:`plan`), runs an estimate
(:func:`run`, reporting to an optional progress bar) and words the error columns and notes.
No numpy, scipy or rich at import time.
"""

from __future__ import annotations

from typing import NamedTuple

from coincli.core.modelspec import ModelSpec
from coincli.errors import compute_error, usage_error
from coincli.io import notes
from coincli.io.options import seed_value
from coincli.io.table import Column

METHODS = ("auto", "quad", "mc", "qmc")
#: the most tosses (mc) or Sobol points (qmc) one command run simulates for --tol, shared by
#: its densities: --method mc refuses a --tol that needs more up front (the tosses a tolerance
#: needs are known from the chances); a qmc run that has not met --tol by then stops, at a
#: point that depends on the inputs and the seed alone, and says so
RUN_BUDGET = 1 << 26
RUN_SECONDS = "2.6 to 6.8 s"  #: RUN_BUDGET's CPU time here (benchmarks/bench_mc_limit.py)


class Accuracy(NamedTuple):
    """The parsed options: a tolerance, a method and (for mc, qmc) a seed."""

    tol: float | None
    method: str
    seed: int | None

    @property
    def sampling(self) -> bool:
        return self.method in ("mc", "qmc")


def parse(tol: str | None, method: str | None, seed: str | None) -> Accuracy | None:
    """The options as an :class:`Accuracy`, or None when none was given."""
    if tol is None and method is None and seed is None:
        return None
    t = None
    if tol is not None:
        from coincli.io import grammar

        try:
            t = grammar.parse_number(tol, "--tol")
            _check_tol(t)
        except ValueError as exc:
            raise usage_error(str(exc)) from None
    m = (method or "auto").strip().lower()
    if m not in METHODS:
        raise usage_error(f"--method must be one of {', '.join(METHODS)}; got {method!r}")
    s = None
    if seed is not None:
        if m not in ("mc", "qmc"):
            raise usage_error("--seed goes with --method mc or qmc (quadrature is not random)")
        s = seed_value(seed)
    elif m in ("mc", "qmc"):
        s = seed_value(None)
    return Accuracy(t, m, s)


def _check_tol(t: float) -> None:
    # the same range as coincli.core.estimators.check_tol, without importing numpy to say so
    if not 1e-16 <= t <= 0.5:
        raise ValueError(f"--tol must be in [1e-16, 0.5] (an absolute error on a chance), "
                         f"got {t!r}")


def require_density(acc: Accuracy | None, has_density: bool,
                    options: str = "--tol, --method and --seed",
                    sources: str = "--psi-dist or --all") -> None:
    if acc is not None and not has_density:
        raise usage_error(f"{options} apply to psi-averaged chances ({sources}); the closed "
                          "forms are exact")


# --------------------------------------------------------------------------- coin design


def design_model(acc: Accuracy | None, model: ModelSpec) -> ModelSpec:
    """The model ``coin design`` solves with: the quadrature order --tol picks."""
    if acc is None:
        return model
    require_density(acc, model.key == "dist", "--tol and --method", "--psi-dist")
    if acc.sampling:
        raise usage_error(f"coin design finds xi by root finding, which needs a smooth, "
                          f"deterministic chance: --method {acc.method} cannot be inverted.  "
                          f"Simulate the designed coin instead: coin table --xi XI --psi-dist "
                          f"{model.density.spec} --method {acc.method}")
    if acc.tol is None:
        return model
    from coincli.core.averages import order_for_tol

    return model.with_order(order_for_tol(acc.tol, model.density))


def design_note(acc: Accuracy | None, model: ModelSpec) -> str:
    if acc is None or acc.tol is None or model.order is None:
        return ""
    from coincli.core.averages import error_bound

    return (f"; quadrature with {model.order} nodes per subinterval for --tol {acc.tol:g} "
            f"(error <= {error_bound(model.order, model.density):.0e})")


# --------------------------------------------------------------------------- coin table

COLUMNS = [
    Column("method", "method", "text"),
    Column("err_heads", "+- heads", "g2"),
    Column("err_sides", "+- sides", "g2"),
    Column("err_tails", "+- tails", "g2"),
]
SEED_COLUMN = Column("seed", "seed", "int")  #: with --method mc or qmc: the seed of each row


def columns(acc: Accuracy, machine: bool = True) -> list:
    """The extra columns of ``coin table`` for these options: with sampling, machine output
    (csv, json, ...) also has the seed's (the human table says it in its note)."""
    return COLUMNS + ([SEED_COLUMN] if acc.sampling and machine else [])


class Budget:
    """The run's :data:`RUN_BUDGET` of tosses (or points), shared by ``densities`` in turn:
    each may use what is left divided by the densities still to come (so each gets at least
    an equal share, and a density that meets --tol early leaves the rest to the others).

    Once :meth:`plan` has the tosses each density needs (``--method mc`` with ``--tol``), each
    may use what is left but what the densities still to come need."""

    def __init__(self, densities: int, total: int | None = None):
        total = RUN_BUDGET if total is None else total
        self.left = total
        self.total = total
        self.densities = self.to_come = max(int(densities), 1)
        self.needs: list[int] | None = None

    def plan(self, needs: list[int]) -> None:
        self.needs = [int(k) for k in needs]
        self.densities = self.to_come = max(len(self.needs), 1)

    def share(self) -> int:
        if self.needs is not None:
            later = sum(self.needs[len(self.needs) - self.to_come + 1:])
            return max(self.left - later, 1)
        return max(self.left // max(self.to_come, 1), 1)

    def used(self, n: int) -> None:
        self.left = max(self.left - int(n), 0)
        self.to_come -= 1


def plan(acc: Accuracy | None, densities: list, x) -> Budget:
    """The run's :class:`Budget` for these densities at x (a float or an array of xi).

    With ``--method mc`` and ``--tol`` the tosses each density needs are known before a toss
    is made: Wilson's half-width is a function of the chances (found by quadrature, in
    milliseconds) and the number of tosses.  A --tol whose tosses, summed over the densities,
    exceed the run's limit is refused here, naming the smallest --tol that fits."""
    budget = Budget(len(densities))
    if acc is None or acc.method != "mc" or acc.tol is None or not densities:
        return budget
    from coincli.core import estimators

    try:
        spreads = [estimators.chance_spread(estimators.quad(x, d, tol=1e-9).value)
                   for d in densities]
    except ValueError as exc:
        raise compute_error(str(exc)) from None
    needs = [estimators.mc_tosses_for_tol(s, acc.tol) for s in spreads]
    if sum(needs) > budget.total:
        smallest = estimators.mc_smallest_tol(spreads, budget.total)
        shared = f" shared by {len(densities)} densities" if len(densities) > 1 else ""
        raise usage_error(
            f"--tol {acc.tol:g} needs about {sum(needs):.2g} simulated tosses with --method "
            f"mc, over the run's limit of {budget.total} tosses{shared} (about "
            f"{RUN_SECONDS} of CPU): the smallest --tol that fits is {smallest:g} (--method "
            f"qmc goes further; --method auto or quad reaches any --tol down to 1e-16)")
    budget.plan(needs)
    return budget


def run(acc: Accuracy, density, x, n: int, budget: Budget | None = None, progress=None):
    """(Outcome, per-row extra cells) for one density at x (a float or an array of n xi).

    A sampling method with --tol draws at most ``budget.share()`` tosses (or points).
    ``progress``, when given, makes the run's progress bar from its label (``mc uniform``):
    ``bar(done, total)`` during the run, ``bar.close()`` after it."""
    from coincli.core import estimators

    if budget is None:
        budget = Budget(1)
    bar = None if progress is None else progress(f"{acc.method} {density.spec}")
    try:
        e = estimators.estimate(x, density, tol=acc.tol, method=acc.method, seed=acc.seed,
                         max_samples=budget.share(), progress=bar)
    except ValueError as exc:
        raise compute_error(str(exc)) from None
    finally:
        if bar is not None:
            bar.close()
    if acc.sampling:
        budget.used(e.n)
    if e.method == "quad":  # the calibrated bound itself
        halves = [tolist(v, n) for v in e.error]
    else:
        halves = [tolist(_max(_sub(hi, v), _sub(v, lo)), n)
                  for v, lo, hi in zip(e.value, e.low, e.high, strict=True)]
    if e.method == "quad":
        how = f"quad n={e.n}"
    elif e.method == "mc":
        how = f"mc {e.n} tosses"
    else:
        how = f"qmc {e.n} points"
    if acc.tol is not None and not e.met:
        worst = max(max(h) for h in halves)
        if acc.sampling:
            shared = (f", shared by {budget.densities} densities" if budget.densities > 1
                      else "")
            why = (f": --tol not met; it stopped at the run's limit of {budget.total} "
                   f"{'tosses' if acc.method == 'mc' else 'points'}{shared}")
        else:
            why = "; that is the double-precision limit"
        _warn(f"{density.spec}: {e.method} reached +-{worst:.2g} ({e.detail}), not --tol "
              f"{acc.tol:g}{why}")
    seed = (acc.seed,) if acc.sampling else ()
    extra = [(how, halves[0][k], halves[1][k], halves[2][k], *seed) for k in range(n)]
    return e.value, extra


def note(acc: Accuracy) -> str:
    parts = ["; +- = half-width of a 95% interval"]
    if acc.method == "mc":
        parts.append(f" (Wilson; seed {acc.seed})")
    elif acc.method == "qmc":
        parts.append(f" (t over 16 scrambles; seed {acc.seed})")
    else:
        parts.append(" or the quadrature's calibrated error bound")
    if acc.tol is not None:
        parts.append(f"; --tol {acc.tol:g}")
    return "".join(parts)


def _sub(a, b):
    return a - b


def _max(a, b):
    if isinstance(a, float):
        return max(a, b)
    import numpy as np

    return np.maximum(a, b)


def tolist(v, n):
    """``v`` as a list of ``n`` values: an array's, or a float (or None) ``n`` times."""
    return v.tolist() if hasattr(v, "tolist") and not isinstance(v, float) else [v] * n


def _warn(message: str) -> None:
    notes.warning(message)
