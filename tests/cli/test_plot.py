"""coin plot: the figures show the core's numbers, the designs and data where they belong, files
of each format are written, the text plots work without matplotlib, errors are one line.

No pixel comparisons: the tests read the data back from the figure objects (found by ``gid``).
"""

from __future__ import annotations

import io
import math
import os
import subprocess
import sys
import threading
import warnings

import numpy as np
import pytest

from coincli.core import models

TOSSES = """\
# three experiments: stacks of quarters and a rod
label,coin,count,diameter,thickness,heads,sides,tails
one,quarter,1,,,49,1,50
eight,quarter,8,,,30,36,34
rod,,,25mm,30mm,10,70,20
"""


def _one(fig, gid):
    found = fig.findobj(lambda a: a.get_gid() == gid)
    assert len(found) == 1, f"{gid}: {len(found)} artists"
    return found[0]


def _all(fig, prefix):
    return list(fig.findobj(lambda a: str(a.get_gid() or "").startswith(prefix)))


@pytest.fixture
def no_matplotlib(monkeypatch):
    """Pretend matplotlib is not installed."""
    for name in list(sys.modules):
        if name == "matplotlib" or name.startswith("matplotlib."):
            monkeypatch.delitem(sys.modules, name)
    monkeypatch.setitem(sys.modules, "matplotlib", None)


# --------------------------------------------------------------------------- text plots


@pytest.mark.parametrize("argv, words", [
    (["plot", "sides", "--terminal"], ["P(sides)", "G  geometric", "D  dynamic", "F  fair"]),
    (["plot", "sides", "--out", "-", "--xi", "0.5", "-p", "1/4", "--log"],
     ["your design xi = 0.5", "your target P(sides) = 0.25", "log scale"]),
    (["plot", "psi", "--terminal", "--psi", "70"], ["P(heads)", "regimes (Table I)",
                                                    "your toss psi = 70 deg"]),
    (["plot", "map", "--terminal", "--xi", "0.5", "--psi", "80"], ["heads likeliest",
                                                                   "your design: xi = 0.5"]),
    (["plot", "phase", "--terminal", "--toss", "1:30"], ["H heads", "vigorous limit (Table I)",
                                                         "X your toss"]),
])
def test_text_plots(coin, argv, words):
    code, out, err = coin(*argv)
    assert code == 0, err
    assert err == ""
    for w in words:
        assert w in out
    assert "\x1b[" not in out  # no colour codes in a pipe


def test_text_plot_values_are_the_cores():
    from coincli.render.figures import psi_data
    from coincli.render.text import Canvas, text_psi

    d = psi_data(0.577, points=70)
    text = text_psi(d, 70, 21).plain
    cv = Canvas(70, 21, (0.0, 180.0), (0.0, 1.0))
    lines = text.splitlines()[2:23]
    axis = lines[0].index("+")  # the y axis: the top row carries the tick label 1
    grid = [line[axis + 1:].ljust(70) for line in lines]
    assert all(line[axis] in "+|" for line in lines)
    # heads is drawn last: where the grid shows an H at a psi grid point, the core agrees
    hits = 0
    for psi, h in zip(d.psi_deg.tolist(), d.heads.tolist(), strict=True):
        c, r = cv.col(psi), cv.row(h)
        if grid[r][c] == "H":
            hits += 1
    assert hits >= 60


def test_text_plot_without_matplotlib(coin, no_matplotlib, tmp_path):
    code, out, err = coin("plot", "sides", "--out", "-", "--data", str(_tosses(tmp_path)))
    assert code == 0 and err == ""
    assert "your tosses (3 rows)" in out and "95% Wilson" in out
    code, out, err = coin("plot", "psi")
    assert code == 0 and "P(sides)" in out and err == ""
    assert sys.modules.get("matplotlib") is None


