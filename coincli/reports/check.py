"""What ``coin check`` and ``coin fit`` print: real tosses against the models.

:func:`check` (one experiment typed as options) and :func:`fit` (a file of experiments) parse
their options' text, call :mod:`coincli.core.stats.tests` and return
:class:`coincli.io.table.Result` tables.  The human output (``--format table``) is a few short
tables; every machine format (csv, tsv, json, jsonl) gets one long table instead, one row per
experiment and model (and, for ``fit``, one per model across experiments), with stable column
names (:data:`MACHINE_COLUMNS`, :data:`FIT_COLUMNS`).  A file of 10^5 experiments is streamed
(:func:`_machine_chunks`).  numpy and scipy load when a report runs, never at import.
"""

from __future__ import annotations

import math
import sys

from coincli.errors import InputError, compute_error, shown, usage_error
from coincli.io import grammar as parse
from coincli.io import options
from coincli.io.files import FileKindError, read_capped, read_regular, stream_reader
from coincli.io.table import CHUNK_ROWS, Column, Result, check_format

__all__ = ["check", "fit", "MACHINE_COLUMNS", "FIT_COLUMNS", "MAX_FILE_BYTES"]

_OUTCOMES = ("heads", "sides", "tails")

# --------------------------------------------------------------------------- option text


def _level(text: str, what: str) -> float:
    try:
        v = parse.parse_probability(text, what)
    except ValueError as exc:
        if "must be in [0, 1]" not in str(exc):
            raise usage_error(str(exc)) from None
        v = math.nan  # out of [0, 1]: the message below states what a level may be
    if not 0.0 < v < 1.0:
        like = "0.05, 1/20 or 5%" if what == "--alpha" else "0.95 or 95%"
        raise usage_error(f"{what} must be strictly between 0 and 1 ({like}), got {text!r}")
    return v


def _densities(specs: str | None) -> dict:
    """--psi-dist, parsed as every command parses it, by machine name."""
    if specs is None:
        return {}
    return {d.spec: d for d in options.psi_densities(specs)}


def _whole(text: str | None, what: str) -> int | None:
    """A count of tosses: a whole number from 0 to :data:`parse.MAX_COUNT` (2**53)."""
    if text is None:
        return None
    digits = text.strip().removeprefix("+")
    if not (digits.isascii() and digits.isdigit()):
        raise usage_error(f"{what} must be a whole number >= 0, got {shown(text)}")
    digits = digits.lstrip("0") or "0"
    if len(digits) > 16 or int(digits) > parse.MAX_COUNT:  # and no int() of 5000 digits
        raise usage_error(f"{what} must be a whole number from 0 to {parse.MAX_COUNT} (2**53), "
                          f"got {shown(text)}")
    return int(digits)


def _check_total(counts, where: str = "") -> None:
    """Every count below 2**53 can still add up to more: the total is held to it too."""
    if counts.n > parse.MAX_COUNT:
        raise usage_error(f"{where}heads + sides + tails = {counts.n}; at most {parse.MAX_COUNT} "
                          "(2**53) tosses are allowed")


def _deg(v: float | None) -> float | None:
    return None if v is None else math.degrees(v)


# --------------------------------------------------------------------------- rows


def _observed_columns() -> list[Column]:
    cols = []
    for name in _OUTCOMES:
        cols += [Column(f"freq_{name}", f"{name} frequency"),
                 Column(f"{name}_wilson_low", f"{name} Wilson low"),
                 Column(f"{name}_wilson_high", f"{name} Wilson high"),
                 Column(f"{name}_cp_low", f"{name} Clopper-Pearson low"),
                 Column(f"{name}_cp_high", f"{name} Clopper-Pearson high")]
    return cols


MACHINE_COLUMNS = [
    Column("scope", "scope", "text"),
    Column("line", "line", "int"),
    Column("label", "label", "text"),
    Column("xi", "xi = h/D"),
    Column("n", "tosses", "int"),
    Column("heads", "heads", "int"),
    Column("sides", "sides", "int"),
    Column("tails", "tails", "int"),
    Column("model", "model", "text"),
    Column("p_heads", "P(heads)"),
    Column("p_sides", "P(sides)"),
    Column("p_tails", "P(tails)"),
    Column("expected_heads", "expected heads"),
    Column("expected_sides", "expected sides"),
    Column("expected_tails", "expected tails"),
    Column("test", "test", "text"),
    Column("exact", "exact", "text"),
    Column("p_value", "p-value"),
    Column("g_statistic", "G"),
    Column("df", "df", "int"),
    Column("log_likelihood", "log-likelihood"),
    Column("verdict", "verdict", "text"),
    *_observed_columns(),
]
FIT_COLUMNS = MACHINE_COLUMNS + [
    Column("n_params", "fitted parameters", "int"),
    Column("aic", "AIC"),
    Column("delta_aic", "delta AIC"),
    Column("sse_sides", "SSE of side frequencies"),
    Column("sigma_deg", "psi sd (deg)"),
    Column("sigma_low_deg", "psi sd low (deg)"),
    Column("sigma_high_deg", "psi sd high (deg)"),
]


#: the columns a table with caught (faces-only) rows adds, after all the others
CAUGHT_MACHINE_COLUMNS = [
    Column("same", "same side", "int"),
    Column("different", "other side", "int"),
    Column("p_same", "P(same | face)"),
    Column("expected_same", "expected same"),
    Column("expected_different", "expected different"),
    Column("freq_same", "same frequency"),
    Column("same_wilson_low", "same Wilson low"),
    Column("same_wilson_high", "same Wilson high"),
    Column("same_cp_low", "same Clopper-Pearson low"),
    Column("same_cp_high", "same Clopper-Pearson high"),
]
#: ... and what ``coin fit`` adds for them: the tossers compared, and each one's fair coin
CAUGHT_FIT_COLUMNS = [
    Column("sigma_note", "psi sd note", "text"),
    Column("heterogeneity_test", "heterogeneity test", "text"),
    Column("heterogeneity_statistic", "heterogeneity statistic"),
    Column("heterogeneity_df", "heterogeneity df", "int"),
    Column("heterogeneity_p", "heterogeneity p-value"),
    Column("sigma_common_deg", "common psi sd (deg)"),
    Column("median_sigma_deg", "median tosser psi sd (deg)"),
    Column("between_sd_log_sigma", "between-tosser sd of log psi sd"),
    Column("design_p_sides", "design P(sides)"),
    Column("design_xi", "design xi"),
    Column("design_thickness_mm", "design thickness (mm)"),
]


def _values(arr) -> list:
    """numpy values as Python ones, NaN as None (an empty cell)."""
    return [None if v != v else v for v in arr.tolist()]


