"""The paper's own numbers, and the invariants every model must keep."""

from __future__ import annotations

import math
import subprocess
import sys
from fractions import Fraction

import mpmath as mp
import pytest

from coincli.core import coins, models
from coincli.core.averages import conditional_inverse, marginal, marginal_inverse
from coincli.core.densities import Cosine, Normal, Table, Uniform
from coincli.io import grammar as parse
from coincli.io.grammar import parse_density

XI_FAIR = 1 / math.sqrt(3)


def test_fair_coins_of_the_paper():
    # eq. 11: geometric fair at 1/(2 sqrt 2); eq. 12: dynamic fair at 1/sqrt 3
    assert models.geometric(models.FAIR_XI_GEOMETRIC).sides == pytest.approx(1 / 3, rel=4e-16)
    assert models.dynamic(XI_FAIR).sides == pytest.approx(1 / 3, rel=4e-16)
    # Sec. IV: P_G(sides) = 1/2 at the dynamic fair coin, P_D = 0.216 at the geometric one
    assert models.geometric(XI_FAIR).sides == pytest.approx(0.5, rel=4e-16)
    assert round(models.dynamic(models.FAIR_XI_GEOMETRIC).sides, 3) == 0.216


@pytest.mark.parametrize(
    "density, printed",
    [(Uniform(), (0.630, 0.281, 0.088)), (Cosine(), (0.439, 0.396, 0.165)),
     (Normal(), (0.478, 0.371, 0.150))],
)
def test_table_ii_to_every_printed_digit(density, printed):
    got = marginal(XI_FAIR, density)
    assert tuple(round(v, 3) for v in got) == printed
    assert sum(got) == pytest.approx(1.0, abs=4e-16)


def test_eight_quarters_make_the_papers_fair_coin():
    q = coins.get_coin("paper-quarter")
    choice = coins.nearest_stack(q, 1 / 3)
    assert choice.count == 8
    assert round(choice.xi, 2) == 0.58
    assert [n for n, _, _ in choice.neighbours] == [7, 8, 9]


def test_zero_thickness_coin_is_diaconis_holmes_montgomery():
    for psi in [math.pi / 4 + 0.01, 1.0, math.pi / 2, 2.0, 3 * math.pi / 4 - 0.01]:
        h, s, t = models.conditional(0.0, psi)
        dhm = 0.5 + math.asin(1 / math.tan(psi) ** 2) / math.pi
        assert h == pytest.approx(dhm, rel=1e-15) and s == 0.0
        assert t == pytest.approx(1 - dhm, rel=1e-14)


def _table_i_mp(xi, psi):
    # enough digits that c = xi/sqrt(1+xi^2) survives subtraction from cos^2 psi, and that
    # 1 - c survives for a thick coin: 60 plus twice the decimal exponent of xi
    mp.mp.dps = 60 + 2 * int(abs(math.log10(xi))) if 0 < xi < math.inf else 60
    xi, psi = mp.mpf(xi), mp.mpf(psi)
    c = xi / mp.sqrt(1 + xi**2)
    a, b = mp.cos(psi) ** 2, mp.sin(psi) ** 2
    if b == 0:
        return (1, 0, 0)
    th1 = mp.pi if (c - a) / b <= -1 else mp.acos((c - a) / b)
    th2 = mp.pi if (-c - a) / b <= -1 else mp.acos((-c - a) / b)
    return th1 / mp.pi, (th2 - th1) / mp.pi, 1 - th2 / mp.pi


@pytest.mark.parametrize("xi", [1e-200, 1e-6, 0.1, 0.5, XI_FAIR, 2.0, 1e3, 1e150])
@pytest.mark.parametrize("psi", [0.3, 0.7, 1.0, 1.4, math.pi / 2, 2.0, 2.9])
def test_conditional_against_table_i_away_from_boundaries(xi, psi):
    t = math.atan2(1, xi) / 2
    if min(abs(psi - t), abs(psi - (math.pi / 2 - t)), abs(math.pi - psi - t),
           abs(math.pi - psi - (math.pi / 2 - t))) < 1e-3:
        pytest.skip("near a regime boundary: covered by the accuracy tests")
    got = models.conditional(xi, psi)
    for g, r in zip(got, _table_i_mp(xi, psi), strict=True):
        if r == 0:
            assert g == 0
        else:
            assert abs(g - float(r)) <= 4 * math.ulp(float(r)), (xi, psi, g, float(r))


