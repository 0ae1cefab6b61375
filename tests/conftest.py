"""Shared pytest plumbing: a report that tests add lines to, printed in the terminal summary,
and ``coin``, the command run in-process."""

from __future__ import annotations

import io
import sys

import pytest

# the helper modules (mpmath references, CLI helpers) are imported by name from every layer
for _sub in ("reference", "cli"):
    _path = str(__import__("pathlib").Path(__file__).with_name(_sub))
    if _path not in sys.path:
        sys.path.insert(0, _path)

_REPORT: dict[str, list[str]] = {}


@pytest.fixture(scope="session")
def report():
    """``report(section, line)``: add a line under ``section`` to the end-of-run summary."""

    def add(section: str, line: str) -> None:
        _REPORT.setdefault(section, []).append(line)

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


def pytest_terminal_summary(terminalreporter):
    for section, lines in _REPORT.items():
        terminalreporter.write_sep("-", section)
        for line in lines:
            terminalreporter.write_line(line)
