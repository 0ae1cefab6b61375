"""``coin phase`` and the picture it shares with ``coin plot phase``: the pre-images of heads,
sides and tails over (u, omega), Fig. 3 of the paper.

Both commands draw the same thing, so they take the same options with the same defaults
(:func:`resolve`): the coin group (default: the fair coin 1/sqrt 3, a quarter's size), ``--psi``
(90), ``--u LOW:HIGH`` (0:3 m/s) and ``--omega LOW:HIGH`` (0:60 rad/s), with units,
``--cols``/``--rows`` (the grid), ``--exact``, ``--no-curves``, ``--toss U:OMEGA`` (marks),
``--g`` and ``--contact``; the old spellings of ``coin plot phase`` (``--u-range``,
``--omega-range``, ``--exact-curves``, ``--resolution``) too.  :func:`data` computes the
picture's grid; :func:`phase` is the report of ``coin phase``.  :func:`contact_value`,
:func:`g_value` and :func:`diameter_m` parse the options every toss command shares.
No numpy, scipy or rich at import.
"""

from __future__ import annotations

import math
from typing import NamedTuple

from coincli.core.models import FAIR_XI_DYNAMIC
from coincli.errors import compute_error, usage_error
from coincli.io import grammar as parse
from coincli.io import options
from coincli.io.table import Column, Result, check_format
from coincli.io.terminal import env_no_color, stdout_is_terminal
from coincli.limits import (
    G_MAX,
    G_MIN,
    OMEGA_TOP,
    PHASE_DATA_CELLS,
    PHASE_FIGURE_CELLS,
    PHASE_OMEGA_DEFAULT,
    PHASE_U_DEFAULT,
    U_MAX,
)

U_DEFAULT, OMEGA_DEFAULT = PHASE_U_DEFAULT, PHASE_OMEGA_DEFAULT  #: m/s, rad/s (coincli.limits)
MIN_SPAN = 1e-6  #: the narrowest range, in m/s or rad/s
MAX_CELLS = 4000  #: along each axis of the grid
MAX_MARKS = 20
#: the grid of a figure file, and of csv/json, along each axis (coincli.limits)
FIGURE_CELLS, DATA_CELLS = PHASE_FIGURE_CELLS, PHASE_DATA_CELLS


class Phase(NamedTuple):
    """The resolved options: SI units (m, m/s, rad/s), psi in degrees."""

    xi: float
    psi_deg: float
    u_range: tuple
    omega_range: tuple
    diameter: float  #: m
    g: float
    contact: str
    exact: bool
    curves: bool
    marks: list
    cols: int | None
    rows: int | None
    typed: dict  #: the user's text of u, omega, g, diameter, xi (for messages)


def _short(v: float) -> str:
    """1e8, 1e-6 (not 1e+08, 1e-06)."""
    return f"{v:g}".replace("e+0", "e").replace("e+", "e").replace("e-0", "e-")


def _range(text: str, what: str, parse_one, unit: str, top: float) -> tuple[float, float]:
    """LOW:HIGH with a unit after HIGH (for both) or after each."""
    rule = (f"{what} must be LOW:HIGH ({unit} or with a unit) with 0 <= LOW < HIGH <= "
            f"{_short(top)} and HIGH - LOW >= {_short(MIN_SPAN)}")
    parts = text.split(":")
    if len(parts) != 2:
        raise usage_error(f"{rule}, got {text!r}")
    units = parse.SPEED_UNITS if unit == "m/s" else parse.SPIN_UNITS
    lo_t, hi_t = (p.strip() for p in parts)
    _, u_lo = parse.split_unit(lo_t, units)
    _, u_hi = parse.split_unit(hi_t, units)
    if u_hi is not None and u_lo is None:
        lo_t = lo_t + u_hi
    try:
        lo, hi = parse_one(lo_t, what), parse_one(hi_t, what)
    except ValueError:
        raise usage_error(f"{rule}, got {text!r}") from None
    if not (0 <= lo < hi <= top and hi - lo >= MIN_SPAN):
        raise usage_error(f"{rule}, got {text!r}")
    return lo, hi


