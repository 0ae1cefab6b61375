"""``coin toss``, ``coin simulate``, ``coin phase``: real tosses of finite vigor (Sec. II, Fig. 3).

Thin: parse the options (angles in degrees, lengths in mm, speeds in m/s, rates in rad/s),
convert to SI radians, call :mod:`coincli.toss`, build a :class:`Result` or a picture, print.
A ValueError from the core is bad input: one line, exit 2.  numpy, scipy and rich load only
inside the commands.
"""

from __future__ import annotations

import math
import shutil
import sys
from typing import Annotated

import typer

from coincli import parse
from coincli.cli import app
from coincli.cli._common import (
    Column,
    FormatOpt,
    QuietOpt,
    Result,
    check_format,
    compute_error,
    emit,
    env_no_color,
    stderr_is_terminal,
    stdout_is_terminal,
    usage_error,
    values_option,
)

FAIR_XI = 1 / math.sqrt(3)
DEFAULT_DIAMETER_MM = 24.26  # a US quarter, the paper's coin
DEG = math.pi / 180
U_MAX = 1e8  # m/s, as coincli.toss.U_MAX (kept here so the module needs no numpy to load)

# --------------------------------------------------------------------------- shared options

XiOpt = Annotated[str, typer.Option("--xi", help="Aspect ratio h/D of the coin (0.577 is the fair "
                                    "three-sided coin).", metavar="XI")]
DiameterOpt = Annotated[
    str, typer.Option("--diameter", "-d", help="Coin diameter in mm (or with a unit: 2.4cm, "
                      "0.955in).  Default: a US quarter, 24.26 mm.", metavar="MM")
]
GOpt = Annotated[str, typer.Option("--g", help="Gravity, m/s^2 (> 0).", metavar="G")]
ContactOpt = Annotated[
    str, typer.Option("--contact", help="rim (the paper's: the rim of the mid-plane disc touches "
                      "the catch plane) or thick (the cylinder's lowest corner; the launch "
                      "height rises by h/2).", metavar="rim|thick")
]


def _usage(fn, *args, **kwargs):
    """Call the core; its ValueError is a usage error (the input is out of range)."""
    try:
        return fn(*args, **kwargs)
    except ValueError as exc:
        raise usage_error(str(exc)) from None


def _contact(text: str) -> str:
    c = text.strip().lower()
    if c not in ("rim", "thick"):
        raise usage_error(f"--contact must be rim or thick, got {text!r}")
    return c


def _number(text: str, what: str, lo: float, hi: float = math.inf, *, lo_open=False) -> float:
    v = _usage(parse.parse_number, text, what)
    if v < lo or v > hi or (lo_open and v == lo):
        rng = (f"> {lo:g}" if lo_open else f">= {lo:g}") if hi == math.inf else f"[{lo:g}, {hi:g}]"
        raise usage_error(f"{what} must be {'in ' if hi != math.inf else ''}{rng}, got {text!r}")
    return v


def _diameter_m(text: str) -> float:
    return _usage(parse.parse_length_mm, text, "--diameter") / 1000.0


def _xi_item(text: str, what: str) -> float:
    v = parse.parse_number(text, what)
    if v < 0:
        raise ValueError(f"{what} must be >= 0, got {text!r}")
    return v


def _nonneg_item(limit):
    def item(text: str, what: str) -> float:
        v = parse.parse_number(text, what)
        if not 0 <= v <= limit:
            raise ValueError(f"{what} must be in [0, {limit:g}], got {text!r}")
        return v

    return item


def _deg_item(text: str, what: str) -> float:
    v = parse.parse_number(text, what)
    if not 0 <= v <= 180:
        raise ValueError(f"{what} must be an angle in [0, 180] degrees, got {text!r}")
    return v


def _rad(deg: float) -> float:
    return math.pi if deg == 180.0 else math.radians(deg)


# --------------------------------------------------------------------------- coin toss


