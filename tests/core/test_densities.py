"""Degenerate psi densities (issue 13): every density ``coin`` accepts gives finite chances in
[0, 1] with no warning, and every one it cannot compute is refused up front with one line
naming --psi-dist and what is allowed.  The class: subnormal and huge sds, means far outside
[0, 180], weights from 1e-320 to 1e308, duplicate and too-close psi points, all-zero weights,
points at exactly 0 and 180, flat (huge-sd) normals.  Hypothesis explores it; the issue's own
examples run through the command line, once with ``PYTHONWARNINGS=error`` in a subprocess.
"""

from __future__ import annotations

import math
import os
import subprocess
import sys
import warnings

import mpmath
import numpy as np
import pytest
from cli_helpers import error, ok
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from coincli.core.averages import marginal, marginal_inverse
from coincli.core.densities import MIN_TABLE_SPAN, Normal, Table, _relative_mass

EXAMPLES = int(os.environ.get("COIN_FUZZ_EXAMPLES", "60"))
DEGENERATE = settings(max_examples=EXAMPLES, deadline=None, derandomize=True,
                      suppress_health_check=[HealthCheck.too_slow])
XIS = [0.0, 5e-324, 1e-300, 1e-8, 0.5, 1 / math.sqrt(3), 3.0, 1e8, 1e300, 1.7976931348623157e308,
       math.inf]
#: what a refusal may say (each names what is allowed)
REFUSALS = ("must be", "must not all be zero", "must spread over at least", "strictly increasing",
            "at least two", "finite numbers only")


