"""coin plot: files of each format are written, the text plots work without matplotlib, errors
are one line.  What the figures and text plots show (the core's numbers, the designs and data
where they belong) is tested on the builders themselves, in tests/render.
"""

from __future__ import annotations

import os
import subprocess
import sys
import threading
from pathlib import Path

import pytest

#: three experiments: stacks of quarters and a rod (tests/render reads the same file)
TOSSES = (Path(__file__).resolve().parents[1] / "data" / "plot_tosses.csv").read_text()


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


# --------------------------------------------------------------------------- files


@pytest.mark.parametrize("fmt, magic", [("png", b"\x89PNG"),
                                        pytest.param("svg", b"<?xml", marks=pytest.mark.slow),
                                        pytest.param("pdf", b"%PDF", marks=pytest.mark.slow)])
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


@pytest.mark.slow
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
@pytest.mark.parametrize("where", [pytest.param("png", marks=pytest.mark.slow),
                                   pytest.param("svg", marks=pytest.mark.slow), "terminal"])
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


@pytest.mark.slow
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


# --------------------------------------------------------------------------- NO_COLOR


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


@pytest.mark.slow
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