@app.command("toss")
def toss_cmd(
    xi: XiOpt,
    psi: Annotated[str, typer.Option("--psi", help="Angle between the angular momentum and the "
                                     "coin's normal at launch, degrees [0, 180] (90: the Keller "
                                     "flip).", metavar="DEG")],
    u: Annotated[str, typer.Option("--u", help="Upward launch speed of the centre, m/s (>= 0).",
                                   metavar="M/S")],
    omega: Annotated[str, typer.Option("--omega", help="Precession rate omega_N = M / I_1 of "
                                       "eq. (2), rad/s (>= 0).", metavar="RAD/S")],
    diameter: DiameterOpt = "24.26",
    g: GOpt = "9.81",
    contact: ContactOpt = "rim",
    z0: Annotated[str | None, typer.Option("--z0", help="Launch height of the centre above the "
                                           "catch plane, mm (default: (sqrt 3/2) a, plus h/2 for "
                                           "thick contact).", metavar="MM")] = None,
    fmt: FormatOpt = "table",
    quiet: QuietOpt = False,
):
    """One deterministic toss: time of flight, turns, final tilt and outcome (eqs. 3-7).

    The coin starts heads up with its centre at z0 = (sqrt 3/2) a, flies up at u and precesses
    at omega; it is caught at z = 0 the first time its lowest point touches (the smallest
    positive root of z(t) - a sin alpha(t) = 0, found without skipping an earlier crossing).
    The outcome is eq. (7): heads if alpha_f <= theta0, tails if alpha_f > 180 - theta0, sides
    in between.  Each of --xi, --psi, --u, --omega also takes a list a,b,c, a range
    start:stop:step or - (stdin); lists of equal length are paired, a single value is reused.

    Examples: coin toss --xi 0.577 --psi 90 --u 2 --omega 40 ;
    coin toss --xi 0.577 --psi 90 --u 2 --omega 30:50:1 --format csv ;
    coin toss --xi 0.577 --psi 90 --u 2 --omega 40 -q
    """
    check_format(fmt)
    ct = _contact(contact)
    dia = _diameter_m(diameter)
    gv = _number(g, "--g", 0.0, 1e100, lo_open=True)
    z0_m = None if z0 is None else _usage(parse.parse_length_mm, z0, "--z0") / 1000.0
    cols = {
        "xi": values_option(xi, "--xi", _xi_item, bounds=(0.0, math.inf)),
        "psi": values_option(psi, "--psi", _deg_item, bounds=(0.0, 180.0)),
        "u": values_option(u, "--u", _nonneg_item(U_MAX), bounds=(0.0, U_MAX)),
        "omega": values_option(omega, "--omega", _nonneg_item(math.inf), bounds=(0.0, math.inf)),
    }
    lens = {k: len(v) for k, v in cols.items()}
    n = max(lens.values())
    bad = [f"--{k} ({m})" for k, m in lens.items() if m not in (1, n)]
    if bad:
        raise usage_error(f"lists must have one value or {n} values; got {', '.join(bad)}")
    from coincli import toss as T

    if n == 1:
        x, p, uu, w = (float(cols[k][0]) for k in ("xi", "psi", "u", "omega"))
        r = _usage(T.toss, x, _rad(p), uu, w, diameter=dia, g=gv, contact=ct, z0=z0_m)
        data = [[x], [p], [uu], [w], [r.t_f], [r.turns], [math.degrees(r.alpha_f)],
                [math.degrees(r.theta0)], [r.vigor], [r.outcome], [r.z0 * 1000], [ct]]
    else:
        import numpy as np

        x, p, uu, w = (np.broadcast_to(np.asarray(cols[k], dtype=float), (n,))
                       for k in ("xi", "psi", "u", "omega"))
        psi_rad = np.where(p == 180.0, math.pi, np.radians(p))
        res = _usage(T.toss_many, x, psi_rad, uu, w, diameter=dia, g=gv, contact=ct, z0=z0_m)
        z0_mm = (np.full(n, z0_m * 1000) if z0_m is not None else
                 (math.sqrt(3) / 2 * dia / 2 + (x * dia / 2 if ct == "thick" else 0.0)) * 1000)
        data = [x.tolist(), p.tolist(), uu.tolist(), w.tolist(), res.t_f.tolist(),
                (w * res.t_f / (2 * math.pi)).tolist(), np.degrees(res.alpha_f).tolist(),
                np.degrees(np.arctan2(1.0, x)).tolist(), (uu * w / gv).tolist(),
                [T.NAMES[c] for c in res.code.tolist()],
                np.broadcast_to(z0_mm, (n,)).tolist(), [ct] * n]
    columns = [
        Column("xi", "xi"), Column("psi_deg", "psi (deg)"), Column("u", "u (m/s)"),
        Column("omega", "omega (rad/s)"), Column("t_f", "t_f (s)", "g10"),
        Column("turns", "turns"), Column("alpha_f_deg", "alpha_f (deg)"),
        Column("theta0_deg", "theta0 (deg)"), Column("vigor", "vigor u*omega/g"),
        Column("outcome", "outcome", "text"), Column("z0_mm", "z0 (mm)"),
        Column("contact", "contact", "text"),
    ]
    note = (f"Deterministic toss (Sec. II): D = {dia * 1000:g} mm, g = {gv:g} m/s^2, contact "
            f"{ct}; heads if alpha_f <= theta0, tails if alpha_f > 180 - theta0 (eq. 7).  "
            "The closed forms (coin design/table) are the limit vigor >> 1.")
    emit(Result("coin toss", columns, [], note, quiet=data[9] if n > 1 else data[9][0],
                vertical=True, data=data), fmt, quiet)


