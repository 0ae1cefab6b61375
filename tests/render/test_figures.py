"""coincli.render.figures: the figures of ``coin plot`` show the core's numbers, the designs and
data where they belong, and leave matplotlib's state alone.

No pixel comparisons: the tests read the data back from the figure objects (found by ``gid``).
``plotmod`` (conftest) is the module, the test skipped without matplotlib.  The command itself
(files, sizes, errors) is tested in tests/cli/test_plot.py.
"""

from __future__ import annotations

import math
import warnings
from pathlib import Path

import numpy as np
import pytest

from coincli.core import models
from coincli.render import maps

#: three experiments: stacks of quarters and a rod
TOSSES = (Path(__file__).resolve().parents[1] / "data" / "plot_tosses.csv").read_text()


def _one(fig, gid):
    found = fig.findobj(lambda a: a.get_gid() == gid)
    assert len(found) == 1, f"{gid}: {len(found)} artists"
    return found[0]


def _all(fig, prefix):
    return list(fig.findobj(lambda a: str(a.get_gid() or "").startswith(prefix)))


def test_sides_curves_are_the_cores(plotmod):
    from coincli.core.averages import marginal
    from coincli.core.densities import Normal

    dens = Normal(math.pi / 2, math.radians(18))
    specs = [plotmod.GEOMETRIC, plotmod.DYNAMIC, plotmod.psi_spec(math.radians(60)),
             plotmod.density_spec(dens)]
    data = plotmod.sides_data(specs, points=101)
    fig = plotmod.sides_figure(data)
    for gid, f in [("geometric", lambda x: models.geometric(x).sides),
                   ("dynamic", lambda x: models.dynamic(x).sides),
                   ("psi=60", lambda x: models.conditional(x, math.radians(60)).sides),
                   (dens.spec, lambda x: marginal(x, dens).sides)]:
        line = _one(fig, f"curve:{gid}")
        x, y = np.asarray(line.get_xdata()), np.asarray(line.get_ydata())
        assert x.size == 101 and x[0] == 0.0 and x[-1] == 2.0
        np.testing.assert_array_equal(y, f(x))
    # the fair coins of both models, on their curves at 1/3
    g, d = _one(fig, "fair:geometric"), _one(fig, "fair:dynamic")
    assert g.get_xdata()[0] == models.FAIR_XI_GEOMETRIC
    assert d.get_xdata()[0] == models.FAIR_XI_DYNAMIC
    assert g.get_ydata()[0] == pytest.approx(1 / 3, abs=1e-15)
    assert d.get_ydata()[0] == pytest.approx(1 / 3, abs=1e-15)
    ax = fig.axes[0]
    assert ax.get_xlabel().startswith("aspect ratio") and ax.get_ylabel() == "P(sides)"
    assert "Fig. 5a" in ax.get_title()


def test_sides_design_marks(plotmod):
    data = plotmod.sides_data(xi_marks=[0.5], p_marks=[0.25], points=51)
    fig = plotmod.sides_figure(data)
    m = _one(fig, "design-xi:0")
    np.testing.assert_array_equal(m.get_xdata(), [0.5, 0.5])
    np.testing.assert_array_equal(m.get_ydata(), [models.geometric(0.5).sides,
                                                  models.dynamic(0.5).sides])
    assert _one(fig, "design-xi-line:0").get_xdata()[0] == 0.5
    m = _one(fig, "design-p:0")
    np.testing.assert_array_equal(m.get_xdata(), [models.geometric_inverse(0.25),
                                                  models.dynamic_inverse(0.25)])
    np.testing.assert_array_equal(m.get_ydata(), [0.25, 0.25])
    # a design beyond the default range widens the axis to show it
    far = plotmod.sides_data(xi_marks=[5.0], points=11)
    assert far.xlim[1] >= 5.0 and not far.skipped