def _cells(text: str | None, what: str) -> int | None:
    if text is None:
        return None
    try:
        v = parse.parse_count(text, what)
    except ValueError:
        v = 0
    if not 2 <= v <= MAX_CELLS:
        raise usage_error(f"{what} must be a whole number from 2 to {MAX_CELLS}, got {text!r}")
    return v


def _marks(text: str | None) -> list[tuple[float, float]]:
    if text is None:
        return []
    out = []
    for item in text.split(","):
        bad = usage_error("--toss must be U:OMEGA, finite numbers >= 0 in m/s and rad/s or with "
                          f"units (1.2:40, 120cm/s:6rev/s; a list a:b,c:d); got {item!r}")
        parts = item.split(":")
        if len(parts) != 2:
            raise bad
        try:
            out.append((parse.parse_speed_ms(parts[0], "--toss"),
                        parse.parse_spin_rads(parts[1], "--toss")))
        except ValueError:
            raise bad from None
    if len(out) > MAX_MARKS:
        raise usage_error(f"--toss marks at most {MAX_MARKS} tosses")
    return out


def contact_value(text: str) -> str:
    c = text.strip().lower()
    if c not in ("rim", "thick"):
        raise usage_error(f"--contact must be rim or thick, got {text!r}")
    return c


def g_value(text: str) -> float:
    try:
        v = parse.parse_number(text, "--g")
    except ValueError:
        v = math.nan
    if not G_MIN <= v <= G_MAX:  # NaN fails
        raise usage_error(f"--g must be a number from {G_MIN:g} to {G_MAX:g} m/s^2, got "
                          f"{text!r}")
    return v


def diameter_m(coins, typed: str | None = None) -> float:
    """The coin's diameter in metres (a quarter's when only --xi is given); ``typed`` is the
    --diameter text, quoted by the error."""
    mm = coins.diameter_mm if coins is not None and coins.diameter_mm is not None else 24.26
    if not 1e-300 <= mm <= 1e103:
        got = repr(typed) if typed is not None else f"{_short(mm)} mm"
        raise usage_error(f"--diameter must be a length from 1e-300 mm to 1e103 mm (1e100 m), "
                          f"got {got}")
    return mm / 1000.0


def resolve(*, xi, coin, count, quarters, diameter, thickness, psi, u, omega, cols, rows,
            exact, no_curves, toss, g, contact, old_u=None, old_omega=None, old_exact=False,
            old_resolution=None) -> Phase:
    """The options of the phase picture, checked, in SI units."""
    for new, old, name_new, name_old in ((u, old_u, "--u", "--u-range"),
                                         (omega, old_omega, "--omega", "--omega-range")):
        if new is not None and old is not None:
            raise usage_error(f"{name_old} is the old spelling of {name_new}; give one")
    u_what = "--u-range" if old_u is not None else "--u"
    w_what = "--omega-range" if old_omega is not None else "--omega"
    u = u if u is not None else old_u
    omega = omega if omega is not None else old_omega
    if old_resolution is not None:
        if cols is not None or rows is not None:
            raise usage_error("--resolution N is the old spelling of --cols N --rows N; give "
                              "one")
        cols = rows = old_resolution
    cols_what = rows_what = "--resolution" if old_resolution is not None else None
    coins = options.resolve_coin(xi, coin, count, quarters, diameter, thickness,
                                  required=False, xi_rule="finite")
    x = FAIR_XI_DYNAMIC if coins is None else float(coins.xis[0])
    ct = contact_value(contact)
    if ct == "thick" and x > 1e100:
        raise usage_error(f"--xi must be at most 1e100 with --contact thick (the launch height "
                          f"rises by h/2), got {xi.strip() if xi is not None else _short(x)}")
    typed = {"u": (u or U_DEFAULT).strip(), "omega": (omega or OMEGA_DEFAULT).strip(),
             "g": f"{g.strip()} m/s^2", "xi": f"{x:g}",
             "diameter": f"{coins.diameter_mm:g} mm" if coins is not None and
             coins.diameter_mm is not None else "24.26 mm"}
    return Phase(
        xi=x, psi_deg=options.psi_angle(psi),
        u_range=_range(u or U_DEFAULT, u_what, parse.parse_speed_ms, "m/s", U_MAX),
        omega_range=_range(omega or OMEGA_DEFAULT, w_what, parse.parse_spin_rads, "rad/s",
                           OMEGA_TOP),
        diameter=diameter_m(coins, diameter), g=g_value(g), contact=ct, exact=exact or old_exact,
        curves=not no_curves, marks=_marks(toss), cols=_cells(cols, cols_what or "--cols"),
        rows=_cells(rows, rows_what or "--rows"), typed=typed)


