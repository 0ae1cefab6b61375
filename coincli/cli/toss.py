"""``coin toss``, ``coin simulate``, ``coin phase``: real tosses of finite vigor (Sec. II, Fig. 3).

Thin: parse the options (angles in degrees, lengths in mm, speeds in m/s, rates in rad/s),
convert to SI radians, call :mod:`coincli.toss`, build a :class:`Result` or a picture, print.
A ValueError from the core is bad input: one line, exit 2.  numpy, scipy and rich load only
inside the commands.
"""

from __future__ import annotations

import math
import re
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
# Limits, as in coincli.toss (kept here so that this module needs no numpy to load).
U_MAX = 1e8  # m/s, coincli.toss.U_MAX
MAX_TOSSES = 10**8  # coincli.toss.MAX_TOSSES: simulate -n; ~1.5 minutes of ordinary tosses
G_MAX = 1e100  # m/s^2
XI_THICK_MAX = 1e100  # h/D with --contact thick (an infinite thickness has no launch height)
LENGTH_MM_MIN = 1e-300  # mm; smaller would underflow on the way to metres
DIAMETER_MM_MAX = 1e103  # mm: coincli.toss takes diameters up to 1e100 m
NORMAL_REACH = 10  # simulate checks a normal up to MEAN + 10 SD (never drawn: P < 1e-23)

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


def _num(v: float) -> str:
    """A number as short as it reads back exactly: 38, 2.5, 0.1, 1e+300."""
    short = f"{v:g}"
    return short if float(short) == v else repr(float(v))


def _mm(text: str) -> str:
    """A length as the user typed it, with its unit: '20' -> '20 mm', '2cm' stays."""
    t = text.strip()
    return f"{t} mm" if _plain_number(t) else t


def _allowed(lo: float, hi: float, unit: str, lo_open: bool = False) -> str:
    u = f" {unit}" if unit else ""
    low = f"> {lo:g}" if lo_open else f">= {lo:g}"
    if hi == math.inf:
        return f"a finite number {low}{u}"
    if lo_open:
        return f"a number {low} and <= {hi:g}{u}"
    return f"a number from {lo:g} to {hi:g}{u}"


def _number(text: str, what: str, lo: float, hi: float = math.inf, *, lo_open=False,
            unit: str = "") -> float:
    try:
        v = parse.parse_number(text, what)
    except ValueError:
        v = math.nan
    if not (lo < v if lo_open else lo <= v) or not v <= hi:  # NaN fails both
        raise usage_error(f"{what} must be {_allowed(lo, hi, unit, lo_open)}, got {text!r}")
    return v


def _g(text: str) -> float:
    return _number(text, "--g", 0.0, G_MAX, lo_open=True, unit="m/s^2")


def _length_mm(text: str, what: str) -> float:
    v = _usage(parse.parse_length_mm, text, what)
    if v < LENGTH_MM_MIN:
        raise usage_error(f"{what} must be a length of at least {LENGTH_MM_MIN:g} mm, got "
                          f"{text!r}")
    return v


def _diameter_m(text: str) -> float:
    v = _length_mm(text, "--diameter")
    if v > DIAMETER_MM_MAX:
        raise usage_error(f"--diameter must be a length from {LENGTH_MM_MIN:g} mm to "
                          f"{DIAMETER_MM_MAX:g} mm, got {text!r}")
    return v / 1000.0


def _z0_m(text: str | None, xi_max: float, dia: float, thick: bool) -> float | None:
    """--z0 in metres; for thick contact above h/2, or the coin would start below the plane."""
    if text is None:
        return None
    z0 = _length_mm(text, "--z0") / 1000.0
    floor = xi_max * dia / 2 if thick else 0.0
    if z0 <= floor:
        raise usage_error(f"--z0 must be above h/2 = {floor * 1000:g} mm with --contact thick "
                          f"(--xi {_num(xi_max)}: the coin would start below the catch plane), "
                          f"got {_mm(text)}")
    return z0


