"""The docs tell the truth: README examples are today's output, every command is documented,
and CI runs exactly the test command README gives."""

from __future__ import annotations

import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
README = (ROOT / "README.md").read_text()


def _commands():
    import typer

    from coincli.cli import app

    group = typer.main.get_command(app)
    return group, sorted(group.commands)


def test_ci_runs_the_readme_test_command():
    blocks = re.findall(r"```sh\n(.*?)```", README, re.S)
    test_cmd = blocks[1].strip()
    assert test_cmd == "pip install '.[test]' && python -m pytest"
    ci = (ROOT / ".ci" / "run").read_text()
    assert "pip install --quiet '.[test]'" in ci
    assert re.search(r"^python -m pytest", ci, re.M)


def test_every_command_has_help_and_a_readme_mention():
    group, names = _commands()
    assert {"design", "table", "stack", "coins", "fair"} <= set(names)
    for name in names:
        cmd = group.commands[name]
        assert (cmd.help or "").strip(), f"coin {name} has no help text"
        assert f"coin {name}" in README, f"README never shows `coin {name}`"


@pytest.mark.skipif(shutil.which("coin") is None, reason="the coin script is not installed")
def test_readme_examples_are_current():
    out = subprocess.run([sys.executable, str(ROOT / "tools" / "render_readme.py"), "--check"],
                         capture_output=True, text=True)
    assert out.returncode == 0, out.stdout + out.stderr