# --------------------------------------------------------------------------- coin simulate


def _spec(text: str, what: str, lo: float, hi: float, unit: str):
    from coincli import toss as T

    return _usage(T.parse_dist, text, what, lo, hi, unit)


def _psi_dist(text: str):
    """--psi-dist: the project's densities (uniform, cosine, normal[:M:S], table:FILE) or
    uniform:LOW:HIGH / a fixed value, in degrees."""
    from coincli import toss as T

    s = text.strip()
    head = s.split(":", 1)[0].strip().lower()
    if head in ("uniform", "unif", "fixed") and ":" in s or _plain_number(s):
        return _spec(s, "--psi-dist", 0.0, 180.0, "deg").scaled(DEG)
    from coincli.densities import parse_density

    try:
        return T.Dist.from_density(parse_density(s))
    except ValueError as exc:
        raise usage_error(f"--psi-dist: {exc}; or uniform:LOW:HIGH in degrees") from None


def _plain_number(s: str) -> bool:
    try:
        parse.parse_number(s)
        return True
    except ValueError:
        return False


@app.command("simulate")
def simulate_cmd(
    xi: XiOpt,
    u: Annotated[str, typer.Option("--u", help="Launch speed, m/s: a value, normal:MEAN:SD or "
                                   "uniform:LOW:HIGH (normals are truncated at 0).",
                                   metavar="SPEC")],
    omega: Annotated[str, typer.Option("--omega", help="Precession rate, rad/s: a value, "
                                       "normal:MEAN:SD or uniform:LOW:HIGH.", metavar="SPEC")],
    psi: Annotated[str | None, typer.Option("--psi", help="A fixed angle psi, degrees [0, 180].",
                                            metavar="DEG")] = None,
    psi_dist: Annotated[
        str | None, typer.Option("--psi-dist", help="A distribution of psi in degrees: "
                                 "normal:MEAN:SD (truncated to [0, 180]), uniform:LOW:HIGH, or "
                                 "the densities of coin design: uniform, cosine, normal, "
                                 "table:FILE.", metavar="SPEC")
    ] = None,
    n: Annotated[str, typer.Option("-n", "--n", help="Number of tosses.", metavar="N")] = "10000",
    seed: Annotated[str | None, typer.Option("--seed", help="Seed of the random initial "
                                             "conditions (a whole number >= 0).  Default: fresh "
                                             "entropy, printed in the note.",
                                             metavar="SEED")] = None,
    stream: Annotated[bool, typer.Option("--stream", help="Print one outcome a line (H, S or "
                                         "T) instead of the summary: a physically honest "
                                         "three-sided die.")] = False,
    diameter: DiameterOpt = "24.26",
    g: GOpt = "9.81",
    contact: ContactOpt = "rim",
    fmt: FormatOpt = "table",
    quiet: QuietOpt = False,
):
    """Many seeded tosses with random initial conditions: frequencies next to the vigorous limit.

    Draws u, omega and psi from the given distributions (vectorized), tosses each coin as
    `coin toss` does, and reports the frequency of heads, sides and tails with 95% Wilson
    intervals next to the closed-form prediction for the same psi distribution (Table I
    averaged; Kemperman-Engel: the limit of vigorous tosses).  xi, the diameter and g are fixed.
    The same seed gives the same tosses, and a shorter run is a prefix of a longer one.  A
    progress bar shows on stderr for long runs on a terminal.

    Examples: coin simulate -n 1000000 --seed 7 --xi 0.577 --u normal:2.4:0.3
    --omega normal:38:4 --psi-dist normal:90:10 ;
    coin simulate -n 5 --seed 1 --xi 0.577 --u 2.4 --omega normal:38:4 --psi 90 --stream
    """
    check_format(fmt)
    if stream and (fmt != "table" or quiet):
        raise usage_error("--stream prints one letter a line; it takes no --format or --quiet")
    ct = _contact(contact)
    dia = _diameter_m(diameter)
    gv = _number(g, "--g", 0.0, 1e100, lo_open=True)
    count = _usage(parse.parse_count, n, "-n")
    if count > 10**10:
        raise usage_error(f"-n must be at most 1e10, got {n!r}")
    xs = values_option(xi, "--xi", _xi_item)
    if len(xs) != 1:
        raise usage_error("simulate takes one --xi (run it once per coin)")
    xv = float(xs[0])
    if (psi is None) == (psi_dist is None):
        raise usage_error("give --psi DEG (a fixed angle) or --psi-dist SPEC (a distribution)")
    if psi is not None:
        psi_spec = _rad(_usage(_deg_item, psi, "--psi"))
    else:
        psi_spec = _psi_dist(psi_dist)
    u_spec = _spec(u, "--u", 0.0, U_MAX, "m/s")
    w_spec = _spec(omega, "--omega", 0.0, math.inf, "rad/s")
    if seed is None:
        import secrets

        seed_v = secrets.randbits(63)
    else:
        s = seed.strip()
        if not (s.isascii() and s.isdigit()) or len(s) > 40:
            raise usage_error(f"--seed must be a whole number >= 0, got {seed!r}")
        seed_v = int(s)
    from coincli import toss as T

    kw = {"xi": xv, "u": u_spec, "omega": w_spec, "psi": psi_spec, "diameter": dia, "g": gv,
          "contact": ct}
    _usage(T.toss_many, xv, 1.0, 1.0, 1.0, diameter=dia, g=gv, contact=ct)  # geometry check
    if stream:
        _stream(T, count, seed_v, kw)
        return
    with _progress(count) as tick:
        sim = _usage(T.simulate, count, seed_v, progress=tick, **kw)
    pred = sim.vigorous
    rows = []
    for f, p in zip(sim.frequencies, pred, strict=True):
        rows.append((f.outcome, f.count, f.p, f.lo, f.hi, float(p), f.p - float(p)))
    columns = [
        Column("outcome", "outcome", "text"), Column("count", "count", "int"),
        Column("frequency", "frequency"), Column("ci_low", "95% low"),
        Column("ci_high", "95% high"), Column("vigorous", "vigorous limit"),
        Column("difference", "freq - limit"),
    ]
    psi_text = f"psi = {psi} deg" if psi is not None else f"psi ~ {psi_dist.strip()} deg"
    note = (f"{count} tosses, seed {seed_v}: xi = {xv:g}, u ~ {u.strip()} m/s, omega ~ "
            f"{omega.strip()} rad/s, {psi_text}; D = {dia * 1000:g} mm, g = {gv:g}, contact {ct}."
            "  95% Wilson intervals.  The vigorous limit is Table I averaged over psi; it holds "
            "when u*omega/g >> 1 and omega*a/u << 1.")
    emit(Result("coin simulate", columns, rows, note, quiet=[r[2] for r in rows]), fmt, quiet)


