"""Accuracy of the closed forms in coincli.core.models against 50-digit mpmath (tests/reference.py).

Error is measured in ulps of the reference value: ``|computed - ref| / ulp(ref)`` (ulp of a
subnormal is 2**-1074; where the reference is exactly 0 or inf the computed value must be too).
The bar, from the issue: 4 ulps on every output of every closed form, on the scalar (math) path
and on the numpy path, everywhere on the grids of ``reference.py`` -- including psi at 1e-12,
1e-9, 1e-6 (relative and absolute) and at 1e-4 .. 0.49 theta0/2 from each of the four regime
boundaries of Table I, and the doubles adjacent to each boundary (whose offset to it can be as
small as ~1e-18 of theta0/2).  The worst error per function and output, and where it occurred,
is printed in the terminal summary ("accuracy (ulps vs mpmath)").

The two paths run the same formula; numpy's SIMD atan/atan2/asin/tan/hypot round differently
from libm by an ulp now and then, so bit-for-bit agreement is checked with numpy's elementary
functions replaced by libm's (test_paths_agree_bit_for_bit_given_the_same_libm), and the
disagreement with numpy's own is measured and reported.
"""

from __future__ import annotations

import functools
import math

import mpmath
import numpy as np
import pytest
from reference import (
    conditional_cases,
    p_grid,
    ref_boundaries,
    ref_conditional,
    ref_dynamic,
    ref_dynamic_inverse,
    ref_geometric,
    ref_geometric_inverse,
    ulp_error,
    xi_grid,
)

from coincli.core import models

BAR = 4.0  #: ulps, every output of every closed form
SECTION = "accuracy (ulps vs mpmath)"
OUTPUTS = ("heads", "sides", "tails")


# --------------------------------------------------------------------------- cases and references


@functools.cache
def _xis():
    return tuple(xi_grid())


@functools.cache
def _ps():
    return tuple(p_grid())


@functools.cache
def _cond_cases():
    return tuple(conditional_cases())


@functools.cache
def _refs(name):
    """Reference values for a function's grid, as tuples of mpf (one per output)."""
    if name == "geometric":
        return tuple(ref_geometric(x) for x in _xis())
    if name == "dynamic":
        return tuple(ref_dynamic(x) for x in _xis())
    if name == "geometric_inverse":
        return tuple((ref_geometric_inverse(p),) for p in _ps())
    if name == "dynamic_inverse":
        return tuple((ref_dynamic_inverse(p),) for p in _ps())
    if name == "conditional":
        return tuple(ref_conditional(x, p) for x, p, _ in _cond_cases())
    raise KeyError(name)


def _inputs(name):
    """Tuple of argument tuples for a function's grid."""
    if name in ("geometric", "dynamic"):
        return tuple((x,) for x in _xis())
    if name in ("geometric_inverse", "dynamic_inverse"):
        return tuple((p,) for p in _ps())
    return tuple((x, p) for x, p, _ in _cond_cases())


def _held_to_bar(name):
    """Indices of the grid held to the 4-ulp bar: all of it."""
    return range(len(_inputs(name)))


def _scalar_outputs(name):
    f = getattr(models, name)
    rows = []
    for args in _inputs(name):
        v = f(*args)
        rows.append(tuple(v) if isinstance(v, tuple) else (v,))
    return rows


def _array_outputs(name):
    f = getattr(models, name)
    cols = [np.array(c, dtype=float) for c in zip(*_inputs(name), strict=True)]
    v = f(*cols)
    v = tuple(v) if isinstance(v, tuple) else (v,)
    return [tuple(float(c[i]) for c in v) for i in range(len(cols[0]))]


def _labels(name):
    return OUTPUTS if name in ("geometric", "dynamic", "conditional") else ("xi",)


def _worst(name, outputs):
    """Per output: (max error, its input, mean error) and the list of failures over the bar."""
    worst, fails = [], []
    refs = _refs(name)
    idx = _held_to_bar(name)
    for k, label in enumerate(_labels(name)):
        errs = {j: ulp_error(outputs[j][k], refs[j][k]) for j in idx}
        i = max(errs, key=errs.__getitem__)
        worst.append((label, errs[i], _inputs(name)[i], sum(errs.values()) / len(errs)))
        fails += [(label, e, _inputs(name)[j], outputs[j][k], float(refs[j][k]))
                  for j, e in errs.items() if e > BAR]
    return worst, fails


FUNCTIONS = ["geometric", "dynamic", "conditional", "geometric_inverse", "dynamic_inverse"]


def _no_band(xp, t, u1, u2):
    return np.zeros(np.shape(t), dtype=bool)


# the fast tier checks numpy's path of the closed forms and inverses; the scalar path, the one
# without long double and conditional's grid (tens of seconds of a core a path) are slow
@pytest.mark.parametrize("path", [pytest.param("scalar", marks=pytest.mark.slow), "numpy",
                                  pytest.param("numpy-without-long-double",
                                               marks=pytest.mark.slow)])
