"""``coin toss`` and ``coin simulate``: real tosses of finite vigor (Sec. II, Fig. 3).

:func:`toss` is one deterministic toss (or a list of them) and :func:`simulate` a seeded run
of many, each from the options as typed: the coin group of :mod:`coincli.cli._options`, angles
in degrees, speeds and spins with units (:func:`coincli.io.grammar.parse_speed_ms`,
:func:`coincli.io.grammar.parse_spin_rads`) or as distributions (:mod:`coincli.reports.launch`),
converted to SI radians for :mod:`coincli.core.toss.flight`.  Whatever is not given is drawn
from a natural hand toss (:data:`coincli.core.toss.flight.HAND_TOSS`) with a seed that is
reported.  A ValueError from the core is bad input: one line, exit 2.  With
``--landing bounce`` the coin lands on a surface instead (:mod:`coincli.reports.bounce`).
numpy loads only inside the reports, rich never, scipy never.
"""

from __future__ import annotations

import math
import sys

from coincli.errors import usage_error
from coincli.io import grammar as parse
from coincli.io import options
from coincli.io.batches import values_option
from coincli.io.table import Column, Result, check_format
from coincli.reports import bounce as bounce_report
from coincli.reports.landing import landing_of, parse_physics
from coincli.reports.launch import (
    DHM,
    HAND,
    U_MAX,
    check_omega,
    core_call,
    launch,
    no_progress,
    reach,
    spec_text,
    tosses_count,
    units_of,
)
from coincli.reports.phase import contact_value, diameter_m, g_value

XI_THICK_MAX = 1e100  # h/D with --contact thick (an infinite thickness has no launch height)
LENGTH_MM_MIN = 1e-300  # mm; smaller would underflow on the way to metres


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


def _in_unit_of(text: str, mm: float) -> str:
    """``mm`` millimetres in the unit ``text`` was typed in (mm when none)."""
    unit = parse.split_unit(text, parse.LENGTH_UNITS)[1] or "mm"
    return f"{mm / float(parse.LENGTH_UNITS[unit]):.4g} {unit}"


def _z0_m(text: str | None, xi_max: float, dia: float, thick: bool,
          bounce=None) -> float | None:
    """--z0 in metres; for thick contact above h/2, or the coin would start below the plane;
    with --landing bounce (``bounce``: its Physics) above h/2 less the surface's depth below
    the launch plane, or the coin would start inside the surface."""
    if text is None:
        return None
    v = core_call(parse.parse_length_mm, text, "--z0")
    if v < LENGTH_MM_MIN:
        raise usage_error(f"--z0 must be a length of at least {LENGTH_MM_MIN:g} mm, got {text!r}")
    z0 = v / 1000.0
    if bounce is not None:
        depth = bounce.height if isinstance(bounce.height, float) else 0.0
        floor = xi_max * dia / 2 - depth
        if z0 <= floor:
            below = "" if not depth else (f" less the surface's {_in_unit_of(text, depth * 1e3)}"
                                          " below the launch plane")
            raise usage_error(f"--z0 must be above h/2 = {_in_unit_of(text, xi_max * dia * 500)}"
                              f"{below} with --landing bounce (the coin is launched flat: it "
                              f"would start inside the surface), got {_mm(text)}")
        return z0
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


def _bounce_coin(physics, coins, xi_v: float, dia: float, *, xi, coin, count, quarters, diameter,
                 thickness) -> None:
    """The engine's limits on the coin (:func:`coincli.reports.physics.check_coin`), naming the
    option that gave it as typed."""
    from coincli.reports.physics import check_coin

    counts = coins.counts
    check_coin(physics, xi_v, dia, xi_text=xi, diameter_text=diameter,
               thickness_text=thickness if count is None else None, count_text=count,
               quarters_text=quarters, coin_text=coin,
               count=int(counts[0]) if counts is not None and len(counts) else None)