def _item(lo: float, hi: float, unit: str, kind: str = "a number"):
    """A values_option item: a finite number in [lo, hi] (hi = inf: any finite number >= lo)."""

    def item(text: str, what: str) -> float:
        try:
            v = parse.parse_number(text, what)
        except ValueError:
            v = math.nan
        if not lo <= v <= hi:  # NaN fails
            rng = (f"a finite number >= {lo:g} {unit}" if hi == math.inf else
                   f"{kind} from {lo:g} to {hi:g} {unit}")
            raise ValueError(f"{what} must be {rng}, got {text!r}")
        return v

    return item


_xi_item = _item(0.0, math.inf, "(h/D)")
_u_item = _item(0.0, U_MAX, "m/s")
_omega_item = _item(0.0, math.inf, "rad/s")
_deg_item = _item(0.0, 180.0, "degrees", "an angle")
_FINITE = (0.0, sys.float_info.max)  # stdin bounds: 1e400 (inf) goes to the item's message


def _xi_for_contact(xi_max: float, xi_text: str, thick: bool):
    if thick and xi_max > XI_THICK_MAX:
        raise usage_error(f"--xi must be from 0 to {XI_THICK_MAX:g} with --contact thick (the "
                          f"launch height rises by h/2), got {xi_text.strip()!r}")


def _rad(deg: float) -> float:
    return math.pi if deg == 180.0 else math.radians(deg)


def _follow(T, xi, psi, u, omega, *, dia, g, ct, z0, got, where=""):
    """Refuse, naming the option at fault, a toss the core cannot follow (T.flight_limits): a
    flight whose length overflows, a phase omega * t beyond T.MAX_PHASE, or omega^2 * a beyond
    a double.  ``got`` holds the user's text of each option (with units); the option blamed is
    the first whose default alone would make the toss followable (--g, --z0, --diameter, --xi
    of a thick coin), else --omega (and --u)."""
    _, phase, problem = T.flight_limits(xi, psi, u, omega, diameter=dia, g=g, contact=ct, z0=z0)
    if not problem:
        return
    kw = {"diameter": dia, "g": g, "contact": ct, "z0": z0}
    alts = []
    if g != T.STANDARD_G:
        alts.append((f"{'raise' if g < T.STANDARD_G else 'lower'} --g (got {got['g']})",
                     {**kw, "g": T.STANDARD_G}))
    if z0 is not None:
        z0_default = T.default_z0(xi, dia, ct)
        alts.append((f"{'lower' if z0 > z0_default else 'raise'} --z0 (got {got['z0']})",
                     {**kw, "z0": None}))
    if dia != T.DEFAULT_DIAMETER:
        alts.append((f"{'lower' if dia > T.DEFAULT_DIAMETER else 'raise'} --diameter (got "
                     f"{got['diameter']})", {**kw, "diameter": T.DEFAULT_DIAMETER}))
    if ct == "thick" and xi > 0:
        alts.append((f"lower --xi (got {got['xi']}: a thick coin is launched h/2 higher)",
                     {**kw, "contact": "rim", "z0": z0 if z0 is not None else
                      T.default_z0(xi, dia, "rim")}))
    # The first option whose default alone makes the toss one the core can follow; else the
    # spin (and the launch speed), which have no default.
    fix = next((f for f, alt in alts if not T.flight_limits(xi, psi, u, omega, **alt)[2]), None)
    if fix is None and len(alts) > 1:  # several at once (--g 1e-300 --z0 1e300)?
        both = dict(kw)
        for _, alt in alts:
            both.update({k: v for k, v in alt.items() if v != kw[k]})
        if not T.flight_limits(xi, psi, u, omega, **both)[2]:
            fix = " and ".join(f for f, _ in alts)
    if fix is None:
        fix = (f"lower --omega (got {got['omega']})" if problem == 3 else
               f"lower --omega (got {got['omega']}) or --u (got {got['u']})")
    if problem == 1:
        what = f"the time of flight{where} overflows a double"
    elif problem == 2:
        what = (f"the coin would turn up to omega * t = {phase:.3g} rad in the air{where}, "
                f"beyond the {T.MAX_PHASE:g} rad where a double no longer holds the phase")
    else:
        what = f"the spin{where} is too fast to follow: omega^2 * a overflows a double"
    raise usage_error(f"{what}; {fix}")


