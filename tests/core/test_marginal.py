"""coincli.core.averages: Table II, the mpmath reference over 600 decades of xi, the calibrated error
of every order, the vectorized path, and the invariants.  No timing here (benchmarks/)."""

from __future__ import annotations

import math
import random

import marginal_reference as ref  # tests/ is on sys.path under pytest
import mpmath
import numpy as np
import pytest

from coincli.core import averages as mg
from coincli.core import models
from coincli.core.averages import error_bound, marginal, order_for_tol
from coincli.core.densities import Cosine, Normal, Table, Uniform

XI_FAIR = 1 / math.sqrt(3)
REFERENCE = ref.load()
PAPER = ("uniform", "cosine", "normal", "normal:90:18.12")


# --------------------------------------------------------------------------- the paper


@pytest.mark.parametrize(
    "density, printed",
    [(Uniform(), (0.630, 0.281, 0.088)), (Cosine(), (0.439, 0.396, 0.165)),
     (Normal(), (0.478, 0.371, 0.150))],
)
def test_table_ii_to_every_printed_digit(density, printed):
    # every order from the one --tol 1e-3 picks to the default rounds to the printed table
    for order in (order_for_tol(1e-3), 8, mg.DEFAULT_ORDER):
        got = marginal(XI_FAIR, density, order=order)
        assert tuple(round(v, 3) for v in got) == printed, order
    exact = [float(v) for v in _reference("uniform" if isinstance(density, Uniform) else
                                          "cosine" if isinstance(density, Cosine) else "normal",
                                          XI_FAIR)]
    assert tuple(round(v, 3) for v in exact) == printed  # the paper's rounding, to the digit


def test_problem_2_curve_is_slightly_above_the_dynamic_one():
    """Problem 2: psi normal about pi/2 with variance 0.1 lifts P(sides) above eq. (12), for
    every xi of `coin table --xi 0.1:2:0.1` (by 0.009 to 0.078: slightly)."""
    xi = np.round(np.arange(1, 21) * 0.1, 10)
    p2 = marginal(xi, Normal(math.pi / 2, math.sqrt(0.1))).sides
    dyn = models.dynamic(xi).sides
    lift = p2 - dyn
    assert (lift > 0).all()
    assert 0.005 < lift.min() and lift.max() < 0.1


def _reference(label, xi):
    for lab, x, _, vals in REFERENCE:
        if lab == label and x == xi:
            return vals
    raise KeyError((label, xi))


# --------------------------------------------------------------------------- mpmath reference


def test_reference_file_covers_600_decades_and_the_stress_densities():
    xis = {x for _, x, _, _ in REFERENCE}
    assert min(x for x in xis if x > 0) <= 1e-300 and max(xis) >= 1e300 and 0.0 in xis
    labels = {lab for lab, _, _, _ in REFERENCE}
    assert set(PAPER) <= labels and len(labels) >= 12


def test_paper_densities_to_a_few_ulps_over_600_decades():
    """Relative error of every chance that is a normal double, xi from 0 and 1e-300 to 1e300."""
    worst = 0.0
    for label, xi, d, vals in REFERENCE:
        if label not in PAPER:
            continue
        got = marginal(xi, d)
        for g, r in zip(got, vals, strict=True):
            if r < 2.3e-308:  # underflows (tails of a coin 1e300 thick is ~1e-600)
                assert g <= 1e-300
                continue
            worst = max(worst, float(abs(g - r) / r))
    assert worst < 4e-15, worst


@pytest.mark.parametrize("order", [2, 3, 4, 5, 6, 8, 10, 11, 12, 13, 16])
def test_every_order_within_its_calibrated_bound(order):
    """The bound --tol relies on, against mpmath for all stored cases (narrow normals on the
    regime boundaries, means at 0 and pi and outside, sd 1e3, a table, xi 1e-300 to 1e300)."""
    for label, xi, d, vals in REFERENCE:
        got = marginal(xi, d, order=order)
        bound = error_bound(order, d)
        for g, r in zip(got, vals, strict=True):
            assert abs(g - float(r)) <= bound, (label, xi, order, g, float(r), bound)


@pytest.mark.slow
def test_reference_file_is_what_the_reference_code_computes():
    """Recompute two stored cases live, so the file cannot drift from marginal_reference.py."""
    for label, xi in (("normal", XI_FAIR), ("normal sd 1e-4 at 60 deg (boundary)", 3.0)):
        d = next(dd for lab, x, dd, _ in REFERENCE if lab == label and x == xi)
        live, err = ref.ref_marginal(xi, d)
        assert err < 1e-38
        with mpmath.workdps(50):
            for a, b in zip(live, _reference(label, xi), strict=True):
                assert abs(a - b) <= 1e-38 * abs(b)