def _close(a, b, ulps=2):
    return all(abs(x - y) <= ulps * math.ulp(max(abs(x), abs(y))) for x, y in zip(a, b,
                                                                                   strict=True))


def test_scalar_and_array_paths_agree():
    # The same formula runs on libm (math) and on numpy's vectorized sin/cos/atan2, which may
    # round differently by an ulp; both must stay within 2 ulps of each other.
    np = pytest.importorskip("numpy")
    xi = np.array([0.0, 1e-300, 0.01, XI_FAIR, 3.0, 1e300, np.inf])
    for psi in (0.0, 0.5, 1.2, math.pi / 2, 2.5, math.pi):
        arr = models.conditional(xi, psi)
        for k, x in enumerate(xi.tolist()):
            assert _close(tuple(float(a[k]) for a in arr), tuple(models.conditional(x, psi)))
    for fn in (models.geometric, models.dynamic):
        arr = fn(xi)
        for k, x in enumerate(xi.tolist()):
            assert _close(tuple(float(a[k]) for a in arr), tuple(fn(x)))


def test_extremes():
    assert models.conditional(math.inf, 1.0) == (0.0, 1.0, 0.0)
    assert models.conditional(math.inf, 0.0) == (1.0, 0.0, 0.0)
    assert models.conditional(0.3, math.pi) == (1.0, 0.0, 0.0)
    assert models.dynamic(math.inf) == (0.0, 1.0, 0.0)
    assert models.geometric(0.0) == (0.5, 0.0, 0.5)
    assert models.dynamic_inverse(1.0) == math.inf and models.dynamic_inverse(0.0) == 0.0
    assert models.geometric_inverse(1.0) == math.inf


@pytest.mark.parametrize("bad", [-1e-300, math.nan, -math.inf])
def test_bad_xi_names_the_argument(bad):
    with pytest.raises(ValueError, match="xi must be"):
        models.dynamic(bad)


@pytest.mark.parametrize("bad", [-0.1, math.pi + 1e-9, math.nan])
def test_bad_psi_names_the_argument(bad):
    with pytest.raises(ValueError, match="psi must be in \\[0, pi\\]"):
        models.conditional(0.5, bad)


def test_asymptotic_series_orders():
    # the error of the n-term series shrinks like the next term
    for model in ("geometric", "dynamic"):
        exact = getattr(models, model)
        e1 = abs(models.asymptotic_sides(1e-2, model, "small") - exact(1e-2).sides)
        e2 = abs(models.asymptotic_sides(1e-3, model, "small") - exact(1e-3).sides)
        assert e2 < e1 * 1e-3 * 1.5  # O(xi^5) after two terms: 1e-5 ratio, allow margin
        e1 = abs(models.asymptotic_sides(1e2, model, "large") - exact(1e2).sides)
        e2 = abs(models.asymptotic_sides(1e3, model, "large") - exact(1e3).sides)
        assert e2 < e1 / 50


@pytest.mark.parametrize("p", [1e-12, 0.1, 1 / 3, 0.5, 0.9, 1 - 1e-9])
def test_root_found_inverses_round_trip(p):
    for d in (Uniform(), Normal(), Normal(math.pi / 2, 0.3)):
        xi = marginal_inverse(p, d)
        assert marginal(xi, d).sides == pytest.approx(p, rel=1e-12)
    xi = conditional_inverse(p, 1.2)
    assert models.conditional(xi, 1.2).sides == pytest.approx(p, rel=1e-12)