def _stream(T, count, seed_v, kw):
    """Write one letter a line, batch by batch; the first batch is computed before any output,
    so bad input still fails cleanly with nothing printed."""
    import numpy as np

    table = np.array([ord(c) for c in T.LETTERS], dtype=np.uint8)
    chunks = T.simulate_chunks(count, seed_v, **kw)
    codes = _usage(next, chunks)
    out = sys.stdout
    while codes is not None:
        buf = np.empty(2 * codes.size, dtype=np.uint8)
        buf[0::2] = table[codes]
        buf[1::2] = ord("\n")
        out.write(buf.tobytes().decode("ascii"))
        codes = next(chunks, None)
    out.flush()


class _progress:
    """A rich progress bar on stderr for long runs on a terminal; a no-op otherwise."""

    def __init__(self, total: int):
        self.total = total
        self.bar = None

    def __enter__(self):
        if self.total >= 200_000 and stderr_is_terminal():
            from rich.console import Console
            from rich.progress import BarColumn, Progress, TimeRemainingColumn

            self.bar = Progress("tossing", BarColumn(), "{task.completed:,}/{task.total:,}",
                                TimeRemainingColumn(), console=Console(stderr=True),
                                transient=True)
            self.bar.start()
            self.task = self.bar.add_task("toss", total=self.total)
        return self._tick

    def _tick(self, done: int):
        if self.bar is not None:
            self.bar.update(self.task, completed=done)

    def __exit__(self, *exc):
        if self.bar is not None:
            self.bar.stop()
        return False


