"""The docs tell the truth: README's examples and the commands reference are today's output,
every command is shown on a guide page, every page is in the site's navigation, README stays
short, and CI runs exactly the test command README gives and builds the site.

The examples of the other pages (docs/*.md) are checked by ``.ci/run`` (``python
tools/render_docs.py --check``), not here: rendering them all re-runs bounce simulations and
takes well over a minute of CPU on a loaded machine, where README and the help reference take a
few seconds.
"""

from __future__ import annotations

import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
README = (ROOT / "README.md").read_text()
DOCS = ROOT / "docs"
COMMANDS = DOCS / "reference" / "commands.md"
RENDER = ROOT / "tools" / "render_docs.py"
TEST_COMMAND = "pip install '.[test]' && python -m pytest"


def _commands():
    import typer

    from coincli.cli import app

    group = typer.main.get_command(app)
    return group, sorted(group.commands)


def _guides() -> dict[str, str]:
    """Every hand-written page of the site (not the generated commands reference)."""
    return {str(p.relative_to(DOCS)): p.read_text() for p in sorted(DOCS.rglob("*.md"))
            if p != COMMANDS}


def _render_check(*pages: str) -> None:
    out = subprocess.run([sys.executable, str(RENDER), "--check", *pages], capture_output=True,
                         text=True, cwd=ROOT)
    assert out.returncode == 0, out.stdout + out.stderr


def test_ci_runs_the_readme_test_command_and_builds_the_site():
    blocks = [b.strip() for b in re.findall(r"```sh\n(.*?)```", README, re.S)]
    assert TEST_COMMAND in blocks
    ci = (ROOT / ".ci" / "run").read_text()
    assert "pip install --quiet '.[test]'" in ci
    assert re.search(r"^python -m pytest", ci, re.M)
    assert re.search(r"^python tools/render_docs\.py --check$", ci, re.M)
    assert re.search(r"^python -m mkdocs build --strict", ci, re.M)


def test_every_command_has_help_and_a_guide():
    group, names = _commands()
    assert {"design", "table", "stack", "coins", "fair"} <= set(names)
    guides = _guides()
    for name in names:
        cmd = group.commands[name]
        assert (cmd.help or "").strip(), f"coin {name} has no help text"
        shown = [page for page, text in guides.items() if f"coin {name}" in text]
        assert shown, f"no page of docs/ shows `coin {name}`"
    plot = group.commands["plot"]
    for sub in plot.commands:
        assert f"coin plot {sub}" in guides["plot.md"], f"docs/plot.md never shows coin plot {sub}"


def test_the_commands_reference_covers_every_command():
    group, names = _commands()
    text = COMMANDS.read_text()
    for name in names:
        assert f"\n## coin {name}\n" in text, f"docs/reference/commands.md has no coin {name}"
    for sub in group.commands["plot"].commands:
        assert f"\n## coin plot {sub}\n" in text


def test_every_page_is_in_the_nav_and_every_nav_entry_is_a_page():
    nav = set(re.findall(r"^\s+- [^:\n]+: ([\w./-]+\.md)\s*$", (ROOT / "mkdocs.yml").read_text(),
                         re.M))
    nav |= set(re.findall(r"^\s+- ([\w./-]+\.md)\s*$", (ROOT / "mkdocs.yml").read_text(), re.M))
    pages = {str(p.relative_to(DOCS)) for p in DOCS.rglob("*.md")}
    assert pages == nav, (f"not in the nav: {sorted(pages - nav)}; "
                          f"in the nav but missing: {sorted(nav - pages)}")


def test_readme_is_short_and_stands_alone():
    assert len(README.splitlines()) <= 250
    assert "arXiv:1008.4559" in README and "Yong and L. Mahadevan" in README
    for name, text in {"README.md": README, **_guides()}.items():
        assert "../shared" not in text, f"{name} points outside the repository"
    for placeholder in ("FEW_CPU", "FEW_MEM", "DISTINCT_CPU", "NOSPREAD_CPU", "FIT_FEW",
                        "FIT_DISTINCT", "FIT_NOSPREAD", "PLOT_FIGS", "<!-- more commands -->"):
        for name, text in {"README.md": README, **_guides()}.items():
            assert placeholder not in text, f"{name} still has {placeholder}"


def test_the_commands_reference_is_current():
    """docs/reference/commands.md is every --help of today (one child process, a few s)."""
    _render_check("docs/reference/commands.md")


@pytest.mark.skipif(shutil.which("coin") is None, reason="the coin script is not installed")
def test_readme_examples_are_current():
    _render_check("README.md")
