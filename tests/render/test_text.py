"""coincli.render.text: the text plots of ``coin plot --terminal`` (the canvas, ticks, sizes,
the phase picture, NO_COLOR) on the builders themselves; the command is tested in
tests/cli/test_plot.py."""

from __future__ import annotations

import io
import math

import pytest


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


def test_text_plot_ticks_survive_degenerate_axes():
    from coincli.render.text import axis_ticks

    assert axis_ticks(0.0, 5e-324, False) == [(0.0, "0"), (5e-324, "4.94066e-324")]
    assert axis_ticks(1.0, 1.0, False) == []
    assert axis_ticks(0.0, 1.0, True) == []
    assert axis_ticks(0.0, math.nan, False) == []


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

# --------------------------------------------------------------------------- the canvas


def test_canvas_maps_the_range_onto_cells_and_refuses_what_is_outside():
    from coincli.render.text import Canvas

    cv = Canvas(11, 6, (0.0, 10.0), (0.0, 1.0))
    assert [cv.col(x) for x in (0.0, 5.0, 10.0, 10.4)] == [0, 5, 10, 10]  # half a cell: inside
    assert [cv.col(x) for x in (-0.6, 10.6, math.nan, math.inf)] == [None] * 4
    assert [cv.row(y) for y in (0.0, 0.2, 1.0)] == [5, 4, 0]  # row 0 is the top
    assert cv.row(1.2) is None and cv.row(math.nan) is None
    log = Canvas(11, 6, (1.0, 1e10), (0.0, 1.0), logx=True)
    assert [log.col(x) for x in (1.0, 1e5, 1e10)] == [0, 5, 10]  # decades equally spaced
    assert log.col(0.0) is None and log.col(-1.0) is None
    assert (Canvas(3, 2, (0.0, 1.0), (0.0, 1.0)).cols, Canvas(3, 2, (0, 1), (0, 1)).rows) == (10, 5)


def test_canvas_higher_layers_win_and_curves_have_no_vertical_gaps():
    from coincli.render.text import Canvas

    cv = Canvas(11, 6, (0.0, 10.0), (0.0, 1.0))
    cv.put(0, 5, "y", layer=3)
    cv.put(0, 5, "z", layer=0)  # below: does not cover
    assert cv.cells[5][0][0] == "y"
    cv.put(0, 5, "w", layer=3)  # the same layer: the later one
    assert cv.cells[5][0][0] == "w"
    cv.put(-1, 0, "q")
    cv.put(11, 0, "q")  # off the grid: nothing
    assert all(ch != "q" for row in cv.cells for ch, _, _ in row)
    # a steep step between neighbouring columns is joined: one cell in every row, half the run
    # in each column
    cv = Canvas(11, 6, (0.0, 10.0), (0.0, 1.0))
    cv.plot([0.0, 1.0], [0.0, 1.0], "a")
    grid = ["".join(ch for ch, _, _ in row) for row in cv.cells]
    assert [g.index("a") for g in grid] == [1, 1, 1, 0, 0, 0]
    assert all(g.count("a") == 1 for g in grid)
    # a point outside the range breaks the curve instead of joining across it
    cv = Canvas(11, 6, (0.0, 10.0), (0.0, 1.0))
    cv.plot([0.0, 1.0, 2.0], [0.0, 5.0, 1.0], "b")
    assert sum(ch == "b" for row in cv.cells for ch, _, _ in row) == 2


def test_canvas_render_draws_axes_ticks_legend_and_notes():
    from coincli.render.text import Canvas

    cv = Canvas(11, 6, (0.0, 10.0), (0.0, 1.0))
    cv.point(10.0, 1.0, "p", "bold")
    cv.vline(5.0, ":")
    text = cv.render(title="T", xlabel="x", ylabel="y", xticks=[(0.0, "0"), (10.0, "10")],
                     yticks=[(0.0, "0"), (1.0, "1")], legend=[("p", "bold", "a point\nwrapped")],
                     notes=["n1"])
    assert text.plain.splitlines() == [
        "T",
        "  y",
        "1 +     :    p",
        "  |     :",
        "  |     :",
        "  |     :",
        "  |     :",
        "0 +     :",
        "  +-----------",
        "   0        10",
        "        x",
        "  p  a point",
        "     wrapped",
        "  note: n1",
    ]
    assert not any(line.endswith(" ") for line in text.plain.splitlines())
    assert [s.style for s in text.spans if text.plain[s.start:s.end] == "p"][:1] == ["bold"]


