"""The launch of a run of tosses, from the options' text: what ``coin simulate``, the bouncing
runs (``--landing bounce`` of simulate, design and ``plot sides``) and their messages share.

- :func:`launch` and :func:`bounce_launch`: ``--u``, ``--omega`` (:func:`launch_dist`:
  a value, ``normal:MEAN:SD`` or ``uniform:LOW:HIGH``, units allowed), ``--psi`` or
  ``--psi-dist`` (:func:`psi_dist`) as :class:`coincli.core.toss.flight.Dist` specs in SI
  units, what is missing drawn from the hand toss (:data:`HAND`), and their description;
- :func:`reach`: the largest value a spec draws (to check a run before it starts), and
  :func:`spec_text`, the typed spec with its unit, for messages;
- :func:`tosses_count` (``-n``, at most :data:`MAX_TOSSES`) and :func:`bounded_number`.

Text to typed values only: no typer, nothing printed.  numpy is not needed to load this module.
"""

from __future__ import annotations

import contextlib
import math
import sys

from coincli.errors import compute_error, shown, usage_error
from coincli.io import grammar as parse
from coincli.io import options
from coincli.limits import (  # noqa: F401 (MAX_TOSSES: the reports' limit of -n)
    BOUNCE_OMEGA_MAX,
    HAND,
    MAX_TOSSES,
    NORMAL_REACH,
    SPEC_FORM,
    U_MAX,
)

# Limits, as in coincli.core.toss.flight (kept here so that this module needs no numpy to load).
DHM = "Diaconis, Holmes & Montgomery 2007"
# HAND (the hand toss of coincli.core.toss.flight.HAND_TOSS, as typed, for help and notes) and
# SPEC_FORM (what --u and --omega of a run take) are coincli.limits', which the help texts name
_KINDS = {"normal": "normal", "norm": "normal", "gauss": "normal", "uniform": "uniform",
          "unif": "uniform", "fixed": "fixed"}


def bounded_number(text: str, what: str, lo: float, hi: float) -> float:
    """A number in [lo, hi], or the usage error that says so."""
    try:
        v = parse.parse_number(text, what)
    except ValueError:
        v = math.nan
    if not lo <= v <= hi:  # NaN fails too
        raise usage_error(f"{what} must be a number from {lo:g} to {hi:g}, got {text!r}")
    return v


def core_call(fn, *args, **kwargs):
    """Call the core; its ValueError is a usage error (the input is out of range), but for the
    one that says valid input gave no answer (``coincli.core.bounce.design.Undetermined``: the
    tosses do not determine a curve), which cannot be computed (exit 1)."""
    try:
        return fn(*args, **kwargs)
    except ValueError as exc:
        design = sys.modules.get("coincli.core.bounce.design")  # loaded if it raised this
        if design is not None and isinstance(exc, design.Undetermined):
            raise compute_error(str(exc)) from None
        raise usage_error(str(exc)) from None


@contextlib.contextmanager
def no_progress(*_):
    """No progress bar (a run's ``progress`` when none is given): a tick that does nothing."""
    yield lambda *done: None


def units_of(kind: str):
    """The units of a speed (``kind`` "u") or of a spin (anything else)."""
    return parse.SPEED_UNITS if kind == "u" else parse.SPIN_UNITS


def tosses_count(text: str) -> int:
    """-n: a whole number from 1 to MAX_TOSSES; beyond, the message says how to get more."""
    digits = text.strip().removeprefix("+").lstrip("0")
    if digits.isascii() and digits.isdigit() and (len(digits) > 9 or int(digits) > MAX_TOSSES):
        typed = digits if len(digits) <= 30 else f"{digits[:12]}... ({len(digits)} digits)"
        raise usage_error(f"-n {typed} is more than the {MAX_TOSSES} (10^8) tosses of one run "
                          "(about 20 seconds); for more, run several times with "
                          "different --seed values and add the counts")
    return options.tosses_value(text, high=MAX_TOSSES)


def launch_dist(text: str, what: str, kind: str):
    """A distribution of u (m/s) or omega (rad/s) for simulate, as a
    :class:`coincli.core.toss.flight.Dist` in SI: a value, ``normal:MEAN:SD`` or
    ``uniform:LOW:HIGH``; a unit once at the end applies to every number
    (``normal:38:4rev/s``), or one after every number."""
    from coincli.core.toss import launch as toss_launch

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
            raise usage_error(f"{what}: unknown distribution {parts[0]!r}; give {SPEC_FORM} "
                              f"({unit_name} or with a unit, e.g. {example})")
        if len(nums) != (1 if name == "fixed" else 2):
            raise usage_error(f"{what} must be {SPEC_FORM} ({unit_name} or with a unit, e.g. "
                              f"{example}), got {text!r}")
        if name == "normal" and nums[1].startswith("-"):
            raise usage_error(f"{what}: normal:MEAN:SD needs SD >= 0, got {text!r}")
    nums = options.unit_at_end(nums, units_of(kind), what, example, text)
    one = parse.parse_speed_ms if kind == "u" else parse.parse_spin_rads
    try:
        if name == "normal":  # the mean of a normal may be negative: it is truncated at 0
            mean = nums[0][1:] if nums[0].startswith("-") else nums[0]
            vals = [(-1.0 if nums[0].startswith("-") else 1.0) * one(mean, what),
                    one(nums[1], f"{what} SD")]
        else:
            vals = [one(p, what) for p in nums]
    except ValueError as exc:
        raise usage_error(f"{exc}; {what} takes {SPEC_FORM}") from None
    rng = f"[{lo:g}, {hi:g}] {unit_name}" if math.isfinite(hi) else f">= 0 {unit_name}"
    if name == "fixed" or (name == "normal" and vals[1] == 0) or (name == "uniform" and
                                                                  vals[0] == vals[1]):
        if not lo <= vals[0] <= hi:
            raise usage_error(f"{what} must be in {rng}, got {text!r}")
        return toss_launch.Dist("fixed", vals[0], 0.0, lo, hi)
    if name == "uniform":
        if not lo <= vals[0] <= vals[1] <= hi:
            raise usage_error(f"{what}: uniform:LOW:HIGH needs LOW <= HIGH, both "
                              f"{'in ' if math.isfinite(hi) else ''}{rng}; got {text!r}")
        return toss_launch.Dist("uniform", vals[0], vals[1], lo, hi)
    mu, sd = vals
    core_call(toss_launch.check_normal_mass, what, text, mu, sd, lo, hi, rng)
    return toss_launch.Dist("normal", mu, sd, lo, hi)


