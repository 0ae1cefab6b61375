"""``coin toss``, ``coin simulate``, ``coin phase``: real tosses of finite vigor (Sec. II, Fig. 3).

Thin: parse the options (the shared coin group and seed of :mod:`coincli.io.options`; angles
in degrees; speeds and spins with units, :func:`coincli.io.grammar.parse_speed_ms` and
:func:`coincli.io.grammar.parse_spin_rads`), convert to SI radians, call :mod:`coincli.core.toss.flight`, build a
:class:`Result` or a picture, print.  Whatever is not given is drawn from a natural hand toss
(:data:`coincli.core.toss.launch.HAND_TOSS`) with a seed that is reported.  A ValueError from the core is
bad input: one line, exit 2.  numpy loads only inside the commands, rich only to draw on a
terminal, scipy never.
"""

from __future__ import annotations

import math
import sys
from typing import Annotated

import typer

from coincli.cli import _bounce as BO
from coincli.cli import _phase, app
from coincli.cli._options import (
    CoinOpt,
    CountOpt,
    DiameterOpt,
    FormatOpt,
    QuartersOpt,
    QuietOpt,
    SeedOpt,
    ThicknessOpt,
    TossesOpt,
    XiOpt,
    XisOpt,
)
from coincli.errors import compute_error
from coincli.io import grammar as parse
from coincli.io import options
from coincli.io.batches import values_option
from coincli.io.table import Column, Result, check_format, emit, stdout_is_terminal, usage_error
from coincli.render.figures import write_figure
from coincli.render.progress import ProgressBar
from coincli.render.terminal import env_no_color

# Limits, as in coincli.core.toss.flight (kept here so that this module needs no numpy to load).
U_MAX = 1e8  # m/s, coincli.core.toss.flight.U_MAX
MAX_TOSSES = 10**8  # coincli.core.toss.flight.MAX_TOSSES: simulate -n; ~20 s of hand tosses
XI_THICK_MAX = 1e100  # h/D with --contact thick (an infinite thickness has no launch height)
LENGTH_MM_MIN = 1e-300  # mm; smaller would underflow on the way to metres
NORMAL_REACH = 10  # simulate checks a normal up to MEAN + 10 SD (never drawn: P < 1e-23)
DHM = "Diaconis, Holmes & Montgomery 2007"
#: the hand toss of coincli.core.toss.launch.HAND_TOSS, as typed (for help and notes)
HAND = {"u": "normal:2.4:0.3", "omega": "normal:38:4rev/s", "psi": "normal:90:10"}

GOpt = _phase.GOpt
ContactOpt = _phase.ContactOpt


def _usage(fn, *args, **kwargs):
    """Call the core; its ValueError is a usage error (the input is out of range)."""
    try:
        return fn(*args, **kwargs)
    except ValueError as exc:
        raise usage_error(str(exc)) from None


def _num(v: float) -> str:
    """A number as short as it reads back exactly: 38, 2.5, 0.1, 1e+300."""
    short = f"{v:g}"
    return short if float(short) == v else repr(float(v))


def _mm(text: str) -> str:
    """A length as the user typed it, with its unit: '20' -> '20 mm', '2cm' stays."""
    t = text.strip()
    try:
        parse.parse_number(t)
        return f"{t} mm"
    except ValueError:
        return t


def _z0_m(text: str | None, xi_max: float, dia: float, thick: bool) -> float | None:
    """--z0 in metres; for thick contact above h/2, or the coin would start below the plane."""
    if text is None:
        return None
    v = _usage(parse.parse_length_mm, text, "--z0")
    if v < LENGTH_MM_MIN:
        raise usage_error(f"--z0 must be a length of at least {LENGTH_MM_MIN:g} mm, got {text!r}")
    z0 = v / 1000.0
    floor = xi_max * dia / 2 if thick else 0.0
    if z0 <= floor:
        raise usage_error(f"--z0 must be above h/2 = {floor * 1000:g} mm with --contact thick "
                          f"(--xi {_num(xi_max)}: the coin would start below the catch plane), "
                          f"got {_mm(text)}")
    return z0


def _xi_for_contact(xi_max: float, thick: bool):
    if thick and xi_max > XI_THICK_MAX:
        raise usage_error(f"--xi must be at most 1e100 with --contact thick (the launch height "
                          f"rises by h/2), got {_num(xi_max)}")


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


def _dia_text(diameter: str | None, dia: float) -> str:
    """The diameter as the user typed it (with its unit), or the default's."""
    return _mm(diameter) if diameter is not None else f"{dia * 1000:g} mm"


def _got(*, xi, u, omega, g, diameter, z0=None):
    """The user's text of each option, with its unit, for the messages of _follow."""
    return {"xi": xi, "u": u, "omega": omega, "g": f"{g.strip()} m/s^2", "diameter": diameter,
            "z0": None if z0 is None else _mm(z0)}


# --------------------------------------------------------------------------- units


def _units_of(kind: str):
    return parse.SPEED_UNITS if kind == "u" else parse.SPIN_UNITS


