"""``coin check`` and ``coin fit``: real tosses against the models.

Thin: parse the options (or the experiments file), call :mod:`coincli.stats`, build
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

from coincli import parse
from coincli._files import FileKindError, read_regular
from coincli.cli import _options, app
from coincli.cli._common import (
    Column,
    FormatOpt,
    QuietOpt,
    Result,
    check_format,
    compute_error,
    emit,
    read_capped,
    shown,
    stream_reader,
    usage_error,
)

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
        raise usage_error(str(exc)) from None
    if not 0.0 < v < 1.0:
        raise usage_error(f"{what} must be strictly between 0 and 1, got {text!r}")
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


def _observed_cells(row) -> list:
    """freq, Wilson low/high, Clopper-Pearson low/high for heads, sides, tails (None if unknown)."""
    by = {p.outcome: p for p in row.proportions}
    cells = []
    for name in _OUTCOMES:
        p = by.get(name)
        cells += ([None] * 5 if p is None else
                  [p.estimate, p.wilson.low, p.wilson.high, p.clopper_pearson.low,
                   p.clopper_pearson.high])
    return cells


def _observed_columns() -> list[Column]:
    cols = []
    for name in _OUTCOMES:
        cols += [Column(f"freq_{name}", f"{name} frequency"),
                 Column(f"{name}_wilson_low", f"{name} Wilson low"),
                 Column(f"{name}_wilson_high", f"{name} Wilson high"),
                 Column(f"{name}_cp_low", f"{name} Clopper-Pearson low"),
                 Column(f"{name}_cp_high", f"{name} Clopper-Pearson high")]
    return cols


def _expected3(t) -> tuple:
    """Expected (heads, sides, tails); faces not told apart: (None, sides, None)."""
    if len(t.expected) == 3:
        return t.expected
    return (None, t.expected[0], None)


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


def _experiment_rows(row, line, extra=None) -> list[tuple]:
    """One machine row per model for one checked experiment."""
    c = row.counts
    out = []
    for t in row.tests:
        eh, es, et = _expected3(t)
        cells = ["experiment", line, row.label, row.xi, c.n, c.heads, c.sides, c.tails, t.model,
                 float(t.chances.heads), float(t.chances.sides), float(t.chances.tails),
                 eh, es, et, t.method, t.exact, t.p_value, t.g_statistic, t.df,
                 t.log_likelihood, t.verdict, *_observed_cells(row)]
        if extra is not None:
            cells += extra(t.model)
        out.append(tuple(cells))
    return out


def _interval_text(iv) -> str:
    return f"{iv.low:.4g} to {iv.high:.4g}"


def _expected_text(t) -> str:
    return " / ".join("-" if v is None else _count_text(v) for v in _expected3(t))


def _count_text(v: float) -> str:
    """An expected count for people: 33.3333, 495000, 12345679 (never 4.95e+05)."""
    return f"{v:.6g}" if abs(v) < 1e6 else f"{v:.0f}"


def _plural(n: int, one: str, many: str) -> str:
    """``1 toss``, ``2 tosses``, ``0 experiments``."""
    return f"{n} {one if n == 1 else many}"


def _observed_result(title: str, rows, confidence: float, with_line: bool) -> Result:
    pct = f"{100 * confidence:g}%"
    cols = ([Column("line", "line", "int"), Column("label", "label", "text"),
             Column("xi", "xi")] if with_line else [])
    cols += [Column("outcome", "outcome", "text"), Column("count", "count", "int"),
             Column("frequency", "frequency"),
             Column("wilson", f"{pct} Wilson", "text"),
             Column("cp", f"{pct} Clopper-Pearson", "text")]
    body = []
    for line, r in rows:
        for p in r.proportions:
            lead = [line, r.label, r.xi] if with_line else []
            body.append((*lead, p.outcome, p.count, p.estimate, _interval_text(p.wilson),
                         _interval_text(p.clopper_pearson)))
    return Result(title, cols, body)


def _tests_result(title: str, rows, note: str, with_line: bool) -> Result:
    cols = ([Column("line", "line", "int"), Column("label", "label", "text")]
            if with_line else [])
    cols += [Column("model", "model", "text"), Column("p_heads", "P(heads)"),
             Column("p_sides", "P(sides)"), Column("p_tails", "P(tails)"),
             Column("expected", "expected H / S / T", "text"), Column("p_value", "p-value"),
             Column("log_likelihood", "log-likelihood"), Column("verdict", "verdict", "text")]
    body = []
    for line, r in rows:
        for t in r.tests:
            lead = [line, r.label] if with_line else []
            body.append((*lead, t.model, float(t.chances.heads), float(t.chances.sides),
                         float(t.chances.tails), _expected_text(t), t.p_value, t.log_likelihood,
                         t.verdict))
    return Result(title, cols, body, note=note)


def _emit_all(human: list[Result], machine: Result, fmt: str, quiet: bool) -> None:
    """Human tables one after another, or the one machine table."""
    if quiet or fmt != "table":
        emit(machine, fmt, quiet)
        return
    for k, res in enumerate(human):
        if k:
            sys.stdout.write("\n")
        emit(res, fmt)


def _test_note(rows) -> str:
    tests = sorted({t.method for r in rows for t in r.tests})
    return (
        f"test: {', '.join(tests)}; p = the chance, under the model, of counts no more likely "
        "than those observed.  'consistent' means the tosses do not contradict the model, not "
        "that they confirm it."
    )


# --------------------------------------------------------------------------- check


def _xi_from_options(xi, quarters, coin, count, diameter, thickness) -> tuple[float, str]:
    """The coin tossed (the shared coin group) and its label."""
    c = _options.resolve_coin(xi, coin, count, quarters, diameter, thickness,
                              xi_rule="positive", command="coin check")
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
    from coincli import stats

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
        row = stats.check(counts, x, chances, confidence=conf, alpha=a, label=label)
    except ValueError as exc:
        raise compute_error(str(exc)) from None
    machine = Result("coin check", MACHINE_COLUMNS, _experiment_rows(row, None),
                     quiet=[t.p_value for t in row.tests])
    coin_text = f"xi = {x:.6g}" if xi is not None else f"{label} (xi = {x:.6g})"
    title = f"coin check: {coin_text}, {_plural(counts.n, 'toss', 'tosses')}"
    human = [
        _observed_result(title, [(None, row)], conf, False),
        _tests_result("models", [(None, row)], _test_note([row]) + _models_note(dens), False),
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
    regular file (:func:`coincli._files.read_regular`).
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


def _experiments(text: str, name: str) -> list:
    """The experiments of ``text``; each count, and each row's total, at most 2**53."""
    from coincli import stats

    name = _file_name(name)
    try:
        exps = stats.parse_experiments(text)
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
    from coincli import stats

    fmt = check_format(fmt)
    a = _level(alpha, "--alpha")
    conf = _level(confidence, "--confidence")
    dens = _densities(psi_dist)
    if quiet and no_spread:
        raise usage_error("--quiet prints the fitted spread of psi; it cannot go with --no-spread")
    text, name = _read_text(file)
    exps = _experiments(text, name)
    try:
        res = stats.fit(exps, dens, confidence=conf, alpha=a, spread=not no_spread)
    except ValueError as exc:
        raise compute_error(str(exc)) from None
    sp = res.spread
    spread_cells = ([_deg(sp.sigma), _deg(sp.low), _deg(sp.high)] if sp is not None
                    else [None] * 3)

    def extra(model):
        return [None] * 4 + (spread_cells if model == stats.SPREAD_MODEL else [None] * 3)

    rows = [(e.line, r) for e, r in zip(exps, res.rows, strict=True)]
    machine_rows = []
    for line, r in rows:
        machine_rows += _experiment_rows(r, line, extra)
    n_total = sum(e.counts.n for e in exps)
    blank = [None] * len(_observed_columns())
    for m in res.models:
        cells = ["model", None, "all", None, n_total, None, None, None, m.model,
                 None, None, None, None, None, None, None, None, None, None, None,
                 m.log_likelihood, None, *blank, m.n_params, m.aic, m.delta_aic, m.sse_sides]
        cells += spread_cells if m.model == stats.SPREAD_MODEL else [None] * 3
        machine_rows.append(tuple(cells))
    machine = Result("coin fit", FIT_COLUMNS, machine_rows,
                     quiet=_deg(sp.sigma) if sp is not None else None)
    human = [
        _observed_result(f"coin fit: {name}, {_plural(len(exps), 'experiment', 'experiments')}, "
                         f"{_plural(n_total, 'toss', 'tosses')}", rows, conf, True),
        _tests_result("models, each experiment", rows, _test_note(res.rows), True),
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