def _got(*, xi, u, omega, g, diameter, z0=None):
    """The user's text of each option, with its unit, for the messages of _follow."""
    return {"xi": xi.strip(), "u": u, "omega": omega, "g": f"{g.strip()} m/s^2",
            "diameter": _mm(diameter), "z0": None if z0 is None else _mm(z0)}


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
    gv = _g(g)
    cols = {
        "xi": values_option(xi, "--xi", _xi_item, bounds=_FINITE),
        "psi": values_option(psi, "--psi", _deg_item, bounds=(0.0, 180.0)),
        "u": values_option(u, "--u", _u_item, bounds=(0.0, U_MAX)),
        "omega": values_option(omega, "--omega", _omega_item, bounds=_FINITE),
    }
    lens = {k: len(v) for k, v in cols.items()}
    n = max(lens.values())
    bad = [f"--{k} ({m})" for k, m in lens.items() if m not in (1, n)]
    if bad:
        raise usage_error(f"lists must have one value or {n} values; got {', '.join(bad)}")
    xs = cols["xi"]
    xi_max = float(xs.max() if hasattr(xs, "max") else max(xs))
    _xi_for_contact(xi_max, xi if len(cols["xi"]) == 1 else _num(xi_max), ct == "thick")
    z0_m = _z0_m(z0, xi_max, dia, ct == "thick")
    from coincli import toss as T

    def follow(x, p, uu, w, where=""):
        got = _got(xi=_num(x), u=f"{_num(uu)} m/s", omega=f"{_num(w)} rad/s", g=g,
                   diameter=diameter, z0=z0)
        _follow(T, x, p, uu, w, dia=dia, g=gv, ct=ct, z0=z0_m, got=got, where=where)

    if n == 1:
        x, p, uu, w = (float(cols[k][0]) for k in ("xi", "psi", "u", "omega"))
        follow(x, _rad(p), uu, w)
        r = _usage(T.toss, x, _rad(p), uu, w, diameter=dia, g=gv, contact=ct, z0=z0_m)
        data = [[x], [p], [uu], [w], [r.t_f], [r.turns], [math.degrees(r.alpha_f)],
                [math.degrees(r.theta0)], [r.vigor], [r.outcome], [r.z0 * 1000], [ct]]
    else:
        import numpy as np

        x, p, uu, w = (np.broadcast_to(np.asarray(cols[k], dtype=float), (n,))
                       for k in ("xi", "psi", "u", "omega"))
        psi_rad = np.where(p == 180.0, math.pi, np.radians(p))
        problem = T.flight_limits(x, psi_rad, uu, w, diameter=dia, g=gv, contact=ct, z0=z0_m)[2]
        if problem.any():
            k = int(np.argmax(problem != 0))
            follow(float(x[k]), float(psi_rad[k]), float(uu[k]), float(w[k]), f" (row {k + 1})")
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
    n: Annotated[str, typer.Option("-n", "--n", help="Number of tosses, 1 to 10^8 (about a "
                                   "minute and a half; for more, run again with another "
                                   "--seed).", metavar="N")] = "10000",
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
    gv = _g(g)
    count = _tosses(n)
    xs = values_option(xi, "--xi", _xi_item)
    if len(xs) != 1:
        raise usage_error("simulate takes one --xi (run it once per coin)")
    xv = float(xs[0])
    _xi_for_contact(xv, xi, ct == "thick")
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
    # Every toss must be one the core can follow, checked at the top of the distributions (the
    # flight and the phase grow with u and omega), so that no batch fails halfway through.
    u_hi, w_hi = _reach(u_spec, U_MAX), _reach(w_spec, math.inf)
    psi_hi = psi_spec if isinstance(psi_spec, float) else math.pi / 2  # the largest omega^2 a
    got = _got(xi=xi, u=_spec_text(u, u_spec, u_hi, "m/s"),
               omega=_spec_text(omega, w_spec, w_hi, "rad/s"), g=g, diameter=diameter)
    _follow(T, xv, psi_hi, u_hi, w_hi, dia=dia, g=gv, ct=ct, z0=None, got=got)
    _usage(T.toss_many, xv, psi_hi, u_hi, w_hi, diameter=dia, g=gv, contact=ct)  # the same, core
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