def _one_value(text: str, what: str, kind: str) -> float:
    """One speed (m/s) or spin (rad/s), a unit allowed; in range."""
    if kind == "u":
        v = parse.parse_speed_ms(text, what)
        if v > U_MAX:
            raise ValueError(f"{what} must be a speed of at most {U_MAX:g} m/s, got {text!r}")
        return v
    return parse.parse_spin_rads(text, what)


def _values(text: str, what: str, kind: str):
    """A value, a list ``a,b``, a range ``start:stop:step`` or ``-`` (stdin), each value with
    its own unit or a range with one unit at its end (``38:40:1rev/s``)."""
    t = text.strip()
    units = _units_of(kind)
    if t.count(":") == 2:
        example = "1:3:0.5m/s" if kind == "u" else "38:40:1rev/s"
        head, unit = options.range_unit(t, units, what, example)
        if unit is not None:
            try:
                parse.parse_range(head, what)
            except ValueError as exc:
                raise options.typed_range_error(exc, head, t) from None
            return values_option(head, what, lambda s, w: _one_value(s + unit, w, kind))
    bounds = (0.0, U_MAX) if kind == "u" else (0.0, sys.float_info.max)
    return values_option(t, what, lambda s, w: _one_value(s, w, kind), bounds=bounds)


_SPEC_FORM = "a value, normal:MEAN:SD or uniform:LOW:HIGH"
_KINDS = {"normal": "normal", "norm": "normal", "gauss": "normal", "uniform": "uniform",
          "unif": "uniform", "fixed": "fixed"}


def _spec(text: str, what: str, kind: str):
    """A distribution of u (m/s) or omega (rad/s) for simulate, as a coincli.core.toss.launch.Dist in SI:
    a value, ``normal:MEAN:SD`` or ``uniform:LOW:HIGH``; a unit once at the end applies to
    every number (``normal:38:4rev/s``), or one after every number."""
    from coincli.core.toss import launch as T

    lo, hi = (0.0, U_MAX) if kind == "u" else (0.0, math.inf)
    unit_name = "m/s" if kind == "u" else "rad/s"
    example = "normal:2.4:0.3 or normal:240:30cm/s" if kind == "u" else \
        "normal:38:4rev/s or normal:240:25"
    parts = [p.strip() for p in text.strip().split(":")]
    if len(parts) == 1:
        name, nums = "fixed", parts
    else:
        name = _KINDS.get(parts[0].lower())
        nums = parts[1:]
        if name is None:
            raise usage_error(f"{what}: unknown distribution {parts[0]!r}; give {_SPEC_FORM} "
                              f"({unit_name} or with a unit, e.g. {example})")
        if len(nums) != (1 if name == "fixed" else 2):
            raise usage_error(f"{what} must be {_SPEC_FORM} ({unit_name} or with a unit, e.g. "
                              f"{example}), got {text!r}")
        if name == "normal" and nums[1].startswith("-"):
            raise usage_error(f"{what}: normal:MEAN:SD needs SD >= 0, got {text!r}")
    nums = options.unit_at_end(nums, _units_of(kind), what, example, text)
    one = parse.parse_speed_ms if kind == "u" else parse.parse_spin_rads
    try:
        if name == "normal":  # the mean of a normal may be negative: it is truncated at 0
            mean = nums[0][1:] if nums[0].startswith("-") else nums[0]
            vals = [(-1.0 if nums[0].startswith("-") else 1.0) * one(mean, what),
                    one(nums[1], f"{what} SD")]
        else:
            vals = [one(p, what) for p in nums]
    except ValueError as exc:
        raise usage_error(f"{exc}; {what} takes {_SPEC_FORM}") from None
    rng = f"[{lo:g}, {hi:g}] {unit_name}" if math.isfinite(hi) else f">= 0 {unit_name}"
    if name == "fixed" or (name == "normal" and vals[1] == 0) or (name == "uniform" and
                                                                  vals[0] == vals[1]):
        if not lo <= vals[0] <= hi:
            raise usage_error(f"{what} must be in {rng}, got {text!r}")
        return T.Dist("fixed", vals[0], 0.0, lo, hi)
    if name == "uniform":
        if not lo <= vals[0] <= vals[1] <= hi:
            raise usage_error(f"{what}: uniform:LOW:HIGH needs LOW <= HIGH, both "
                              f"{'in ' if math.isfinite(hi) else ''}{rng}; got {text!r}")
        return T.Dist("uniform", vals[0], vals[1], lo, hi)
    mu, sd = vals
    _usage(T.check_normal_mass, what, text, mu, sd, lo, hi, rng)
    return T.Dist("normal", mu, sd, lo, hi)


# --------------------------------------------------------------------------- coin toss

UValuesOpt = Annotated[str | None, typer.Option(
    "--u", metavar="SPEED", help="Launch speed: 2 (m/s), 240cm/s, 8.6km/h; a list, a range "
    "or -.  Default: drawn (hand toss).")]
OmegaValuesOpt = Annotated[str | None, typer.Option(
    "--omega", metavar="SPIN", help="Spin omega_N = M/I1 of eq. (2): 40 (rad/s), 38rev/s, "
    "2300rpm; a list, a range or -.  Default: drawn.")]
PsiValuesOpt = Annotated[str | None, typer.Option(
    "--psi", metavar="DEG", help="Angle psi of the angular momentum to the normal, degrees "
    "[0, 180]; a list, a range or -.  Default: drawn.")]
