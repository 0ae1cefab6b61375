"""Speeds and spins with units (coincli.io.grammar.parse_speed_ms, parse_spin_rads) and the commands
that take them: exact factors rounded once, one-line errors naming what is allowed."""

from __future__ import annotations

import csv
import io
import math
from fractions import Fraction

import mpmath
import pytest
from cli_helpers import error as _error
from cli_helpers import ok as _ok

from coincli.io import grammar as parse

SPEEDS = [  # (text, exact value in m/s)
    ("2", Fraction(2)), ("2m/s", Fraction(2)), ("2 m/s", Fraction(2)), ("240cm/s", Fraction(12, 5)),
    ("2400mm/s", Fraction(12, 5)), ("8.6km/h", Fraction(86, 36)), ("8.6 KM/H", Fraction(86, 36)),
    ("8.6kph", Fraction(86, 36)), ("0.0024km/s", Fraction(12, 5)),
    ("7.9ft/s", Fraction(79, 10) * Fraction(3048, 10000)), ("7.9fps", Fraction(79, 10) *
                                                            Fraction(3048, 10000)),
    ("94in/s", 94 * Fraction(254, 10000)), ("5.4mph", Fraction(54, 10) * Fraction(44704, 100000)),
    ("0", Fraction(0)), ("1e-300cm/s", Fraction(1, 10**302)), ("+3", Fraction(3)),
]


@pytest.mark.parametrize("text, exact", SPEEDS)
def test_speeds_are_the_exact_value_rounded_once(text, exact):
    assert parse.parse_speed_ms(text) == float(exact)


SPINS = [  # (text, exact value in rad/s as a multiple of pi, or a plain number)
    ("40", None, 40.0), ("40rad/s", None, 40.0), ("38rev/s", Fraction(76), None),
    ("38Hz", Fraction(76), None), ("38 rps", Fraction(76), None),
    ("2300rpm", Fraction(2300 * 2, 60), None), ("2300rev/min", Fraction(2300 * 2, 60), None),
    ("13700deg/s", Fraction(13700, 180), None), ("360°/s", Fraction(2), None),
    ("1e-300rev/s", Fraction(2, 10**300), None),
]


@pytest.mark.parametrize("text, pi_multiple, plain", SPINS)
def test_spins_are_the_exact_value_rounded_once(text, pi_multiple, plain):
    got = parse.parse_spin_rads(text)
    if plain is not None:
        assert got == plain
        return
    with mpmath.workdps(60):
        exact = mpmath.mpf(pi_multiple.numerator) / pi_multiple.denominator * mpmath.pi
        assert got == float(exact)  # correctly rounded (mpf -> float rounds to nearest)


@pytest.mark.parametrize("fn, text, words", [
    (parse.parse_speed_ms, "-1", ["finite speed >= 0", "m/s (the default)", "km/h", "'-1'"]),
    (parse.parse_speed_ms, "2furlongs/s", ["must be a speed like", "cm/s", "'2furlongs/s'"]),
    (parse.parse_speed_ms, "nan", ["must be a speed like"]),
    (parse.parse_speed_ms, "inf", ["must be a speed like"]),
    (parse.parse_speed_ms, "1e308km/s", ["finite speed"]),
    (parse.parse_speed_ms, "m/s", ["must be a speed like"]),
    (parse.parse_spin_rads, "-38rev/s", ["finite spin rate >= 0", "rpm", "'-38rev/s'"]),
    (parse.parse_spin_rads, "38 rev", ["must be a spin rate like", "rev/s (= Hz)"]),
    (parse.parse_spin_rads, "1e308rev/s", ["finite spin rate"]),
])
def test_bad_units_say_what_is_allowed_in_one_line(fn, text, words):
    with pytest.raises(ValueError) as e:
        fn(text, "--x")
    msg = str(e.value)
    assert "\n" not in msg and msg.startswith("--x must be")
    for w in words:
        assert w in msg, (w, msg)