def _check_chances(density):
    """Scalar and array paths: finite, in [0, 1], summing to 1, no warning of any kind."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        arr = np.array(marginal(np.array(XIS), density))
        for k, x in enumerate(XIS):
            one = marginal(x, density)
            for v in one:
                assert isinstance(v, float) and 0.0 <= v <= 1.0, (density.spec, x, one)
            assert abs(sum(one) - 1.0) <= 4.5e-16, (density.spec, x, one)
            assert np.allclose(arr[:, k], one, rtol=1e-12, atol=1e-300), (x, arr[:, k], one)
        assert np.isfinite(arr).all()


# --------------------------------------------------------------------------- normals


finite_angle = st.floats(min_value=-1e306, max_value=1e306, allow_nan=False)
any_sd = st.one_of(st.floats(min_value=5e-324, max_value=1e-290),
                   st.floats(min_value=1e-290, max_value=1e306),
                   st.sampled_from([5e-324, 1e-320, 2.0**-1022, 1e-160, 1e-20, 1e300, 1e306]))
special_mean = st.sampled_from([0.0, 5e-324, 1e-320, 1e-300, math.pi / 2, math.pi,
                                math.nextafter(math.pi, 0.0), -1e-300, -1e306, 1e306, -3.0, 5.0])


@DEGENERATE
@given(mean=st.one_of(finite_angle, special_mean), sd=any_sd)
def test_every_normal_gives_finite_chances(mean, sd):
    d = Normal(mean, sd)
    _check_chances(d)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        pdf = d.pdf(np.linspace(0.0, math.pi, 7))
        assert not np.isnan(pdf).any() and (pdf >= 0).all()
        try:
            x = marginal_inverse(0.3, d)
        except ValueError as exc:
            assert "not reachable" in str(exc) or "only p_sides = 0" in str(exc)
        else:
            assert 0 < x < math.inf


@pytest.mark.parametrize("mean, sd", [
    (math.pi / 2, 0.7), (0.0, 0.1), (1.0, 1e3), (1.0, 1e300), (-0.5, 0.2), (-10.0, 1.0),
    (-100.0, 1.0), (-1e3, 10.0), (-1.0, 100.0), (4.0, 0.1), (-1e-3, 1e-4), (-0.1, 1e300)])
def test_normal_normalizer_against_mpmath(mean, sd):
    """The mass relative to the peak, int exp(-((x - m)^2 - (peak - m)^2)/(2 sd^2)) dx / sd,
    to 3 ulps: means inside and far outside, flat and narrow."""
    with mpmath.workdps(40):
        m, s = mpmath.mpf(mean), mpmath.mpf(sd)
        peak = min(max(m, 0), mpmath.pi)
        f = lambda x: mpmath.exp(-((x - m) ** 2 - (peak - m) ** 2) / (2 * s * s))  # noqa: E731
        w = s * min(1, s / max(-m, m - mpmath.pi)) if not 0 <= m <= mpmath.pi else s
        pts = sorted({mpmath.mpf(0), mpmath.pi, *[min(max(peak + k * w, 0), mpmath.pi)
                                                  for k in (-40, -8, -2, 0, 2, 8, 40)]})
        ref = mpmath.quad(f, pts) / s
        assert abs(_relative_mass(mean, sd) - ref) <= 3 * 2.0**-52 * ref, (mean, sd)


def test_normal_pdf_integrates_to_one():
    for mean, sd in ((math.pi / 2, 0.7), (0.0, 1e-3), (-0.2, 0.05), (1.0, 1e6)):
        d = Normal(mean, sd)
        x = np.linspace(0.0, math.pi, 2_000_001)
        y = d.pdf(x)
        assert abs(np.sum((y[1:] + y[:-1]) / 2 * np.diff(x)) - 1.0) < 1e-6, (mean, sd)


def test_subnormal_and_flat_normals_have_their_limits():
    """sd -> 0 at psi = 0: heads always (the mass never reaches theta0/2 >= 2.8e-309);
    sd -> inf: the uniform density; a mean 1e306 rad below 0: a delta at psi = 0."""
    from coincli.core.densities import Uniform

    for sd in (5e-324, 1e-320, 1e-310):
        for x in (0.5, 1e300, 1.7976931348623157e308):
            got = marginal(x, Normal(0.0, sd))
            if sd == 1e-310 and x > 1e300:  # theta0/2 = 2.8e-309 is 28 sd: a tail of 1e-171
                assert got.tails == 0 and 1e-172 < got.sides < 1e-170
            else:
                assert got == (1.0, 0.0, 0.0)
    flat = np.array(marginal(np.array([0.1, 0.5, 3.0]), Normal(1.0, 1e300)))
    uni = np.array(marginal(np.array([0.1, 0.5, 3.0]), Uniform()))
    assert np.allclose(flat, uni, rtol=1e-14, atol=0)
    assert marginal(0.5, Normal(-1e306, 1.0)) == (1.0, 0.0, 0.0)


# --------------------------------------------------------------------------- tables


weights = st.one_of(st.floats(min_value=0.0, max_value=1.7e308),
                    st.sampled_from([0.0, 5e-324, 1e-320, 1e-300, 1.0, 1e300, 1e308]))


@DEGENERATE
@given(psi=st.lists(st.one_of(st.floats(min_value=0.0, max_value=math.pi),
                              st.sampled_from([0.0, 5e-324, 1e-320, 1e-300, math.pi])),
                    min_size=2, max_size=12),
       w=st.lists(weights, min_size=12, max_size=12))
def test_every_table_gives_finite_chances_or_a_refusal(psi, w):
    psi = sorted(psi)
    try:
        d = Table(psi, w[:len(psi)])
    except ValueError as exc:
        assert any(r in str(exc) for r in REFUSALS), exc
        return
    _check_chances(d)


def test_tables_at_the_edges():
    # weights of 1e308 (their area overflowed) and 1e-320 (subnormal): the same as weights 1
    one = marginal(0.5, Table([0.0, 1.0, math.pi], [1.0, 1.0, 1.0]))
    for big in (1e308, 1.7976931348623157e308, 1e-320, 5e-324):
        assert marginal(0.5, Table([0.0, 1.0, math.pi], [big] * 3)) == pytest.approx(one, 1e-15)
    with pytest.raises(ValueError, match="strictly increasing"):
        Table([0.0, 0.5, 0.5, 1.0], [1, 1, 1, 1])
    with pytest.raises(ValueError, match="must not all be zero"):
        Table([0.0, 1.0], [0.0, 0.0])
    with pytest.raises(ValueError, match="must spread over at least"):
        Table([0.0, 1e-320], [1.0, 1.0])
    assert Table([0.0, 1e-290], [1.0, 1.0]).w.max() < 1e300  # the narrowest allowed
    assert MIN_TABLE_SPAN == 2.0**-1000


# --------------------------------------------------------------------------- the command line


def test_the_issues_examples(coin, tmp_path):
    t = tmp_path / "t.tab"
    t.write_text("0,1\n1e-320,1\n")
    error(coin("table", "--xi", "0.5", "--psi-dist", f"table:{t}"), 2, "--psi-dist",
          "must spread over at least", "--psi")
    big = tmp_path / "big.tab"
    big.write_text("0,1e308\n90,1e308\n180,1e308\n")
    out = ok(coin("table", "--xi", "0.5", "--psi-dist", f"table:{big}", "-f", "csv"))
    assert "nan" not in out and "inf" not in out
    for cmd in (("table", "--xi", "0.5"), ("stack", "--coin", "quarter", "--count", "3"),
                ("simulate", "-n", "200", "--seed", "1", "--xi", "0.5", "--u", "2.4",
                 "--omega", "38")):
        out = ok(coin(*cmd, "--psi-dist", "normal:0:1e-320", "-f", "csv"))
        assert "nan" not in out.lower()
    for cmd in (("design", "-p", "0.3"), ("fair",)):
        rc, out, err = coin(*cmd, "--psi-dist", "normal:1e-320:1e-320")
        assert rc == 1 and out == "" and err.count("\n") == 1 and "solver" not in err, err
        assert "not reachable" in err or "reaches" in err, err
    dup = tmp_path / "dup.tab"
    dup.write_text("30,1\n30,2\n90,1\n")
    error(coin("table", "--xi", "0.5", "--psi-dist", f"table:{dup}"), 2, "--psi-dist",
          "line 2", "strictly increasing")


@pytest.mark.parametrize("args", [
    ["table", "--xi", "0.5", "--psi-dist", "normal:0:1e-320"],
    ["table", "--xi", "0.5", "--psi-dist", "normal:90:1e308", "--method", "mc", "--tol", "0.02",
     "--seed", "1"],
    ["design", "-p", "0.3", "--psi-dist", "normal:-1000:10"],
    ["simulate", "-n", "100", "--seed", "1", "--xi", "0.5", "--u", "2.4", "--omega", "38",
     "--psi-dist", "normal:-1e300:1"],
])
def test_no_warning_escapes_under_pythonwarnings_error(args):
    env = dict(os.environ, PYTHONWARNINGS="error")
    r = subprocess.run([sys.executable, "-m", "coincli", *args], capture_output=True, text=True,
                       env=env, timeout=120)
    assert r.returncode in (0, 1), r.stderr
    assert r.stderr == "" or (r.returncode == 1 and r.stderr.count("\n") == 1), r.stderr
    assert "nan" not in r.stdout.lower()


# --------------------------------------------------------------------------- big tables


def test_a_big_tables_work_is_bounded(coin, tmp_path):
    """Every table point is a breakpoint (exact between them), so points x xi values are capped
    (averages.MAX_TABLE_WORK): within the cap the run completes, beyond it one line says how
    many values fit.  The timing is in benchmarks/bench_core.py, not here."""
    from coincli.core.averages import MAX_TABLE_WORK

    n = 20_000
    rng = np.random.default_rng(5)
    t = tmp_path / "big.tab"
    t.write_text("".join(f"{float(x)!r},{float(w)!r}\n" for x, w in zip(
        np.linspace(0, 180, n), rng.random(n), strict=True)))
    fits = MAX_TABLE_WORK // n
    out = ok(coin("table", "--xi", f"0.1:3:{2.9 / 40!r}", "--psi-dist", f"table:{t}", "-q"))
    assert len(out.splitlines()) >= 40
    many = 2 * fits
    error(coin("table", "--xi", f"0.1:3:{2.9 / many!r}", "--psi-dist", f"table:{t}"), 1,
          "--psi-dist", "at most", "xi values")
    error(coin("design", "-p", "0.1:0.9:0.001", "--psi-dist", f"table:{t}"), 1, "--psi-dist",
          "targets")


def test_fewer_nodes_on_a_tables_short_subintervals_change_nothing():
    """The per-subinterval node counts of a table with thousands of points agree with 16 nodes
    everywhere, and with 32, to the rounding of such a table's steep segments (1e-14)."""

    rng = np.random.default_rng(9)
    d = Table(np.linspace(0.0, math.pi, 5000), rng.random(5000))
    xs = np.concatenate([np.geomspace(1e-6, 1e6, 9), [0.3, 1 / math.sqrt(3), 2.0]])
    few = np.array(marginal(xs, d))
    full = np.array(marginal(xs, d, order=32))
    assert np.abs(few - full).max() <= 1e-14


@pytest.mark.parametrize("text, words", [
    ("30,1\n30,2\n90,1\n", ("line 2", "does not exceed", "strictly increasing")),
    ("30,1\n20,2\n90,1\n", ("line 2", "does not exceed")),
    ("0,1\n181,2\n", ("line 2", "outside [0, 180] degrees")),
    ("0,1\nnan,2\n", ("line 2", "outside [0, 180]")),
    ("0,1\n30,-2\n", ("line 2", "weight '-2'", ">= 0")),
    ("0,1\n30,1e999\n", ("line 2", "finite")),
    ("0,0\n90,0\n", ("must not all be zero",)),
    ("0,1\n1e-320,1\n", ("must spread over at least", "5e-300 deg")),
])
def test_table_files_are_refused_by_line(coin, tmp_path, text, words):
    t = tmp_path / "t.tab"
    t.write_text(text)
    error(coin("table", "--xi", "0.5", "--psi-dist", f"table:{t}"), 2, "--psi-dist", *words)