Z0Opt = Annotated[str | None, typer.Option(
    "--z0", metavar="MM", help="Launch height of the centre, mm or with a unit (default: "
    "(sqrt 3/2) a, plus h/2 for thick contact).")]


@app.command("toss")
def toss_cmd(
    xi: XisOpt = None,
    coin: CoinOpt = None,
    count: CountOpt = None,
    quarters: QuartersOpt = None,
    diameter: DiameterOpt = None,
    thickness: ThicknessOpt = None,
    psi: PsiValuesOpt = None,
    u: UValuesOpt = None,
    omega: OmegaValuesOpt = None,
    seed: SeedOpt = None,
    g: GOpt = "9.81",
    contact: ContactOpt = "rim",
    z0: Z0Opt = None,
    landing: BO.LandingOpt = "catch",
    surface: BO.SurfaceOpt = None,
    restitution: BO.RestitutionOpt = None,
    friction: BO.FrictionOpt = None,
    torsional: BO.TorsionalOpt = None,
    rolling: BO.RollingOpt = None,
    height: BO.ReleaseHeightOpt = None,
    vx: BO.VxOpt = None,
    dt: BO.DtOpt = None,
    t_max: BO.TMaxOpt = None,
    trajectory: Annotated[str | None, typer.Option("--trajectory", help="With --landing "
                                                   "bounce: write the time series (time, "
                                                   "position, quaternion, velocities, tilt, "
                                                   "energy, contacts) to this CSV file.",
                                                   metavar="FILE.csv")] = None,
    fmt: FormatOpt = "table",
    quiet: QuietOpt = False,
):
    """One deterministic toss: time of flight, turns, final tilt and outcome (eqs. 3-7).

    The coin starts heads up with its centre at z0 = (sqrt 3/2) a, flies up at u and spins at
    omega; it is caught at z = 0 the first time it touches (the smallest positive root of
    z(t) - a sin alpha(t) = 0, never skipping an earlier one).  Heads if alpha_f <= theta0,
    tails if alpha_f > 180 - theta0, sides between (eq. 7).  Whatever of --u, --omega, --psi
    is missing is drawn from a natural hand toss (see README; Diaconis, Holmes & Montgomery,
    SIAM Review 49 (2007) 211: u ~ normal:2.4:0.3 m/s, omega ~ normal:38:4 rev/s, psi ~
    normal:90:10 deg) with a seed that is reported.  Lists of equal length are paired.

    --landing bounce drops the coin onto a surface instead and follows it (MuJoCo, pip install
    'thickcoin[physics]') until it settles: its bounces, time to settle and final side;
    --trajectory FILE.csv writes the motion.

    Examples: coin toss --xi 0.577 ;  coin toss --xi 0.577 --psi 90 --u 2 --omega 40 ;
    coin toss --coin quarter --psi 90 --u 2 --omega 38:40:1 -f csv ;
    coin toss --xi 0.577 --psi 85 --u 2.4 --omega 38 --landing bounce --surface wood
    --trajectory toss.csv
    """
    check_format(fmt)
    physics = BO.parse_physics(BO.landing_of(landing), surface=surface, restitution=restitution,
                               friction=friction, torsional=torsional, rolling=rolling,
                               height=height, vx=vx, dt=dt, t_max=t_max)
    if physics is None and trajectory is not None:
        raise usage_error("--trajectory goes with --landing bounce (a caught toss is the "
                          "closed-form flight: coin toss prints it)")
    if physics is not None and contact.strip().lower() != "rim":
        raise usage_error("--contact goes with --landing bounce only as rim (a bounce is the "
                          "whole cylinder on the surface)")
    coins = options.resolve_coin(xi, coin, count, quarters, diameter, thickness, many=True,
                                  xi_rule="finite", command="coin toss")
    ct = _phase.contact_value(contact)
    dia = _phase.diameter_m(coins, diameter)
    gv = _phase.g_value(g)
    given = {"psi": psi, "u": u, "omega": omega}
    cols = {"xi": coins.xis}
    if psi is not None:
        cols["psi"] = values_option(psi, "--psi", options._deg_item, bounds=(0.0, 180.0))
    if u is not None:
        cols["u"] = _values(u, "--u", "u")
    if omega is not None:
        cols["omega"] = _values(omega, "--omega", "omega")
    lens = {k: len(v) for k, v in cols.items()}
    n = max(lens.values())
    bad = [f"--{k} ({m})" for k, m in lens.items() if m not in (1, n)]
    if bad:
        raise usage_error(f"lists must have one value or {n} values; got {', '.join(bad)}")
    drawn = [k for k in ("u", "omega", "psi") if given[k] is None]
    if seed is not None and not drawn:
        raise usage_error("--seed seeds what is drawn for a missing --u, --omega or --psi; all "
                          "three are given")
    xs = cols["xi"]
    xi_max = float(xs.max() if hasattr(xs, "max") else max(xs))
    _xi_for_contact(xi_max, ct == "thick")
    z0_m = _z0_m(z0, xi_max, dia, ct == "thick")
    import numpy as np

    from coincli.core.toss import batch as TB
    from coincli.core.toss import flight as T
    from coincli.core.toss import launch as TL

    seed_v = options.seed_value(seed) if drawn else None
    if drawn:
        from coincli.core._numerics.backend import numpy_random

        rng = numpy_random().default_rng(seed_v)
        spec = {k: (TL.HAND_TOSS[k] if k in drawn else TL.Dist("fixed", 0.0)) for k in
                ("u", "omega", "psi")}
        got = TL.sample_conditions(n, rng, **spec)
        for k in drawn:
            v = np.broadcast_to(got[k], (n,))
            cols[k] = np.degrees(v) if k == "psi" else v
    x, p, uu, w = (np.broadcast_to(np.asarray(cols[k], dtype=float), (n,))
                   for k in ("xi", "psi", "u", "omega"))
    psi_rad = np.where(p == 180.0, math.pi, np.radians(p))
    if "psi" in drawn:  # drawn in radians: no round trip through degrees
        psi_rad = np.broadcast_to(got["psi"], (n,))
    problem = T.flight_limits(x, psi_rad, uu, w, diameter=dia, g=gv, contact=ct, z0=z0_m)[2]
    if problem.any():
        k = int(np.argmax(problem != 0))
        gt = _got(xi=_num(float(x[k])), u=f"{_num(float(uu[k]))} m/s",
                  omega=f"{_num(float(w[k]))} rad/s", g=g, diameter=_dia_text(diameter, dia),
                  z0=z0)
        _follow(T, float(x[k]), float(psi_rad[k]), float(uu[k]), float(w[k]), dia=dia, g=gv,
                ct=ct, z0=z0_m, got=gt, where=f" (row {k + 1})" if n > 1 else "")
    if physics is not None:
        if n != 1:
            raise usage_error("coin toss --landing bounce takes one toss (one value of --xi, "
                              "--psi, --u, --omega); coin simulate --landing bounce takes many")
        xf, uf, wf = float(x[0]), float(uu[0]), float(w[0])
        if xf == 0 or xf > 100:
            raise usage_error(f"--xi must be above 0 and at most 100 with --landing bounce, "
                              f"got {_num(xf)}")
        if wf > 1e4:
            raise usage_error(f"--omega must be at most 10000 rad/s with --landing bounce, got "
                              f"{_num(wf)} rad/s")
        BO.check_coin(physics, xf, dia, xi_text=xi, diameter_text=diameter,
                      thickness_text=thickness)
        BO.check_speed(physics, uf, gv, u if u is not None else f"{_num(uf)} m/s")
        extra = ""
        if drawn:
            what = ", ".join(f"{k} ~ {TL.HAND_TOSS_TEXT[k]}" for k in drawn)
            extra = (f"  Drawn from a hand toss ({DHM}): {what}; seed {seed_v} (--seed {seed_v} "
                     "repeats it).")
            if quiet:
                options.report_seed(seed_v, seed is not None)
        BO.toss(physics, xi=xf, psi=float(psi_rad[0]), u=uf, omega=wf, diameter=dia, g=gv,
                z0=z0_m, trajectory=trajectory, fmt=fmt, quiet=quiet, note_extra=extra,
                seed=seed_v if drawn else None)
        return
    res = _usage(TB.toss_many, x, psi_rad, uu, w, diameter=dia, g=gv, contact=ct, z0=z0_m)
    z0_mm = (np.full(n, z0_m * 1000) if z0_m is not None else
             (math.sqrt(3) / 2 * dia / 2 + (x * dia / 2 if ct == "thick" else 0.0)) * 1000)
    outcome = [T.NAMES[c] for c in res.code.tolist()]
    data = [x.tolist(), p.tolist(), uu.tolist(), w.tolist(), res.t_f.tolist(),
            (w * res.t_f / (2 * math.pi)).tolist(), np.degrees(res.alpha_f).tolist(),
            np.degrees(np.arctan2(1.0, x)).tolist(), (uu * w / gv).tolist(), outcome,
            np.broadcast_to(z0_mm, (n,)).tolist(), [ct] * n]
    columns = [
        Column("xi", "xi"), Column("psi_deg", "psi (deg)"), Column("u", "u (m/s)"),
        Column("omega", "omega (rad/s)"), Column("t_f", "t_f (s)", "g10"),
        Column("turns", "turns"), Column("alpha_f_deg", "alpha_f (deg)"),
        Column("theta0_deg", "theta0 (deg)"), Column("vigor", "vigor u*omega/g"),
        Column("outcome", "outcome", "text"), Column("z0_mm", "z0 (mm)"),
        Column("contact", "contact", "text"),
    ]
    if drawn and fmt != "table":
        columns.append(Column("seed", "seed", "int"))
        data.append([seed_v] * n)
    typed = [f"{k} = {given[k].strip()}" for k in ("u", "omega") if given[k] is not None
             and parse.split_unit(given[k], _units_of(k))[1] not in (None, "m/s", "rad/s")]
    note = (f"Deterministic toss (Sec. II), caught at first contact: D = {dia * 1000:g} mm, g = {gv:g} m/s^2, contact "
            f"{ct}; heads if alpha_f <= theta0, tails if alpha_f > 180 - theta0 (eq. 7).  "
            "The closed forms (coin design/table) are the limit vigor >> 1.")
    if typed:
        note += f"  Typed {', '.join(typed)}; shown in m/s and rad/s."
    if drawn:
        what = ", ".join(f"{k} ~ {TL.HAND_TOSS_TEXT[k]}" for k in drawn)
        note += (f"  Drawn from a hand toss ({DHM}): {what}; seed {seed_v} (--seed {seed_v} "
                 "repeats it).")
        if quiet:
            options.report_seed(seed_v, seed is not None)
    emit(Result("coin toss", columns, [], note, quiet=outcome if n > 1 else outcome[0],
                vertical=True, data=data), fmt, quiet)