@pytest.mark.parametrize("name", [pytest.param(n, marks=pytest.mark.slow) if n == "conditional"
                                  else n for n in FUNCTIONS])
def test_within_4_ulp(name, path, report, monkeypatch):
    """Every output within 4 ulps; the last path is numpy's on a platform where long double is a
    plain double (conditional then takes the double-double path for every near offset, and
    finishes in double)."""
    if path == "numpy-without-long-double":
        if name != "conditional":
            pytest.skip("only conditional uses long double")
        monkeypatch.setattr(models, "_long_double_band", _no_band)
        monkeypatch.setattr(models, "long_double_64", lambda xp: False)
    outputs = _scalar_outputs(name) if path == "scalar" else _array_outputs(name)
    worst, fails = _worst(name, outputs)
    for label, err, where, mean in worst:
        report(SECTION, f"{name:18s} {path:6s} {label:5s} max {err:5.2f}  mean {mean:5.3f}  "
                        f"at {where!r}  ({len(outputs)} inputs)")
    assert not fails, f"{len(fails)} outputs over {BAR} ulps, e.g. {fails[:5]}"


@pytest.mark.slow
def test_conditional_by_region(report):
    """The conditional grid split by kind: boundary neighbourhoods (1e-12..1e-6), interior."""
    outputs = _scalar_outputs("conditional")
    refs = _refs("conditional")
    kinds = [k for _, _, k in _cond_cases()]
    for kind in ("boundary", "interior"):
        idx = [i for i, k in enumerate(kinds) if k == kind]
        errs = [(ulp_error(outputs[i][k], refs[i][k]), OUTPUTS[k], _inputs("conditional")[i])
                for i in idx for k in range(3)]
        err, label, where = max(errs, key=lambda e: e[0])
        report(SECTION, f"conditional {kind:9s} ({len(idx)} psi): max {err:5.2f} ({label}) "
                        f"at {where!r}")
        assert err <= BAR, (kind, err, label, where)


def _relative_offset(xi, psi):
    """|u| / (theta0/2): distance from psi to the nearest regime boundary, exactly (mpmath)."""
    bounds = ref_boundaries(xi)
    t = bounds[0]
    if t == 0:
        return math.inf
    with mpmath.workdps(60):
        return float(min(abs(mpmath.mpf(psi) - b) for b in bounds) / t)


@pytest.mark.parametrize("path", [pytest.param("scalar", marks=pytest.mark.slow), "numpy"])
def test_conditional_at_the_doubles_adjacent_to_a_boundary(path, report):
    """The doubles nearest each boundary: offsets down to ~1e-18 of theta0/2, below what a
    double-double theta0/2 resolves (models._offsets_exact takes over there).  Held to the bar;
    the closest offset on the grid is reported, to show how far in the bar was tested."""
    outputs = _scalar_outputs("conditional") if path == "scalar" else _array_outputs("conditional")
    refs = _refs("conditional")
    worst, closest, fails = (0.0, None), math.inf, []
    for i, (xi, psi, kind) in enumerate(_cond_cases()):
        if kind != "adjacent":
            continue
        closest = min(closest, _relative_offset(xi, psi))
        for k in range(3):
            err = ulp_error(outputs[i][k], refs[i][k])
            worst = max(worst, (err, (xi, psi, OUTPUTS[k])), key=lambda w: w[0])
            if err > BAR:
                fails.append((xi, psi, OUTPUTS[k], err))
    report(SECTION, f"conditional adjacent  {path:6s}: max {worst[0]:.2f} at {worst[1]!r}; "
                    f"closest offset |u|/(theta0/2) = {closest:.2g}")
    assert closest < 1e-16  # the grid does reach past the double-double's resolution
    assert not fails, fails[:5]


def test_exact_values():
    """Values that are exact in the reference come out exact."""
    assert models.conditional(0.3, 0.0) == (1.0, 0.0, 0.0)
    assert models.conditional(math.inf, 0.0) == (1.0, 0.0, 0.0)
    assert models.conditional(math.inf, 1.0) == (0.0, 1.0, 0.0)
    assert models.conditional(math.inf, 2.0**-1074) == (0.0, 1.0, 0.0)
    assert models.conditional(0.0, 1.2).sides == 0.0
    assert models.geometric(0.0) == (0.5, 0.0, 0.5)
    assert models.geometric(math.inf) == (0.0, 1.0, 0.0)
    assert models.dynamic(0.0) == (0.5, 0.0, 0.5)
    assert models.dynamic(math.inf) == (0.0, 1.0, 0.0)
    assert models.geometric_inverse(0.0) == 0.0 and models.geometric_inverse(1.0) == math.inf
    assert models.dynamic_inverse(0.0) == 0.0 and models.dynamic_inverse(1.0) == math.inf


# --------------------------------------------------------------------------- scalar vs numpy


def _libm_ufunc(fn, nin):
    u = np.frompyfunc(fn, nin, 1)
    return lambda *a: np.asarray(u(*a), dtype=float)