def test_reference_integrand_matches_the_textbook_table_i():
    rng = random.Random(4)
    pts = [(10 ** rng.uniform(-3, 3), rng.uniform(0, math.pi / 2)) for _ in range(60)]
    pts += [(XI_FAIR, math.pi / 2), (0.1, 1.0), (10.0, 1.5)]
    assert ref.check_identities(pts) < 1e-70


# --------------------------------------------------------------------------- order and tol


def test_order_for_tol_is_monotone_and_bounded():
    tols = [0.5, 0.1, 1e-2, 1e-3, 1e-4, 1e-6, 1e-8, 1e-10, 1e-12, 1e-13, 1e-14, 1e-16]
    orders = [order_for_tol(t) for t in tols]
    assert orders == sorted(orders)
    assert orders[0] == mg.MIN_ORDER and orders[-1] == mg.DEFAULT_ORDER
    for t in tols[:-3]:
        assert error_bound(order_for_tol(t)) <= t


@pytest.mark.parametrize("bad", [0, 1, 65, 16.0, True, "16", None])
def test_bad_order_names_the_argument_and_range(bad):
    with pytest.raises(ValueError, match=r"order must be an integer in \[2, 64\]"):
        marginal(0.5, Uniform(), order=bad)


@pytest.mark.parametrize("bad", [0.0, -1e-3, float("nan"), True, "1e-3"])
def test_bad_tol_names_the_argument(bad):
    with pytest.raises(ValueError, match="tol must be a number > 0"):
        order_for_tol(bad)


def test_bad_density_is_a_value_error():
    with pytest.raises(ValueError, match="density must be a coincli.core.densities.Density"):
        marginal(0.5, "normal")


# --------------------------------------------------------------------------- vectorized


def test_array_matches_scalar_path_to_rounding():
    xs = np.concatenate([np.geomspace(1e-300, 1e300, 61), [0.0, XI_FAIR, math.inf]])
    for d in (Uniform(), Normal(1.0, 1e-3), Table([0, 1, 2, 3], [0, 1, 3, 0])):
        arr = np.array(marginal(xs, d))
        one = np.array([list(marginal(float(x), d)) for x in xs]).T
        assert np.allclose(arr, one, rtol=2e-15, atol=1e-300)


def test_shapes_duplicates_and_chunks(monkeypatch):
    xs = np.array([[0.1, 0.5, 0.1], [2.0, math.inf, 0.5]])
    o = marginal(xs, Normal())
    assert o.sides.shape == (2, 3) and o.sides[0, 0] == o.sides[0, 2] and o.sides[1, 1] == 1.0
    flat = np.geomspace(1e-3, 1e3, 300)
    whole = np.array(marginal(flat, Cosine()))
    monkeypatch.setattr(mg, "_CHUNK", 64 * 7)  # a few xi per pass
    monkeypatch.setattr(mg, "_BLOCK", 16 * 5)  # five subintervals per numpy pass
    assert np.array_equal(np.array(marginal(flat, Cosine())), whole) or np.allclose(
        np.array(marginal(flat, Cosine())), whole, rtol=1e-15, atol=0)


def test_invariants_over_600_decades():
    xs = np.geomspace(1e-300, 1e300, 601)
    for d in (Uniform(), Cosine(), Normal(), Normal(math.pi / 2, 1e-6), Normal(0.0, 0.2),
              Normal(-0.5, 0.2), Table([0.0, 0.3, 0.9, 1.6, 2.2, math.pi],
                                       [0.0, 1.0, 0.5, 2.0, 0.25, 0.0])):
        h, s, t = (np.asarray(v) for v in marginal(xs, d))
        for v in (h, s, t):
            assert ((v >= 0) & (v <= 1)).all()
        assert np.abs(h + s + t - 1).max() <= 2.3e-16
        assert (np.diff(s) >= -1e-15).all()  # sides grows with thickness (to rounding)


def test_narrow_normal_tends_to_table_i_at_its_mean():
    """O(sd^2) off the regime boundaries, O(sqrt(sd)) on one (where Table I has a square-root
    kink: psi = pi/3 is the boundary pi/2 - theta0/2 of the fair coin)."""
    for psi in (0.3, 1.0, math.pi / 3, 1.4, math.pi / 2, 2.5):
        for xi in (0.1, XI_FAIR, 3.0):
            cond = models.conditional(xi, psi)
            t = models.theta0(xi) / 2
            edge = min(abs(psi - t), abs(psi - (math.pi / 2 - t)), abs(psi - (math.pi / 2 + t)),
                       abs(psi - (math.pi - t)))
            for sd in (1e-5, 1e-7):
                got = marginal(xi, Normal(psi, sd))
                bound = math.sqrt(sd) if edge < 1e-12 else 100 * sd * sd + 3e-14
                for g, c in zip(got, cond, strict=True):
                    assert abs(g - c) <= bound, (psi, xi, sd, g, c)
    # too narrow for any quadrature (mean +- sd/2 rounds to the mean): Table I itself
    assert marginal(0.5, Normal(1.0, 1e-300)) == models.conditional(0.5, 1.0)