# --------------------------------------------------------------------------- coin simulate


def _psi_dist(text: str):
    """--psi-dist: the shared psi grammar (uniform[:LOW:HIGH], cosine, normal[:MEAN:SD],
    table:FILE), or a fixed angle in degrees."""
    from coincli.core.toss import launch as T

    s = text.strip()
    try:
        v = parse.parse_number(s, "--psi-dist")
    except ValueError:
        return T.Dist.from_density(options.psi_density(s))
    if not 0.0 <= v <= 180.0:
        raise usage_error(f"--psi-dist: a fixed angle must be from 0 to 180 degrees, got {s!r}")
    return options.radians(v)


@app.command("simulate")
def simulate_cmd(
    xi: XiOpt = None,
    coin: CoinOpt = None,
    count: CountOpt = None,
    quarters: QuartersOpt = None,
    diameter: DiameterOpt = None,
    thickness: ThicknessOpt = None,
    u: Annotated[str | None, typer.Option(
        "--u", metavar="SPEC", help=f"Launch speed: {_SPEC_FORM}, in m/s or with a unit "
        f"(normal:240:30cm/s).  Default: {HAND['u']} (hand toss).")] = None,
    omega: Annotated[str | None, typer.Option(
        "--omega", metavar="SPEC", help=f"Spin: {_SPEC_FORM}, in rad/s or with a unit.  "
        f"Default: {HAND['omega']} (hand toss).")] = None,
    psi: Annotated[str | None, typer.Option(
        "--psi", metavar="DEG", help="A fixed angle psi, degrees [0, 180].")] = None,
    psi_dist: Annotated[str | None, typer.Option(
        "--psi-dist", metavar="SPEC", help="psi density: uniform[:LOW:HIGH], cosine, "
        f"normal[:MEAN:SD] (deg), table:FILE.  Default: {HAND['psi']}.")] = None,
    tosses: TossesOpt = None,
    seed: SeedOpt = None,
    stream: Annotated[bool, typer.Option(
        "--stream", help="Print one outcome a line (H, S or T) instead of the summary.")] = False,
    g: GOpt = "9.81",
    contact: ContactOpt = "rim",
    landing: BO.LandingOpt = "catch",
    surface: BO.SurfaceOpt = None,
    restitution: BO.RestitutionOpt = None,
    friction: BO.FrictionOpt = None,
    torsional: BO.TorsionalOpt = None,
    rolling: BO.RollingOpt = None,
    height: BO.ReleaseHeightOpt = None,
    vx: BO.VxOpt = None,
    jobs: BO.JobsOpt = None,
    dt: BO.DtOpt = None,
    t_max: BO.TMaxOpt = None,
    fmt: FormatOpt = "table",
    quiet: QuietOpt = False,
):
    """Many seeded tosses with random initial conditions: frequencies next to the vigorous limit.

    Draws u, omega and psi (by default a natural hand toss, after Diaconis, Holmes &
    Montgomery, SIAM Review 49 (2007) 211), tosses each coin as `coin toss` does, and reports
    the frequencies of heads, sides and tails with 95% Wilson intervals next to Table I
    averaged over the same psi (the vigorous limit).  -n is 10000 by default, at most 10^8.
    The seed is reported; the same seed gives the same tosses.

    --landing bounce tosses the coins onto a surface (--surface, or --restitution and
    --friction) and lets them bounce and settle, simulated with MuJoCo (pip install
    'thickcoin[physics]'): a simulated table, not the paper's catch.  It is slow: 20-30 ms of
    CPU a toss, 74-108 tosses a second on two idle cores (docs/performance.md), so the default
    10,000 tosses take some 4.5 CPU-minutes; a progress bar on a terminal shows the time left.

    Examples: coin simulate --xi 0.577 ;
    coin simulate -n 1000000 --seed 7 --xi 0.577 --omega normal:6:1rev/s ;
    coin simulate -n 5 --seed 1 --xi 0.577 --psi 90 --stream ;
    coin simulate -n 2000 --seed 1 --xi 0.577 --psi 90 --landing bounce --surface wood
    """
    check_format(fmt)
    if stream and (fmt != "table" or quiet):
        raise usage_error("--stream prints one letter a line; it takes no --format or --quiet")
    physics = BO.parse_physics(BO.landing_of(landing), surface=surface, restitution=restitution,
                               friction=friction, torsional=torsional, rolling=rolling,
                               height=height, vx=vx, jobs=jobs, dt=dt, t_max=t_max)
    if physics is not None and stream:
        raise usage_error("--stream goes with --landing catch (a bounce run prints its summary)")
    if physics is not None and contact.strip().lower() != "rim":
        raise usage_error("--contact goes with --landing catch (a bounce is the whole cylinder "
                          "on the surface)")
    coins = options.resolve_coin(xi, coin, count, quarters, diameter, thickness,
                                  xi_rule="finite", command="coin simulate")
    ct = _phase.contact_value(contact)
    dia = _phase.diameter_m(coins, diameter)
    gv = _phase.g_value(g)
    count_n = _tosses(tosses) if tosses is not None else 10_000
    xv = coins.xi
    _xi_for_contact(xv, ct == "thick")
    from coincli.core.toss import flight as T
    from coincli.core.toss import simulate as TS

    u_spec, w_spec, psi_spec, labels = launch(psi, psi_dist, u, omega)
    seed_v = options.seed_value(seed)
    kw = {"xi": xv, "u": u_spec, "omega": w_spec, "psi": psi_spec, "diameter": dia, "g": gv,
          "contact": ct}
    # Every toss must be one the core can follow, checked at the top of the distributions (the
    # flight and the phase grow with u and omega), so that no batch fails halfway through.
    u_hi, w_hi = _reach(u_spec, U_MAX), _reach(w_spec, math.inf)
    psi_hi = psi_spec if isinstance(psi_spec, float) else math.pi / 2  # the largest omega^2 a
    got = _got(xi=_num(xv), u=_spec_text(u or HAND["u"], u_spec, u_hi, "m/s"),
               omega=_spec_text(omega or HAND["omega"], w_spec, w_hi, "rad/s"), g=g,
               diameter=_dia_text(diameter, dia))
    _follow(T, xv, psi_hi, u_hi, w_hi, dia=dia, g=gv, ct=ct, z0=None, got=got)
    _usage(T.check_toss, xv, psi_hi, u_hi, w_hi, diameter=dia, g=gv, contact=ct)  # the same, core
    if physics is not None:
        BO.check_coin(physics, xv, dia, xi_text=xi, diameter_text=diameter,
                      thickness_text=thickness)
        BO.check_speed(physics, u_hi, gv, u or HAND["u"])
        if quiet:
            options.report_seed(seed_v, seed is not None)
        BO.simulate(physics, count=count_n, seed=seed_v, xi=xv, u=u_spec, omega=w_spec,
                    psi=psi_spec, diameter=dia, g=gv, labels=labels, fmt=fmt, quiet=quiet,
                    progress=lambda total: ProgressBar("tossing", total, least=200))
        return
    if stream:
        options.report_seed(seed_v, seed is not None)
        _stream(T, count_n, seed_v, kw)
        return
    with ProgressBar("tossing", count_n, least=200_000) as tick:
        sim = _usage(TS.simulate, count_n, seed_v, progress=tick, **kw)
    machine = fmt != "table"
    rows = []
    for f, p in zip(sim.frequencies, sim.vigorous, strict=True):
        rows.append((f.outcome, f.count, f.p, f.lo, f.hi, float(p), f.p - float(p))
                    + ((seed_v,) if machine else ()))
    columns = [
        Column("outcome", "outcome", "text"), Column("count", "count", "int"),
        Column("frequency", "frequency"), Column("ci_low", "95% low"),
        Column("ci_high", "95% high"), Column("vigorous", "vigorous limit"),
        Column("difference", "freq - limit"),
    ] + ([Column("seed", "seed", "int")] if machine else [])
    note = (f"{count_n} toss{'es' if count_n != 1 else ''}, seed {seed_v}: xi = {xv:g}, "
            f"{labels}; D = {dia * 1000:g} mm, g = {gv:g} m/s^2, "
            f"contact {ct}; caught at first contact (the paper's landing; --landing bounce for a "
            "table).  95% Wilson intervals.  The vigorous limit is Table I averaged over "
            "psi; it holds when u*omega/g >> 1 and omega*a/u << 1.")
    if quiet:
        options.report_seed(seed_v, seed is not None)
    emit(Result("coin simulate", columns, rows, note, quiet=[r[2] for r in rows]), fmt, quiet)


