"""``coin check`` and ``coin fit``: real tosses against the models.

Thin: parse the options (or the experiments file), call :mod:`coincli.core.stats.tests`, build
:class:`Result` tables, emit them.  The human output (``--format table``) is a few short tables;
every machine format (csv, tsv, json, jsonl) gets one long table instead, one row per experiment
and model (and, for ``fit``, one per model across experiments), with stable column names.
numpy and scipy load when a command runs, never at import.
"""

from __future__ import annotations

import math
import sys
from typing import Annotated

import typer

from coincli.cli import _options, app
from coincli.cli._options import FormatOpt, QuietOpt
from coincli.errors import compute_error, shown, usage_error
from coincli.io import grammar as parse
from coincli.io.files import Unreadable, read_text
from coincli.io.table import CHUNK_ROWS, Column, Result, check_format, emit

_OUTCOMES = ("heads", "sides", "tails")

# --------------------------------------------------------------------------- shared options

PsiDistsOpt = _options.PsiDistsOpt
AlphaOpt = Annotated[
    str, typer.Option("--alpha", help="Significance level of the verdicts.", metavar="A")
]
ConfidenceOpt = Annotated[
    str, typer.Option("--confidence", help="Confidence level of the intervals.", metavar="C")
]


def _opt(*names: str, mv: str, help: str):
    return typer.Option(*names, metavar=mv, help=help)


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
    return {d.spec: d for d in _options.psi_densities(specs)}


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


def _values(arr) -> list:
    """numpy values as Python ones, NaN as None (an empty cell)."""
    return [None if v != v else v for v in arr.tolist()]