def text_size(ph: Phase, extra_lines: int = 10) -> tuple[int, int]:
    """The grid of a picture in the terminal: ``--cols``/``--rows``, or what fits it with the
    command line above it and the next prompt below (the axis labels take a few columns; the
    title, axes and legend 8 lines, the two prompts 2: ``extra_lines``)."""
    from coincli.io.terminal import terminal_height, terminal_width

    tw, th = terminal_width(), terminal_height()
    label = max(len(f"{ph.omega_range[1]:g}"), 4) + 3
    cols = ph.cols if ph.cols is not None else max(10, min(tw, MAX_CELLS) - label)
    rows = ph.rows if ph.rows is not None else max(6, min(th, MAX_CELLS) - extra_lines)
    return cols, rows


def check_followable(ph: Phase) -> None:
    """Every cell must be a toss the core can follow: check the top corner of the ranges."""
    from coincli.core.toss import flight

    _, phase, problem = flight.flight_limits(ph.xi, options.radians(ph.psi_deg), ph.u_range[1],
                                        ph.omega_range[1], diameter=ph.diameter, g=ph.g,
                                        contact=ph.contact)
    if not problem:
        return
    if problem == 1:
        what = "the time of flight at the top of --u overflows a double; raise --g"
    elif problem == 2:
        what = (f"the coin would turn up to omega * t = {phase:.3g} rad in the air at the top "
                f"of the --u and --omega ranges, beyond the {flight.MAX_PHASE:g} rad where a "
                "double "
                f"no longer holds the phase; lower --omega (got {ph.typed['omega']}) or --u "
                f"(got {ph.typed['u']})")
    else:
        what = (f"the spin at the top of --omega is too fast to follow: omega^2 * a overflows "
                f"a double; lower --omega (got {ph.typed['omega']})")
    raise usage_error(what)


def data(ph: Phase, nu: int, nw: int, *, figure: bool = False):
    """The picture's data on an ``nu`` by ``nw`` grid: :class:`coincli.render.maps.PhaseData`
    for a figure; for text and csv the same fields from
    :func:`coincli.core.toss.flight.phase_map` directly (so that they load no plotting
    module)."""
    check_followable(ph)
    if figure:
        from coincli.render import maps

        try:
            d = maps.phase_data(ph.xi, ph.psi_deg, u_range=ph.u_range,
                                   omega_range=ph.omega_range, nu=nu, nw=nw, marks=ph.marks,
                                   exact_curves=ph.exact, diameter=ph.diameter, g=ph.g,
                                   contact=ph.contact)
        except ValueError as exc:
            raise usage_error(str(exc)) from None
        if not ph.curves:
            d.curves = []
        return d
    import types

    from coincli.core.models import conditional
    from coincli.core.toss import phase as toss_phase

    psi = options.radians(ph.psi_deg)
    try:
        pm = toss_phase.phase_map(ph.xi, psi, ph.u_range, ph.omega_range, (nu, nw),
                                  diameter=ph.diameter, g=ph.g, contact=ph.contact,
                                  exact_curves=ph.exact)
    except ValueError as exc:
        raise usage_error(str(exc)) from None
    return types.SimpleNamespace(
        xi=ph.xi, psi_deg=ph.psi_deg, u=pm.u, omega=pm.omega, outcome=pm.codes,
        curves=list(pm.curves) if ph.curves else [], fractions=pm.fractions(),
        vigorous=conditional(ph.xi, psi), marks=list(ph.marks), exact_curves=ph.exact,
        u_range=ph.u_range, omega_range=ph.omega_range)


