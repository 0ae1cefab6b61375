"""Observed tosses: validated counts, a row of experiments, and the binomial law of the counts.

Counts
    ``(heads, sides, tails)`` when the faces were told apart (a trinomial), or ``sides`` out of
    ``n`` when they were not (a binomial: side or face).  :func:`make_counts` validates them
    (:class:`CountsError` names the offending argument); :func:`check_probs` validates the
    chances a model gives them.  :class:`Experiment` is one coin's ``xi`` with its counts (a row
    of an experiments file, read by :mod:`coincli.io.experiments`); :class:`CountColumns` holds
    the counts of many experiments as arrays.

Binomial law
    Log-factorials (:class:`LogFactorial`), the binomial log-pmf and both tails, vectorized
    numpy over scipy.special: the pieces of the exact tests (:mod:`coincli.core.stats.tests`)
    and of the likelihoods of the fit (:mod:`coincli.core.stats.fit`).

numpy and scipy.special are imported inside the functions that need them (the CLI's start-up
budget).  Nothing here prints.
"""

from __future__ import annotations

import math
from collections import namedtuple
from collections.abc import Sequence

__all__ = [
    "MAX_COUNT",
    "CountsError",
    "Counts",
    "make_counts",
    "Caught",
    "make_caught",
    "Experiment",
    "ExperimentColumns",
]


# --------------------------------------------------------------------------- validation


#: The largest count of tosses (every count is exact in a double up to here)
MAX_COUNT = 2**53


def whole_count(value, name: str) -> int | None:
    """A count: None, or a whole number >= 0 (int, or a float/numpy number with no fraction)."""
    if value is None:
        return None
    if isinstance(value, (bool, str, bytes)):
        raise ValueError(f"{name} must be a whole number >= 0, got {value!r}")
    import operator

    try:
        v = operator.index(value)  # int and numpy integers
    except TypeError:
        v = None
    if v is None:
        try:
            f = float(value)
        except (TypeError, ValueError):
            raise ValueError(f"{name} must be a whole number >= 0, got {value!r}") from None
        if not math.isfinite(f) or f != math.floor(f) or abs(f) > 2.0**53:
            raise ValueError(f"{name} must be a whole number >= 0, got {value!r}")
        v = int(f)
    if v < 0:
        raise ValueError(f"{name} must be a whole number >= 0, got {value!r}")
    if v > MAX_COUNT:
        raise ValueError(f"{name} must be a whole number from 0 to {MAX_COUNT} (2**53), "
                         f"got {value!r}")
    return int(v)


class CountsError(ValueError):
    """A bad count; ``argument`` names the offending one (heads, sides, tails or n)."""

    def __init__(self, message: str, argument: str):
        super().__init__(message)
        self.argument = argument


class Counts(namedtuple("Counts", "n sides heads tails", defaults=(None, None))):
    """Observed tosses: ``sides`` of ``n``, and ``heads``/``tails`` when faces were told apart."""

    # n: int
    # sides: int
    # heads: int | None
    # tails: int | None
    __slots__ = ()

    @property
    def faces(self) -> bool:
        """True when heads and tails were counted separately (a trinomial observation)."""
        return self.heads is not None

    @property
    def categories(self) -> tuple[str, ...]:
        return ("heads", "sides", "tails") if self.faces else ("sides", "faces")

    @property
    def values(self) -> tuple[int, ...]:
        """The counts in the order of :attr:`categories`."""
        if self.faces:
            return (self.heads, self.sides, self.tails)
        return (self.sides, self.n - self.sides)


