"""coincli.render.progress: the progress bar of long runs, drawn on stderr and only on a
terminal (``stderr_is_terminal`` is patched: the test run's stderr is not one)."""

from __future__ import annotations

import io
import sys

import pytest

import coincli.render.progress as progress


@pytest.fixture
def terminal(monkeypatch):
    """stderr is a terminal (a buffer, returned), as far as the bar can tell."""
    monkeypatch.setattr(progress, "stderr_is_terminal", lambda: True)
    buf = io.StringIO()
    monkeypatch.setattr(sys, "stderr", buf)
    return buf


def test_progress_bar_draws_on_stderr_only_after_a_second(monkeypatch):
    import coincli.render.progress as acc

    monkeypatch.setattr(acc, "stderr_is_terminal", lambda: True)
    buf = io.StringIO()
    monkeypatch.setattr(sys, "stderr", buf)
    bar = acc.ProgressBar("mc test", delay=3600)
    bar(10, 100)
    assert bar.bar is None  # not within the delay
    bar = acc.ProgressBar("mc test", delay=0)
    bar(10, 100)
    assert bar.bar is not None
    bar(100, 100)
    bar.close()


def test_no_bar_off_a_terminal(monkeypatch, capsys):
    monkeypatch.setattr(progress, "stderr_is_terminal", lambda: False)
    for bar in (progress.ProgressBar("tossing", 10), progress.ProgressBar("mc", delay=0)):
        assert not bar.enabled
        with bar:
            bar(5)
            bar(7, 20)
            assert bar.bar is None
    assert capsys.readouterr() == ("", "")


def test_a_delayed_bar_is_not_drawn_for_the_last_report(terminal):
    bar = progress.ProgressBar("mc", delay=0)
    bar(100, 100)  # done: nothing left to show
    assert bar.bar is None
    bar(10, 100)
    assert bar.bar is not None
    bar.close()


def test_a_bar_has_its_columns_follows_the_total_and_is_gone_at_the_end(terminal, capsys):
    with progress.ProgressBar("tossing", 1000, unit="tosses") as bar:
        assert bar.bar is not None  # drawn on entering the block (no delay)
        columns = bar.bar.columns
        assert columns[0] == "tossing" and columns[2:4] == ("{task.completed:,}/{task.total:,}",
                                                            "tosses")
        assert type(columns[-1]).__name__ == "TimeRemainingColumn"
        bar(500)
        task = bar.bar.tasks[0]
        assert (task.completed, task.total) == (500, 1000)
        bar(600, 100)  # a new total, never below what is done
        task = bar.bar.tasks[0]
        assert (task.completed, task.total) == (600, 600)
    assert bar.bar is None
    bar.close()  # twice is harmless
    assert capsys.readouterr().out == ""  # never on stdout


def test_the_commands_bars(terminal):
    assert not progress.tossing_bar(199_999).enabled  # short runs: no bar
    assert progress.tossing_bar(200_000).enabled
    assert progress.tossing_bar(10, least=5).enabled
    sim = progress.simulating_bar()
    assert (sim.label, sim.unit, sim.elapsed, sim.delay) == ("simulating", "tosses", True, None)
    with sim:
        assert type(sim.bar.columns[-1]).__name__ == "TimeElapsedColumn"
        sim(10, 180)
        sim(180, 540)  # the plan grows
        task = sim.bar.tasks[0]
        assert (task.completed, task.total) == (180, 540)
    est = progress.estimator_bar("uniform: mc")
    assert (est.label, est.delay) == ("uniform: mc", 1.0)