@pytest.mark.parametrize("sub", ["sides", "psi", "map", "phase"])
def test_missing_matplotlib_is_one_line_with_the_hint(coin, no_matplotlib, tmp_path, sub):
    path = tmp_path / "f.png"
    code, out, err = coin("plot", sub, "--out", str(path))
    assert code == 1 and out == ""
    assert err.count("\n") == 1 and "pip install -U 'thickcoin[plot]'" in err
    assert not path.exists()


# --------------------------------------------------------------------------- errors


@pytest.mark.parametrize("argv, code, words", [
    (["plot", "sides", "--out", "x.jpg"], 2, ".png, .svg or .pdf"),
    (["plot", "sides", "--out", "x.png", "--terminal"], 2, "not both"),
    (["plot", "sides", "--xi", "-1"], 2, "--xi"),
    (["plot", "sides", "-p", "2"], 2, "--p-sides"),
    (["plot", "sides", "--psi-dist", "normal:90"], 2, "--psi-dist"),
    (["plot", "sides", "--data", "/nonexistent/t.csv"], 2, "--data"),
    (["plot", "sides", "--xi-range", "1:0.5"], 2, "--xi-range"),
    (["plot", "sides", "--log", "--xi-range", "0:2"], 2, "1e-6 <= LOW"),
    (["plot", "psi", "--xi", "abc"], 2, "--xi"),
    (["plot", "psi", "--psi", "200"], 2, "[0, 180]"),
    (["plot", "map", "--style", "pie"], 2, "--style"),
    (["plot", "phase", "--contact", "edge"], 2, "--contact"),
    (["plot", "phase", "--u-range", "2:1"], 2, "--u-range"),
    (["plot", "phase", "--toss", "1"], 2, "--toss"),
    (["plot", "sides", "--dpi", "0"], 2, "--dpi"),
    (["plot", "nosuch"], 2, "No such command"),
])
def test_errors_are_one_line(coin, argv, code, words):
    got, out, err = coin(*argv)
    assert got == code, err
    assert out == ""
    assert err.startswith("coin: error: ") and err.count("\n") == 1 and words in err
    assert "Traceback" not in err


def test_bad_data_file_names_the_line(coin, tmp_path):
    p = tmp_path / "t.csv"
    p.write_text("xi,heads,sides,tails\n0.5,1,2,3\n0.5,1,x,3\n")
    code, out, err = coin("plot", "sides", "--data", str(p))
    assert code == 2 and "line 3" in err and err.count("\n") == 1


def test_data_from_stdin(coin, monkeypatch):
    import io

    monkeypatch.setattr(sys, "stdin", io.StringIO("xi,sides,n\n0.5,30,100\n"))
    code, out, err = coin("plot", "sides", "--data", "-", "--terminal")
    assert code == 0, err
    assert "your tosses (1 row)" in out


def test_unwritable_output_is_exit_1(coin, tmp_path):
    pytest.importorskip("matplotlib")
    code, out, err = coin("plot", "psi", "--out", str(tmp_path / "no" / "dir" / "f.png"))
    assert code == 1 and err.count("\n") == 1 and "cannot write" in err


@pytest.mark.parametrize("name", [".png", ".SVG", "sub/.pdf"])
def test_an_extension_alone_is_not_a_file_name(coin, tmp_path, name):
    code, out, err = coin("plot", "sides", "--out", str(tmp_path / name))
    assert code == 2 and err.count("\n") == 1 and out == ""
    assert "is an extension without a file name; give a name such as figure." in err
    assert not any(tmp_path.rglob("*"))


def test_import_budget():
    """Registering and asking for help loads neither numpy nor matplotlib nor rich; a text plot
    does not load matplotlib."""
    probe = (
        "import sys\nfrom coincli.cli import run\n"
        "import coincli.cli.plot\n"
        "print('A', sorted(m for m in ('numpy','scipy','rich','matplotlib') if m in sys.modules))\n"
        "run(['plot','psi','--terminal'])\n"
        "print('B', 'matplotlib' in sys.modules)\n"
    )
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True,
                         timeout=120)
    assert out.returncode == 0, out.stderr
    lines = out.stdout.strip().splitlines()
    assert lines[0] == "A []"
    assert lines[-1] == "B False"