def make_counts(heads=None, sides=None, tails=None, n=None) -> Counts:
    """Validate observed counts and return :class:`Counts`.

    Give ``heads``, ``sides`` and ``tails`` (``n`` optional, then it must be their sum), or
    ``sides`` and ``n`` when the faces were not told apart.  One of heads/tails with ``n`` fixes
    the other.  Every count must be a whole number >= 0 and ``n`` must be >= 1.

    Raises
    ------
    CountsError (a ValueError)
        Naming the argument, e.g. ``heads must be a whole number >= 0, got -1``.

    >>> make_counts(35, 33, 32)
    Counts(n=100, sides=33, heads=35, tails=32)
    >>> make_counts(sides=33, n=100)
    Counts(n=100, sides=33, heads=None, tails=None)
    """
    vals = {}
    for name, v in (("heads", heads), ("sides", sides), ("tails", tails), ("n", n)):
        try:
            vals[name] = whole_count(v, name)
        except ValueError as exc:
            raise CountsError(str(exc), name) from None
    h, s, t, m = vals["heads"], vals["sides"], vals["tails"], vals["n"]
    if s is None:
        raise CountsError("sides is required (the number of tosses that landed on a side)",
                          "sides")
    if (h is None) != (t is None):
        given, missing = ("heads", "tails") if t is None else ("tails", "heads")
        if m is None:
            raise CountsError(f"{given} was given without {missing}; give both, or n", missing)
        other = m - s - (h if h is not None else t)
        if other < 0:
            raise CountsError(
                f"{given} + sides = {m - other} exceeds n = {m}", "n")
        h, t = (h, other) if t is None else (other, t)
    if h is not None:
        total = h + s + t
        if total > MAX_COUNT:
            raise CountsError(f"heads + sides + tails = {total}; at most {MAX_COUNT} (2**53) "
                              "tosses are allowed", "n")
        if m is not None and m != total:
            raise CountsError(f"heads + sides + tails = {total} but n = {m}", "n")
        m = total
        if m == 0:
            raise CountsError("heads, sides and tails are all zero: no tosses to check", "n")
        return Counts(m, s, h, t)
    if m is None:
        raise CountsError("give n (the number of tosses) with sides, or heads and tails too", "n")
    if m == 0:
        raise CountsError("n must be >= 1 (no tosses to check), got 0", "n")
    if s > m:
        raise CountsError(f"sides = {s} exceeds n = {m}", "sides")
    return Counts(m, s)


class Caught(namedtuple("Caught", "n same different")):
    """Caught flips, faces only: ``same`` landed on the side they started on, ``different`` on
    the other (a binomial observation; see :mod:`coincli.core.stats.caught`)."""

    # n: int
    # same: int
    # different: int
    __slots__ = ()

    faces = False
    caught = True
    heads = tails = sides = None
    categories = ("same", "different")

    @property
    def values(self) -> tuple[int, ...]:
        return (self.same, self.different)


def make_caught(same=None, different=None, n=None) -> Caught:
    """Validate caught faces-only counts: ``same`` and ``different`` (``n`` optional, then it
    must be their sum), or ``same`` and ``n``.

    >>> make_caught(5080, 4920)
    Caught(n=10000, same=5080, different=4920)
    >>> make_caught(same=51, n=100)
    Caught(n=100, same=51, different=49)
    """
    vals = {}
    for name, v in (("same", same), ("different", different), ("n", n)):
        try:
            vals[name] = whole_count(v, name)
        except ValueError as exc:
            raise CountsError(str(exc), name) from None
    s, d, m = vals["same"], vals["different"], vals["n"]
    if s is None and d is None:
        raise CountsError("give same and different (or n) for caught flips", "same")
    if s is None or d is None:
        if m is None:
            given, missing = ("same", "different") if d is None else ("different", "same")
            raise CountsError(f"{given} was given without {missing}; give both, or n", missing)
        known = s if s is not None else d
        if known > m:
            name = "same" if s is not None else "different"
            raise CountsError(f"{name} = {known} exceeds n = {m}", name)
        s, d = (s, m - s) if d is None else (m - d, d)
    total = s + d
    if m is not None and m != total:
        raise CountsError(f"same + different = {total} but n = {m}", "n")
    if total == 0:
        raise CountsError("same and different are both zero: no flips to check", "n")
    if total > MAX_COUNT:
        raise CountsError(f"same + different = {total}; at most {MAX_COUNT} (2**53) flips are "
                          "allowed", "n")
    return Caught(total, s, d)