# --------------------------------------------------------------------------- coin phase


def _pair(text: str, what: str, unit: str) -> tuple[float, float]:
    parts = text.split(":")
    if len(parts) != 2:
        raise usage_error(f"{what} must be LOW:HIGH ({unit}), got {text!r}")
    lo, hi = (_usage(parse.parse_number, p, what) for p in parts)
    if not 0 <= lo < hi:
        raise usage_error(f"{what} must satisfy 0 <= LOW < HIGH ({unit}), got {text!r}")
    return lo, hi


def _size(text: str | None, what: str, default: int, hi: int) -> int:
    if text is None:
        return default
    v = _usage(parse.parse_count, text, what)
    if not 2 <= v <= hi:
        raise usage_error(f"{what} must be from 2 to {hi}, got {text!r}")
    return v


PHASE_COLOURS = {"heads": "grey93", "sides": "grey15", "tails": "dodger_blue2"}
CURVE_COLOUR = "orange1"


@app.command("phase")
def phase_cmd(
    xi: Annotated[str, typer.Option("--xi", help="Aspect ratio h/D (default 0.57735: the fair "
                                    "coin of Fig. 3).", metavar="XI")] = "0.5773502691896257",
    psi: Annotated[str, typer.Option("--psi", help="Angle psi, degrees [0, 180] (Fig. 3: 90).",
                                     metavar="DEG")] = "90",
    u: Annotated[str, typer.Option("--u", help="Range of launch speeds LOW:HIGH, m/s.",
                                   metavar="LOW:HIGH")] = "0:3",
    omega: Annotated[str, typer.Option("--omega", help="Range of precession rates LOW:HIGH, "
                                       "rad/s.", metavar="LOW:HIGH")] = "0:60",
    cols: Annotated[str | None, typer.Option("--cols", help="Grid cells along u (default: fit "
                                             "the terminal; 400 for --out; 100 for csv/json).",
                                             metavar="N")] = None,
    rows: Annotated[str | None, typer.Option("--rows", help="Grid cells along omega (default: "
                                             "fit the terminal; 400 for --out; 100 for "
                                             "csv/json).", metavar="N")] = None,
    exact: Annotated[bool, typer.Option("--exact", help="Draw the exact boundary curves (t_f "
                                        "solved at the contact height) instead of eq. (10)'s "
                                        "t_f = 2u/g.")] = False,
    no_curves: Annotated[bool, typer.Option("--no-curves", help="Do not overlay the boundary "
                                            "curves.")] = False,
    out: Annotated[str | None, typer.Option("--out", "-o", help="Write a figure: .png, .svg or "
                                            ".pdf (needs matplotlib: pip install "
                                            "'coincli\\[plot]').", metavar="FILE")] = None,
    diameter: DiameterOpt = "24.26",
    g: GOpt = "9.81",
    contact: ContactOpt = "rim",
    fmt: FormatOpt = "table",
):
    """The pre-images of heads, sides and tails over (u, omega): Fig. 3 of the paper.

    Each cell is one deterministic toss (as `coin toss`) from the cell's centre.  On a terminal:
    coloured blocks with a legend, the boundary curves of eq. (10) (omega = (2n +- theta0/pi)
    pi g / 2u and (2n+1 +- theta0/pi) pi g / 2u at psi = 90; theta1, theta2 of Table I
    otherwise) marked with dots.  In a pipe or with NO_COLOR: letters H, S, T, lower-case where
    a curve passes.  --format csv/json: one row per cell.  --out FILE: a figure (PNG/SVG/PDF).

    Examples: coin phase ;  coin phase --xi 0.577 --psi 90 --u 0:3 --omega 0:60 ;
    coin phase --xi 0.3 --u 0:5 --omega 0:100 --out phase.png ;  coin phase --format csv
    """
    check_format(fmt)
    if out is not None and fmt != "table":
        raise usage_error("--out writes a figure; it takes no --format")
    ct = _contact(contact)
    dia = _diameter_m(diameter)
    gv = _number(g, "--g", 0.0, 1e100, lo_open=True)
    xv = _number(xi, "--xi", 0.0, 1e100)
    psi_deg = _usage(_deg_item, psi, "--psi")
    ur = _pair(u, "--u", "m/s")
    wr = _pair(omega, "--omega", "rad/s")
    if out is not None:
        return _phase_figure(out, xv, psi_deg, ur, wr, _size(cols, "--cols", 400, 4000),
                             _size(rows, "--rows", 400, 4000), exact, no_curves, dia, gv, ct)
    text = fmt == "table"
    if text:
        tw, th = shutil.get_terminal_size((80, 24))
        nu = _size(cols, "--cols", max(10, min(tw, 400) - 9), 2000)
        nw = _size(rows, "--rows", max(6, min(th, 200) - 7), 2000)
    else:
        nu = _size(cols, "--cols", 100, 2000)
        nw = _size(rows, "--rows", 100, 2000)
    from coincli import toss as T

    pm = _usage(T.phase_map, xv, _rad(psi_deg), ur, wr, (nu, nw), diameter=dia, g=gv, contact=ct,
                exact_curves=exact)
    if not text:
        import numpy as np

        uu = np.broadcast_to(pm.u[None, :], pm.codes.shape).ravel().tolist()
        ww = np.broadcast_to(pm.omega[:, None], pm.codes.shape).ravel().tolist()
        codes = pm.codes.ravel().tolist()
        data = [uu, ww, [T.NAMES[c] for c in codes], codes]
        columns = [Column("u", "u (m/s)"), Column("omega", "omega (rad/s)"),
                   Column("outcome", "outcome", "text"), Column("code", "code", "int")]
        emit(Result("coin phase", columns, [], "", data=data), fmt)
        return
    _phase_text(pm, xv, psi_deg, ur, wr, [] if no_curves else pm.curves, exact)