def _machine_chunks(ch, lines, extra=None, tail_rows=(), caught_extra=None, row_extra=None):
    """The machine table a chunk at a time (lists of columns, at most CHUNK_ROWS rows): one
    row per experiment and model (experiment-major), then ``tail_rows`` (tuples).
    ``extra(k)`` gives the fit's extra cells of model ``k``.  A file of 10^5 experiments is
    written without ever holding its 10^5 x models x 45 cells, nor every row's tests: each
    chunk's are computed when it is written (:meth:`Checks.part`).  ``lines``: each row's line
    (an array), or None.  With caught rows the :data:`CAUGHT_MACHINE_COLUMNS` follow (then
    ``caught_extra``, makers of the fit's caught columns); ``row_extra`` maps a column index to
    a maker that replaces it.  A maker takes ``(a, b)``, the rows of the chunk."""
    import numpy as np

    M = len(ch.models)
    T = len(ch)
    cc = ch.cc
    faces = cc.faces
    now = {}  # the chunk being written: its tests and intervals (ch.part)

    def per_exp(arr):
        return lambda a, b: [v for v in _values(arr[a:b]) for _ in range(M)]

    def per_exp_where(mask, arr, keep=True):
        """``arr`` where ``mask`` is ``keep``, NaN elsewhere, made a chunk at a time."""
        def make(a, b):
            m = mask[a:b] if keep else ~mask[a:b]
            return [v for v in _values(np.where(m, arr[a:b], np.nan)) for _ in range(M)]
        return make

    def per_exp_list(seq):
        return lambda a, b: [v for v in seq[a:b] for _ in range(M)]

    def per_test_of(column):
        """A column of every model's test (``column(t, a, b)``: the chunk's test ``t``, and
        rows a to b of the whole), stacked a model at a time."""
        return lambda a, b: _values(np.stack([column(t, a, b) for t in now["tests"]],
                                             axis=1).ravel())

    def per_test_list(attr):
        def make(a, b):
            lists = [getattr(t, attr) for t in now["tests"]]
            return [lst[i] for i in range(b - a) for lst in lists]
        return make

    def per_interval(name, j):
        return lambda a, b: [v for v in _values(now["intervals"][name][j]) for _ in range(M)]

    def const(v):
        return lambda a, b: [v] * ((b - a) * M)

    nan = np.nan

    def expected_of(j, caught=None):
        """Expected heads (j = 0), sides (1) or tails (2); NaN where not counted (and on caught
        rows, when ``caught`` is given)."""
        def column(t, a, b):
            f = faces[a:b]
            e = t.expected[j] if j != 1 else np.where(f, t.expected[1], t.expected[0])
            if j != 1:
                e = np.where(f, e, nan)
            return e if caught is None else np.where(caught[a:b], nan, e)
        return per_test_of(column)

    models = ch.models
    makers = [
        const("experiment"),
        per_exp(lines) if lines is not None else const(None),
        per_exp_list(ch.labels),
        per_exp(np.asarray(ch.xi, dtype=float)),
        per_exp(cc.n),
        per_exp_where(faces, cc.heads) if not faces.all() else per_exp(cc.heads),
        per_exp(cc.sides),
        per_exp_where(faces, cc.tails) if not faces.all() else per_exp(cc.tails),
        lambda a, b: models * (b - a),
        *(per_test_of(lambda t, a, b, j=j: t.raw[j]) for j in range(3)),
        *(expected_of(j) for j in range(3)),
        per_test_list("method"),
        per_test_of(lambda t, a, b: t.exact),
        per_test_of(lambda t, a, b: t.p_value),
        per_test_of(lambda t, a, b: t.g),
        per_test_of(lambda t, a, b: t.df),
        per_test_of(lambda t, a, b: t.log_likelihood),
        per_test_list("verdict"),
    ]
    for name in _OUTCOMES:
        makers += [per_interval(name, j) for j in range(5)]
    if extra is not None:
        for c in range(len(extra(0))):
            cells = [extra(k)[c] for k in range(M)]
            makers.append(lambda a, b, cells=cells: cells * (b - a))
    # heads and tails: int columns with None where faces were not told apart
    makers[5], makers[7] = _ints(makers[5]), _ints(makers[7])
    if cc.caught.any():
        caught = cc.caught
        makers[6] = _ints(per_exp_where(caught, cc.sides, keep=False))

        def p_same(t, a, b):
            with np.errstate(divide="ignore", invalid="ignore"):
                return np.where(caught[a:b], t.raw[0] / (t.raw[0] + t.raw[2]), nan)

        for j in range(3):  # a caught row has no expected heads, sides or tails
            makers[12 + j] = expected_of(j, caught)
        makers += [
            _ints(per_exp_where(caught, cc.same)),
            _ints(lambda a, b: per_exp_where(caught[a:b], cc.n[a:b] - cc.same[a:b])(0, b - a)),
            per_test_of(p_same),
            per_test_of(lambda t, a, b: np.where(caught[a:b], t.expected[0], nan)),
            per_test_of(lambda t, a, b: np.where(caught[a:b], t.expected[1], nan)),
            *(per_interval("same", j) for j in range(5)),
        ]
        if caught_extra is not None:
            makers += caught_extra
    if row_extra is not None:  # per-row cells that replace the fit's constant ones
        for c, make in row_extra.items():
            makers[c] = make
    step = max(1, min(CHUNK_ROWS, 8192) // M)  # 45 columns: 8192 rows of cells at a time
    for a in range(0, T, step):
        b = min(a + step, T)
        part = ch.part(a, b)
        now["tests"], now["intervals"] = part.tests, part.intervals
        yield [make(a, b) for make in makers]
    now.clear()
    if tail_rows:
        yield [list(col) for col in zip(*tail_rows, strict=True)]


def _ints(make):
    """Counts read back from a float array (NaN for absent) as ints."""
    return lambda a, b: [None if v is None else int(v) for v in make(a, b)]


def _count_text(v: float) -> str:
    """An expected count for people: 33.3333, 495000, 12345679 (never 4.95e+05)."""
    return f"{v:.6g}" if abs(v) < 1e6 else f"{v:.0f}"


def _plural(n: int, one: str, many: str) -> str:
    """``1 toss``, ``2 tosses``, ``0 experiments``."""
    return f"{n} {one if n == 1 else many}"


def _interval_text(lo: float, hi: float) -> str:
    return f"{lo:.4g} to {hi:.4g}"


def _observed_result(title: str, ch, lines, confidence: float) -> Result:
    """Frequencies with their intervals, one row per experiment and counted outcome."""
    from coincli.core.stats.tests import percent

    pct = percent(confidence)
    with_line = lines is not None
    cols = ([Column("line", "line", "int"), Column("label", "label", "text"),
             Column("xi", "xi")] if with_line else [])
    cols += [Column("outcome", "outcome", "text"), Column("count", "count", "int"),
             Column("frequency", "frequency"),
             Column("wilson", f"{pct} Wilson", "text"),
             Column("cp", f"{pct} Clopper-Pearson", "text")]
    cc = ch.cc

    caught = cc.caught
    names = _OUTCOMES + (("same",) if caught.any() else ())

    def rows(a: int, b: int) -> list[tuple]:
        iv = ch.part(a, b, tests=False).intervals
        per = {name: [v.tolist() for v in iv[name]] for name in names}
        line = lines[a:b].tolist() if with_line else None
        counts = {"heads": cc.heads[a:b].tolist(), "sides": cc.sides[a:b].tolist(),
                  "tails": cc.tails[a:b].tolist(), "same": cc.same[a:b].tolist()}
        xi = ch.xi[a:b].tolist()
        body = []
        for j, (f, c) in enumerate(zip(cc.faces[a:b].tolist(), caught[a:b].tolist(),
                                       strict=True)):
            lead = [line[j], ch.labels[a + j], xi[j]] if with_line else []
            for name in (_OUTCOMES if f else ("same",) if c else ("sides",)):
                est, wl, wh, cl, chh = (col[j] for col in per[name])
                body.append((*lead, name, counts[name][j], est, _interval_text(wl, wh),
                             _interval_text(cl, chh)))
        return body

    return _chunked(title, cols, rows, len(ch), 3)


def _chunked(title: str, cols, rows, n: int, per: int, note: str = "") -> Result:
    """A human table of ``n`` experiments: one chunk when small, else streamed by chunks of
    experiments (``rows(a, b)`` gives their rows, at most ``per`` each), so that a file of 10^5
    experiments is never held as text at once."""
    step = max(1, min(CHUNK_ROWS, 8192) // per)
    if n <= step:
        return Result(title, cols, rows(0, n), note=note)

    def chunks():
        for a in range(0, n, step):
            body = rows(a, min(a + step, n))
            yield [list(c) for c in zip(*body, strict=True)]

    return Result(title, cols, [], note=note, chunks=chunks())


def _tests_result(title: str, ch, lines, note: str) -> Result:
    with_line = lines is not None
    cols = ([Column("line", "line", "int"), Column("label", "label", "text")]
            if with_line else [])
    caught = ch.cc.caught
    any_caught = bool(caught.any())
    cols += [Column("model", "model", "text"), Column("p_heads", "P(heads)"),
             Column("p_sides", "P(sides)"), Column("p_tails", "P(tails)")]
    if any_caught:
        cols += [Column("p_same", "P(same | face)"),
                 Column("expected", "expected H / S / T or same / other", "text")]
    else:
        cols += [Column("expected", "expected H / S / T", "text")]
    cols += [Column("p_value", "p-value"),
             Column("log_likelihood", "log-likelihood"), Column("verdict", "verdict", "text")]

    def rows(a: int, b: int) -> list[tuple]:
        tests = [(t.model, t.raw.T.tolist(), t.expected.T.tolist(), t.p_value.tolist(),
                  t.log_likelihood.tolist(), t.verdict)
                 for t in ch.part(a, b, intervals=False).tests]
        line = lines[a:b].tolist() if with_line else None
        body = []
        for j, (f, c) in enumerate(zip(ch.cc.faces[a:b].tolist(), caught[a:b].tolist(),
                                       strict=True)):
            lead = [line[j], ch.labels[a + j]] if with_line else []
            for model, raw, exp, pv, ll, ver in tests:
                e = exp[j]
                shown = e if f else (e[0], e[1]) if c else (None, e[0], None)
                mid = []
                if any_caught:
                    h, _, t = raw[j]
                    mid = [h / (h + t) if c and h + t > 0 else None]
                body.append((*lead, model, *raw[j], *mid,
                             " / ".join("-" if v is None else _count_text(v) for v in shown),
                             pv[j], ll[j], ver[j]))
        return body

    return _chunked(title, cols, rows, len(ch), len(ch.models), note)


def _test_note(ch) -> str:
    tests = sorted(ch.methods())
    return (
        f"test: {', '.join(tests)}; p = the chance, under the model, of counts no more likely "
        "than those observed.  'consistent' means the tosses do not contradict the model, not "
        "that they confirm it."
    )


# --------------------------------------------------------------------------- check


def _xi_from_options(xi, quarters, coin, count, diameter, thickness) -> tuple[float, str]:
    """The coin tossed (the shared coin group) and its label."""
    c = options.resolve_coin(xi, coin, count, quarters, diameter, thickness,
                             xi_rule="finite", command="coin check")
    return c.xi, c.label()


def check(*, xi: str | None = None, quarters: str | None = None, coin: str | None = None,
          count: str | None = None, diameter: str | None = None, thickness: str | None = None,
          heads: str | None = None, sides: str | None = None, tails: str | None = None,
          tosses: str | None = None, same: str | None = None, different: str | None = None,
          psi_dist: str | None = None, expect: str | None = None, fair: bool = False,
          landing: str = "catch", surface=None, restitution=None, friction=None,
          torsional=None, rolling=None, release_height=None, vx=None, u=None, omega=None,
          psi=None, seed=None, jobs=None, dt=None, t_max=None, calibration=None,
          scheduler=None, checkpoint=None, timeout=None, alpha: str = "0.05",
          confidence: str = "0.95", fmt: str = "table", quiet: bool = False):
    """What ``coin check`` prints: the observed frequencies with their intervals, and for each
    model the expected counts, the exact test's p-value, the log-likelihood and a verdict.

    The options' text as ``coin check`` takes it (the coin group, ``--heads``, ``--sides``,
    ``--tails``, ``-n/--tosses``, ``--psi-dist``, ``--alpha``, ``--confidence``).  ``expect``
    (``1/3,1/3,1/3``) or ``fair``: also a test against stated chances (the row ``expected``;
    the coin is then optional).  ``landing="bounce"``: also a test against a table simulated
    with the surface and launch options (:func:`_bounce_row`: the two sets of counts tested for
    one set of chances, so the simulation's own sampling error is counted).  Returns two human
    tables (a list) for ``fmt="table"``, else the one machine :class:`Result` (its ``quiet``
    the p-values, one per model).  Raises InputError for a wrong input, NotComputable when the
    models cannot be evaluated.
    """
    from coincli.core.stats import tests as stats
    from coincli.core.stats.counts import make_counts

    fmt = check_format(fmt)
    a = _level(alpha, "--alpha")
    conf = _level(confidence, "--confidence")
    expected = _expectation(expect, fair)
    bounce = _bounce_options(landing, surface=surface, restitution=restitution,
                             friction=friction, torsional=torsional, rolling=rolling,
                             height=release_height, vx=vx, jobs=jobs, dt=dt, t_max=t_max,
                             calibration=calibration, scheduler=scheduler,
                             checkpoint=checkpoint, timeout=timeout, u=u, omega=omega, psi=psi,
                             seed=seed)
    if bounce is not None and (same is not None or different is not None):
        raise usage_error("--same/--different are caught flips: caught in the hand, they never "
                          "met a table; --landing bounce checks tosses that landed on one")
    coin_given = any(v is not None for v in (xi, quarters, coin, count, diameter, thickness))
    if expected is not None and not coin_given and bounce is None:
        x, label = math.nan, ""  # stated chances need no coin
    else:
        x, label = _xi_from_options(xi, quarters, coin, count, diameter, thickness)
    if same is not None or different is not None:
        counts = _caught_counts(x, same, different, tosses, (heads, sides, tails))
    else:
        vals = {name: _whole(v, f"--{name}")
                for name, v in (("heads", heads), ("sides", sides), ("tails", tails))}
        vals["n"] = None if tosses is None else options.tosses_value(tosses)  # as everywhere
        try:
            counts = make_counts(**vals)
        except ValueError as exc:
            raise usage_error(str(exc)) from None
    _check_total(counts)
    dens = _densities(psi_dist) if bounce is None else {}
    sim = None
    if bounce is not None:  # its own errors: a wrong option is exit 2, no settled toss exit 1
        sim = _simulate_table(bounce, x, counts, xi=xi, diameter=diameter, thickness=thickness,
                              coin_texts=(quarters, coin, count),
                              launch=(u, omega, psi, psi_dist, seed))
    try:
        chances = stats.model_chances(x, dens) if math.isfinite(x) else {}
        if expected is not None:
            chances["expected"] = expected
        if sim is not None:
            chances[sim.name] = sim.chances
        ch = stats.check_many([counts], x, chances, confidence=conf, alpha=a, labels=[label])
    except ValueError as exc:
        raise compute_error(str(exc)) from None
    if sim is not None:
        _two_sample(ch, sim, counts, a)
    caught = bool(ch.cc.caught[0])
    if quiet or fmt != "table":
        if sim is not None:  # the note that names the seed is not printed: say a drawn one
            options.report_seed(sim.seed, seed is not None)
        return Result("coin check", MACHINE_COLUMNS + (CAUGHT_MACHINE_COLUMNS if caught else []),
                      [], data=next(_machine_chunks(ch, None)),
                      quiet=[float(t.p_value[0]) for t in ch.tests])
    coin_text = (f"xi = {x:.6g}" if xi is not None else f"{label} (xi = {x:.6g})"
                 if math.isfinite(x) else "against stated chances")
    title = f"coin check: {coin_text}, {_plural(counts.n, 'toss', 'tosses')}"
    if caught:
        title = f"coin check: {coin_text}, {_plural(counts.n, 'caught flip', 'caught flips')}"
    note = _test_note(ch) + (_models_note(dens) if math.isfinite(x) else "")
    if expected is not None:
        note += (f"  expected = the chances you stated: heads {expected.heads:.6g}, sides "
                 f"{expected.sides:.6g}, tails {expected.tails:.6g}.")
    if sim is not None:
        note += "\n" + sim.note
    if caught:
        note += "\n" + _caught_note(x, counts, conf)
    return [
        _observed_result(title, ch, None, conf),
        _tests_result("models", ch, None, note),
    ]


def _expectation(expect: str | None, fair: bool):
    """The chances ``--expect H,S,T`` states (each 0.3, 1/3 or 30%; they must sum to 1) or
    ``--fair`` (1/3 each), as an Outcome; None when neither is given."""
    from coincli.core.models import Outcome

    if fair and expect is not None:
        raise usage_error("--fair is --expect 1/3,1/3,1/3: give one of them")
    if fair:
        return Outcome(1 / 3, 1 / 3, 1 / 3)
    if expect is None:
        return None
    parts = expect.split(",")
    if len(parts) != 3:
        raise usage_error(f"--expect takes the chances of heads, sides and tails, three numbers "
                          f"a,b,c (0.3, 1/3 or 30% each), got {shown(expect)}")
    try:
        ps = [parse.parse_probability(t, "--expect") for t in parts]
    except ValueError as exc:
        raise usage_error(str(exc)) from None
    total = math.fsum(ps)
    if abs(total - 1.0) > 1e-6:
        raise usage_error(f"--expect: the three chances must add up to 1, got {shown(expect)} "
                          f"(sum {total:.10g})")
    return Outcome(*(p / total for p in ps))


class _Simulated:
    """The simulated table a check compares with: its name, chances (the frequencies among the
    settled tosses), counts (heads, sides, tails), and the note that says how it was made."""

    def __init__(self, name, chances, counts, note, seed):
        self.name, self.chances, self.counts, self.note = name, chances, counts, note
        self.seed = seed


#: the simulated tosses of ``coin check --landing bounce``: ten times the experiment's, at
#: least 4000 (so the simulation adds little to the experiment's own error), at most 10^5
SIM_TOSSES = (4000, 10, 100_000)


def _bounce_options(landing, *, u, omega, psi, seed, **surface):
    """The table of ``--landing bounce`` (a :class:`coincli.reports.bounce.Physics`), or None
    for the catch (then no table or launch option may be given)."""
    if landing.strip().lower() == "catch" and all(v is None for v in (
            *surface.values(), u, omega, psi, seed)):
        return None
    from coincli.reports import bounce as BO

    physics = BO.parse_physics(BO.landing_of(landing), **surface)
    if physics is None:
        extra = [name for name, v in (("--u", u), ("--omega", omega), ("--psi", psi),
                                      ("--seed", seed)) if v is not None]
        raise usage_error(f"{', '.join(extra)} go{'es' if len(extra) == 1 else ''} with "
                          "--landing bounce (the tosses simulated on a table)")
    return physics


def _simulate_table(physics, x, counts, *, xi, diameter, thickness, coin_texts, launch):
    """Toss the coin on the table (:func:`coincli.core.bounce.runs.simulate`), as many tosses
    as :data:`SIM_TOSSES` says for this experiment."""
    from coincli.core.bounce import runs
    from coincli.core.models import Outcome
    from coincli.limits import STANDARD_G
    from coincli.reports import bounce as BO
    from coincli.reports.calibrate import bounce_launch_for
    from coincli.reports.launch import U_MAX, core_call, reach
    from coincli.reports.phase import diameter_m

    u, omega, psi, psi_dist, seed = launch
    coins = options.resolve_coin(xi, coin_texts[1], coin_texts[2], coin_texts[0], diameter,
                                 thickness, xi_rule="finite", command="coin check")
    dia = diameter_m(coins, diameter)
    BO.check_coin(physics, x, dia, xi_text=xi, diameter_text=diameter, thickness_text=thickness)
    u_spec, w_spec, psi_spec, labels = bounce_launch_for(physics, psi, psi_dist, u, omega)
    BO.check_landing(physics, u_top=reach(u_spec, U_MAX), g=STANDARD_G, xi=x, dia=dia,
                     u_text=u or "the hand toss's")
    least, times, most = SIM_TOSSES
    n = min(max(least, times * counts.n), most)
    seed_v = options.seed_value(seed)
    from coincli.reports.executor import executor

    with executor(physics, "coin check --landing bounce", **{
            "-n": n, "--seed": seed_v, "--xi": x, "--u": u_spec, "--omega": w_spec,
            "--psi": psi_spec, "--diameter": dia, "--g": STANDARD_G}) as run:
        sim = core_call(runs.simulate, n, seed_v, xi=x, u=u_spec, omega=w_spec, psi=psi_spec,
                        surf=physics.surface, landing="bounce", height=physics.height,
                        vx=physics.vx, diameter=dia, g=STANDARD_G, dt=physics.dt,
                        t_max=physics.t_max, jobs=physics.jobs, executor=run)
    h, s, t, unsettled = sim.counts
    if h + s + t == 0:
        raise compute_error(f"none of the {n} tosses simulated on {physics.surface.name} "
                            f"settled within --t-max {physics.t_max:g} s: no table to compare "
                            "with")
    name = f"bounce on {physics.surface.name}"
    note = (f"{name}: {n} tosses simulated (MuJoCo; seed {seed_v}; {labels}; "
            f"{physics.describe()}), {h + s + t} settled ({unsettled} still moving at "
            f"{physics.t_max:g} s left out): heads {h}, sides {s}, tails {t}.  Its p-value is "
            "the test that your counts and the simulated counts share one set of chances (a 2 x "
            "3 table: exact conditional, Freeman-Halton; a G-test when too large to "
            "enumerate), so the simulation's own sampling error is counted, not ignored.")
    total = h + s + t
    return _Simulated(name, Outcome(h / total, s / total, t / total), (h, s, t), note, seed_v)


def _two_sample(ch, sim: _Simulated, counts, alpha: float) -> None:
    """Replace the simulated table's test (a point null at the simulated frequencies) by the
    two-sample test of homogeneity (:func:`coincli.core.stats.homogeneity.homogeneity`)."""
    from coincli.core.stats import tests as stats
    from coincli.core.stats.homogeneity import homogeneity

    test = next(t for t in ch.tests if t.model == sim.name)
    h, s, t = sim.counts
    if counts.faces:
        mine, theirs = (counts.heads, counts.sides, counts.tails), (h, s, t)
    else:  # sides and n: sides against faces
        mine, theirs = (counts.sides, counts.n - counts.sides), (s, h + t)
    r = homogeneity(mine, theirs)
    test.p_value[0] = r.p_value
    test.exact[0] = r.exact
    test.g[0] = r.g
    test.df[0] = r.df
    test.method[0] = ("exact conditional (Freeman-Halton), your counts against the simulated"
                      if r.exact else f"{r.method}, your counts against the simulated")
    test.verdict[0] = stats.verdict(r.p_value, alpha, exact=r.exact)


def _caught_counts(x: float, same, different, tosses, three):
    """``--same``/``--different`` (``-n`` optional): caught flips, faces only."""
    from coincli.core.stats.counts import make_caught

    if any(v is not None for v in three):
        raise usage_error("--same/--different are caught flips (faces only); they cannot go "
                          "with --heads, --sides or --tails")
    vals = {name: _whole(v, f"--{name}" if name != "n" else "-n")
            for name, v in (("same", same), ("different", different), ("n", tosses))}
    try:
        counts = make_caught(**vals)
    except ValueError as exc:
        raise usage_error(_option_words(str(exc))) from None
    _warn_thick(x, "")
    return counts


def _option_words(message: str) -> str:
    """A core message about same/different/n in the words of the options."""
    import re

    message = re.sub(r"\b(?<!-)(same|different)\b(?= (\+|=|must|was|exceeds|and))", r"--\1",
                     message)
    for a, b in (("but n =", "but -n ="), ("exceeds n =", "exceeds -n ="),
                 ("without different", "without --different"), ("without same", "without --same"),
                 ("or n", "or -n"), ("and different are", "and --different are")):
        message = message.replace(a, b)
    return message


def _warn_thick(x: float, where: str) -> None:
    """Caught flips of a thick coin: warn (stderr), once per run."""
    from coincli.core.stats.caught import CAUGHT_XI_LIMIT

    if x > CAUGHT_XI_LIMIT:
        sys.stderr.write(f"coin: warning: {where}xi = {x:.6g} is above {CAUGHT_XI_LIMIT}: "
                         "caught flips (faces only) are the thin coin's case; this coin lands "
                         "on a side often enough that conditioning on a face may not describe "
                         "how it was caught\n")


def _caught_note(x: float, counts, conf: float) -> str:
    """What a caught check means, and this tosser's own spread of psi."""
    from coincli.core.stats import caught as cs

    f = cs.fit_rows([x], [counts.same], [counts.n], confidence=conf)
    text = (f"caught flips (faces only): each model is tested on the chance of landing on the "
            f"side it started on given that it landed on a face, P(H) / (P(H) + P(T)) with the "
            f"start side as heads (a caught coin never shows a side, so P(sides) is conditioned "
            f"away).  Every model of a Keller flip gives 1/2; a spread of psi favours the "
            f"starting side.  This tosser's spread: sd of psi {_fmt_deg(float(f.sigma[0]))} "
            f"deg, {percent_text(conf)} profile-likelihood interval "
            f"{_fmt_deg(float(f.low[0]))} to {_fmt_deg(float(f.high[0]))} deg")
    bound = _bound_note(int(f.at_bound[0]))
    return text + (f" ({bound})" if bound else "") + "."


def percent_text(conf: float) -> str:
    from coincli.core.stats.tests import percent

    return percent(conf)


def _bound_note(b: int) -> str:
    if b < 0:
        return ("the estimate is at the bound sigma = 0: no more flips landed on the starting "
                "side than on the other, which a Keller flip (1/2) already explains")
    if b > 0:
        return ("the estimate is at the bound sigma = inf: as many flips landed on the starting "
                "side as psi uniform gives, or more")
    return ""

def _models_note(dens) -> str:
    base = "  geometric = eq. 11, dynamic = eq. 12 (Keller flip, psi = 90 deg)"
    return base + "".join(f"; {name} = psi-averaged (eq. 15)" for name in dens) + "."


# --------------------------------------------------------------------------- fit


MAX_FILE_BYTES = 50_000_000  #: the largest experiments file (coin fit FILE or -)


def _read_text(path: str) -> tuple[str, str]:
    """The text of an experiments file, or of stdin for '-', and the name to call it by.

    At most :data:`MAX_FILE_BYTES` are read, in chunks, whatever the file claims to be
    (/dev/zero and pipes have no size); reading stops at a NUL byte.  A named file must be a
    regular file (:func:`coincli.io.files.read_regular`).
    """
    if path.strip() == "-":
        if sys.stdin is None:
            raise usage_error("FILE '-' reads the experiments from standard input, but there "
                              "is none")
        name = "stdin"
        data, why = read_capped(stream_reader(sys.stdin), MAX_FILE_BYTES)
    else:
        name = path
        try:
            data, why = read_regular(path, MAX_FILE_BYTES)  # a FIFO or device: refused
        except FileKindError as exc:
            raise usage_error(f"cannot read {_clipped(path)}: it is {exc.kind}, not a regular "
                              "file; give an experiments file, or '-' to read a pipe") from None
        except OSError as exc:
            raise usage_error(f"cannot read {_clipped(path)}: {exc.strerror or exc}") from None
    if why == "size":
        raise usage_error(f"{_file_name(name)}: larger than {MAX_FILE_BYTES // 10**6} MB; is this "
                          f"an experiments file? (at most {MAX_FILE_BYTES} bytes)")
    if why == "nul":
        raise usage_error(f"{_file_name(name)}: contains a NUL byte; expected a CSV text file")
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError:
        raise usage_error(f"{_file_name(name)}: not UTF-8 text") from None
    return text, name


def _clipped(text: str, limit: int = 60) -> str:
    """User text (a path, a number) for an error message: unquoted unless it holds control
    characters (then as repr writes it: one line), cut to about ``limit`` characters."""
    if not text.isprintable():
        return shown(text, limit)
    return text if len(text) <= limit + 2 else text[:limit - 3] + "..."


def _file_name(path: str) -> str:
    """A file that opened: its whole name (at most PATH_MAX), on one line."""
    return _clipped(path, 4096)


def _experiments(text: str, name: str, delimiter: str | None = None, caught: bool = True):
    """The experiments of ``text`` as columns (:class:`ExperimentColumns`: a file of 10^5 rows
    holds numbers, not row objects); each count, and each row's total, at most 2**53."""
    from coincli.io.experiments import parse_experiment_columns

    name = _file_name(name)

    def each(e):
        c = e.counts
        for column in ("heads", "sides", "tails", "n"):
            v = getattr(c, column)
            if v is not None and v > parse.MAX_COUNT and (column != "n" or c.heads is None):
                raise usage_error(f"{name} line {e.line}, column {column!r}: {column} must be a "
                                  f"whole number from 0 to {parse.MAX_COUNT} (2**53), got "
                                  f"{_clipped(str(v))}")
        _check_total(c, f"{name} line {e.line}: ")

    try:
        return parse_experiment_columns(text, delimiter=delimiter, each=each, caught=caught)
    except InputError:
        raise
    except ValueError as exc:
        raise usage_error(f"{name} {exc}") from None


def fit(file: str, *, psi_dist: str | None = None, no_spread: bool = False,
        delimiter: str | None = None, design: str | None = None, alpha: str = "0.05",
        confidence: str = "0.95", landing: str = "catch", fit: str | None = None,
        seed: str | None = None, save: str | None = None, design_tosses: str | None = None,
        surface: str | None = None, restitution: str | None = None,
        friction: str | None = None, torsional: str | None = None, rolling: str | None = None,
        release_height: str | None = None, vx: str | None = None, u: str | None = None,
        omega: str | None = None, psi: str | None = None, jobs: str | None = None,
        dt: str | None = None, t_max: str | None = None, scheduler: str | None = None,
        checkpoint: str | None = None, timeout: str | None = None,
        calibration: str | None = None, fmt: str = "table", quiet: bool = False,
        progress=None):
    """What ``coin fit FILE`` prints: every experiment of ``file`` checked as :func:`check`
    does, then the models compared across experiments (log-likelihood, AIC, the paper's sum of
    squared errors of the side frequencies) and the maximum-likelihood spread of psi with its
    profile-likelihood interval.

    ``file`` is a path, or ``-`` for standard input.  Returns three human tables (a list) for
    ``fmt="table"``, else the one machine :class:`Result`, streamed by chunks (under ``quiet``:
    the fitted spread in degrees).  Raises InputError for a wrong input or file, NotComputable
    when the fit cannot be computed.

    ``landing="bounce"``: the table is calibrated instead (:func:`coincli.reports.calibrate.fit`,
    with ``fit``, ``seed``, ``save``, ``design_tosses``, the surface and launch options and
    where the design's tosses run, ``scheduler``, ``checkpoint``, ``timeout``; ``progress()``: a
    progress bar, or None).

    ``design`` with ``calibration`` (a calibration file): each tosser's coin is designed on the
    calibrated table too (:func:`_table_designs`: a bouncing design per tosser, at most
    ``design_tosses`` tosses each, ``seed``, ``jobs``).
    """
    from coincli.reports.bounce import landing_of

    bounce = {"--fit": fit, "--seed": seed, "--save": save, "--design-tosses": design_tosses,
              "--surface": surface, "--restitution": restitution, "--friction": friction,
              "--torsional": torsional, "--rolling": rolling, "--release-height": release_height,
              "--vx": vx, "--u": u, "--omega": omega, "--psi": psi, "--jobs": jobs, "--dt": dt,
              "--t-max": t_max, "--scheduler": scheduler, "--checkpoint": checkpoint,
              "--timeout": timeout}
    if landing_of(landing) == "bounce":
        from coincli.reports import calibrate

        if calibration is not None:
            raise usage_error("--calibration goes with --design (each tosser's coin on your "
                              "calibrated table); --landing bounce fits a calibration (--save)")
        if no_spread or alpha != "0.05" or design is not None:
            raise usage_error("--no-spread, --design and --alpha go with the models (no "
                              "--landing); --landing bounce calibrates a table")
        return calibrate.fit(file, fit_params=fit, seed=seed, save=save,
                             design_tosses=design_tosses, delimiter=delimiter, surface=surface,
                             restitution=restitution, friction=friction, torsional=torsional,
                             rolling=rolling, release_height=release_height, vx=vx, u=u,
                             omega=omega, psi=psi, psi_dist=psi_dist, jobs=jobs, dt=dt,
                             t_max=t_max, confidence=confidence, fmt=fmt, quiet=quiet,
                             progress=progress, scheduler=scheduler, checkpoint=checkpoint,
                             timeout=timeout)
    with_table = ("--seed", "--design-tosses", "--jobs", "--dt", "--t-max", "--release-height",
                  "--vx", "--surface", "--restitution", "--friction", "--torsional", "--rolling")
    extra = [k for k, v in bounce.items() if v is not None
             and (calibration is None or k not in with_table)]
    if extra:
        raise usage_error(f"{', '.join(extra)} go{'es' if len(extra) == 1 else ''} with "
                          "--landing bounce" + (" (or --seed, --design-tosses and --jobs with "
                                                "--calibration)" if calibration else ""))
    physics = None
    if calibration is not None:
        if design is None:
            raise usage_error("--calibration goes with --design P: each tosser's coin, "
                              "designed on your calibrated table too")
        physics = _table_physics(calibration, surface=surface, restitution=restitution,
                                 friction=friction, torsional=torsional, rolling=rolling,
                                 release_height=release_height, vx=vx, jobs=jobs, dt=dt,
                                 t_max=t_max)
    from coincli.core.stats import fit as stats
    from coincli.io.experiments import delimiter_of

    fmt = check_format(fmt)
    a = _level(alpha, "--alpha")
    conf = _level(confidence, "--confidence")
    dens = _densities(psi_dist)
    if quiet and no_spread:
        raise usage_error("--quiet prints the fitted spread of psi; it cannot go with --no-spread")
    try:
        sep = None if delimiter is None else delimiter_of(delimiter)
    except ValueError as exc:
        raise usage_error(f"--{exc}") from None
    p_design = _design(design)
    text, name = _read_text(file)
    exps = _experiments(text, name, sep)
    del text
    is_caught = exps.cc.caught
    if is_caught.any():
        from coincli.core.stats.caught import CAUGHT_XI_LIMIT

        over = (is_caught & (exps.xi > CAUGHT_XI_LIMIT)).nonzero()[0]
        if len(over):
            first = exps[int(over[0])]
            _warn_thick(first.xi, f"{_file_name(name)} line {first.line}"
                        + (f" and {len(over) - 1} more rows" if len(over) > 1 else "") + ": ")
    elif p_design is not None:
        raise usage_error("--design gives each tosser's fair coin from caught flips (same and "
                          f"different); {_file_name(name)} has no caught rows")
    try:
        res = stats.fit(exps, dens, confidence=conf, alpha=a, spread=not no_spread,
                        design=p_design)
    except ValueError as exc:
        raise compute_error(str(exc)) from None
    sp = res.spread
    if quiet:
        return Result("coin fit", FIT_COLUMNS, [], quiet=_deg(sp.sigma))
    table = None
    if physics is not None:
        table = _table_designs(physics, res.caught, exps, p_design, seed=seed,
                               design_tosses=design_tosses, progress=progress)
    lines = exps.line
    n_total = _total(exps.cc.n)
    cf = res.caught
    if fmt == "table":
        out = [
            _observed_result(f"coin fit: {name}, "
                             f"{_plural(len(exps), 'experiment', 'experiments')}, "
                             f"{_plural(n_total, 'toss', 'tosses')}", res.rows, lines, conf),
            _tests_result("models, each experiment", res.rows, lines, _test_note(res.rows)),
            _comparison_result(res, conf),
        ]
        if cf is not None:
            out.append(_tossers_result(exps, cf, lines, conf, p_design, table))
        return out
    spread_cells = ([_deg(sp.sigma), _deg(sp.low), _deg(sp.high)] if sp is not None
                    else [None] * 3)
    models = res.rows.models

    def extra(k):
        return [None] * 4 + (spread_cells if models[k] == stats.SPREAD_MODEL else [None] * 3)

    blank = [None] * len(_observed_columns())
    tail = []
    for m in res.models:
        cells = ["model", None, "all", None, n_total, None, None, None, m.model,
                 None, None, None, None, None, None, None, None, None, None, None,
                 m.log_likelihood, None, *blank, m.n_params, m.aic,
                 None if math.isnan(m.delta_aic) else m.delta_aic, m.sse_sides]
        cells += spread_cells if m.model == stats.SPREAD_MODEL else [None] * 3
        tail.append(tuple(cells))
    if cf is None:
        return Result("coin fit", FIT_COLUMNS, [],
                      chunks=_machine_chunks(res.rows, lines, extra, tail))
    return _caught_fit_result(res, exps, lines, extra, tail, spread_cells, p_design, table)


def _design(text: str | None) -> float | None:
    """--design P: the chance of a side of each tosser's coin (1/3: fair three-sided)."""
    if text is None:
        return None
    try:
        v = parse.parse_probability(text, "--design")
    except ValueError:
        v = math.nan
    if not 0.0 < v < 1.0:
        raise usage_error(f"--design must be a chance of a side strictly between 0 and 1 (1/3 "
                          f"for a fair three-sided coin), got {shown(text)}")
    return v


_N_CAUGHT_FIT = len(CAUGHT_FIT_COLUMNS)


def _caught_fit_result(res, exps, lines, extra, tail, spread_cells, p_design,
                       table=None) -> Result:
    """The machine table of a fit with caught rows: every column, the caught ones last; each
    caught row's psi-spread line carries its own spread; a row of scope ``all`` the tossers'
    heterogeneity.  Each row's cells are made from arrays when its chunk is written."""
    import numpy as np

    from coincli.core.stats import fit as stats

    cf = res.caught
    T = len(res.rows)
    models = res.rows.models
    M = len(models)
    k_spread = models.index(stats.SPREAD_MODEL) if stats.SPREAD_MODEL in models else None
    own = (cf.fits.sigma, cf.fits.low, cf.fits.high)  # radians, of the caught rows alone
    is_caught = res.rows.cc.caught
    bound = np.zeros(T, np.int8)
    bound[cf.rows] = cf.fits.at_bound
    notes = {b: _bound_note(b) or None for b in (-1, 0, 1)}
    design_xi = None
    if cf.fair_xi is not None:
        design_xi = np.full(T, np.nan)
        design_xi[cf.rows] = cf.fair_xi
    base = len(FIT_COLUMNS)  # the sigma columns are the last three of FIT_COLUMNS

    def sigma_maker(c):
        pooled = spread_cells[c]

        def make(a, b):
            j0, j1 = np.searchsorted(cf.rows, [a, b]).tolist()  # the chunk's caught rows
            mine = np.full(b - a, np.nan)
            mine[cf.rows[j0:j1] - a] = np.degrees(own[c][j0:j1])
            out = []
            for caught_i, v in zip(is_caught[a:b].tolist(), mine.tolist(), strict=True):
                for k in range(M):
                    if k != k_spread:
                        out.append(None)
                    elif caught_i:
                        out.append(None if v != v else v)
                    else:
                        out.append(pooled)
            return out
        return make

    def row_cells(j):
        def make(a, b):
            if j == 0:
                return [notes[v] if k == k_spread else None for v in bound[a:b].tolist()
                        for k in range(M)]
            if design_xi is None or not 8 <= j <= 10:
                return [None] * ((b - a) * M)
            xs, cs = design_xi[a:b].tolist(), is_caught[a:b].tolist()
            if j == 8:
                cells = [p_design if c else None for c in cs]
            elif j == 9:
                cells = [x if c else None for x, c in zip(xs, cs, strict=True)]
            else:
                cells = [(None if d != d else x * d) if c else None
                         for x, c, d in zip(xs, cs, exps.diameter[a:b].tolist(), strict=True)]
            return [v for v in cells for _ in range(M)]
        return make

    caught_extra = [row_cells(j) for j in range(_N_CAUGHT_FIT)]
    table_columns = []
    if table is not None:  # each tosser's coin on the calibrated table
        table_columns = TABLE_DESIGN_COLUMNS
        for c in range(len(table_columns)):
            col = np.full(T, None, dtype=object)
            col[cf.rows] = [row[c] for row in table.rows]
            caught_extra.append(lambda a, b, col=col: [v for v in col[a:b].tolist()
                                                       for _ in range(M)])
    row_extra = {base - 3 + c: sigma_maker(c) for c in range(3)}
    n_caught = len(CAUGHT_MACHINE_COLUMNS) + _N_CAUGHT_FIT + len(table_columns)
    tail = [t + (None,) * n_caught for t in tail]
    het = cf.heterogeneity
    if het is not None:
        from coincli.core.stats.caught import HETEROGENEITY_METHOD

        n_c = _total(res.rows.cc.n[cf.rows])
        cells = ["all", None, "caught rows", None, n_c] + [None] * 3 + [stats.SPREAD_MODEL]
        cells += [None] * (base - len(cells) - 3)
        cells += [_deg(het.sigma_common), None, None]
        cells += [None] * len(CAUGHT_MACHINE_COLUMNS)
        cells += [None, HETEROGENEITY_METHOD, het.statistic, het.df, het.p_value,
                  _deg(het.sigma_common), _deg(math.exp(het.mu)), het.tau, None, None, None]
        cells += [None] * len(table_columns)
        tail.append(tuple(cells))
    return Result("coin fit", FIT_COLUMNS + CAUGHT_MACHINE_COLUMNS + CAUGHT_FIT_COLUMNS
                  + table_columns, [], note="" if table is None else table.note,
                  chunks=_machine_chunks(res.rows, lines, extra, tail, caught_extra,
                                         row_extra))


def _total(n) -> int:
    """The sum of an int64 array of counts, exact (a Python int: 10^5 counts of up to 2**53
    overflow int64), a block at a time."""
    return sum(sum(n[a:a + 4096].tolist()) for a in range(0, len(n), 4096))


#: the columns of each tosser's coin on a calibrated table (``coin fit --design P
#: --calibration CAL.json``), after every other column
TABLE_DESIGN_COLUMNS = [
    Column("table_design_xi", "xi on your table"),
    Column("table_design_xi_low", "95% low"),
    Column("table_design_xi_high", "95% high"),
    Column("table_design_diameter_mm", "diameter (mm)"),
    Column("table_design_thickness_mm", "thickness (mm) on your table"),
    Column("table_design_thickness_low_mm", "thickness 95% low"),
    Column("table_design_thickness_high_mm", "thickness 95% high"),
    Column("table_design_dominant", "larger uncertainty", "text"),
    Column("table_design_tosses", "tosses simulated", "int"),
    Column("table_design_seed", "seed", "int"),
]
#: the most tosses of each tosser's design on a calibrated table (``--design-tosses``)
TABLE_DESIGN_TOSSES = 2000


class _TableDesigns:
    """Each caught row's coin on the calibrated table: ``rows`` (one tuple of
    :data:`TABLE_DESIGN_COLUMNS` per caught row, in order) and the ``note`` that says how."""

    def __init__(self, rows, note):
        self.rows, self.note = rows, note


def _table_physics(calibration: str, *, release_height, **opts):
    """The calibrated table of ``--calibration`` (the surface options refused with it)."""
    from coincli.reports.bounce import parse_physics

    return parse_physics("bounce", calibration=calibration, height=release_height, **opts)


def _table_designs(physics, cf, exps, p_design: float, *, seed, design_tosses,
                   progress=None) -> _TableDesigns:
    """Each tosser's coin with the chance of a side ``p_design`` on the calibrated table
    (:func:`coincli.reports.calibrate.design`, as ``coin design --landing bounce --calibration``
    makes it): the calibration's launch (speed and spin) with psi ~ normal(90 deg, the
    tosser's fitted sd) truncated to [0, 180] (sd 0: psi = 90 deg; inf: uniform), the row's
    diameter (else the calibration's prototypes'), at most ``design_tosses`` tosses
    (:data:`TABLE_DESIGN_TOSSES`) and no time limit, so that the seed repeats it.  Tossers of
    one spread and diameter share one design.  Its interval holds the simulation's and the
    calibration's uncertainty (added in variance), not that of the tosser's own sd."""
    from coincli.core.bounce import design as BD
    from coincli.core.toss.launch import Dist
    from coincli.io.options import seed_value
    from coincli.limits import MAX_BOUNCE_TOSSES, STANDARD_G
    from coincli.reports import calibrate
    from coincli.reports.bounce import bounce_tosses, check_coin, check_landing
    from coincli.reports.launch import U_MAX, reach

    least = BD.DESIGN_LEAST
    most = (TABLE_DESIGN_TOSSES if design_tosses is None else
            bounce_tosses(design_tosses, "--design-tosses", least, MAX_BOUNCE_TOSSES))
    seed_v = seed_value(seed)
    path, cal = physics.calibration
    u_spec = calibrate.launch_of(cal)[0]
    done: dict = {}
    rows = []
    for j, i in enumerate(cf.rows.tolist()):
        sigma = float(cf.fits.sigma[j])
        d = float(exps.diameter[i])
        dia_mm = float(cal["diameter_mm"]) if math.isnan(d) else d
        key = (sigma, dia_mm)
        if key not in done:
            psi = (math.pi / 2 if sigma == 0 else
                   Dist("uniform", 0.0, math.pi, 0.0, math.pi) if math.isinf(sigma) else
                   Dist("normal", math.pi / 2, sigma, 0.0, math.pi))
            dia = dia_mm / 1000
            check_coin(physics, None, dia, xi_low=min(BD.DESIGN_GRID),
                       command="coin fit --design --calibration")
            check_landing(physics, u_top=reach(u_spec, U_MAX), g=STANDARD_G,
                          xi=max(BD.DESIGN_GRID), dia=dia, u_text="the calibration's")
            r = calibrate.design(physics, targets=[p_design], seed=seed_v, tol=0.01,
                                 max_tosses=most, time_limit=1e9, diameter=dia, g=STANDARD_G,
                                 given={"u": None, "omega": None, "psi": None},
                                 progress=progress, psi=psi)
            v = dict(zip((c.name for c in r.columns), r.rows[0], strict=True))
            done[key] = (v["xi"], v["xi_low"], v["xi_high"], dia_mm, v["thickness_mm"],
                         v["thickness_low_mm"], v["thickness_high_mm"], v["dominant"],
                         v["tosses"], v["seed"])
        rows.append(done[key])
    tab = ", ".join(f"{n} {cal['parameters'][n]['estimate']:.3g}" for n in cal["fitted"])
    note = (f"on your table: each tosser's coin with P(sides) = {p_design:.6g} designed on the "
            f"calibrated table ({path}: {tab}), simulated (MuJoCo): the calibration's launch "
            "(speed, spin) with psi ~ normal about 90 deg with the tosser's fitted sd, "
            f"truncated to [0, 180]; {len(done)} bouncing design"
            f"{'' if len(done) == 1 else 's'} (one per distinct sd and diameter), at most "
            f"{most} tosses each (--design-tosses) and more on tables either side of the "
            f"calibration, {sum(v[8] for v in done.values())} tosses in all, seed {seed_v}.  "
            "Each interval holds the "
            "simulation's and the calibration's uncertainty (delta method, added in variance; "
            "table_design_dominant says which is larger), not that of the tosser's own sd.  "
            "A row with no diameter is designed for the calibration's prototypes "
            f"({float(cal['diameter_mm']):g} mm).")
    return _TableDesigns(rows, note)


def _tossers_result(exps, cf, lines, conf: float, p_design, table=None) -> Result:
    """The human table of the caught rows: each tosser's spread (and fair coin)."""
    from coincli.core.stats.tests import percent

    pct = percent(conf)
    cols = [Column("line", "line", "int"), Column("label", "label", "text"),
            Column("same", "same / n", "text"), Column("sigma_deg", "psi sd (deg)"),
            Column("interval", f"{pct} profile interval (deg)", "text")]
    if cf.fair_xi is not None:
        cols += [Column("design_xi", f"xi for P(sides) = {p_design:.6g}"),
                 Column("design_thickness_mm", "thickness (mm)")]
    if table is not None:
        cols += [Column("table_design_xi", "xi on your table"),
                 Column("table_interval", "95% interval", "text"),
                 Column("table_design_thickness_mm", "thickness (mm) on your table")]
    rows_of = cf.rows

    def body(a: int, b: int) -> list[tuple]:
        """Caught rows ``a`` to ``b`` (of the caught rows alone)."""
        out = []
        for j, i in enumerate(rows_of[a:b].tolist(), start=a):
            e = exps[i]
            row = [int(lines[i]), e.label, f"{e.counts.same} / {e.counts.n}",
                   _deg(float(cf.fits.sigma[j])),
                   f"{_fmt_deg(float(cf.fits.low[j]))} to {_fmt_deg(float(cf.fits.high[j]))}"]
            if cf.fair_xi is not None:
                x = float(cf.fair_xi[j])
                row += [x, None if e.diameter is None else x * e.diameter]
            if table is not None:
                t = table.rows[j]
                row += [t[0], f"{t[1]:.4g} to {t[2]:.4g}", t[4]]
            out.append(tuple(row))
        return out

    notes = ["caught flips (faces only): each row is one tosser, fitted alone: psi ~ normal "
             "about 90 deg truncated to [0, 180], the chance of the same side "
             "P(H) / (P(H) + P(T)) (the start side as heads); a row at a bound is noted in "
             "the machine output (sigma_note)."]
    bounds = int((cf.fits.at_bound != 0).sum())
    if bounds:
        notes.append(f"{_plural(bounds, 'row has', 'rows have')} the estimate at a bound "
                     "(sd 0: no more same-side flips than a Keller flip's 1/2; inf: as many as "
                     "psi uniform gives, or more).")
    het = cf.heterogeneity
    if het is not None:
        notes.append(
            f"one spread for all tossers: sd {_fmt_deg(het.sigma_common)} deg; do they differ? "
            f"likelihood-ratio test of one spread per tosser against one for all: "
            f"{het.statistic:.4g} on {het.df} df, p = {het.p_value:.3g}; random effects "
            f"(log sd ~ normal, maximum marginal likelihood): median tosser "
            f"{_fmt_deg(math.exp(het.mu))} deg, sd of log sd between tossers {het.tau:.3g} "
            f"(a factor of {math.exp(het.tau):.3g}).")
    if cf.fair_xi is not None:
        notes.append(f"design: the xi whose chance of a side is {p_design:.6g} under each "
                     "tosser's fitted spread (the paper's model, no bounce); the thickness for "
                     "the row's diameter when the row gives one (coin or diameter).")
    if table is not None:
        notes.append(table.note)
    return _chunked("each tosser (caught rows)", cols, body, len(rows_of), 1, "\n".join(notes))

def _comparison_result(res, conf: float) -> Result:
    cols = [Column("model", "model", "text"), Column("n_params", "fitted parameters", "int"),
            Column("log_likelihood", "log-likelihood"), Column("aic", "AIC"),
            Column("delta_aic", "delta AIC"), Column("sse_sides", "SSE of side frequencies")]
    body = [(m.model, m.n_params, m.log_likelihood, m.aic, m.delta_aic, m.sse_sides)
            for m in res.models]
    sp = res.spread
    notes = ["AIC = 2k - 2 log L (lower is better; a difference below 2 is no real preference); "
             "SSE = sum over experiments of (observed - predicted side frequency)^2, as in "
             "Sec. IV of the paper."]
    if sp is not None:
        pieces = ", ".join(f"{_fmt_deg(lo)} to {_fmt_deg(hi)}" for lo, hi in sp.pieces)
        notes.append(
            f"psi-spread: psi ~ normal about 90 deg truncated to [0, 180]; maximum-likelihood sd "
            f"{_fmt_deg(sp.sigma)} deg, {100 * conf:g}% profile-likelihood interval {pieces} deg"
            + (f" ({sp.note})" if sp.note else "") + "."
        )
    return Result("model comparison, all experiments", cols, body, note="\n".join(notes))


def _fmt_deg(v: float) -> str:
    return "inf (uniform psi)" if math.isinf(v) else f"{math.degrees(v):.3g}"