def check_probs(probs, k: int, name: str = "probabilities") -> tuple[float, ...]:
    """k finite probabilities >= 0 summing to 1 within 1e-6; returned renormalized."""
    try:
        p = [float(v) for v in probs]
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be {k} numbers, got {probs!r}") from None
    if len(p) != k:
        raise ValueError(f"{name} must be {k} numbers, got {len(p)}")
    if any(not math.isfinite(v) or v < 0 for v in p):
        raise ValueError(f"{name} must be finite and >= 0, got {p!r}")
    total = math.fsum(p)
    if not abs(total - 1.0) <= 1e-6:
        raise ValueError(f"{name} must sum to 1, got {p!r} (sum {total!r})")
    return tuple(v / total for v in p)


# --------------------------------------------------------------------------- experiments


class Experiment(namedtuple("Experiment", "line xi counts label diameter", defaults=(None,))):
    """One row of an experiments file: a coin's aspect ratio and its tosses.

    :func:`coincli.io.experiments.parse_experiments` reads them; :func:`coincli.core.stats.fit.fit`
    takes them."""

    # line: int  line number in the file (1-based)
    # xi: float
    # counts: Counts
    # label: str  the label column, else a description of the coin ("nickel x3", "xi=0.583")
    # diameter: float | None  the coin's diameter in mm when the row gives it (coin or diameter)
    __slots__ = ()


class RowSequence(Sequence):
    """A sequence whose rows are made on demand by ``_row(i)`` (``0 <= i < len``): indexing
    with negative numbers and slices (lists of rows), as a list's."""

    def __getitem__(self, i):
        if isinstance(i, slice):
            return [self._row(k) for k in range(*i.indices(len(self)))]
        if i < 0:
            i += len(self)
        if not 0 <= i < len(self):
            raise IndexError(i)
        return self._row(i)


class ExperimentColumns(RowSequence):
    """Many :class:`Experiment` rows held as columns (numpy arrays, and a list of labels): a
    file of 10^5 rows in a few MB instead of 10^5 row objects.  ``rows[i]`` builds row ``i``'s
    :class:`Experiment` on demand.

    Columns: ``line`` (int), ``xi`` (float), ``diameter`` (float, NaN when the row gives
    none), ``labels`` (list of str) and ``cc`` (the counts, :class:`CountColumns`)."""

    def __init__(self, line, xi, labels, diameter, cc):
        self.line, self.xi, self.labels, self.diameter, self.cc = line, xi, labels, diameter, cc

    @classmethod
    def from_rows(cls, rows) -> ExperimentColumns:
        """Collect an iterable of :class:`Experiment` (each dropped once read)."""
        from array import array

        import numpy as np

        line, xi, diameter = array("q"), array("d"), array("d")
        n, sides, heads, tails, same = (array("q") for _ in range(5))
        faces, caught = array("b"), array("b")
        labels = _Labels()
        for e in rows:
            c = e.counts
            line.append(e.line)
            xi.append(e.xi)
            diameter.append(math.nan if e.diameter is None else e.diameter)
            labels.append(e.label)
            n.append(c.n)
            sides.append(c.sides or 0)
            heads.append(c.heads or 0)
            tails.append(c.tails or 0)
            is_caught = isinstance(c, Caught)
            same.append(c.same if is_caught else 0)
            faces.append(c.heads is not None)
            caught.append(is_caught)
        labels.close()

        def ints(a):  # the array's own buffer, not a copy
            return np.frombuffer(a, dtype=np.int64) if len(a) else np.zeros(0, np.int64)

        def counts(a):  # a count no row has (heads of caught flips): one read-only 0
            v = ints(a)
            return np.broadcast_to(np.int64(0), v.shape) if not v.any() else v

        def floats(a):
            return np.frombuffer(a, dtype=float) if len(a) else np.zeros(0)

        def bools(a):
            return np.array(a, dtype=bool)

        cc = CountColumns.from_arrays(
            faces=bools(faces), sides=counts(sides), n=ints(n), heads=counts(heads),
            tails=counts(tails), caught=bools(caught), same=counts(same))
        return cls(ints(line), floats(xi), labels, floats(diameter), cc)

    def __len__(self):
        return len(self.xi)

    def _row(self, i):
        d = float(self.diameter[i])
        return Experiment(int(self.line[i]), float(self.xi[i]), self.cc.count(i),
                          self.labels[i], None if math.isnan(d) else d)