def _curve_marks(pm, curves, ur, wr):
    """Boolean (rows, cols): the cells a boundary curve passes through, in the columns where it
    is at least two rows from its neighbours (denser curves would only paint every cell)."""
    import numpy as np

    nw, nu = pm.codes.shape
    marks = np.zeros((nw, nu), dtype=bool)
    du = (ur[1] - ur[0]) / nu
    edges = ur[0] + du * np.arange(nu + 1)
    dw = (wr[1] - wr[0]) / nw
    curves = sorted(curves, key=lambda b: b.phase)
    stack = np.array([np.asarray(b.omega, dtype=float) for b in curves])  # (curves, nu)
    with np.errstate(invalid="ignore"):
        gap = np.full(stack.shape, np.inf)
        if len(curves) > 1:
            d = np.abs(np.diff(stack, axis=0))
            gap[:-1] = np.fmin(gap[:-1], d)
            gap[1:] = np.fmin(gap[1:], d)
    for k, b in enumerate(curves):
        with np.errstate(divide="ignore", invalid="ignore"):
            if b.phase <= 0:
                continue
            # omega(u) = phase / t*(u) with t* = 2u/g (eq. 10) or the exact contact time: take
            # the omega at both edges of each column from the curve sampled at the centres.
            w_c = np.asarray(b.omega, dtype=float)
            w_e = np.interp(edges, pm.u, w_c, left=np.nan, right=np.nan)
            w_e[0] = w_c[0] if not np.isfinite(w_e[0]) else w_e[0]
            w_e[-1] = w_c[-1] if not np.isfinite(w_e[-1]) else w_e[-1]
            lo = np.fmin(w_e[:-1], w_e[1:])
            hi = np.fmax(w_e[:-1], w_e[1:])
            lo = np.where(np.isfinite(lo), lo, w_c)
            hi = np.where(np.isfinite(hi), hi, w_c)
            r0 = np.floor((lo - wr[0]) / dw)
            r1 = np.floor((hi - wr[0]) / dw)
        for j in range(nu):
            if not (np.isfinite(r0[j]) and np.isfinite(r1[j])) or not gap[k, j] >= 2 * dw:
                continue
            a, z = int(max(r0[j], 0)), int(min(r1[j], nw - 1))
            if a <= z:
                marks[a:z + 1, j] = True
    return marks