# --------------------------------------------------------------------------- figures

mpl = None


@pytest.fixture
def plotmod():
    global mpl
    mpl = pytest.importorskip("matplotlib")
    from coincli.render import figures as plot

    return plot


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
    data = plotmod.map_data(nx=31, ny=37, xi_marks=[0.5], psi_marks_deg=[80.0])
    fig = plotmod.map_figure(data, style=style)
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
        np.testing.assert_allclose(rgb, plotmod.ternary_colours(o.heads, o.sides, o.tails))
    assert all(a.get_xdata()[0] == 0.5 for a in _all(fig, "design-xi:0"))
    assert all(a.get_ydata()[0] == 80.0 for a in _all(fig, "design-psi:0"))
    star = _all(fig, "fair:dynamic")[0]
    assert (star.get_xdata()[0], star.get_ydata()[0]) == (models.FAIR_XI_DYNAMIC, 90.0)


def test_phase_map_and_hyperbolae(plotmod):
    from coincli.core.toss import flight as toss

    data = plotmod.phase_data(u_range=(0.0, 2.0), omega_range=(0.0, 60.0), nu=24, nw=20,
                              marks=[(1.0, 30.0)])
    fig = plotmod.phase_figure(data)
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
    before = dict(mpl.rcParams)
    backend = mpl.get_backend()
    fig = plotmod.psi_figure(plotmod.psi_data(0.5, points=31))
    plotmod.save_figure(fig, str(tmp_path / "f.svg"))
    assert mpl.get_backend() == backend
    assert dict(mpl.rcParams) == before


# --------------------------------------------------------------------------- files


@pytest.mark.parametrize("fmt, magic", [("png", b"\x89PNG"), ("svg", b"<?xml"),
                                        ("pdf", b"%PDF")])
@pytest.mark.parametrize("argv", [
    ["plot", "sides", "--xi", "0.5"],
    ["plot", "psi", "--xi", "0.577"],
    ["plot", "map", "--style", "ternary"],
    ["plot", "phase", "--resolution", "30"],
])
def test_files_of_each_format(coin, tmp_path, plotmod, fmt, magic, argv):
    path = tmp_path / f"fig.{fmt}"
    code, out, err = coin(*argv, "--out", str(path), "--dpi", "50")
    assert code == 0, err
    assert out == ""
    data = path.read_bytes()
    assert len(data) > 1000 and data.startswith(magic)


def test_png_size_follows_dpi_width_height(coin, tmp_path, plotmod):
    path = tmp_path / "f.png"
    code, _, err = coin("plot", "psi", "--out", str(path), "--dpi", "40", "--width", "5",
                        "--height", "3")
    assert code == 0, err
    head = path.read_bytes()[16:24]
    assert (int.from_bytes(head[:4], "big"), int.from_bytes(head[4:], "big")) == (200, 120)


def test_svg_is_deterministic(coin, tmp_path, plotmod):
    outs = []
    for k in range(2):
        path = tmp_path / f"f{k}.svg"
        code, _, err = coin("plot", "sides", "--xi", "0.5", "-p", "0.3", "--data",
                            str(_tosses(tmp_path)), "--out", str(path))
        assert code == 0, err
        outs.append(path.read_bytes())
    assert outs[0] == outs[1]
    assert b"<dc:date>" not in outs[0]


def _tosses(tmp_path):
    p = tmp_path / "tosses.csv"
    p.write_text(TOSSES)
    return p


def test_title_option(capsys, tmp_path, plotmod):
    from coincli.render.figures import psi_data, psi_figure

    fig = psi_figure(psi_data(0.3, points=11), title="My coin")
    assert fig.axes[0].get_title() == "My coin"