def test_sides_experiments_with_wilson_bars(plotmod, tmp_path):
    from coincli.core.stats.intervals import proportion
    from coincli.io.experiments import parse_experiments

    exps = parse_experiments(TOSSES)
    data = plotmod.sides_data(experiments=plotmod.experiment_points(exps), points=51)
    fig = plotmod.sides_figure(data)
    pts = _one(fig, "data")
    assert list(pts.get_xdata()) == [e.xi for e in exps]
    assert list(pts.get_ydata()) == [e.counts.sides / e.counts.n for e in exps]
    bars = _one(fig, "data-errorbars")
    for seg, e in zip(bars.get_segments(), exps, strict=True):
        w = proportion(e.counts.sides, e.counts.n).wilson
        assert seg[0][0] == seg[1][0] == e.xi
        assert sorted([seg[0][1], seg[1][1]]) == pytest.approx([w.low, w.high], rel=1e-12)
    assert data.xlim[1] >= 1.2  # the rod (xi = 1.2) is on the axis
    labels = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    assert any("SSE" in t for t in labels)


def test_psi_curves_and_regimes(plotmod):
    xi = 0.577
    data = plotmod.psi_data(xi, [70.0], points=181)
    fig = plotmod.psi_figure(data)
    for name in ("heads", "sides", "tails"):
        line = _one(fig, f"curve:{name}")
        x = np.asarray(line.get_xdata())
        # past 90 deg at the mirror angle, taken in degrees (as coin table --psi)
        want = getattr(models.conditional(xi, np.radians(np.where(x > 90, 180 - x, x))), name)
        want = np.where(x == 90.0, getattr(models.dynamic(xi), name), want)  # the Keller flip
        np.testing.assert_array_equal(line.get_ydata(), want)
    t = math.degrees(models.theta0(xi)) / 2
    x = np.asarray(_one(fig, "curve:heads").get_xdata())
    for b in (t, 90 - t, 90 + t, 180 - t):
        assert b in x  # the kinks are grid points
    spans = _all(fig, "regime:")
    assert len(spans) == 5
    names = [s.get_gid().split(":")[2] for s in spans]
    assert names == ["heads only", "heads or sides", "all three", "heads or sides", "heads only"]
    mark = _one(fig, "design-psi:0")
    o = models.conditional(xi, math.radians(70))
    np.testing.assert_array_equal(mark.get_ydata(), [o.heads, o.sides, o.tails])
    assert list(mark.get_xdata()) == [70.0] * 3
    assert "degrees" in fig.axes[0].get_xlabel()


@pytest.mark.parametrize("style", ["panels", "ternary"])
def test_map_values(plotmod, style):
    data = maps.map_data(nx=31, ny=37, xi_marks=[0.5], psi_marks_deg=[80.0])
    fig = maps.map_figure(data, style=style)
    d = data.psi_deg
    o = models.conditional(data.xi[None, :], np.radians(np.where(d > 90, 180 - d, d))[:, None])
    k = models.dynamic(data.xi)  # the row at 90 deg is the Keller flip, eq. (12)
    at90 = (data.psi_deg == 90.0)[:, None]
    o = models.Outcome(*(np.where(at90, a[None, :], b) for a, b in zip(k, o, strict=True)))
    assert at90.any()
    if style == "panels":
        for name in ("heads", "sides", "tails"):
            mesh = _one(fig, f"mesh:{name}")
            np.testing.assert_array_equal(np.asarray(mesh.get_array()).reshape(37, 31),
                                          getattr(o, name))
            edges = mesh.get_coordinates()
            np.testing.assert_allclose((edges[0, :-1, 0] + edges[0, 1:, 0]) / 2, data.xi,
                                       atol=1e-12)
    else:
        mesh = _one(fig, "mesh:ternary")
        rgb = np.asarray(mesh.get_array()).reshape(37, 31, -1)[..., :3]
        np.testing.assert_allclose(rgb, maps.ternary_colours(o.heads, o.sides, o.tails))
    assert all(a.get_xdata()[0] == 0.5 for a in _all(fig, "design-xi:0"))
    assert all(a.get_ydata()[0] == 80.0 for a in _all(fig, "design-psi:0"))
    star = _all(fig, "fair:dynamic")[0]
    assert (star.get_xdata()[0], star.get_ydata()[0]) == (models.FAIR_XI_DYNAMIC, 90.0)


