"""Shared pytest plumbing: a report that tests add lines to, printed in the terminal summary."""

from __future__ import annotations

import pytest

_REPORT: dict[str, list[str]] = {}


@pytest.fixture(scope="session")
def report():
    """``report(section, line)``: add a line under ``section`` to the end-of-run summary."""

    def add(section: str, line: str) -> None:
        _REPORT.setdefault(section, []).append(line)

    return add


def pytest_terminal_summary(terminalreporter):
    for section, lines in _REPORT.items():
        terminalreporter.write_sep("-", section)
        for line in lines:
            terminalreporter.write_line(line)