def _tosses(text: str) -> int:
    """-n: a whole number from 1 to MAX_TOSSES; beyond, the message says how to get more."""
    digits = text.strip().removeprefix("+").lstrip("0")
    if digits.isascii() and digits.isdigit() and (len(digits) > 9 or int(digits) > MAX_TOSSES):
        shown = digits if len(digits) <= 30 else f"{digits[:12]}... ({len(digits)} digits)"
        raise usage_error(f"-n {shown} is more than the {MAX_TOSSES} (10^8) tosses of one run "
                          "(about 20 seconds); for more, run several times with "
                          "different --seed values and add the counts")
    return options.tosses_value(text, high=MAX_TOSSES)


def _reach(dist, hi: float) -> float:
    """The largest value a distribution of simulate draws: a fixed value, a uniform's HIGH, a
    normal's MEAN + 10 SD (truncated to ``hi``; beyond it the chance is below 1e-23 a draw)."""
    if dist.kind == "fixed" or dist.p2 == 0:
        return dist.p1
    if dist.kind == "uniform":
        return dist.p2
    return min(max(dist.p1 + NORMAL_REACH * dist.p2, 0.0), hi)


def _spec_text(text: str, dist, reach: float, unit: str) -> str:
    """The typed distribution with its unit, for messages."""
    t = text.strip()
    units = parse.SPEED_UNITS if unit == "m/s" else parse.SPIN_UNITS
    typed_unit = parse.split_unit(t.split(":")[-1], units)[1] is not None
    if dist.kind == "normal" and dist.p2 > 0:
        if typed_unit:
            return f"{t}, which reaches {reach:g} {unit} at MEAN + {NORMAL_REACH} SD"
        return f"{t} {unit}, which reaches {reach:g} at MEAN + {NORMAL_REACH} SD"
    return t if typed_unit else f"{t} {unit}"