# --------------------------------------------------------------------------- sizes, ranges


def _one_error(code, out, err, option, *words):
    """Exit 2, nothing on stdout, one stderr line that names the option and what is allowed."""
    assert code == 2, err
    assert out == ""
    assert err.startswith("coin: error: ") and err.count("\n") == 1, err
    assert option in err, err
    for w in words:
        assert w in err, err
    assert "Traceback" not in err and "Warning" not in err


@pytest.mark.parametrize("option, allowed", [("--width", "from 1 to 100"),
                                             ("--height", "from 1 to 100"),
                                             ("--dpi", "from 10 to 2000")])
@pytest.mark.parametrize("value", ["nan", "NaN", "inf", "-inf", "0", "-1", "1e9", "1e400", "abc",
                                   ""])
@pytest.mark.parametrize("sub", ["sides", "psi", "map", "phase"])
def test_bad_figure_size_is_exit_2_naming_the_option(coin, tmp_path, sub, option, allowed,
                                                     value):
    """nan passed click's FloatRange (nan < 1 is False) and reached matplotlib: exit 1 with
    "figure size must be positive finite not (nan, 4.5)"."""
    path = tmp_path / "f.png"
    code, out, err = coin("plot", sub, "--out", str(path), option, value)
    _one_error(code, out, err, option, allowed)
    assert not path.exists()


def test_bad_figure_size_is_refused_for_a_text_plot_too(coin):
    code, out, err = coin("plot", "psi", "--terminal", "--width", "nan")
    _one_error(code, out, err, "--width", "from 1 to 100")


@pytest.mark.parametrize("argv", [
    ["plot", "sides", "--width", "100", "--dpi", "2000"],  # was 1.8e9 pixels: 7 GB, 90 s
    ["plot", "psi", "--width", "100", "--height", "100", "--dpi", "100"],
    ["plot", "map", "--dpi", "1000"],  # the map's default 12 x 4.4 inches
    ["plot", "phase", "--height", "60", "--dpi", "300"],  # 9.5 x 60 inches: 51 million
])
def test_too_many_pixels_is_exit_2_before_computing(coin, tmp_path, argv):
    path = tmp_path / "f.png"
    code, out, err = coin(*argv, "--out", str(path))
    _one_error(code, out, err, "--dpi", "--width", "50,000,000")
    assert not path.exists()


def test_pixel_cap_is_not_applied_to_a_text_plot(coin):
    code, out, err = coin("plot", "psi", "--terminal", "--width", "100", "--dpi", "2000")
    assert code == 0 and err == "" and "P(sides)" in out


def test_check_figure_size_limits():
    from coincli.render.figures import MAX_PIXELS, check_figure_size

    check_figure_size(10.0, 5.0, 1000.0)  # exactly MAX_PIXELS
    assert 10.0 * 5.0 * 1000.0**2 == MAX_PIXELS
    for w, h, dpi in [(10.0, 5.0, 1000.5), (math.nan, 4.5, 150.0), (7.0, math.inf, 150.0),
                      (7.0, 4.5, math.nan), (0.5, 4.5, 150.0), (7.0, 4.5, 5.0)]:
        with pytest.raises(ValueError):
            check_figure_size(w, h, dpi)


def test_figure_too_small_for_its_labels_is_exit_2_and_writes_nothing(coin, tmp_path, plotmod):
    """matplotlib printed "UserWarning: constrained_layout not applied because axes sizes
    collapsed to zero" and wrote a figure with its axes over the labels."""
    path = tmp_path / "f.png"
    code, out, err = coin("plot", "psi", "--width", "1", "--height", "1", "--out", str(path))
    _one_error(code, out, err, "--width", "too small")
    assert not path.exists()
    with pytest.raises(plotmod.FigureTooSmall):
        plotmod.save_figure(plotmod.psi_figure(plotmod.psi_data(0.5, points=11), width=1,
                                               height=1), str(path))
    assert not path.exists()


