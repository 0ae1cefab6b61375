"""What ``coin check`` and ``coin fit`` share: the tables of real tosses against the models.

The human output (``--format table``) is a few short tables (:func:`observed_result`,
:func:`tests_result`); every machine format (csv, tsv, json, jsonl) gets one long table
instead, one row per experiment and model (and, for ``fit``, one per model across
experiments), with stable column names (:data:`MACHINE_COLUMNS`, :data:`FIT_COLUMNS`), streamed
a chunk at a time (:func:`machine_chunks`: a file of 10^5 experiments).  And the notes both
commands write (:func:`test_note`, :func:`bound_note`, :func:`warn_thick`).  numpy and scipy
load when a report runs, never at import.
"""

from __future__ import annotations

import math

from coincli.io import notes
from coincli.io import options
from coincli.io.table import CHUNK_ROWS, Column, Result

OUTCOMES = ("heads", "sides", "tails")


def psi_densities_by_spec(specs: str | None) -> dict:
    """--psi-dist, parsed as every command parses it, by machine name."""
    if specs is None:
        return {}
    return {d.spec: d for d in options.psi_densities(specs)}


def degrees(v: float | None) -> float | None:
    return None if v is None else math.degrees(v)


def observed_columns() -> list[Column]:
    cols = []
    for name in OUTCOMES:
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
    *observed_columns(),
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


def machine_chunks(ch, lines, extra=None, tail_rows=(), caught_extra=None, row_extra=None):
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
    for name in OUTCOMES:
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


def plural(n: int, one: str, many: str) -> str:
    """``1 toss``, ``2 tosses``, ``0 experiments``."""
    return f"{n} {one if n == 1 else many}"


def _interval_text(lo: float, hi: float) -> str:
    return f"{lo:.4g} to {hi:.4g}"


def observed_result(title: str, ch, lines, confidence: float) -> Result:
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
    names = OUTCOMES + (("same",) if caught.any() else ())

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
            for name in (OUTCOMES if f else ("same",) if c else ("sides",)):
                est, wl, wh, cl, chh = (col[j] for col in per[name])
                body.append((*lead, name, counts[name][j], est, _interval_text(wl, wh),
                             _interval_text(cl, chh)))
        return body

    return chunked(title, cols, rows, len(ch), 3)


def chunked(title: str, cols, rows, n: int, per: int, note: str = "") -> Result:
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


def tests_result(title: str, ch, lines, note: str) -> Result:
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

    return chunked(title, cols, rows, len(ch), len(ch.models), note)


def test_note(ch) -> str:
    tests = sorted(ch.methods())
    return (
        f"test: {', '.join(tests)}; p = the chance, under the model, of counts no more likely "
        "than those observed.  'consistent' means the tosses do not contradict the model, not "
        "that they confirm it."
    )


def warn_thick(x: float, where: str) -> None:
    """Caught flips of a thick coin: warn (:mod:`coincli.io.notes`), once per run."""
    from coincli.core.stats.caught import CAUGHT_XI_LIMIT

    if x > CAUGHT_XI_LIMIT:
        notes.warning(f"{where}xi = {x:.6g} is above {CAUGHT_XI_LIMIT}: caught flips (faces "
                      "only) are the thin coin's case; this coin lands on a side often enough "
                      "that conditioning on a face may not describe how it was caught")


def percent_text(conf: float) -> str:
    from coincli.core.stats.tests import percent

    return percent(conf)


def bound_note(b: int) -> str:
    if b < 0:
        return ("the estimate is at the bound sigma = 0: no more flips landed on the starting "
                "side than on the other, which a Keller flip (1/2) already explains")
    if b > 0:
        return ("the estimate is at the bound sigma = inf: as many flips landed on the starting "
                "side as psi uniform gives, or more")
    return ""


def deg_text(v: float) -> str:
    return "inf (uniform psi)" if math.isinf(v) else f"{math.degrees(v):.3g}"