# --------------------------------------------------------------------------- ticks and sizes


def test_ticks_are_round_steps_or_decades():
    from coincli.render.text import _round_ticks, axis_ticks

    assert [s for _, s in axis_ticks(0.0, 1.0, False)] == ["0", "0.2", "0.4", "0.6", "0.8", "1"]
    assert [s for _, s in axis_ticks(0.0, 10.0, False, 3)] == ["0", "5", "10"]
    assert [s for _, s in axis_ticks(0.0, 180.0, False)] == ["0", "50", "100", "150"]  # 2.5 x 10^1 > 36
    assert axis_ticks(0.5, 2000.0, True) == [(1.0, "1"), (10.0, "10"), (100.0, "100"),
                                          (1000.0, "1000")]
    # a tick a cell at most, each in the cell that holds it
    assert _round_ticks(0.0, 10.0, 10, 5) == [(0, "0"), (5, "5"), (9, "10")]


def test_plot_size_is_the_given_one_or_the_terminals_less_the_labels(monkeypatch):
    import coincli.io.terminal as terminal
    from coincli.render.text import plot_size

    assert plot_size(50, 12) == (50, 12)
    assert plot_size(3, 2) == (10, 5)  # the smallest canvas
    for cols, width in [(80, 70), (200, 110), (20, 30)]:  # 30 to 110 columns
        monkeypatch.setattr(terminal, "terminal_width", lambda cols=cols: cols)
        assert plot_size() == (width, 21)
    assert plot_size(None, None, default_rows=9)[1] == 9


# --------------------------------------------------------------------------- the phase picture


def _phase(outcome, marks=()):
    from types import SimpleNamespace

    from coincli.core.models import Outcome

    nw, nu = len(outcome), len(outcome[0])
    return SimpleNamespace(
        xi=0.5, psi_deg=90.0, outcome=outcome, u=[(j + 0.5) * 2.0 / nu for j in range(nu)],
        u_range=(0.0, 2.0), omega_range=(0.0, 60.0), curves=[], marks=list(marks),
        fractions=Outcome(0.5, 0.25, 0.25), vigorous=Outcome(0.4, 0.2, 0.4),
        exact_curves=False)


def test_phase_text_is_one_letter_a_cell_with_omega_upwards():
    from coincli.render.text import phase_text, phase_title

    # rows of omega from the bottom: the first row (low spin) is printed last
    data = _phase([[0, 0, 1, 1], [2, 2, 0, 0]], marks=[(1.9, 50.0)])
    title = phase_title(data, "rim")
    assert title == "Fig. 3: outcome over (u, omega); xi = 0.5, psi = 90 deg, rim contact"
    text = phase_text(data, colour=False, title=title)
    assert isinstance(text, str)
    lines = text.splitlines()
    assert lines[0] == title and lines[1] == "omega (rad/s)"
    # the toss at u = 1.9, omega = 50 is the X; ticks at round values, one a cell
    assert lines[2:7] == ["  |TTHX", "0 +HHSS", "  ++--+", "   0  2", "   u (m/s)"]
    assert "H heads 50.0%" in text and "S sides 25.0%" in text and "T tails 25.0%" in text
    assert "X your toss" in text and "X your tosses" not in text
    assert "vigorous limit (Table I): heads 0.400, sides 0.200, tails 0.400" in text
    assert "boundary" not in text  # no curves, no boundary entry


def test_phase_text_in_colour_is_blocks_and_the_same_legend():
    from coincli.render.text import PHASE_BLOCK, phase_text

    data = _phase([[0, 0, 1, 1], [2, 2, 0, 0]])
    text = phase_text(data, colour=True, title="t")
    assert "HHSS" not in text.plain and "heads 50.0%" in text.plain
    styles = {str(s.style) for s in text.spans}
    assert {PHASE_BLOCK["heads"], PHASE_BLOCK["sides"], PHASE_BLOCK["tails"]} <= styles
    plain = phase_text(data, colour=False, title="t")
    assert len(text.plain.splitlines()) == len(plain.splitlines())