@pytest.mark.parametrize("argv, option, allowed", [
    (["plot", "sides", "--xi-range", "0:1e308"], "--xi-range", "HIGH <= 1e6"),
    (["plot", "sides", "--xi-range", "1e300:1e308"], "--xi-range", "HIGH <= 1e6"),
    (["plot", "sides", "--xi-range", "0:inf"], "--xi-range", "HIGH <= 1e6"),
    (["plot", "sides", "--xi-range", "nan:1"], "--xi-range", "0 <= LOW"),
    (["plot", "sides", "--xi-range", "0:5e-324"], "--xi-range", "HIGH - LOW >= 1e-6"),
    (["plot", "sides", "--xi-range", "1:1.0000000000000002"], "--xi-range", "HIGH - LOW"),
    (["plot", "sides", "--log", "--xi-range", "1e-300:1e300"], "--log", "1e-6 <= LOW"),
    (["plot", "sides", "--log", "--xi-range", "1:1e300"], "--log", "HIGH <= 1e6"),
    (["plot", "map", "--xi-range", "0:1e308"], "--xi-range", "HIGH <= 1e6"),
    (["plot", "map", "--log", "--xi-range", "1e-300:1"], "--log", "1e-6 <= LOW"),
    (["plot", "phase", "--u-range", "0:1e308"], "--u-range", "HIGH <= 1e8"),
    (["plot", "phase", "--u-range", "0:5e-324"], "--u-range", "HIGH - LOW >= 1e-6"),
    (["plot", "phase", "--omega-range", "0:1e300"], "--omega-range", "HIGH <= 1e12"),
    (["plot", "phase", "--omega-range", "0:inf"], "--omega-range", "rad/s"),
])
@pytest.mark.parametrize("where", ["file", "terminal"])
def test_axis_ranges_beyond_the_limits_are_exit_2(coin, tmp_path, argv, option, allowed,
                                                  where):
    """--xi-range 0:1e308 wrote the figure but printed matplotlib's RuntimeWarning (overflow in
    the tick arithmetic) on stderr; --log 1:1e300 failed with exit 1 after five warning lines;
    tiny spans crashed the text plot (math domain error)."""
    dest = ["--out", str(tmp_path / "f.png")] if where == "file" else ["--terminal"]
    code, out, err = coin(*argv, *dest)
    _one_error(code, out, err, option, allowed, "LOW:HIGH")


@pytest.mark.parametrize("argv, option, allowed", [
    (["plot", "psi", "--xi", "inf"], "--xi", "finite number >= 0"),
    (["plot", "psi", "--xi", "nan"], "--xi", "finite number >= 0"),
    (["plot", "psi", "--xi", "1e400"], "--xi", "finite number >= 0"),
    (["plot", "sides", "--xi", "0.5,inf"], "--xi", "finite number >= 0"),
    (["plot", "map", "--xi", "-inf"], "--xi", "finite number >= 0"),
    (["plot", "phase", "--xi", "inf"], "--xi", "finite number >= 0"),
    (["plot", "psi", "--psi", "inf"], "--psi", "[0, 180] degrees"),
    (["plot", "phase", "--psi", "nan"], "--psi", "[0, 180] degrees"),
    (["plot", "phase", "--toss", "inf:1"], "--toss", "finite numbers >= 0"),
    (["plot", "phase", "--toss", "1:nan"], "--toss", "finite numbers >= 0"),
    (["plot", "phase", "--xi", "0.5", "--diameter", "1e300"], "--diameter", "1e100 m"),
    (["plot", "phase", "--xi", "1e300", "--contact", "thick"], "--xi", "at most 1e100"),
])
def test_non_finite_values_say_what_is_allowed(coin, argv, option, allowed):
    """--xi inf said "--xi must be a number, got 'inf'", which does not say what is allowed."""
    code, out, err = coin(*argv, "--terminal")
    _one_error(code, out, err, option, allowed)
    assert "must be a number, got" not in err