def _stream(T, count, seed_v, kw):
    """Write one letter a line, batch by batch; the first batch is computed before any output,
    so bad input still fails cleanly with nothing printed."""
    import numpy as np

    from coincli.core.toss.simulate import simulate_chunks

    table = np.array([ord(c) for c in T.LETTERS], dtype=np.uint8)
    chunks = simulate_chunks(count, seed_v, **kw)
    codes = _usage(next, chunks)
    out = sys.stdout
    while codes is not None:
        buf = np.empty(2 * codes.size, dtype=np.uint8)
        buf[0::2] = table[codes]
        buf[1::2] = ord("\n")
        out.write(buf.tobytes().decode("ascii"))
        codes = next(chunks, None)
    out.flush()


# ------------------------------------------------------------------------ design --landing bounce


def launch(psi, psi_dist, u, omega):
    """The launch distributions of a run of many tosses (``coin simulate``, and ``coin design``
    and ``coin plot sides`` with --landing bounce): --u, --omega, --psi (fixed) or --psi-dist;
    what is not given is the hand toss (:data:`coincli.core.toss.launch.HAND_TOSS`).  Returns the three
    specs and their description (``u ~ ..., omega ~ ..., psi ...``, units named)."""
    from coincli.core.toss import launch as T

    options.refuse_psi_and_dist(psi, psi_dist)
    if psi is not None:
        psi_spec = options.radians(options.psi_angle(psi))
        psi_text = f"psi = {psi.strip()} deg"
    elif psi_dist is not None:
        psi_spec = _psi_dist(psi_dist)
        psi_text = f"psi ~ {psi_dist.strip()} deg"
    else:
        psi_spec, psi_text = T.HAND_TOSS["psi"], f"psi ~ {T.HAND_TOSS_TEXT['psi']}"
    u_spec = _spec(u, "--u", "u") if u is not None else T.HAND_TOSS["u"]
    w_spec = _spec(omega, "--omega", "omega") if omega is not None else T.HAND_TOSS["omega"]
    u_text = (T.HAND_TOSS_TEXT["u"] if u is None else u.strip() + (
        "" if parse.split_unit(u.split(":")[-1], parse.SPEED_UNITS)[1] else " m/s"))
    w_text = (T.HAND_TOSS_TEXT["omega"] if omega is None else omega.strip() + (
        "" if parse.split_unit(omega.split(":")[-1], parse.SPIN_UNITS)[1] else " rad/s"))
    hand = [k for k, v in (("u", u), ("omega", omega), ("psi", psi or psi_dist)) if v is None]
    source = f" (hand toss, {DHM}: {', '.join(hand)})" if hand else ""
    return u_spec, w_spec, psi_spec, f"u ~ {u_text}, omega ~ {w_text}, {psi_text}{source}"