def test_conditional_inverse_unreachable():
    with pytest.raises(ValueError, match="only p_sides = 0"):
        conditional_inverse(0.2, 0.0)


def test_densities_are_normalized():
    np = pytest.importorskip("numpy")
    psi = np.linspace(0, math.pi, 200001)
    for d in (Uniform(), Cosine(), Normal(), Normal(0.1, 0.05), Normal(3.0, 2.0),
              Table([0, 1, 2, 3], [0, 1, 3, 0])):
        assert np.trapezoid(d.pdf(psi), psi) == pytest.approx(1.0, rel=1e-6)


def test_parse_forms():
    assert parse.parse_probability("1/3") == 1 / 3
    assert parse.parse_probability("33%") == 0.33
    assert parse.parse_probability("0.33") == 0.33
    assert parse.parse_length_mm("0.955in") == pytest.approx(24.257)
    assert parse.parse_values("0.1:0.3:0.1", "x") == [0.1, 0.2, 0.3]
    for bad in ("1/0", "nan", "2", "-1%", "", "1e400", "0x1"):
        with pytest.raises(ValueError):
            parse.parse_probability(bad)
    with pytest.raises(ValueError, match="at most"):
        parse.parse_values("0:1e9:1", "x")
    with pytest.raises(ValueError, match="step must be > 0"):
        parse.parse_values("0:1:0", "x")
    assert parse_density("normal:90:18").spec == "normal:90:18"
    with pytest.raises(ValueError, match="normal:MEAN:SD"):
        parse_density("normal:90")


@pytest.mark.parametrize("start,stop,step", [
    ("0.3", "0.4", "0.05"), ("0", "2", "0.01"),
    pytest.param("0.001", "1000", "0.001", marks=pytest.mark.slow),  # a million values
    ("-1.5", "1.5", "0.1"),
    ("1e-3", "2e-3", "1e-5"), ("0", "1", "1/3"), ("1/7", "3", "2/7"), ("0.5", "0.5", "0.1"),
    ("123.456", "123.5", "0.0001"), ("2.5e2", "2.6e2", "0.25")])
def test_range_values_are_the_nearest_doubles_of_the_exact_grid(start, stop, step):
    """Each value of a decimal or fractional range is the double nearest start + k step done in
    exact rationals (Fraction), in the Python path (parse_values) and the numpy path (chunk)."""
    r = parse.parse_range(f"{start}:{stop}:{step}", "x")
    a = Fraction(start) if "/" not in start else Fraction(*map(int, start.split("/")))
    d = Fraction(step) if "/" not in step else Fraction(*map(int, step.split("/")))
    want = [float(a + k * d) for k in range(r.count)]
    want[-1] = min(want[-1], float(Fraction(stop) if "/" not in stop else Fraction(
        *map(int, stop.split("/")))))
    got = r.chunk(0, r.count).tolist()
    assert got == want
    assert [r.value(k) for k in range(r.count)] == want
    assert parse.parse_values(f"{start}:{stop}:{step}", "x") == want
    # chunks join to the whole
    mid = r.count // 3
    assert r.chunk(0, mid).tolist() + r.chunk(mid, r.count).tolist() == want


def test_range_beyond_exact_integers_falls_back_to_doubles():
    """Parts too long or too large for the integer form keep start + k*step in doubles, the
    same in both paths, and never pass stop."""
    for text in ("1e300:1.0000000000000002e300:1e284", "0.1234567890123456789:0.2:0.01",
                 "9007199254740990.5:9007199254740993:0.5"):
        r = parse.parse_range(text, "x")
        vals = r.chunk(0, r.count).tolist()
        assert vals == [r.value(k) for k in range(r.count)]
        assert vals[0] == r.start and max(vals) <= r.stop


def _exact_stack_xi(coin, n):
    from fractions import Fraction

    try:
        return float(Fraction(n) * Fraction(coin.thickness_mm) / Fraction(coin.diameter_mm))
    except OverflowError:
        return math.inf