def test_commands_take_units_and_print_si_with_the_unit(coin):
    out = _ok(coin("toss", "--xi", "0.577", "--psi", "90", "--u", "240cm/s", "--omega",
                   "38:40:1rev/s", "-f", "csv"))
    rows = list(csv.DictReader(io.StringIO(out)))
    assert [float(r["u"]) for r in rows] == [2.4] * 3
    assert [float(r["omega"]) for r in rows] == [parse.parse_spin_rads(f"{k}rev/s")
                                                 for k in (38, 39, 40)]
    human = _ok(coin("toss", "--xi", "0.577", "--psi", "90", "--u", "8.64km/h", "--omega",
                     "2300rpm"))
    assert "u (m/s)          2.4" in human and "omega (rad/s)" in human
    assert "Typed u = 8.64km/h, omega = 2300rpm; shown in m/s and rad/s." in human
    # a distribution with one unit at its end: the same tosses as in SI
    si = _ok(coin("simulate", "--xi", "0.577", "-n", "2000", "--seed", "3", "--u",
                  "normal:2.4:0.3", "--omega", f"normal:{2 * math.pi * 38!r}:{2 * math.pi * 4!r}",
                  "-f", "csv"))
    with_units = _ok(coin("simulate", "--xi", "0.577", "-n", "2000", "--seed", "3", "--u",
                          "normal:240:30cm/s", "--omega", "normal:38:4rev/s", "-f", "csv"))
    assert [r.split(",")[1] for r in si.splitlines()] == \
        [r.split(",")[1] for r in with_units.splitlines()]
    phase = _ok(coin("phase", "--u", "0:300cm/s", "--omega", "0:10rev/s", "--cols", "4",
                     "--rows", "3", "-f", "csv"))
    us = sorted({float(r["u"]) for r in csv.DictReader(io.StringIO(phase))})
    assert us == [0.375, 1.125, 1.875, 2.625]


def test_command_unit_errors_are_one_line(coin):
    _error(coin("toss", "--xi", "0.5", "--u", "2furlongs/s"), 2, "--u must be a speed like")
    _error(coin("simulate", "--xi", "0.5", "--omega", "normal:38rev/s:4"), 2,
           "--omega: give the unit once at the end")
    _error(coin("phase", "--u", "0:3furlongs/s"), 2, "--u must be LOW:HIGH")
    _error(coin("toss", "--xi", "0.5", "--u", "1e9m/s"), 2, "at most 1e+08 m/s")


@pytest.mark.parametrize("fn, text", [
    (parse.parse_number, "1e-400"), (parse.parse_probability, "1e-400"),
    (parse.parse_probability, "1e-400%"), (parse.parse_probability, "1/1e400"),
    (parse.parse_ratio, "1e-400"), (parse.parse_ratio, "3/1e999"),
    (parse.parse_speed_ms, "2e-400cm/s"), (parse.parse_spin_rads, "1e-330rev/s"),
])
def test_a_nonzero_number_that_underflows_is_refused(fn, text):
    with pytest.raises(ValueError, match="nonzero but below the smallest positive double"):
        fn(text)


@pytest.mark.parametrize("fn, text", [
    (parse.parse_number, "0e-400"), (parse.parse_probability, "0.000e-5"),
    (parse.parse_ratio, "0/7"), (parse.parse_speed_ms, "-0.0"), (parse.parse_spin_rads, "0rpm"),
])
def test_zero_typed_is_zero(fn, text):
    assert fn(text) == 0.0


def test_underflow_is_refused_by_the_commands_and_on_stdin(coin):
    _error(coin("design", "-p", "1e-400", "-q"), 2, "--p-sides", "smallest positive double")
    _error(coin("table", "--xi", "1/1e400", "-q"), 2, "--xi", "smallest positive double")
    _error(coin("toss", "--xi", "0.5", "--u", "1e-400", "--omega", "40", "--psi", "90"), 2,
           "--u", "smallest positive double")
    big = "\n".join(["0.3"] * 70000 + ["1e-400"]) + "\n"  # the fast stdin path
    _error(coin("design", "-p", "-", "-q", stdin=big), 2, "stdin line 70001", "smallest positive")
    assert _ok(coin("design", "-p", "5e-324", "-q")).strip() != "0.0"