def bounce_launch(psi, psi_dist, u, omega):
    """:func:`launch` for a bounce run, whose spin stays at most 10^4 rad/s."""
    u_spec, w_spec, psi_spec, labels = launch(psi, psi_dist, u, omega)
    if _reach(w_spec, math.inf) > 1e4:
        raise usage_error(f"--omega must stay at most 10000 rad/s with --landing bounce, got "
                          f"{omega.strip()!r}")
    return u_spec, w_spec, psi_spec, labels


def bounce_design(physics, *, p_sides, psi, psi_dist, u, omega, diameter, coin, tol, seed,
                  max_tosses, time_limit, fmt, quiet):
    """``coin design --landing bounce``."""
    from coincli.core import coins as coin_catalog

    targets = values_option(p_sides, "--p-sides", parse.parse_probability, bounds=(0.0, 1.0))
    targets = [float(t) for t in targets]
    if len(targets) > 20:
        raise usage_error(f"--landing bounce designs at most 20 targets a run, got "
                          f"{len(targets)}")
    for t in targets:
        if not 0.0 < t < 1.0:
            raise usage_error(f"--p-sides must be strictly between 0 and 1 with --landing "
                              f"bounce, got {t:g}")
    tol_v = 0.01 if tol is None else _bounded(tol, "--tol", 1e-4, 1.0)
    mt = 200_000 if max_tosses is None else _tosses(max_tosses)
    tl = 300.0 if time_limit is None else _bounded(time_limit, "--time-limit", 1.0, 1e6)
    if diameter is not None:
        try:
            dia = parse.parse_length_mm(diameter, "--diameter") / 1000
        except ValueError as exc:
            raise usage_error(str(exc)) from None
    else:
        try:
            dia = coin_catalog.get_coin(coin).diameter_mm / 1000
        except ValueError as exc:
            raise usage_error(str(exc)) from None
    u_spec, w_spec, psi_spec, labels = bounce_launch(psi, psi_dist, u, omega)
    BO.check_coin(physics, None, dia, diameter_text=diameter)
    BO.check_speed(physics, _reach(u_spec, U_MAX), T_G, u or HAND["u"])
    BO.design(physics, targets=targets, seed=options.seed_value(seed), tol=tol_v, max_tosses=mt,
              time_limit=tl, u=u_spec, omega=w_spec, psi=psi_spec, diameter=dia, g=T_G,
              labels=labels, fmt=fmt, quiet=quiet, progress=lambda: ProgressBar("simulating", unit="tosses",
                                                     elapsed=True))