def test_stack_xi_is_correctly_rounded_scalar_and_vectorized(monkeypatch):
    import random

    import numpy as np

    rng = random.Random(5)
    cs = list(coins.CATALOG.values())
    cs += [coins.custom_coin(rng.uniform(1, 100), rng.uniform(0.01, 10)) for _ in range(20)]
    cs += [coins.custom_coin(1e-300, 1e300), coins.custom_coin(1e300, 1e-300),
           coins.custom_coin(3.0, 1.0), coins.custom_coin(0.1, 0.3)]
    counts = [1, 2, 3, 7, 9, 10, 2**26 + 1, 2**52 + 1, 2**53]
    counts += [rng.randint(1, 10 ** rng.randint(1, 15)) for _ in range(300)]
    for c in cs:
        want = [_exact_stack_xi(c, n) for n in counts]
        assert [coins.stack_xi(c, n) for n in counts] == want, c
        assert coins.stack_xis(c, np.array(counts, dtype=float)).tolist() == want, c
        assert c.xi == coins.stack_xi(c, 1) == c.thickness_mm / c.diameter_mm
    q = coins.CATALOG["quarter"]
    assert coins.stack_xi(q, 9) == 9 * 1.75 / 24.26 != 9 * q.xi  # one rounding, not two
    # the exact fallback (taken when the double arithmetic cannot decide) gives the same doubles
    monkeypatch.setattr(coins, "_MARGIN", 0.0)
    cent = coins.CATALOG["cent"]
    assert coins.stack_xis(cent, np.array(counts, dtype=float)).tolist() == [
        _exact_stack_xi(cent, n) for n in counts]
    for bad in (0, -1, 2.0, True):
        with pytest.raises(ValueError, match="whole number >= 1"):
            coins.stack_xi(q, bad)


def test_nearest_stack_past_the_cap_is_a_no_stack_error():
    q = coins.CATALOG["quarter"]
    with pytest.raises(coins.NoStackError, match=r"no stack of up to 2\^40 \(about 1\.1 x 10\^12\)"):
        coins.nearest_stack(q, 0.5, lambda x: models.conditional(x, math.radians(1e-10)).sides)
    assert issubclass(coins.NoStackError, ValueError)
    ch = coins.nearest_stack(q, 0.5, lambda x: models.conditional(x, math.radians(0.001)).sides)
    assert ch.xi == coins.stack_xi(q, ch.count)
    assert [x for _, x, _ in ch.neighbours] == [coins.stack_xi(q, k) for k, _, _ in ch.neighbours]


def test_numpy_random_is_imported_without_secrets_and_still_draws_entropy():
    # coincli.core._numerics.backend.numpy_random: a stand-in `secrets` (randbits only) while numpy.random
    # is imported, removed at once; unseeded SeedSequences still get 128 bits of entropy, and
    # `import secrets` afterwards is the real module.
    code = """
import sys
from coincli.core._numerics.backend import numpy_random, randbits
npr = numpy_random()
assert "secrets" not in sys.modules and "hashlib" not in sys.modules, sorted(sys.modules)
a, b = npr.SeedSequence().entropy, npr.SeedSequence().entropy
assert a != b and 0 < a < 2**128 and 0 < b < 2**128
assert npr.default_rng().random() != npr.default_rng().random()
assert npr.default_rng(7).integers(0, 2**62) == npr.default_rng(7).integers(0, 2**62)
import secrets
assert hasattr(secrets, "token_hex") and secrets.randbits(8) < 256
assert numpy_random() is npr
bits = [randbits(k) for k in (0, 1, 7, 8, 9, 63, 128) for _ in range(50)]
assert all(0 <= x < 2**k for x, k in zip(bits, [k for k in (0, 1, 7, 8, 9, 63, 128) for _ in range(50)]))
assert max(randbits(63) for _ in range(64)) >= 2**61  # the top bits are drawn
print("ok")
"""
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert p.returncode == 0 and p.stdout.strip() == "ok", p.stderr