class _Labels(RowSequence):
    """Many short texts held as one string and the offsets of their ends (a file of 10^5
    labels in a few hundred kB instead of 10^5 string objects): ``labels[i]``, slices (lists),
    ``len``.  Filled by :meth:`append`, then :meth:`close`."""

    _JOIN = 4096  #: labels joined into one string at a time while filling

    def __init__(self, texts=()):
        from array import array

        self._parts, self._pending, self._text = [], [], None
        self._ends = array("q")
        for t in texts:
            self.append(t)
        self.close()

    def append(self, text: str) -> None:
        self._pending.append(text)
        self._ends.append((self._ends[-1] if self._ends else 0) + len(text))
        if len(self._pending) >= self._JOIN:
            self._parts.append("".join(self._pending))
            self._pending = []

    def close(self) -> None:
        self._text = "".join(self._parts) + "".join(self._pending)
        self._parts, self._pending = [], []

    def __len__(self):
        return len(self._ends)

    def _row(self, i):
        return self._text[self._ends[i - 1] if i else 0:self._ends[i]]

    def __eq__(self, other):
        return isinstance(other, Sequence) and list(self) == list(other)


class CountColumns:
    """Counts of many experiments as arrays: heads, sides, tails (0 where faces were not told
    apart), n, and ``faces``."""

    def __init__(self, counts: Sequence[Counts]):
        import numpy as np

        if not all(isinstance(c, (Counts, Caught)) for c in counts):
            bad = next(c for c in counts if not isinstance(c, (Counts, Caught)))
            raise ValueError(f"counts must be a Counts (see make_counts), got {bad!r}")
        self.counts = counts
        self.faces = np.fromiter((c.heads is not None for c in counts), bool, len(counts))
        self.sides = np.fromiter((c.sides or 0 for c in counts), np.int64, len(counts))
        self.n = np.fromiter((c.n for c in counts), np.int64, len(counts))
        self.heads = np.fromiter((c.heads or 0 for c in counts), np.int64, len(counts))
        self.tails = np.fromiter((c.tails or 0 for c in counts), np.int64, len(counts))
        #: caught rows (faces only, :class:`Caught`): ``same`` of ``n``; 0 elsewhere
        self.caught = np.fromiter((isinstance(c, Caught) for c in counts), bool, len(counts))
        self.same = np.fromiter((getattr(c, "same", 0) for c in counts), np.int64, len(counts))
        #: rows of side counts alone (neither faces told apart nor caught)
        self.sides_only = ~self.faces & ~self.caught

    @classmethod
    def from_arrays(cls, *, faces, sides, n, heads, tails, caught, same) -> CountColumns:
        """Columns given as arrays (0 where a count is absent); ``count(i)`` rebuilds a row."""
        self = cls.__new__(cls)
        self.counts = None
        self.faces, self.sides, self.n, self.heads, self.tails = faces, sides, n, heads, tails
        self.caught, self.same = caught, same
        self.sides_only = ~faces & ~caught
        return self

    def rows(self, a: int, b: int) -> CountColumns:
        """Rows ``a`` to ``b`` (views of the arrays)."""
        part = CountColumns.from_arrays(
            faces=self.faces[a:b], sides=self.sides[a:b], n=self.n[a:b], heads=self.heads[a:b],
            tails=self.tails[a:b], caught=self.caught[a:b], same=self.same[a:b])
        if self.counts is not None:
            part.counts = self.counts[a:b]
        return part

    def count(self, i: int):
        """Row ``i``'s :class:`Counts` (or :class:`Caught`)."""
        if self.counts is not None:
            return self.counts[i]
        n = int(self.n[i])
        if self.caught[i]:
            same = int(self.same[i])
            return Caught(n, same, n - same)
        if self.faces[i]:
            return Counts(n, int(self.sides[i]), int(self.heads[i]), int(self.tails[i]))
        return Counts(n, int(self.sides[i]))

    def __len__(self):
        return len(self.n)

    def matrix(self):
        import numpy as np

        return np.stack([self.heads, self.sides, self.tails], axis=1)