def _phase_text(pm, xi, psi_deg, ur, wr, curves, exact):
    from rich.console import Console
    from rich.text import Text

    from coincli import toss as T

    nw, nu = pm.codes.shape
    marks = _curve_marks(pm, curves, ur, wr) if curves else None
    colour = stdout_is_terminal() and not env_no_color()
    f = pm.fractions()
    src = "exact contact-time curves" if exact else "eq. (10), t_f = 2u/g"
    lines = Text()
    lines.append(f"Pre-images of a toss (Fig. 3): xi = {xi:g}, psi = {psi_deg:g} deg, contact "
                 f"{pm.contact}\n")
    label_w = 8
    for i in range(nw - 1, -1, -1):
        w = wr[0] + (i + 1) * (wr[1] - wr[0]) / nw
        label = f"{w:7.4g} " if (nw - 1 - i) % 5 == 0 else " " * label_w
        lines.append(label)
        for j in range(nu):
            code = int(pm.codes[i, j])
            curve = marks is not None and marks[i, j]
            if colour:
                name = T.NAMES[code]
                lines.append("•" if curve else " ", style=f"bold {CURVE_COLOUR} on "
                             f"{PHASE_COLOURS[name]}" if curve else f"on {PHASE_COLOURS[name]}")
            else:
                ch = T.LETTERS[code]
                lines.append(ch.lower() if curve else ch)
        lines.append("\n")
    axis = [" "] * nu
    ticks = []
    for k in range(5):
        j = round(k * (nu - 1) / 4)
        val = ur[0] + (j + 0.5) * (ur[1] - ur[0]) / nu
        ticks.append((j, f"{val:.3g}"))
    for j, s in ticks:
        j = min(j, nu - len(s))  # the last label ends at the last column
        for m, ch in enumerate(s):
            if 0 <= j + m < nu:
                axis[j + m] = ch
    lines.append(" " * label_w + "".join(axis) + "\n")
    lines.append(" " * label_w + "u (m/s) ->   omega (rad/s) on the left\n")
    if colour:
        for name in T.NAMES:
            lines.append("  ")
            lines.append("  ", style=f"on {PHASE_COLOURS[name]}")
            lines.append(f" {name} {getattr(f, name):.1%}")
        if curves:
            lines.append("   ")
            lines.append("•", style=f"bold {CURVE_COLOUR}")
            lines.append(f" boundary, {src}")
    else:
        lines.append(f"  H heads {f.heads:.1%}   S sides {f.sides:.1%}   T tails {f.tails:.1%}")
        if curves:
            lines.append(f"   h/s/t: a boundary passes ({src})")
    lines.append("\n")
    vig = pm_vigorous(xi, psi_deg)
    lines.append(f"Vigorous limit (Table I): heads {vig.heads:.3f}, sides {vig.sides:.3f}, tails "
                 f"{vig.tails:.3f}\n")
    console = Console(file=sys.stdout, highlight=False, soft_wrap=True, emoji=False,
                      markup=False, no_color=not colour, force_terminal=colour or None,
                      width=max(nu + label_w + 2, 40))
    console.print(lines, end="")


def pm_vigorous(xi, psi_deg):
    from coincli.models import conditional

    return conditional(xi, _rad(psi_deg))


def _phase_figure(path, xi, psi_deg, ur, wr, nu, nw, exact, no_curves, dia, g, ct):
    from coincli import plot as P

    try:
        P.figure_format(path)
    except ValueError as exc:
        raise usage_error(f"--out: {exc}") from None
    try:
        P.require_matplotlib()
    except P.MatplotlibMissing as exc:
        raise compute_error(str(exc)) from None
    data = _usage(P.phase_data, xi, psi_deg, u_range=ur, omega_range=wr, nu=nu, nw=nw,
                  exact_curves=exact, diameter=dia, g=g, contact=ct)
    if no_curves:
        data.curves = []
    fig = P.phase_figure(data)
    try:
        size = P.save_figure(fig, path)
    except OSError as exc:
        raise compute_error(f"cannot write {path!r}: {exc.strerror or exc}") from None
    if stderr_is_terminal():
        sys.stderr.write(f"coin: wrote {path} ({size:,} bytes)\n")