def psi_dist(text: str):
    """--psi-dist: the shared psi grammar (uniform[:LOW:HIGH], cosine, normal[:MEAN:SD],
    table:FILE), or a fixed angle in degrees."""
    from coincli.core.toss import launch as toss_launch

    s = text.strip()
    try:
        v = parse.parse_number(s, "--psi-dist")
    except ValueError:
        return toss_launch.Dist.from_density(options.psi_density(s))
    if not 0.0 <= v <= 180.0:
        raise usage_error(f"--psi-dist: a fixed angle must be from 0 to 180 degrees, got {s!r}")
    return options.radians(v)


def reach(dist, hi: float) -> float:
    """The largest value a distribution of simulate draws: a fixed value, a uniform's HIGH, a
    normal's MEAN + 10 SD (truncated to ``hi``; beyond it the chance is below 1e-23 a draw)."""
    if dist.kind == "fixed" or dist.p2 == 0:
        return dist.p1
    if dist.kind == "uniform":
        return dist.p2
    return min(max(dist.p1 + NORMAL_REACH * dist.p2, 0.0), hi)


def spec_text(text: str, dist, reach: float, unit: str) -> str:
    """The typed distribution with its unit, for messages."""
    t = text.strip()
    units = parse.SPEED_UNITS if unit == "m/s" else parse.SPIN_UNITS
    typed_unit = parse.split_unit(t.split(":")[-1], units)[1] is not None
    if dist.kind == "normal" and dist.p2 > 0:
        if typed_unit:
            return f"{t}, which reaches {reach:g} {unit} at MEAN + {NORMAL_REACH} SD"
        return f"{t} {unit}, which reaches {reach:g} at MEAN + {NORMAL_REACH} SD"
    return t if typed_unit else f"{t} {unit}"


def launch(psi, psi_dist_text, u, omega):
    """The launch distributions of a run of many tosses (``coin simulate``, and ``coin design``
    and ``coin plot sides`` with --landing bounce): --u, --omega, --psi (fixed) or --psi-dist;
    what is not given is the hand toss (:data:`coincli.core.toss.flight.HAND_TOSS`).  Returns
    the three specs and their description (``u ~ ..., omega ~ ..., psi ...``, units named)."""
    from coincli.core.toss import launch as toss_launch

    options.refuse_psi_and_dist(psi, psi_dist_text)
    if psi is not None:
        psi_spec = options.radians(options.psi_angle(psi))
        psi_text = f"psi = {psi.strip()} deg"
    elif psi_dist_text is not None:
        psi_spec = psi_dist(psi_dist_text)
        psi_text = f"psi ~ {psi_dist_text.strip()} deg"
    else:
        psi_spec = toss_launch.HAND_TOSS["psi"]
        psi_text = f"psi ~ {toss_launch.HAND_TOSS_TEXT['psi']}"
    u_spec = launch_dist(u, "--u", "u") if u is not None else toss_launch.HAND_TOSS["u"]
    w_spec = launch_dist(omega, "--omega", "omega") if omega is not None else \
        toss_launch.HAND_TOSS["omega"]
    u_text = (toss_launch.HAND_TOSS_TEXT["u"] if u is None else u.strip() + (
        "" if parse.split_unit(u.split(":")[-1], parse.SPEED_UNITS)[1] else " m/s"))
    w_text = (toss_launch.HAND_TOSS_TEXT["omega"] if omega is None else omega.strip() + (
        "" if parse.split_unit(omega.split(":")[-1], parse.SPIN_UNITS)[1] else " rad/s"))
    hand = [k for k, v in (("u", u), ("omega", omega), ("psi", psi or psi_dist_text))
            if v is None]
    source = f" (hand toss, {DHM}: {', '.join(hand)})" if hand else ""
    return u_spec, w_spec, psi_spec, f"u ~ {u_text}, omega ~ {w_text}, {psi_text}{source}"


def check_omega(top: float, text: str) -> None:
    """``--omega`` of a bouncing run (the largest spin it draws, ``top``) at most
    :data:`coincli.limits.BOUNCE_OMEGA_MAX`: faster, the coin turns a radian or more in a
    MuJoCo step at the default --dt, and its contacts are not followed."""
    if not top <= BOUNCE_OMEGA_MAX:
        raise usage_error(f"--omega must be at most {BOUNCE_OMEGA_MAX:g} rad/s with --landing "
                          "bounce (faster, the coin turns a radian a MuJoCo step), got "
                          f"{shown(text.strip())}")


def bounce_launch(psi, psi_dist_text, u, omega):
    """:func:`launch` for a bounce run, whose spin stays within the engine's limit
    (:func:`check_omega`)."""
    u_spec, w_spec, psi_spec, labels = launch(psi, psi_dist_text, u, omega)
    check_omega(reach(w_spec, math.inf), omega or HAND["omega"])
    return u_spec, w_spec, psi_spec, labels