def test_phase_map_and_hyperbolae(plotmod):
    from coincli.core.toss import batch as toss

    data = maps.phase_data(u_range=(0.0, 2.0), omega_range=(0.0, 60.0), nu=24, nw=20,
                              marks=[(1.0, 30.0)])
    fig = maps.phase_figure(data)
    codes = np.asarray(_one(fig, "mesh:phase").get_array()).reshape(20, 24)
    for i, j in [(0, 0), (5, 7), (19, 23), (12, 3)]:
        t = toss.toss(models.FAIR_XI_DYNAMIC, math.pi / 2, float(data.u[j]),
                      float(data.omega[i]))
        assert codes[i, j] == t.code
    # eq. 10 for the fair coin: omega = (2n +- 1/3) pi g / (2u), (2n + 1 +- 1/3) pi g / (2u)
    u = data.u
    coeffs = sorted(round(b.coefficient, 9) for b in data.curves)
    assert coeffs[:4] == [round(c, 9) for c in (1 / 3, 2 / 3, 4 / 3, 5 / 3)]
    for k, b in enumerate(data.curves):
        line = _one(fig, f"hyperbola:{k}")
        np.testing.assert_allclose(line.get_ydata(), b.coefficient * math.pi * 9.81 / (2 * u),
                                   rtol=1e-12)
    assert list(_one(fig, "design:0").get_xydata()[0]) == [1.0, 30.0]
    assert "(m/s)" in fig.axes[0].get_xlabel() and "(rad/s)" in fig.axes[0].get_ylabel()


def test_builders_leave_matplotlib_state_alone(plotmod, tmp_path):
    import matplotlib as mpl

    before = dict(mpl.rcParams)
    backend = mpl.get_backend()
    fig = plotmod.psi_figure(plotmod.psi_data(0.5, points=31))
    plotmod.save_figure(fig, str(tmp_path / "f.svg"))
    assert mpl.get_backend() == backend
    assert dict(mpl.rcParams) == before


def test_title_option(capsys, tmp_path, plotmod):
    from coincli.render.figures import psi_data, psi_figure

    fig = psi_figure(psi_data(0.3, points=11), title="My coin")
    assert fig.axes[0].get_title() == "My coin"


# --------------------------------------------------------------------------- sizes, ranges


def test_check_figure_size_limits():
    from coincli.render.figures import MAX_PIXELS, check_figure_size

    check_figure_size(10.0, 5.0, 1000.0)  # exactly MAX_PIXELS
    assert 10.0 * 5.0 * 1000.0**2 == MAX_PIXELS
    for w, h, dpi in [(10.0, 5.0, 1000.5), (math.nan, 4.5, 150.0), (7.0, math.inf, 150.0),
                      (7.0, 4.5, math.nan), (0.5, 4.5, 150.0), (7.0, 4.5, 5.0)]:
        with pytest.raises(ValueError):
            check_figure_size(w, h, dpi)


@pytest.mark.parametrize("log, xi_range", [(False, (0.0, 1e6)), (True, (1e-6, 1e6)),
                                           (False, (0.0, 1e-6)), (True, (1e6 - 1e-6, 1e6))])
