"""Shared pytest plumbing: a report that tests add lines to, printed in the terminal summary,
``coin``, the command run in-process, and ``plotmod``, the matplotlib figures' module.

The suite runs on every core (pytest-xdist, ``-n auto`` in pyproject.toml; ``-p no:xdist`` runs
it in one process).  A worker's report lines reach the summary through a folder of files that
the controlling process makes and reads (:envvar:`COIN_TEST_REPORT_DIR`)."""

from __future__ import annotations

import io
import json
import os
import shutil
import sys
import tempfile

import pytest

# the helper modules (mpmath references, CLI helpers) are imported by name from every layer
for _sub in ("reference", "cli"):
    _path = str(__import__("pathlib").Path(__file__).with_name(_sub))
    if _path not in sys.path:
        sys.path.insert(0, _path)

_REPORT: dict[str, list[str]] = {}
_REPORT_DIR = "COIN_TEST_REPORT_DIR"


def pytest_configure(config):
    if os.environ.get("PYTEST_XDIST_WORKER") is None:  # the controlling process (or the only)
        os.environ[_REPORT_DIR] = tempfile.mkdtemp(prefix="coin-test-report-")


@pytest.fixture(scope="session")
def report():
    """``report(section, line)``: add a line under ``section`` to the end-of-run summary."""
    worker = os.environ.get("PYTEST_XDIST_WORKER")

    def add(section: str, line: str) -> None:
        if worker is None:
            _REPORT.setdefault(section, []).append(line)
            return
        with open(os.path.join(os.environ[_REPORT_DIR], f"{worker}.jsonl"), "a") as f:
            f.write(json.dumps([section, line]) + "\n")

    return add


@pytest.fixture
def coin(capsys, monkeypatch):
    """``coin(*argv, stdin=None) -> (exit code, stdout, stderr)``, in-process through
    :func:`coincli.cli.run`; ``stdin`` is text, bytes or a file object."""
    from coincli.cli import run

    def call(*argv, stdin=None):
        if isinstance(stdin, (str, bytes)):
            data = stdin.encode() if isinstance(stdin, str) else stdin
            stdin = io.TextIOWrapper(io.BytesIO(data))
        if stdin is not None:
            monkeypatch.setattr(sys, "stdin", stdin)
        code = run([str(a) for a in argv])
        out, err = capsys.readouterr()
        return code, out, err

    return call


@pytest.fixture
def plotmod():
    """:mod:`coincli.render.figures`, the matplotlib figures (the test is skipped without
    matplotlib)."""
    pytest.importorskip("matplotlib")
    from coincli.render import figures

    return figures


def pytest_terminal_summary(terminalreporter):
    folder = os.environ.get(_REPORT_DIR)
    if folder and os.environ.get("PYTEST_XDIST_WORKER") is None and os.path.isdir(folder):
        for name in sorted(os.listdir(folder)):
            with open(os.path.join(folder, name)) as f:
                for row in f:
                    section, line = json.loads(row)
                    _REPORT.setdefault(section, []).append(line)
        shutil.rmtree(folder, ignore_errors=True)
    for section, lines in _REPORT.items():
        terminalreporter.write_sep("-", section)
        for line in lines:
            terminalreporter.write_line(line)