T_G = 9.81  # coincli.core.toss.flight.STANDARD_G


def _bounded(text: str, what: str, lo: float, hi: float) -> float:
    """A number in [lo, hi], or the usage error that says so."""
    try:
        v = parse.parse_number(text, what)
    except ValueError:
        v = math.nan
    if not lo <= v <= hi:  # NaN fails too
        raise usage_error(f"{what} must be a number from {lo:g} to {hi:g}, got {text!r}")
    return v


# --------------------------------------------------------------------------- coin phase


@app.command("phase")
def phase_cmd(
    xi: XiOpt = None,
    coin: CoinOpt = None,
    count: CountOpt = None,
    quarters: QuartersOpt = None,
    diameter: DiameterOpt = None,
    thickness: ThicknessOpt = None,
    psi: _phase.PsiOpt = "90",
    u: _phase.URangeOpt = None,
    omega: _phase.OmegaRangeOpt = None,
    cols: _phase.ColsOpt = None,
    rows: _phase.RowsOpt = None,
    exact: _phase.ExactOpt = False,
    no_curves: _phase.NoCurvesOpt = False,
    toss: _phase.TossMarkOpt = None,
    g: GOpt = "9.81",
    contact: ContactOpt = "rim",
    out: Annotated[str | None, typer.Option(
        "--out", "-o", metavar="FILE", help="Write a figure: .png, .svg or .pdf (needs "
        "matplotlib: pip install 'coincli\\[plot]').")] = None,
    fmt: FormatOpt = "table",
):
    """The pre-images of heads, sides and tails over (u, omega): Fig. 3 of the paper.

    Each cell is one deterministic toss (as `coin toss`) from the cell's centre; the coin is
    the fair one (1/sqrt 3, a quarter's size) unless given.  On a terminal: coloured blocks,
    boundaries of eq. (10) as dots, round ticks.  In a pipe or with NO_COLOR: letters H, S,
    T, lower case where a boundary passes.  --format csv/json: one row per cell.  --out
    FILE: a figure.  coin plot phase takes the same options.

    Examples: coin phase ;  coin phase --xi 0.577 --psi 90 --u 0:3 --omega 0:60 ;
    coin phase --xi 0.3 --u 0:5 --omega 0:100 --out phase.png ;  coin phase -f csv
    """
    check_format(fmt)
    if out is not None and fmt != "table":
        raise usage_error("--out writes a figure; it takes no --format")
    ph = _phase.resolve(xi=xi, coin=coin, count=count, quarters=quarters, diameter=diameter,
                        thickness=thickness, psi=psi, u=u, omega=omega, cols=cols, rows=rows,
                        exact=exact, no_curves=no_curves, toss=toss, g=g, contact=contact)
    if out is not None:
        return _phase_figure(out, ph)
    if fmt != "table":
        d = _phase.data(ph, ph.cols or _phase.DATA_CELLS, ph.rows or _phase.DATA_CELLS)
        import numpy as np

        from coincli.core.toss import flight as T

        shape = np.asarray(d.outcome).shape
        uu = np.broadcast_to(np.asarray(d.u)[None, :], shape).ravel().tolist()
        ww = np.broadcast_to(np.asarray(d.omega)[:, None], shape).ravel().tolist()
        codes = np.asarray(d.outcome).ravel().tolist()
        data = [uu, ww, [T.NAMES[c] for c in codes], codes]
        columns = [Column("u", "u (m/s)"), Column("omega", "omega (rad/s)"),
                   Column("outcome", "outcome", "text"), Column("code", "code", "int")]
        emit(Result("coin phase", columns, [], "", data=data), fmt)
        return
    nu, nw = _phase.text_size(ph)
    d = _phase.data(ph, nu, nw)
    from coincli.render.text import phase_text, phase_title

    colour = stdout_is_terminal() and not env_no_color()
    from coincli.render.terminal import terminal_width

    pic = phase_text(d, colour=colour, title=phase_title(d, ph.contact),
                     width=terminal_width() if stdout_is_terminal() else None)
    if not colour:
        sys.stdout.write(pic)
        return
    from rich.console import Console

    Console(file=sys.stdout, highlight=False, soft_wrap=True, emoji=False, markup=False,
            force_terminal=True).print(pic, end="")


def _phase_figure(path, ph):
    from coincli.io.files import check_output_path
    from coincli.render import figures as P

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
    data = _phase.data(ph, ph.cols or _phase.FIGURE_CELLS, ph.rows or _phase.FIGURE_CELLS,
                       figure=True)
    write_figure(P.phase_figure(data), path)