def _follow(flight, xi, psi, u, omega, *, dia, g, ct, z0, got, where=""):
    """Refuse, naming the option at fault, a toss the core cannot follow (flight.flight_limits): a
    flight whose length overflows, a phase omega * t beyond flight.MAX_PHASE, or omega^2 * a beyond
    a double.  ``got`` holds the user's text of each option (with units); the option blamed is
    the first whose default alone would make the toss followable (--g, --z0, --diameter, --xi
    of a thick coin), else --omega (and --u)."""
    _, phase, problem = flight.flight_limits(xi, psi, u, omega, diameter=dia, g=g, contact=ct,
                                             z0=z0)
    if not problem:
        return
    kw = {"diameter": dia, "g": g, "contact": ct, "z0": z0}
    alts = []
    if g != flight.STANDARD_G:
        alts.append((f"{'raise' if g < flight.STANDARD_G else 'lower'} --g (got {got['g']})",
                     {**kw, "g": flight.STANDARD_G}))
    if z0 is not None:
        z0_default = flight.default_z0(xi, dia, ct)
        alts.append((f"{'lower' if z0 > z0_default else 'raise'} --z0 (got {got['z0']})",
                     {**kw, "z0": None}))
    if dia != flight.DEFAULT_DIAMETER:
        alts.append((f"{'lower' if dia > flight.DEFAULT_DIAMETER else 'raise'} --diameter (got "
                     f"{got['diameter']})", {**kw, "diameter": flight.DEFAULT_DIAMETER}))
    if ct == "thick" and xi > 0:
        alts.append((f"lower --xi (got {got['xi']}: a thick coin is launched h/2 higher)",
                     {**kw, "contact": "rim", "z0": z0 if z0 is not None else
                      flight.default_z0(xi, dia, "rim")}))
    # The first option whose default alone makes the toss one the core can follow; else the
    # spin (and the launch speed), which have no default.
    fix = next((f for f, alt in alts if not flight.flight_limits(xi, psi, u, omega, **alt)[2]),
               None)
    if fix is None and len(alts) > 1:  # several at once (--g 1e-300 --z0 1e300)?
        both = dict(kw)
        for _, alt in alts:
            both.update({k: v for k, v in alt.items() if v != kw[k]})
        if not flight.flight_limits(xi, psi, u, omega, **both)[2]:
            fix = " and ".join(f for f, _ in alts)
    if fix is None:
        fix = (f"lower --omega (got {got['omega']})" if problem == 3 else
               f"lower --omega (got {got['omega']}) or --u (got {got['u']})")
    if problem == 1:
        what = f"the time of flight{where} overflows a double"
    elif problem == 2:
        what = (f"the coin would turn up to omega * t = {phase:.3g} rad in the air{where}, "
                f"beyond the {flight.MAX_PHASE:g} rad where a double no longer holds the phase")
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
    units = units_of(kind)
    if t.count(":") == 2:
        example = "1:3:0.5m/s" if kind == "u" else "38:40:1rev/s"
        head, unit = options.range_unit(t, units, what, example)
        if unit is not None:
            try:
                parse.parse_range(head, what)
            except ValueError as exc:
                raise options.typed_range_error(exc, head, t) from None
            try:
                return values_option(head, what, lambda s, w: _one_value(s + unit, w, kind))
            except ValueError as exc:  # the range as typed, with its unit
                raise options.typed_range_error(exc, head, t) from None
    bounds = (0.0, U_MAX) if kind == "u" else (0.0, sys.float_info.max)
    return values_option(t, what, lambda s, w: _one_value(s, w, kind), bounds=bounds)


# --------------------------------------------------------------------------- coin toss