# --------------------------------------------------------------------------- no warnings on stderr


@pytest.mark.parametrize("argv", [
    ["plot", "sides", "--xi-range", "0:1e6", "--xi", "1e6", "-p", "0.999"],
    ["plot", "sides", "--log", "--xi-range", "1e-6:1e6", "--psi", "0,180", "--psi-dist",
     "normal:0:0.001,uniform"],
    ["plot", "sides", "--xi-range", "0:1e-6"],
    ["plot", "sides", "--xi-range", "999999.999999:1e6"],
    ["plot", "map", "--log", "--xi-range", "1e-6:1e6", "--style", "ternary"],
    ["plot", "map", "--xi-range", "999999.999999:1e6", "--psi", "0,180"],
    ["plot", "psi", "--xi", "1e300", "--psi", "0,180"],
    ["plot", "psi", "--xi", "5e-324"],
    ["plot", "phase", "--u-range", "0:1e8", "--resolution", "20"],
    ["plot", "phase", "--u-range", "0:1e-6", "--omega-range", "0:1e-6", "--resolution", "20"],
    ["plot", "phase", "--omega-range", "999999999999.9999:1e12", "--resolution", "20"],
])
@pytest.mark.parametrize("where", ["png", "svg", "terminal"])
def test_extreme_allowed_ranges_draw_without_warnings(coin, tmp_path, argv, where):
    if where != "terminal":
        pytest.importorskip("matplotlib")
    path = tmp_path / f"f.{where}"
    dest = ["--terminal"] if where == "terminal" else ["--out", str(path), "--dpi", "40"]
    code, out, err = coin(*argv, *dest)
    assert code == 0, err
    if where == "terminal":
        assert err == ""
    else:  # the one line a tool that writes a file prints, and no warning
        lines = err.splitlines()
        assert lines[0].startswith(f"coin: wrote {path} (") and lines[0].endswith(")"), err
        assert all(n.startswith("coin: note: ") for n in lines[1:]), err
        assert out == "" and path.stat().st_size > 1000


@pytest.mark.parametrize("log, xi_range", [(False, (0.0, 1e6)), (True, (1e-6, 1e6)),
                                           (False, (0.0, 1e-6)), (True, (1e6 - 1e-6, 1e6))])