def test_a_normal_too_narrow_to_square_its_sd_scales_like_a_wide_one():
    """sd below 1e-154 (sd**2 underflows): the density is evaluated in units of sd.  Far in the
    planar regime (xi > 1e20) Table I depends on psi/theta0 alone, so scaling xi up and sd down
    by the same power of 2 must leave the chances unchanged.  The unscaled case, a half-normal
    at psi = 0 with sd = 1e-20 rad and xi = 1e20 (theta0/2 = sd/2), is checked against
    tests/marginal_reference.py (ref_marginal at 20 digits, 23 s, hence its value here)."""
    ref = (0.61163703519808669, 0.38836296480191331)
    for k in (0, 300, 600, 900):
        got = marginal(1e20 * 2.0**k, Normal(0.0, 1e-20 * 2.0**-k))
        assert got.tails == 0.0
        for g, r in zip(got[:2], ref, strict=True):
            assert abs(g - r) <= 4e-15 * r, (k, got)


def test_narrow_normals_at_the_poles_never_give_nan_or_warnings(recwarn):
    for sd in (1e-150, 1e-160, 1e-300, 5e-324):
        for mean in (0.0, 1e-300, math.pi):
            d = Normal(mean, sd)
            for xi in (0.0, 1e-320, 0.5, 3.0, 1e300):
                o = marginal(xi, d)
                assert all(0.0 <= v <= 1.0 for v in o), (sd, mean, xi, o)
                assert abs(sum(o) - 1.0) <= 4e-16, (sd, mean, xi, o)
            arr = marginal(np.array([0.0, 1e-320, 0.5, 3.0, 1e300]), d)
            assert np.isfinite(np.array(arr)).all()
    assert not [w for w in recwarn if issubclass(w.category, RuntimeWarning)]


@pytest.mark.parametrize("spec", ["normal:90:10", "normal:90:18.12", "normal:45:5", "normal:60:0.1",
                                  "normal:30:0.05", "normal:0:6", "normal:170:3", "uniform:10:80"])
def test_scalar_path_finite_and_equal_to_the_array_path(spec):
    """One xi at a time and many at once give the same finite chances (the scalar path once
    built a NaN breakpoint where a far-tail offset passed the end of its piece: xi = 0.05 with
    normal:90:10 printed nan)."""
    from coincli.io.grammar import parse_density

    d = parse_density(spec)
    xs = np.concatenate([np.geomspace(1e-3, 1e3, 121), [0.05, 0.0725, 1 / math.sqrt(3)]])
    many = marginal(xs, d)
    for i, x in enumerate(xs.tolist()):
        one = marginal(x, d)
        for got, arr in zip(one, many, strict=True):
            assert math.isfinite(got) and 0.0 <= got <= 1.0, (spec, x, one)
            assert got == pytest.approx(float(arr[i]), rel=1e-13, abs=1e-16), (spec, x)


@pytest.mark.parametrize("n", [2, 3, 5, 8, 16, 17, 33, 64])
def test_gauss_legendre_rule_against_mpmath(n):
    """The rule of coincli.core._numerics.quadrature (its own Newton on P_n, no numpy.polynomial) against 40-digit
    roots of P_n: nodes on [0, 1] within one 2^-53, weights within 2e-13 relative."""
    import mpmath

    from coincli.core._numerics.quadrature import gauss_legendre

    x, w = gauss_legendre(n)
    assert x.shape == w.shape == (n,)
    assert np.all(np.diff(x) > 0) and np.all(w > 0)
    with mpmath.workdps(40):
        for xv, wv in zip(x, w):
            r = mpmath.findroot(lambda s: mpmath.legendre(n, s), 2 * mpmath.mpf(float(xv)) - 1)
            d = mpmath.diff(lambda s: mpmath.legendre(n, s), r)
            assert abs(mpmath.mpf(float(xv)) - (r + 1) / 2) <= 2.0**-53
            w_ref = 1 / ((1 - r * r) * d * d)
            assert abs(mpmath.mpf(float(wv)) - w_ref) <= 2e-13 * w_ref
    # the rule integrates polynomials of degree 2n - 1 exactly: x^(2n-1) over [0, 1] is 1/(2n)
    assert abs(float(np.sum(w * x ** (2 * n - 1))) - 1 / (2 * n)) <= 1e-14