def toss(*, xi=None, coin=None, count=None, quarters=None, diameter=None, thickness=None,
         psi=None, u=None, omega=None, seed=None, g="9.81", contact="rim", z0=None,
         landing="catch", surface=None, restitution=None, friction=None, torsional=None,
         rolling=None, release_height=None, vx=None, dt=None, t_max=None, trajectory=None,
         calibration=None, fmt="table", quiet=False) -> Result:
    """``coin toss``: one deterministic toss per row (lists of equal length are paired), or
    with ``landing="bounce"`` one toss onto a surface (:func:`coincli.reports.bounce.toss`).

    Whatever of ``u``, ``omega``, ``psi`` is missing is drawn from the hand toss with ``seed``
    (drawn itself when None; said on stderr with ``quiet``).
    """
    check_format(fmt)
    physics = parse_physics(landing_of(landing), surface=surface, restitution=restitution,
                            friction=friction, torsional=torsional, rolling=rolling,
                            height=release_height, vx=vx, dt=dt, t_max=t_max,
                            calibration=calibration)
    if physics is None and trajectory is not None:
        raise usage_error("--trajectory goes with --landing bounce (a caught toss is the "
                          "closed-form flight: coin toss prints it)")
    if physics is not None and contact.strip().lower() != "rim":
        raise usage_error("--contact goes with --landing bounce only as rim (a bounce is the "
                          "whole cylinder on the surface)")
    coins = options.resolve_coin(xi, coin, count, quarters, diameter, thickness, many=True,
                                  xi_rule="finite", command="coin toss")
    ct = contact_value(contact)
    dia = diameter_m(coins, diameter)
    gv = g_value(g)
    if physics is not None:
        from coincli.reports.physics import check_g

        check_g(gv, g)
    given = {"psi": psi, "u": u, "omega": omega}
    cols = {"xi": coins.xis}
    if psi is not None:
        cols["psi"] = values_option(psi, "--psi", options.psi_item, bounds=(0.0, 180.0))
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
    z0_m = _z0_m(z0, xi_max, dia, ct == "thick", bounce=physics)
    import numpy as np

    from coincli.core.toss import batch as toss_batch
    from coincli.core.toss import flight
    from coincli.core.toss import launch as toss_launch

    seed_v = options.seed_value(seed) if drawn else None
    if drawn:
        from coincli.core._numerics.backend import numpy_random

        rng = numpy_random().default_rng(seed_v)
        spec = {k: (toss_launch.HAND_TOSS[k] if k in drawn else toss_launch.Dist("fixed", 0.0))
                for k in ("u", "omega", "psi")}
        got = toss_launch.sample_conditions(n, rng, **spec)
        for k in drawn:
            v = np.broadcast_to(got[k], (n,))
            cols[k] = np.degrees(v) if k == "psi" else v
    x, p, uu, w = (np.broadcast_to(np.asarray(cols[k], dtype=float), (n,))
                   for k in ("xi", "psi", "u", "omega"))
    psi_rad = np.where(p == 180.0, math.pi, np.radians(p))
    if "psi" in drawn:  # drawn in radians: no round trip through degrees
        psi_rad = np.broadcast_to(got["psi"], (n,))
    problem = flight.flight_limits(x, psi_rad, uu, w, diameter=dia, g=gv, contact=ct, z0=z0_m)[2]
    if problem.any():
        k = int(np.argmax(problem != 0))
        gt = _got(xi=_num(float(x[k])), u=f"{_num(float(uu[k]))} m/s",
                  omega=f"{_num(float(w[k]))} rad/s", g=g, diameter=_dia_text(diameter, dia),
                  z0=z0)
        _follow(flight, float(x[k]), float(psi_rad[k]), float(uu[k]), float(w[k]), dia=dia, g=gv,
                ct=ct, z0=z0_m, got=gt, where=f" (row {k + 1})" if n > 1 else "")
    if physics is not None:
        if n != 1:
            raise usage_error("coin toss --landing bounce takes one toss (one value of --xi, "
                              "--psi, --u, --omega); coin simulate --landing bounce takes many")
        xf, uf, wf = float(x[0]), float(uu[0]), float(w[0])
        _bounce_coin(physics, coins, xf, dia, xi=xi, coin=coin, count=count,
                     quarters=quarters, diameter=diameter, thickness=thickness)
        from coincli.reports.physics import check_landing

        check_omega(wf, omega if omega is not None else f"{_num(wf)} rad/s")
        check_landing(physics, u_top=uf, g=gv, xi=xf, dia=dia, z0=z0_m,
                      u_text=u if u is not None else f"{_num(uf)} m/s")
        extra = ""
        if drawn:
            what = ", ".join(f"{k} ~ {toss_launch.HAND_TOSS_TEXT[k]}" for k in drawn)
            extra = (f"  Drawn from a hand toss ({DHM}): {what}; seed {seed_v} (--seed {seed_v} "
                     "repeats it).")
            if quiet:
                options.report_seed(seed_v, seed is not None)
        return bounce_report.toss(physics, xi=xf, psi=float(psi_rad[0]), u=uf, omega=wf,
                                  diameter=dia, g=gv, z0=z0_m, trajectory=trajectory, fmt=fmt,
                                  note_extra=extra, seed=seed_v if drawn else None)
    res = core_call(toss_batch.toss_many, x, psi_rad, uu, w, diameter=dia, g=gv, contact=ct,
                    z0=z0_m)
    z0_mm = (np.full(n, z0_m * 1000) if z0_m is not None else
             (math.sqrt(3) / 2 * dia / 2 + (x * dia / 2 if ct == "thick" else 0.0)) * 1000)
    outcome = [flight.NAMES[c] for c in res.code.tolist()]
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
             and parse.split_unit(given[k], units_of(k))[1] not in (None, "m/s", "rad/s")]
    note = (f"Deterministic toss (Sec. II), caught at first contact: D = {dia * 1000:g} mm, "
            f"g = {gv:g} m/s^2, contact "
            f"{ct}; heads if alpha_f <= theta0, tails if alpha_f > 180 - theta0 (eq. 7).  "
            "The closed forms (coin design/table) are the limit vigor >> 1.")
    if typed:
        note += f"  Typed {', '.join(typed)}; shown in m/s and rad/s."
    if drawn:
        what = ", ".join(f"{k} ~ {toss_launch.HAND_TOSS_TEXT[k]}" for k in drawn)
        note += (f"  Drawn from a hand toss ({DHM}): {what}; seed {seed_v} (--seed {seed_v} "
                 "repeats it).")
        if quiet:
            options.report_seed(seed_v, seed is not None)
    return Result("coin toss", columns, [], note, quiet=outcome if n > 1 else outcome[0],
                  vertical=True, data=data)