# --------------------------------------------------------------------------- special functions
# Vectorized numpy over scipy.special (Boost and Cephes underneath).  scipy.stats is never
# imported: its import alone costs 0.6 s, twice what the answer needs.  The formulas are the
# ones scipy.stats uses, so the numbers are the same:
#   binomial log-pmf   gammaln(n+1) - (gammaln(k+1) + gammaln(n-k+1)) + k ln p + (n-k) ln(1-p)
#   P(X <= k)          I_{1-p}(n - k, k + 1)    (betainc; 1 - p passed as the complement chance)
#   P(X >= k)          I_p(k, n - k + 1)
#   (the chi-square tail, chdtrc, is in coincli.core.stats.tests; the beta quantiles of the
#   Clopper-Pearson interval in coincli.core.stats.intervals)

_TABLE_MAX = 1 << 21  #: log-factorials are tabulated up to this n (16 MiB); gammaln beyond


class LogFactorial:
    """``v -> log(v!)`` for whole numbers ``0 <= v <= nmax``: a table of gammaln(k + 1) (the same
    numbers, looked up instead of recomputed) when ``nmax`` is small enough, else gammaln."""

    def __init__(self, nmax: int):
        import numpy as np
        from scipy.special import gammaln

        self._gammaln = gammaln
        self._table = (gammaln(np.arange(int(nmax) + 1, dtype=float) + 1.0)
                       if nmax <= _TABLE_MAX else None)

    def __call__(self, v):
        import numpy as np

        if self._table is not None:
            return self._table[np.asarray(v, dtype=np.int64)]
        return self._gammaln(np.asarray(v, dtype=float) + 1.0)


def binom_logpmf(k, n, p, lf=None):
    """log P(X = k) for X ~ Binomial(n, p), arrays; scipy.stats.binom.logpmf's formula."""
    import numpy as np
    from scipy.special import xlog1py, xlogy

    k = np.asarray(k)
    n = np.asarray(n)
    if lf is None:
        lf = LogFactorial(int(np.max(n, initial=0)))
    return (lf(n) - (lf(k) + lf(n - k))) + xlogy(k, p) + xlog1py(n - k, -p)


def binom_cdf(k, n, p1):
    """P(X <= k) for X ~ Binomial(n, p) with ``p1 = 1 - p`` given (not formed from p)."""
    import numpy as np
    from scipy.special import betainc

    k, n = np.asarray(k, dtype=float), np.asarray(n, dtype=float)
    inside = (k >= 0) & (k < n)
    with np.errstate(invalid="ignore", divide="ignore"):
        v = betainc(np.where(inside, n - k, 1.0), np.where(inside, k + 1, 1.0), p1)
    return np.where(inside, v, np.where(k >= n, 1.0, 0.0))


def binom_upper(k, n, p):
    """P(X >= k) for X ~ Binomial(n, p)."""
    import numpy as np
    from scipy.special import betainc

    k, n = np.asarray(k, dtype=float), np.asarray(n, dtype=float)
    inside = (k >= 1) & (k <= n)
    with np.errstate(invalid="ignore", divide="ignore"):
        v = betainc(np.where(inside, k, 1.0), np.where(inside, n - k + 1, 1.0), p)
    return np.where(inside, v, np.where(k <= 0, 1.0, 0.0))