def _machine_chunks(ch, lines, extra=None, tail_rows=()):
    """The machine table a chunk at a time (lists of columns, at most CHUNK_ROWS rows): one
    row per experiment and model (experiment-major), then ``tail_rows`` (tuples).
    ``extra(k)`` gives the fit's extra cells of model ``k``.  A file of 10^5 experiments is
    written without ever holding its 10^5 x models x 45 cells."""
    import numpy as np

    M = len(ch.tests)
    T = len(ch)
    cc = ch.cc
    faces = cc.faces

    def per_exp(arr):
        return lambda a, b: [v for v in _values(arr[a:b]) for _ in range(M)]

    def per_exp_list(seq):
        return lambda a, b: [v for v in seq[a:b] for _ in range(M)]

    def per_test(stack):
        return lambda a, b: _values(stack[a:b].ravel())

    def per_test_list(lists):
        return lambda a, b: [lst[i] for i in range(a, b) for lst in lists]

    def const(v):
        return lambda a, b: [v] * ((b - a) * M)

    tests = ch.tests
    nan = np.nan
    raw = [np.stack([t.raw[j] for t in tests], axis=1) for j in range(3)]
    exp_cols = []
    for j in range(3):
        e = np.stack([t.expected[j] if j != 1 else
                      np.where(faces, t.expected[1], t.expected[0]) for t in tests], axis=1)
        if j != 1:
            e = np.where(faces[:, None], e, nan)
        exp_cols.append(e)
    makers = [
        const("experiment"),
        per_exp_list(lines) if lines is not None else const(None),
        per_exp_list(ch.labels),
        per_exp(np.asarray(ch.xi, dtype=float)),
        per_exp(cc.n),
        per_exp(np.where(faces, cc.heads, nan) if not faces.all() else cc.heads),
        per_exp(cc.sides),
        per_exp(np.where(faces, cc.tails, nan) if not faces.all() else cc.tails),
        lambda a, b: [t.model for _ in range(a, b) for t in tests],
        per_test(raw[0]), per_test(raw[1]), per_test(raw[2]),
        per_test(exp_cols[0]), per_test(exp_cols[1]), per_test(exp_cols[2]),
        per_test_list([t.method for t in tests]),
        per_test(np.stack([t.exact for t in tests], axis=1)),
        per_test(np.stack([t.p_value for t in tests], axis=1)),
        per_test(np.stack([t.g for t in tests], axis=1)),
        per_test(np.stack([t.df for t in tests], axis=1)),
        per_test(np.stack([t.log_likelihood for t in tests], axis=1)),
        per_test_list([t.verdict for t in tests]),
    ]
    for name in _OUTCOMES:
        makers += [per_exp(v) for v in ch.intervals[name]]
    if extra is not None:
        for c in range(len(extra(0))):
            cells = [extra(k)[c] for k in range(M)]
            makers.append(lambda a, b, cells=cells: cells * (b - a))
    # heads and tails: int columns with None where faces were not told apart
    makers[5], makers[7] = _ints(makers[5]), _ints(makers[7])
    step = max(1, min(CHUNK_ROWS, 8192) // M)  # 45 columns: 8192 rows of cells at a time
    for a in range(0, T, step):
        yield [make(a, min(a + step, T)) for make in makers]
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

    def rows(a: int, b: int) -> list[tuple]:
        per = {name: [v[a:b].tolist() for v in ch.intervals[name]] for name in _OUTCOMES}
        counts = {"heads": cc.heads[a:b].tolist(), "sides": cc.sides[a:b].tolist(),
                  "tails": cc.tails[a:b].tolist()}
        xi = ch.xi[a:b].tolist()
        body = []
        for j, f in enumerate(cc.faces[a:b].tolist()):
            lead = [lines[a + j], ch.labels[a + j], xi[j]] if with_line else []
            for name in (_OUTCOMES if f else ("sides",)):
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
    cols += [Column("model", "model", "text"), Column("p_heads", "P(heads)"),
             Column("p_sides", "P(sides)"), Column("p_tails", "P(tails)"),
             Column("expected", "expected H / S / T", "text"), Column("p_value", "p-value"),
             Column("log_likelihood", "log-likelihood"), Column("verdict", "verdict", "text")]
    def rows(a: int, b: int) -> list[tuple]:
        tests = [(t.model, t.raw[:, a:b].T.tolist(), t.expected[:, a:b].T.tolist(),
                  t.p_value[a:b].tolist(), t.log_likelihood[a:b].tolist(), t.verdict[a:b])
                 for t in ch.tests]
        body = []
        for j, f in enumerate(ch.cc.faces[a:b].tolist()):
            lead = [lines[a + j], ch.labels[a + j]] if with_line else []
            for model, raw, exp, pv, ll, ver in tests:
                e = exp[j]
                shown = e if f else (None, e[0], None)
                body.append((*lead, model, *raw[j],
                             " / ".join("-" if v is None else _count_text(v) for v in shown),
                             pv[j], ll[j], ver[j]))
        return body

    return _chunked(title, cols, rows, len(ch), len(ch.tests), note)


def _emit_all(human: list[Result], machine: Result, fmt: str, quiet: bool) -> None:
    """Human tables one after another, or the one machine table."""
    if quiet or fmt != "table":
        emit(machine, fmt, quiet)
        return
    for k, res in enumerate(human):
        if k:
            sys.stdout.write("\n")
        emit(res, fmt)


def _test_note(ch) -> str:
    tests = sorted({m for t in ch.tests for m in set(t.method)})
    return (
        f"test: {', '.join(tests)}; p = the chance, under the model, of counts no more likely "
        "than those observed.  'consistent' means the tosses do not contradict the model, not "
        "that they confirm it."
    )


# --------------------------------------------------------------------------- check


def _xi_from_options(xi, quarters, coin, count, diameter, thickness) -> tuple[float, str]:
    """The coin tossed (the shared coin group) and its label."""
    c = _options.resolve_coin(xi, coin, count, quarters, diameter, thickness,
                              xi_rule="finite", command="coin check")
    return c.xi, c.label()


@app.command()
def check(
    xi: _options.XiOpt = None,
    quarters: _options.QuartersOpt = None,
    coin: _options.CoinOpt = None,
    count: _options.CountOpt = None,
    diameter: _options.DiameterOpt = None,
    thickness: _options.ThicknessOpt = None,
    heads: Annotated[str | None, _opt("--heads", mv="H", help="Tosses that landed heads.")
                     ] = None,
    sides: Annotated[str | None, _opt("--sides", "-s", mv="S",
                                      help="Tosses that landed on a side.")] = None,
    tails: Annotated[str | None, _opt("--tails", mv="T", help="Tosses that landed tails.")
                     ] = None,
    tosses: _options.TossesOpt = None,
    psi_dist: PsiDistsOpt = None,
    alpha: AlphaOpt = "0.05",
    confidence: ConfidenceOpt = "0.95",
    fmt: FormatOpt = "table",
    quiet: QuietOpt = False,
):
    """Are your tosses consistent with the models?  Intervals, exact tests, verdicts.

    Gives the observed frequencies with Wilson and Clopper-Pearson intervals and, for the
    geometric and dynamic models (and each --psi-dist), the expected counts, an exact
    multinomial goodness-of-fit p-value (binomial with --sides and -n alone), the
    log-likelihood and a verdict.  --quiet prints the p-values, one per model.

    Examples: coin check --xi 0.583 --heads 35 --sides 33 --tails 32 ;
    coin check --quarters 8 --sides 33 -n 100 ;  coin check --coin nickel --count 3 --heads 60
    --sides 9 --tails 31 --psi-dist normal:90:20 --format json
    """
    from coincli.core.stats import tests as stats

    fmt = check_format(fmt)
    a = _level(alpha, "--alpha")
    conf = _level(confidence, "--confidence")
    x, label = _xi_from_options(xi, quarters, coin, count, diameter, thickness)
    vals = {name: _whole(v, f"--{name}" if name != "n" else "-n")
            for name, v in (("heads", heads), ("sides", sides), ("tails", tails), ("n", tosses))}
    try:
        counts = stats.make_counts(**vals)
    except ValueError as exc:
        raise usage_error(str(exc)) from None
    _check_total(counts)
    dens = _densities(psi_dist)
    try:
        chances = stats.model_chances(x, dens)
        ch = stats.check_many([counts], x, chances, confidence=conf, alpha=a, labels=[label])
    except ValueError as exc:
        raise compute_error(str(exc)) from None
    machine = Result("coin check", MACHINE_COLUMNS, [],
                     data=next(_machine_chunks(ch, None)),
                     quiet=[float(t.p_value[0]) for t in ch.tests])
    coin_text = f"xi = {x:.6g}" if xi is not None else f"{label} (xi = {x:.6g})"
    title = f"coin check: {coin_text}, {_plural(counts.n, 'toss', 'tosses')}"
    human = [
        _observed_result(title, ch, None, conf),
        _tests_result("models", ch, None, _test_note(ch) + _models_note(dens)),
    ]
    _emit_all(human, machine, fmt, quiet)


def _models_note(dens) -> str:
    base = "  geometric = eq. 11, dynamic = eq. 12 (Keller flip, psi = 90 deg)"
    return base + "".join(f"; {name} = psi-averaged (eq. 15)" for name in dens) + "."


# --------------------------------------------------------------------------- fit


MAX_FILE_BYTES = 50_000_000  #: the largest experiments file (coin fit FILE or -)


def _read_text(path: str) -> tuple[str, str]:
    """The text of an experiments file, or of stdin for '-', and the name to call it by.

    At most :data:`MAX_FILE_BYTES` are read, in chunks, whatever the file claims to be
    (/dev/zero and pipes have no size); reading stops at a NUL byte.  A named file must be a
    regular file (:func:`coincli.io.files.read_text`).
    """
    stdin = path.strip() == "-"
    if stdin and sys.stdin is None:
        raise usage_error("FILE '-' reads the experiments from standard input, but there "
                          "is none")
    name = "stdin" if stdin else path
    try:
        return read_text(sys.stdin if stdin else path, MAX_FILE_BYTES), name
    except Unreadable as exc:
        if exc.reason == "system" and stdin:  # as any failure of the system: exit 1, its words
            raise compute_error(exc.detail) from None
        raise usage_error({
            "kind": f"cannot read {_clipped(path)}: it is {exc.detail}, not a regular file; "
                    "give an experiments file, or '-' to read a pipe",
            "system": f"cannot read {_clipped(path)}: {exc.detail}",
            "size": f"{_file_name(name)}: larger than {MAX_FILE_BYTES // 10**6} MB; is this an "
                    f"experiments file? (at most {MAX_FILE_BYTES} bytes)",
            "nul": f"{_file_name(name)}: contains a NUL byte; expected a CSV text file",
            "utf8": f"{_file_name(name)}: not UTF-8 text",
        }[exc.reason]) from None


def _clipped(text: str, limit: int = 60) -> str:
    """User text (a path, a number) for an error message: unquoted unless it holds control
    characters (then as repr writes it: one line), cut to about ``limit`` characters."""
    if not text.isprintable():
        return shown(text, limit)
    return text if len(text) <= limit + 2 else text[:limit - 3] + "..."


def _file_name(path: str) -> str:
    """A file that opened: its whole name (at most PATH_MAX), on one line."""
    return _clipped(path, 4096)


def _experiments(text: str, name: str, delimiter: str | None = None) -> list:
    """The experiments of ``text``; each count, and each row's total, at most 2**53."""
    from coincli.core.stats import tests as stats

    name = _file_name(name)
    try:
        exps = stats.parse_experiments(text, delimiter=delimiter)
    except ValueError as exc:
        raise usage_error(f"{name} {exc}") from None
    for e in exps:
        c = e.counts
        for column in ("heads", "sides", "tails", "n"):
            v = getattr(c, column)
            if v is not None and v > parse.MAX_COUNT and (column != "n" or c.heads is None):
                raise usage_error(f"{name} line {e.line}, column {column!r}: {column} must be a "
                                  f"whole number from 0 to {parse.MAX_COUNT} (2**53), got "
                                  f"{_clipped(str(v))}")
        _check_total(c, f"{name} line {e.line}: ")
    return exps


@app.command()
def fit(
    file: Annotated[str, typer.Argument(help="Experiments CSV, or - for stdin.",
                                        metavar="FILE")],
    psi_dist: PsiDistsOpt = None,
    no_spread: Annotated[bool, typer.Option("--no-spread", help="Skip the fit of the spread "
                                            "of psi.")] = False,
    delimiter: Annotated[str | None, typer.Option(
        "--delimiter", help="Separator of FILE: comma, semicolon or tab (default: the one the "
        "header uses).", metavar="SEP")] = None,
    alpha: AlphaOpt = "0.05",
    confidence: ConfidenceOpt = "0.95",
    fmt: FormatOpt = "table",
    quiet: QuietOpt = False,
):
    """Which model do your tosses follow?  Checks a file of experiments and compares models.

    FILE has a header and one experiment a row: the coin as xi, or coin (and count), or
    diameter and thickness; the tosses as heads, sides, tails, or sides and n; optionally a
    label.  Reports every row as `coin check` does, then across rows: the paper's sum of
    squared errors of the side frequencies, each model's log-likelihood and AIC, and the
    maximum-likelihood spread of psi (sd of a normal about 90 deg, truncated to [0, 180]) with
    its profile-likelihood interval.  --quiet prints that spread in degrees.

    Examples: coin fit tosses.csv ;  coin fit tosses.csv --format csv ;
    coin fit - --psi-dist uniform,cosine < tosses.csv
    """
    from coincli.core.stats import tests as stats

    fmt = check_format(fmt)
    a = _level(alpha, "--alpha")
    conf = _level(confidence, "--confidence")
    dens = _densities(psi_dist)
    if quiet and no_spread:
        raise usage_error("--quiet prints the fitted spread of psi; it cannot go with --no-spread")
    try:
        sep = None if delimiter is None else stats.delimiter_of(delimiter)
    except ValueError as exc:
        raise usage_error(f"--{exc}") from None
    text, name = _read_text(file)
    exps = _experiments(text, name, sep)
    del text
    try:
        res = stats.fit(exps, dens, confidence=conf, alpha=a, spread=not no_spread)
    except ValueError as exc:
        raise compute_error(str(exc)) from None
    sp = res.spread
    spread_cells = ([_deg(sp.sigma), _deg(sp.low), _deg(sp.high)] if sp is not None
                    else [None] * 3)
    models = [t.model for t in res.rows.tests]

    def extra(k):
        return [None] * 4 + (spread_cells if models[k] == stats.SPREAD_MODEL else [None] * 3)

    lines = [e.line for e in exps]
    n_total = sum(e.counts.n for e in exps)
    blank = [None] * len(_observed_columns())
    tail = []
    for m in res.models:
        cells = ["model", None, "all", None, n_total, None, None, None, m.model,
                 None, None, None, None, None, None, None, None, None, None, None,
                 m.log_likelihood, None, *blank, m.n_params, m.aic,
                 None if math.isnan(m.delta_aic) else m.delta_aic, m.sse_sides]
        cells += spread_cells if m.model == stats.SPREAD_MODEL else [None] * 3
        tail.append(tuple(cells))
    if quiet:
        machine = Result("coin fit", FIT_COLUMNS, [], quiet=_deg(sp.sigma))
    else:
        machine = Result("coin fit", FIT_COLUMNS, [],
                         chunks=_machine_chunks(res.rows, lines, extra, tail))
    if quiet or fmt != "table":
        human = []
    else:
        human = [
            _observed_result(f"coin fit: {name}, "
                             f"{_plural(len(exps), 'experiment', 'experiments')}, "
                             f"{_plural(n_total, 'toss', 'tosses')}", res.rows, lines, conf),
            _tests_result("models, each experiment", res.rows, lines, _test_note(res.rows)),
            _comparison_result(res, conf),
        ]
    _emit_all(human, machine, fmt, quiet)


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