_LIBM = {
    "atan": (math.atan, 1), "atan2": (math.atan2, 2), "asin": (math.asin, 1),
    "tan": (math.tan, 1), "hypot": (math.hypot, 2), "sin": (math.sin, 1),
    "cos": (math.cos, 1), "sqrt": (math.sqrt, 1),
}


def _bits(rows):
    return np.array(rows, dtype=float).view(np.uint64)


@pytest.mark.parametrize("name", FUNCTIONS)
def test_paths_agree_bit_for_bit_given_the_same_libm(name, monkeypatch):
    """One formula, two backends: with numpy's elementary functions replaced by libm's (the ones
    the math path calls), the numpy path reproduces the scalar path bit for bit."""
    scalar = _scalar_outputs(name)
    for attr, (fn, nin) in _LIBM.items():
        monkeypatch.setattr(np, attr, _libm_ufunc(fn, nin))
    # the numpy path's long-double shortcut near a boundary and its long-double finish have no
    # math twin: off, as on a platform whose long double is a double (the double-double path
    # and the double formulas the scalar path takes)
    monkeypatch.setattr(models, "_long_double_band", _no_band)
    monkeypatch.setattr(models, "long_double_64", lambda xp: False)
    array = _array_outputs(name)
    monkeypatch.undo()
    same = _bits(scalar) == _bits(array)
    bad = [(_inputs(name)[i], scalar[i], array[i]) for i in np.flatnonzero(~same.all(axis=1))]
    assert not bad, f"{len(bad)} inputs differ, e.g. {bad[:3]}"


@pytest.mark.parametrize("name", FUNCTIONS)
def test_paths_with_numpys_own_functions(name, report):
    """With numpy's SIMD elementary functions the paths may differ; measure by how much (each
    path is held to the 4-ulp bar on its own by test_within_4_ulp)."""
    scalar = np.array(_scalar_outputs(name), dtype=float)
    array = np.array(_array_outputs(name), dtype=float)
    differ = scalar != array
    with np.errstate(invalid="ignore"):  # inf - inf where both are inf (and equal)
        ulps = np.abs(scalar - array) / np.spacing(np.abs(scalar))
    worst = float(ulps[differ].max()) if differ.any() else 0.0
    report("scalar vs numpy path (numpy's own atan/atan2/asin/tan/hypot)",
           f"{name:18s} {int(differ.any(axis=1).sum()):4d} of {len(scalar)} inputs differ, "
           f"by at most {worst:g} ulp")
    assert worst <= 2 * BAR


# --------------------------------------------------------------------------- asymptotics


@pytest.mark.parametrize("model", ["geometric", "dynamic"])
@pytest.mark.parametrize("regime", ["small", "large"])
@pytest.mark.parametrize("order", [1, 2, 3])
def test_asymptotic_sides_converges_at_the_expected_order(model, regime, order, report):
    """The truncation error of asymptotic_sides shrinks like the first omitted term.

    Small xi: the n-term series leaves O(xi**(2n+1)) (both models).  Large xi: the geometric
    series leaves O(xi**-2n), the dynamic (atan) one O(xi**-(2n+1)).  The slope of log error
    against log xi between two points a decade apart must match, and error / xi**k must tend to
    the first omitted coefficient.
    """
    exact = ref_geometric if model == "geometric" else ref_dynamic
    # two xi where the relative truncation error is about 1e-6 and 1e-8: far above roundoff, and
    # xi small (large) enough that the next term changes the ratio by well under 1%
    if regime == "small":
        k = 2 * order + 1
        xs = [10.0 ** (-6 / (k - 1)), 10.0 ** (-8 / (k - 1))]
    else:
        k = 2 * order if model == "geometric" else 2 * order + 1
        xs = [10.0 ** (6 / k), 10.0 ** (8 / k)]
    errs, ratios = [], []
    for x in xs:
        approx = models.asymptotic_sides(x, model=model, regime=regime, order=order)
        e = abs(approx - float(exact(x)[1]))
        errs.append(e)
        ratios.append(e / (x**k if regime == "small" else x**-k))
    slope = math.log10(errs[1] / errs[0]) / math.log10(xs[1] / xs[0])
    expected = k if regime == "small" else -k
    # first omitted coefficient: binomial C(-1/2, n) (times 2/pi... for atan: 1/(2n+1))
    if model == "geometric":
        coeff = abs(math.comb(2 * order, order) / 4**order)  # |C(-1/2, n)|
    else:
        coeff = 2 / math.pi / (2 * order + 1)
    report("asymptotic_sides truncation error",
           f"{model:9s} {regime:5s} order {order}: slope {slope:7.3f} (expected {expected:+d}), "
           f"error/xi^{expected:+d} -> {ratios[1]:.6f} (first omitted term {coeff:.6f})")
    assert abs(slope - expected) < 0.05
    assert ratios[1] == pytest.approx(coeff, rel=0.05)