def test_figures_at_the_axis_limits_raise_no_warning(plotmod, tmp_path, log, xi_range):
    """Not only hidden by the command: at the limits matplotlib and numpy do not warn at all."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        d = plotmod.sides_data(xi_range=xi_range, log=log, points=51, xi_marks=[xi_range[1]],
                               p_marks=[0.3])
        plotmod.save_figure(plotmod.sides_figure(d), str(tmp_path / "s.png"), 40)
        m = plotmod.map_data(xi_range=xi_range, log=log, nx=21, ny=21, psi_marks_deg=[0, 180])
        plotmod.save_figure(plotmod.map_figure(m), str(tmp_path / "m.svg"), 40)


def test_marks_beyond_the_axis_limits_are_notes(coin, tmp_path, plotmod):
    """--xi 1.7e308 widened the axis to infinity: exit 1, "the xi range must be finite"."""
    d = plotmod.sides_data(xi_marks=[1.7e308, 0.5], points=11)
    assert d.xlim == (0.0, plotmod.XI_AXIS_MAX)
    assert any("1.7e+308 is outside the plotted range" in n for n in d.skipped)
    d = plotmod.sides_data(xi_marks=[1e-320], log=True, points=11)
    assert d.xlim[0] == plotmod.XI_LOG_MIN
    code, out, err = coin("plot", "sides", "--xi", "1.7e308", "--out", str(tmp_path / "f.png"),
                          "--dpi", "40")
    assert code == 0 and out == ""
    wrote, note = err.splitlines()
    assert wrote == f"coin: wrote {tmp_path / 'f.png'} (280 x 180 pixels)"
    assert note.startswith("coin: note: xi = 1.7e+308 is outside")
    code, out, err = coin("plot", "map", "--xi", "1.7e308", "--terminal")
    assert code == 0 and err == ""


def test_tosses_off_the_axis_are_a_note(plotmod):
    from coincli.io.experiments import parse_experiments

    pts = plotmod.experiment_points(parse_experiments(TOSSES))
    d = plotmod.sides_data(experiments=pts, xi_range=(0.0, 1.0), points=11)
    assert [n for n in d.skipped if "tosses" in n] == [
        "the tosses 'rod' at xi = 1.2 are outside the plotted range 0 to 1"]


def test_text_plot_ticks_survive_degenerate_axes():
    from coincli.render.text import _ticks

    assert _ticks(0.0, 5e-324, False) == [(0.0, "0"), (5e-324, "4.94066e-324")]
    assert _ticks(1.0, 1.0, False) == []
    assert _ticks(0.0, 1.0, True) == []
    assert _ticks(0.0, math.nan, False) == []


# --------------------------------------------------------------------------- NO_COLOR


class _Tty(io.StringIO):
    def isatty(self):
        return True


@pytest.mark.parametrize("no_color, escapes", [(None, True), ("", True), ("1", False)])
def test_text_plot_emit_honours_no_color(monkeypatch, no_color, escapes):
    from coincli.render.figures import psi_data
    from coincli.render.text import emit, text_psi

    for k in ("NO_COLOR", "FORCE_COLOR", "TTY_COMPATIBLE", "TTY_INTERACTIVE"):
        monkeypatch.delenv(k, raising=False)
    monkeypatch.setenv("TERM", "xterm-256color")
    if no_color is not None:
        monkeypatch.setenv("NO_COLOR", no_color)
    out = _Tty()
    emit(text_psi(psi_data(0.577, [70.0], points=70), 70, 21), out)
    text = out.getvalue()
    assert "P(heads)" in text
    assert ("\x1b[" in text) is escapes


def _on_a_terminal(argv, extra_env):
    """Run ``coin argv`` with stdout on a pseudo-terminal; return (exit code, stdout, stderr)."""
    master, slave = os.openpty()
    env = {k: v for k, v in os.environ.items() if k not in ("NO_COLOR", "FORCE_COLOR")}
    env.update({"TERM": "xterm-256color", "COLUMNS": "100", **extra_env})
    chunks = []

    def drain():  # read while the child writes: a full pty buffer would block it
        while True:
            try:
                data = os.read(master, 65536)
            except OSError:  # EIO: the terminal has no more writers
                return
            if not data:
                return
            chunks.append(data)

    reader = threading.Thread(target=drain, daemon=True)
    reader.start()
    try:
        p = subprocess.run([sys.executable, "-m", "coincli", *argv], stdout=slave,
                           stderr=subprocess.PIPE, env=env, timeout=120)
    finally:
        os.close(slave)
    reader.join(30)
    os.close(master)
    return p.returncode, b"".join(chunks).decode(), p.stderr.decode()


@pytest.mark.skipif(not hasattr(os, "openpty"), reason="needs a pseudo-terminal")
@pytest.mark.parametrize("sub", [["psi", "--xi", "0.577", "--psi", "70"], ["map", "--xi", "0.5"],
                                 ["sides", "-p", "1/3"]])
def test_no_color_on_a_terminal_removes_every_escape(sub):
    """NO_COLOR=1 coin plot psi --terminal on a terminal still wrote bold and italic codes."""
    argv = ["plot", *sub, "--terminal"]
    code, styled, err = _on_a_terminal(argv, {})
    assert code == 0 and err == "", err
    assert "\x1b[" in styled  # colour on a terminal
    code, plain, err = _on_a_terminal(argv, {"NO_COLOR": "1"})
    assert code == 0 and err == "", err
    assert "\x1b" not in plain
    assert "coin plot" in plain and "your" in plain


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