# --------------------------------------------------------------------------- coin simulate


def simulate(*, xi=None, coin=None, count=None, quarters=None, diameter=None, thickness=None,
             u=None, omega=None, psi=None, psi_dist=None, tosses=None, seed=None, stream=False,
             g="9.81", contact="rim", landing="catch", surface=None, restitution=None,
             friction=None, torsional=None, rolling=None, release_height=None, vx=None,
             jobs=None, dt=None, t_max=None, calibration=None, scheduler=None,
             checkpoint=None, timeout=None, fmt="table", quiet=False,
             progress=None) -> Result:
    """``coin simulate``: ``tosses`` seeded tosses (10000 by default) from the launch
    distributions (:func:`coincli.reports.launch.launch`), their frequencies with 95% Wilson
    intervals next to the vigorous limit; with ``landing="bounce"`` onto a surface
    (:func:`coincli.reports.bounce.simulate`).

    ``stream``: one outcome a line instead, a :class:`Result` of one text column whose every
    chunk is one cell holding a batch of lines (computed as it is written: emit it with
    ``quiet``).  ``progress(total, least)``: a progress bar of the run (a context manager
    giving ``tick(done)``; ``least``: the fewest tosses worth a bar), or None.
    """
    check_format(fmt)
    if stream and (fmt != "table" or quiet):
        raise usage_error("--stream prints one letter a line; it takes no --format or --quiet")
    physics = parse_physics(landing_of(landing), surface=surface, restitution=restitution,
                            friction=friction, torsional=torsional, rolling=rolling,
                            height=release_height, vx=vx, jobs=jobs, dt=dt, t_max=t_max,
                            calibration=calibration, scheduler=scheduler,
                            checkpoint=checkpoint, timeout=timeout)
    if physics is not None and stream:
        raise usage_error("--stream goes with --landing catch (a bounce run prints its summary)")
    if physics is not None and contact.strip().lower() != "rim":
        raise usage_error("--contact goes with --landing catch (a bounce is the whole cylinder "
                          "on the surface)")
    coins = options.resolve_coin(xi, coin, count, quarters, diameter, thickness,
                                  xi_rule="finite", command="coin simulate")
    ct = contact_value(contact)
    dia = diameter_m(coins, diameter)
    xv = coins.xi
    if physics is not None:  # the engine's limits first, each named as typed
        _bounce_coin(physics, coins, xv, dia, xi=xi, coin=coin, count=count,
                     quarters=quarters, diameter=diameter, thickness=thickness)
    gv = g_value(g)
    if physics is not None:
        from coincli.reports.physics import check_g

        check_g(gv, g)
    if tosses is None:
        count_n = 10_000
    elif physics is not None:
        from coincli.reports.physics import bounce_tosses

        count_n = bounce_tosses(tosses)
    else:
        count_n = tosses_count(tosses)
    _xi_for_contact(xv, ct == "thick")
    from coincli.core.toss import flight
    from coincli.core.toss import simulate as toss_simulate

    u_spec, w_spec, psi_spec, labels = launch(psi, psi_dist, u, omega)
    cal_note = None
    if physics is not None and physics.calibration is not None:  # its launch, not the hand's
        from coincli.reports.calibrated import launch_on

        u_spec, w_spec, psi_spec, labels, cal_note = launch_on(physics, psi, psi_dist, u, omega)
    if physics is not None:
        check_omega(reach(w_spec, math.inf), omega or HAND["omega"])
    seed_v = options.seed_value(seed)
    kw = {"xi": xv, "u": u_spec, "omega": w_spec, "psi": psi_spec, "diameter": dia, "g": gv,
          "contact": ct}
    # Every toss must be one the core can follow, checked at the top of the distributions (the
    # flight and the phase grow with u and omega), so that no batch fails halfway through.
    u_hi, w_hi = reach(u_spec, U_MAX), reach(w_spec, math.inf)
    psi_hi = psi_spec if isinstance(psi_spec, float) else math.pi / 2  # the largest omega^2 a
    got = _got(xi=_num(xv), u=spec_text(u or HAND["u"], u_spec, u_hi, "m/s"),
               omega=spec_text(omega or HAND["omega"], w_spec, w_hi, "rad/s"), g=g,
               diameter=_dia_text(diameter, dia))
    _follow(flight, xv, psi_hi, u_hi, w_hi, dia=dia, g=gv, ct=ct, z0=None, got=got)
    core_call(flight.check_toss, xv, psi_hi, u_hi, w_hi, diameter=dia, g=gv, contact=ct)  # the same
    if physics is not None:
        from coincli.reports.physics import check_landing

        check_landing(physics, u_top=u_hi, g=gv, xi=xv, dia=dia, u_text=u or HAND["u"])
        if quiet:
            options.report_seed(seed_v, seed is not None)
        bar = None if progress is None else (lambda total: progress(total, 200))
        r = bounce_report.simulate(physics, count=count_n, seed=seed_v, xi=xv, u=u_spec,
                                   omega=w_spec, psi=psi_spec, diameter=dia, g=gv, labels=labels,
                                   fmt=fmt, progress=bar)
        if cal_note:
            r.notes.append(cal_note)
        return r
    if stream:
        options.report_seed(seed_v, seed is not None)
        return Result("coin simulate --stream", [Column("outcome", "outcome", "text")], [],
                      quiet=0, chunks=_letters(flight, count_n, seed_v, kw))
    with (progress or no_progress)(count_n) as tick:
        sim = core_call(toss_simulate.simulate, count_n, seed_v, progress=tick, **kw)
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
    return Result("coin simulate", columns, rows, note, quiet=[r[2] for r in rows])


def _letters(flight, count, seed_v, kw):
    """The chunks of ``--stream``: each one cell, the letters of a batch of tosses one a line
    (the trailing newline is the writer's).  The first batch is computed before any output
    (by the writer), so bad input still fails cleanly with nothing printed."""
    import numpy as np

    from coincli.core.toss import simulate as toss_simulate

    table = np.array([ord(c) for c in flight.LETTERS], dtype=np.uint8)
    chunks = toss_simulate.simulate_chunks(count, seed_v, **kw)
    codes = core_call(next, chunks)
    while codes is not None:
        buf = np.empty(2 * codes.size - 1, dtype=np.uint8)
        buf[0::2] = table[codes]
        buf[1::2] = ord("\n")
        yield [[buf.tobytes().decode("ascii")]]
        codes = next(chunks, None)