def test_figures_at_the_axis_limits_raise_no_warning(plotmod, tmp_path, log, xi_range):
    """Not only hidden by the command: at the limits matplotlib and numpy do not warn at all."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        d = plotmod.sides_data(xi_range=xi_range, log=log, points=51, xi_marks=[xi_range[1]],
                               p_marks=[0.3])
        plotmod.save_figure(plotmod.sides_figure(d), str(tmp_path / "s.png"), 40)
        m = maps.map_data(xi_range=xi_range, log=log, nx=21, ny=21, psi_marks_deg=[0, 180])
        plotmod.save_figure(maps.map_figure(m), str(tmp_path / "m.svg"), 40)


def test_tosses_off_the_axis_are_a_note(plotmod):
    from coincli.io.experiments import parse_experiments

    pts = plotmod.experiment_points(parse_experiments(TOSSES))
    d = plotmod.sides_data(experiments=pts, xi_range=(0.0, 1.0), points=11)
    assert [n for n in d.skipped if "tosses" in n] == [
        "the tosses 'rod' at xi = 1.2 are outside the plotted range 0 to 1"]


@pytest.mark.parametrize("xi", [0.577, 1e15, 1e300])
def test_psi_90_is_the_keller_flip_in_every_plot(plotmod, xi):
    """`plot psi --psi 90`, its curve at 90 and `plot phase --psi 90` mark what `coin table --psi
    90` prints: eq. (12) exactly (Table I at the double nearest pi/2 lost the tails of a coin
    thicker than 1e16 and was 1% off at 1e15)."""
    from coincli.core.modelspec import ModelSpec

    want = ModelSpec.fixed_psi(math.radians(90.0)).forward(xi)
    assert want == models.dynamic(xi)
    data = plotmod.psi_data(xi, [90.0], points=181)
    assert data.marks[0][1] == want
    k = int(np.flatnonzero(data.psi_deg == 90.0)[0])
    assert (data.heads[k], data.sides[k], data.tails[k]) == tuple(want)
    assert data.marks[0][1].tails > 0


# ------------------------------------------------ your tosses and simulated tosses kept apart


def _fake_fit(p_value):
    """A SidesFit as coin plot sides --landing bounce fits one (alpha, beta on ln xi)."""
    from coincli.core.bounce.design import SidesFit

    return SidesFit(alpha=0.2, beta=1.5, cov=((0.01, 0.0), (0.0, 0.01)), points=[],
                    deviance=30.0, df=6, p_value=p_value)


def test_sides_user_and_simulated_points_have_their_own_markers_and_sse(plotmod):
    """The user's tosses and the simulated tosses of --landing bounce are two series, two
    legend entries; the SSE in the legend is of the user's tosses only (it mixed them)."""
    from coincli.io.experiments import parse_experiments

    mine = plotmod.experiment_points(parse_experiments(TOSSES))
    sims = [plotmod.ExperimentPoint("simulated bounce on wood", x, 400, s, s / 400, lo, hi,
                                    simulated=True)
            for x, s, lo, hi in [(0.2, 20, 0.03, 0.08), (0.6, 300, 0.7, 0.8)]]
    data = plotmod.sides_data(experiments=mine + sims, points=51)
    fig = plotmod.sides_figure(data)
    assert list(_one(fig, "data").get_xdata()) == [e.xi for e in mine]
    assert list(_one(fig, "simulated").get_xdata()) == [0.2, 0.6]
    assert _one(fig, "data").get_marker() != _one(fig, "simulated").get_marker()
    labels = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    assert sum(lab.startswith("your tosses (") for lab in labels) == 1
    assert sum(lab.startswith("simulated bounce on wood (2 points, 400 settled") for lab in labels) == 1
    # SSE against the geometric model, by hand over the user's rows only
    want = math.fsum((e.frequency - float(models.geometric(e.xi).sides)) ** 2 for e in mine)
    assert plotmod.sse(data, "geometric") == pytest.approx(want, rel=1e-12)
    mixed = want + math.fsum((e.frequency - float(models.geometric(e.xi).sides)) ** 2
                             for e in sims)
    assert plotmod.sse(data, "geometric") != pytest.approx(mixed, rel=1e-6)
    only_sims = plotmod.sides_data(experiments=sims, points=51)
    assert plotmod.sse(only_sims, "geometric") is None  # simulated points are not data


@pytest.mark.parametrize("p_value, rejected", [(6.4e-6, True), (0.049, True), (0.05, False),
                                                (0.7, False), (math.nan, False)])
def test_sides_rejected_bounce_fit_is_dashed_and_labelled(plotmod, p_value, rejected):
    from coincli.reports.bounce import FittedSpec

    spec = FittedSpec(_fake_fit(p_value), "wood")
    assert spec.rejected is rejected
    assert ("REJECTED" in spec.label) is rejected
    data = plotmod.sides_data([plotmod.GEOMETRIC, spec], points=51)
    line = _one(plotmod.sides_figure(data), "curve:bounce")
    assert line.get_linestyle() == ("--" if rejected else "-")
    text = line.get_label().replace("\n", " ")
    assert ("shown for reference" in text) is rejected