# --------------------------------------------------------------------------- coin phase


def phase(*, xi=None, coin=None, count=None, quarters=None, diameter=None, thickness=None,
          psi="90", u=None, omega=None, cols=None, rows=None, exact=False, no_curves=False,
          toss=None, g="9.81", contact="rim", out=None, fmt="table"):
    """``coin phase``: the outcome of one deterministic toss from each cell of a grid over
    (u, omega).

    Returns, by what is asked: a :class:`coincli.io.table.Result` with one row per cell
    (``fmt`` csv, tsv, json, jsonl, markdown; a :data:`DATA_CELLS` square grid unless
    ``cols``/``rows``); an empty list when ``out`` names a figure file, which is written (a
    :data:`FIGURE_CELLS` square grid); otherwise the picture for the terminal, sized to it:
    coloured blocks (a :class:`rich.text.Text`) when stdout is a terminal and colour is
    allowed, else letters H, S, T (a ``str``).
    """
    check_format(fmt)
    if out is not None and fmt != "table":
        raise usage_error("--out writes a figure; it takes no --format")
    ph = resolve(xi=xi, coin=coin, count=count, quarters=quarters, diameter=diameter,
                 thickness=thickness, psi=psi, u=u, omega=omega, cols=cols, rows=rows,
                 exact=exact, no_curves=no_curves, toss=toss, g=g, contact=contact)
    if out is not None:
        _figure(out, ph)
        return []
    if fmt != "table":
        return _cells_result(ph)
    return _picture(ph)


def _cells_result(ph: Phase):
    """The grid of csv/json: one row per cell (u, omega, outcome and its code)."""
    import numpy as np

    from coincli.core.toss import flight

    d = data(ph, ph.cols or DATA_CELLS, ph.rows or DATA_CELLS)
    shape = np.asarray(d.outcome).shape
    uu = np.broadcast_to(np.asarray(d.u)[None, :], shape).ravel().tolist()
    ww = np.broadcast_to(np.asarray(d.omega)[:, None], shape).ravel().tolist()
    codes = np.asarray(d.outcome).ravel().tolist()
    cells = [uu, ww, [flight.NAMES[c] for c in codes], codes]
    columns = [Column("u", "u (m/s)"), Column("omega", "omega (rad/s)"),
               Column("outcome", "outcome", "text"), Column("code", "code", "int")]
    return Result("coin phase", columns, [], "", data=cells)


def _picture(ph: Phase):
    """The picture in the terminal's size: a rich Text on a colour terminal, else a str."""
    nu, nw = text_size(ph)
    d = data(ph, nu, nw)
    from coincli.render.text import phase_text, phase_title

    colour = stdout_is_terminal() and not env_no_color()
    from coincli.io.terminal import terminal_width

    return phase_text(d, colour=colour, title=phase_title(d, ph.contact),
                      width=terminal_width() if stdout_is_terminal() else None)


def _figure(path, ph: Phase) -> None:
    """Write the picture as a figure file (checked before any computing)."""
    from coincli.io.files import check_output_path
    from coincli.render import figures, maps
    from coincli.render.figures import write_figure

    try:
        figures.figure_format(path)
        check_output_path(path)  # a FIFO, device or directory: refused before any computing
    except ValueError as exc:
        raise usage_error(f"--out: {exc}") from None
    except OSError as exc:
        raise compute_error(f"cannot write {path!r}: {exc.strerror or exc}") from None
    try:
        figures.require_matplotlib()
    except figures.MatplotlibMissing as exc:
        raise compute_error(str(exc)) from None
    d = data(ph, ph.cols or FIGURE_CELLS, ph.rows or FIGURE_CELLS, figure=True)
    write_figure(maps.phase_figure(d), path)