def _tosses(text: str) -> int:
    """-n: a whole number from 1 to MAX_TOSSES."""
    s = text.strip()
    digits = s.removeprefix("+").lstrip("0")
    if not (s.isascii() and re.fullmatch(r"\+?\d+", s)) or not digits:
        raise usage_error(f"-n must be a whole number from 1 to {MAX_TOSSES} (10^8), got "
                          f"{text!r}")
    if len(digits) > len(str(MAX_TOSSES)) or int(digits) > MAX_TOSSES:
        shown = digits if len(digits) <= 30 else f"{digits[:12]}... ({len(digits)} digits)"
        raise usage_error(f"-n {shown} is more than the {MAX_TOSSES} (10^8) tosses of one run "
                          "(about a minute and a half); for more, run several times with "
                          "different --seed values and add the counts")
    return int(digits)


def _reach(dist, hi: float) -> float:
    """The largest value a distribution of simulate draws: a fixed value, a uniform's HIGH, a
    normal's MEAN + 10 SD (truncated to ``hi``; beyond it the chance is below 1e-23 a draw)."""
    if dist.kind == "fixed" or dist.p2 == 0:
        return dist.p1
    if dist.kind == "uniform":
        return dist.p2
    return min(max(dist.p1 + NORMAL_REACH * dist.p2, 0.0), hi)


def _spec_text(text: str, dist, reach: float, unit: str) -> str:
    t = text.strip()
    if dist.kind == "normal" and dist.p2 > 0:
        return f"{t} {unit}, which reaches {reach:g} at MEAN + {NORMAL_REACH} SD"
    return f"{t} {unit}"


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


def _pair(text: str, what: str, unit: str, top: float = math.inf) -> tuple[float, float]:
    parts = text.split(":")
    rule = "0 <= LOW < HIGH" + (f" <= {top:g}" if top < math.inf else "")
    if len(parts) != 2:
        raise usage_error(f"{what} must be LOW:HIGH with {rule} ({unit}), got {text!r}")
    lo, hi = (_usage(parse.parse_number, p, what) for p in parts)
    if not 0 <= lo < hi <= top:
        raise usage_error(f"{what} must be LOW:HIGH with {rule} ({unit}), got {text!r}")
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
    gv = _g(g)
    xv = _usage(_xi_item, xi, "--xi")
    _xi_for_contact(xv, xi, ct == "thick")
    psi_deg = _usage(_deg_item, psi, "--psi")
    ur = _pair(u, "--u", "m/s", U_MAX)
    wr = _pair(omega, "--omega", "rad/s")
    from coincli import toss as T

    # Every cell must be a toss the core can follow: check the top corner of the ranges.
    got = _got(xi=xi, u=f"{u.strip()} m/s", omega=f"{omega.strip()} rad/s", g=g,
               diameter=diameter)
    _follow(T, xv, _rad(psi_deg), ur[1], wr[1], dia=dia, g=gv, ct=ct, z0=None, got=got,
            where=" at the top of the --u and --omega ranges")
    if out is not None:
        return _phase_figure(out, xv, psi_deg, ur, wr, _size(cols, "--cols", 400, 4000),
                             _size(rows, "--rows", 400, 4000), exact, no_curves, dia, gv, ct)
    text = fmt == "table"
    if text:
        from coincli._terminal import terminal_height, terminal_width

        tw, th = terminal_width(), terminal_height()
        nu = _size(cols, "--cols", max(10, min(tw, 400) - 9), 2000)
        nw = _size(rows, "--rows", max(6, min(th, 200) - 7), 2000)
    else:
        nu = _size(cols, "--cols", 100, 2000)
        nw = _size(rows, "--rows", 100, 2000)

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

    from coincli._files import FileKindError, check_output_path

    try:
        P.figure_format(path)
        check_output_path(path)  # a FIFO, device or directory: refused before any computing
    except ValueError as exc:
        raise usage_error(f"--out: {exc}") from None
    except OSError as exc:
        raise compute_error(f"cannot write {path!r}: {exc.strerror or exc}") from None
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
    except FileKindError as exc:
        raise usage_error(f"--out: {exc}") from None
    except OSError as exc:
        raise compute_error(f"cannot write {path!r}: {exc.strerror or exc}") from None
    if stderr_is_terminal():
        sys.stderr.write(f"coin: wrote {path} ({size:,} bytes)\n")

