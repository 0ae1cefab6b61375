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


# --------------------------------------------------------------------------- output blocks


def _render_docs():
    """tools/render_docs.py as a module (it is a script, not part of the package)."""
    import importlib.util

    spec = importlib.util.spec_from_file_location("render_docs", RENDER)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_every_output_block_is_rendered_or_marked_as_an_excerpt():
    """An output shown on a page is re-run by render_docs.py --check, or says where it came
    from: no block of old output passes for today's (issue 38, item 19)."""
    rd = _render_docs()
    unmarked = {str(p.relative_to(ROOT)): rd.unchecked_blocks(p.read_text())
                for p in rd.pages() if p != COMMANDS}
    assert {page: lines for page, lines in unmarked.items() if lines} == {}


UNMARKED = [
    "```\ncoin design\nxi = h/D  0.5\n```\n",                         # no language
    "```text\ncoin design\nxi = h/D  0.5\n```\n",                     # text without a command
    "```console\nxi = h/D  0.5\n```\n",
    "```sh\n$ coin design -p 1/3\nxi = h/D  0.5\n```\n",              # a transcript
    "- a list\n\n  ```sh\n  $ cat a.csv\n  x,y\n  ```\n",              # indented, in a list
    "Excerpt:\n\n```\nxi = h/D  0.5\n```\n",                          # no version
    "*Excerpt, from coin 0.2.0*\n\nmore text\n\n```\nxi 0.5\n```\n",  # not just before
]
MARKED_OR_NOT_OUTPUT = [
    "```text\n$ coin design -p 1/3 -q\n0.57735\n```\n",               # rendered
    "```sh\ncoin design -p 1/3      # a comment\n```\n",              # commands alone
    "```sh\n$ coin fit a.csv --save t.json\n$ coin design --calibration t.json\n```\n",
    "```python\nx = 1   # 1\n```\n",
    "```tree\ncoincli/\n  cli/\n```\n",
    "*Excerpt, from coin 0.2.0 (minutes of simulation):*\n\n```\nxi = h/D  0.5\n```\n",
    "- a list\n\n  *Excerpt, from coin 0.2.0, abridged.*\n\n  ```sh\n  $ coin fit a.csv\n  f 0.3\n"
    "  ```\n",
]


@pytest.mark.parametrize("page", UNMARKED)
def test_an_output_block_neither_rendered_nor_an_excerpt_is_found(page):
    assert _render_docs().unchecked_blocks("# A page\n\n" + page) == [3 + page.count("\n", 0,
                                                                         page.index("```"))]


@pytest.mark.parametrize("page", MARKED_OR_NOT_OUTPUT)
def test_a_rendered_block_an_excerpt_or_code_is_not_an_unchecked_output(page):
    assert _render_docs().unchecked_blocks("# A page\n\n" + page) == []


def test_the_check_fails_on_an_unmarked_output_block(tmp_path, monkeypatch, capsys):
    rd = _render_docs()
    monkeypatch.setattr(rd, "ROOT", tmp_path)
    page = tmp_path / "README.md"
    page.write_text("# coin\n\nOld output:\n\n```\nxi = h/D  0.492841\n```\n")
    assert rd.main(["--check", "README.md"]) == 1
    out = capsys.readouterr().out
    assert "README.md:5" in out and "Excerpt, from coin X.Y.Z" in out
    page.write_text("# coin\n\n*Excerpt, from coin 0.2.0:*\n\n```\nxi = h/D  0.492841\n```\n")
    assert rd.main(["--check", "README.md"]) == 0


def test_every_guide_is_in_the_what_to_read_lists():
    """README's "Read more" and docs/index.md's "What to read" list every guide of the nav
    (calibration and the cluster were missing: issue 38, item 19)."""
    nav = (ROOT / "mkdocs.yml").read_text()
    guides = re.search(r"^  - Guides:\n((?:      - .*\n)+)", nav, re.M).group(1)
    pages = re.findall(r": ([\w-]+\.md)$", guides, re.M)
    assert "calibration.md" in pages and "cluster.md" in pages
    index = (DOCS / "index.md").read_text()
    for page in pages:
        assert f"(docs/{page})" in README, f"README's Read more does not list docs/{page}"
        assert f"]({page})" in index, f"docs/index.md's What to read does not list {page}"


def test_every_figure_is_drawn_by_a_command_a_page_shows():
    rd = _render_docs()
    shown = "\n".join(p.read_text() for p in rd.pages())
    for figure, command in rd.FIGURES.items():
        assert (ROOT / figure).exists()
        assert command in shown, f"no page shows `{command}`"
        assert f"--out {figure}" in command
    pictures = {str(p.relative_to(ROOT)) for p in DOCS.glob("fig-*.png")}
    assert pictures == set(rd.FIGURES)


def test_a_figure_differs_when_drawn_otherwise(tmp_path):
    pytest.importorskip("matplotlib")
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rd = _render_docs()

    def figure(name, top):  # a band over 0 to top of an axis from 0 to 3 (fig-phase's change)
        fig, ax = plt.subplots(figsize=(4, 3), dpi=50)
        ax.axvspan(0, top, color="tab:blue")
        ax.set_xlim(0, 3)
        fig.savefig(tmp_path / name)
        plt.close(fig)
        return tmp_path / name

    a, b, c = figure("a.png", 2), figure("b.png", 2), figure("c.png", 3)
    assert not rd.figure_differs(a, b)
    assert rd.figure_differs(a, c)
    assert rd.figure_differs(tmp_path / "missing.png", a)


def test_the_install_section_leads_with_a_checkout_and_documents_completion():
    """thickcoin is not on the package index yet: README's and the home page's first install
    lines work from a checkout; shell completion is in both (issue 38, items 18 and 20)."""
    index = (DOCS / "index.md").read_text()
    for name, text in {"README.md": README, "docs/index.md": index}.items():
        install = text[text.index("## Install"):]
        first = re.search(r"```sh\n(.*?)```", install, re.S).group(1).splitlines()[0]
        assert first.startswith("pipx install ."), f"{name}: {first}"
        assert "not on the package index yet" in " ".join(install.split())
        assert "coin --install-completion" in text and "_COIN_COMPLETE=source_bash coin" in text
