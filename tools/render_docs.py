"""Render what the docs show from what the code does: the examples of README.md and of every
page under docs/, and the commands reference, docs/reference/commands.md.

**Examples.**  An example is a fenced ```text block whose lines start with ``$ command``;
everything after a ``$`` line up to the next ``$`` line or the end of the block is that
command's output: stdout and stderr through one pipe, in the order a terminal shows them
(Python unbuffered, so an error line is not held back behind buffered output).  Commands run
from the repository root and see an 80 x 24 terminal (COLUMNS, LINES) unless the example states
its own size (``$ COLUMNS=60 coin ...``), and no colour (NO_COLOR).  Other blocks (```sh, an
untagged block of output, ```python) are left as they are (but see the next paragraph).

**Every output shown is today's, or says where it came from.**  ``--check`` also fails on an
*output block* that is not rendered: a fenced block with no language, ```text, ```console or
```output that does not start with a ``$`` line, or a block of any language with a ``$`` line
followed by lines that are not ``$`` lines (a transcript with its output), unless the line just
before the block (blank lines skipped) marks it as an excerpt with the version it came from,
"Excerpt, from coin X.Y.Z" (a caption, e.g. ``*Excerpt, from coin 0.2.0: ...*``).  That is
how a slow example (minutes of bounce simulation) shows a run without re-running it.  Commands
alone (```sh without output), code (```python) and diagrams (```tree) are not output.

**Figures.**  Each figure of :data:`FIGURES` is drawn by the command its page shows (which
must appear on a page verbatim); rendering redraws it, ``--check`` draws it into a temporary
directory and fails if it differs from the file in the repository by more than anti-aliasing
(:func:`figure_differs`; needs matplotlib, the ``plot`` extra).

**Commands reference.**  docs/reference/commands.md is written whole from ``coin --help`` and
every ``coin COMMAND --help`` and ``coin plot SUBCOMMAND --help``, all read in one child
process at a fixed width (COLUMNS=80, TERM=dumb, NO_COLOR), in the order ``coin --help`` lists
them.

    python tools/render_docs.py                 # rewrite every page that is out of date
    python tools/render_docs.py --check         # exit 1 if any page is out of date
    python tools/render_docs.py --check README.md docs/reference/commands.md   # these only

A page named on the command line is rendered alone (README.md, docs/PAGE.md, or
docs/reference/commands.md for the help reference; docs/fig-NAME.png for a figure).
"""

from __future__ import annotations

import difflib
import importlib.util
import os
import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
COMMANDS = DOCS / "reference" / "commands.md"
BLOCK = re.compile(r"```text\n(.*?)```", re.S)

#: the environment of every command run: a fixed terminal, no colour, unbuffered Python
ENV = {"NO_COLOR": "1", "COLUMNS": "80", "LINES": "24", "PYTHONUNBUFFERED": "1", "TERM": "dumb"}


def _env() -> dict:
    env = dict(os.environ, **ENV)
    for name in ("FORCE_COLOR", "CLICOLOR_FORCE", "COIN_TRACEBACK"):
        env.pop(name, None)
    return env


# --------------------------------------------------------------------------- examples


def run(cmd: str) -> str:
    """What ``cmd`` prints to a terminal (stdout and stderr, in order), run by the shell."""
    out = subprocess.run(cmd, shell=True, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                         text=True, cwd=ROOT, env=_env())
    return out.stdout


def render_block(body: str) -> str:
    cmds = [line[2:] for line in body.splitlines() if line.startswith("$ ")]
    if not cmds:
        return body
    return "".join(f"$ {c}\n{run(c)}" for c in cmds)


def render(text: str) -> str:
    """``text`` with every example block re-run."""
    return BLOCK.sub(lambda m: "```text\n" + render_block(m.group(1)) + "```", text)


# --------------------------------------------------------------------------- output blocks

#: a fenced block: its indentation, its language (info string) and its body
FENCE = re.compile(r"^([ \t]*)```([^\n`]*)\n(.*?)^\1```[ \t]*$", re.S | re.M)
#: the languages of a block that shows output
OUTPUT_TAGS = {"", "text", "console", "output"}
#: what marks a block as an excerpt: the version it came from
EXCERPT = re.compile(r"Excerpt, from coin \d+\.\d+\.\d+")


def unchecked_blocks(text: str) -> list[int]:
    """The first line (1-based) of every output block of ``text`` that is neither rendered (a
    ```text block whose first line is a ``$`` command) nor marked as an excerpt (the line just
    before it, blank lines skipped, says "Excerpt, from coin X.Y.Z")."""
    found = []
    for m in FENCE.finditer(text):
        tag = m.group(2).strip()
        lines = [line.strip() for line in m.group(3).splitlines()]
        if tag == "text" and lines and lines[0].startswith("$ "):
            continue  # rendered: re-run and compared
        after_command = False
        transcript = False
        for line in lines:
            if line.startswith("$ "):
                after_command = True
            elif line and after_command:
                transcript = True
                break
        if tag not in OUTPUT_TAGS and not transcript:
            continue
        before = [line for line in text[:m.start()].splitlines() if line.strip()]
        if before and EXCERPT.search(before[-1]):
            continue
        found.append(text.count("\n", 0, m.start()) + 1)
    return found


# --------------------------------------------------------------------------- figures

#: every figure of the docs and the command that draws it, as its page shows it
FIGURES = {
    "docs/fig-sides.png":
        "coin plot sides --p-sides 25% --data docs/fig-sides-tosses.csv --out docs/fig-sides.png",
    "docs/fig-psi.png": "coin plot psi --xi 0.577 --out docs/fig-psi.png",
    "docs/fig-map.png": "coin plot map --out docs/fig-map.png",
    "docs/fig-phase.png": "coin plot phase --out docs/fig-phase.png",
    "docs/fig-book.png": "coin book --size 235x155x30 --spin 0.4,40,0.3 --out docs/fig-book.png",
}
# docs/work-precision.png is benchmarks/work_precision.py's (a timing run, with its page)


def draw(figure: str, out: Path) -> str:
    """Draw ``figure`` (a key of FIGURES) to ``out`` with its command; what it printed."""
    cmd = FIGURES[figure].replace(f"--out {figure}", f"--out {out}")
    done = subprocess.run(cmd, shell=True, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                          text=True, cwd=ROOT, env=_env())
    if done.returncode != 0 or not out.exists():
        raise SystemExit(f"{FIGURES[figure]} failed (exit {done.returncode}):\n{done.stdout}")
    return done.stdout


def figure_differs(old: Path, new: Path, tolerance: float = 0.005) -> bool:
    """Whether two images differ by more than anti-aliasing: another size, or a mean absolute
    difference of the pixels (0 to 1) above ``tolerance`` (the same command draws the same
    bytes, 0; fig-phase.png's speed axis drawn to 3 m/s instead of 2 was 0.16, fig-sides.png's
    legend reworded 0.018)."""
    if not old.exists():
        return True
    from matplotlib.image import imread

    a, b = imread(old), imread(new)
    if a.shape != b.shape:
        return True
    return float(abs(a.astype(float) - b.astype(float)).mean()) > tolerance


# --------------------------------------------------------------------------- commands reference


#: run in one child process (a fixed terminal, no colour): every command's path after ``coin``
#: in the order of ``coin --help`` (a group's subcommands right after it) and its ``--help``,
#: printed as JSON.  ``coincli.cli.run`` is what the ``coin`` script runs.
HELP_SCRIPT = r"""
import contextlib, io, json, sys
import typer
from coincli.cli import app, run

def walk(cmd, path):  # typer's own click: no isinstance on click's classes
    yield path
    if hasattr(cmd, "list_commands"):
        ctx = cmd.context_class(cmd, info_name=" ".join(("coin",) + path))
        for name in cmd.list_commands(ctx):
            sub = cmd.get_command(ctx, name)
            if sub is not None and not sub.hidden:
                yield from walk(sub, path + (name,))

helps = []
for path in walk(typer.main.get_command(app), ()):
    buf = io.StringIO()
    with contextlib.redirect_stdout(buf), contextlib.redirect_stderr(buf):
        code = run([*path, "--help"])
    if code != 0:
        sys.exit(f"coin {' '.join(path)} --help exited {code}: {buf.getvalue()}")
    helps.append([list(path), buf.getvalue()])
print(json.dumps(helps))
"""


def helps() -> list[tuple[tuple[str, ...], str]]:
    """``(path, text)`` of every command's ``--help``, as an 80-column terminal without colour
    shows it (one child process for all: a few seconds at most)."""
    import json

    out = subprocess.run([sys.executable, "-c", HELP_SCRIPT], stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, text=True, cwd=ROOT, env=_env())
    if out.returncode != 0:
        raise SystemExit(f"the help of coin's commands could not be read:\n{out.stderr}")
    return [(tuple(path), text) for path, text in json.loads(out.stdout)]


INTRO = """\
# Commands

<!-- Written by tools/render_docs.py from each command's --help: do not edit by hand. -->

Every command's `--help`, as a terminal 80 columns wide shows it (`coin COMMAND --help`, or
`-h`: plain text with examples one a line).  How values are written is in
[Values, units and inputs](grammar.md), the machine columns in
[Output formats and columns](output.md), the exit codes in [Errors and exit codes](exit-codes.md).

`coin --version` prints the version.  Shell completion for bash, zsh and fish:
`coin --install-completion`, or `eval "$(_COIN_COMPLETE=source_bash coin)"` (`source_zsh`,
`source_fish`); any other `_COIN_COMPLETE` value is one error line, exit 2.
"""


def commands_page() -> str:
    parts = [INTRO]
    for path, text in helps():
        name = " ".join(("coin",) + path)
        parts.append(f"\n## {name}\n\n```text\n$ {name} --help\n{text}```\n")
    return "".join(parts)


# --------------------------------------------------------------------------- driver


def pages() -> list[Path]:
    """README.md and every Markdown page under docs/ (the commands reference is written, not
    rendered)."""
    found = sorted(p for p in DOCS.rglob("*.md") if p != COMMANDS)
    return [ROOT / "README.md", *found, COMMANDS]


def rendered(path: Path) -> str:
    if path == COMMANDS:
        return commands_page()
    return render(path.read_text())


def main(argv: list[str]) -> int:
    import shutil
    import tempfile

    check = "--check" in argv
    named = [a for a in argv if a != "--check"]
    figures = [f for f in named if f in FIGURES] if named else list(FIGURES)
    targets = [(ROOT / a).resolve() for a in named if a not in FIGURES] if named else pages()
    stale, unmarked = [], []
    for path in targets:
        old = path.read_text() if path.exists() else ""
        rel = path.relative_to(ROOT)
        if path != COMMANDS:
            unmarked += [f"{rel}:{line}" for line in unchecked_blocks(old)]
        new = rendered(path)
        if new == old:
            continue
        stale.append(rel)
        if check:
            diff = list(difflib.unified_diff(old.splitlines(), new.splitlines(), f"{rel} (now)",
                                             f"{rel} (rendered)", lineterm="", n=1))
            print("\n".join(diff[:40] + (["..."] if len(diff) > 40 else [])))
        else:
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_text(new)
            print(f"wrote {rel}", file=sys.stderr)
    if figures and importlib.util.find_spec("matplotlib") is None:
        print("figures not checked: matplotlib is not installed (pip install '.[plot]')",
              file=sys.stderr)
        figures = []
    if figures:
        shown = "\n".join(p.read_text() for p in pages())
        tmp = Path(tempfile.mkdtemp(prefix="render_docs-"))
        try:
            for figure in figures:
                if FIGURES[figure] not in shown:
                    stale.append(f"{figure} (no page shows `{FIGURES[figure]}`)")
                    continue
                out = tmp / Path(figure).name
                draw(figure, out)
                if figure_differs(ROOT / figure, out):
                    stale.append(figure)
                    if not check:
                        shutil.copyfile(out, ROOT / figure)
                        print(f"wrote {figure}", file=sys.stderr)
        finally:
            shutil.rmtree(tmp, ignore_errors=True)
    if unmarked:
        print("output blocks neither rendered (```text starting with a $ command) nor marked as "
              "an excerpt (a line 'Excerpt, from coin X.Y.Z' just before): "
              + ", ".join(unmarked))
    if check and stale:
        print(f"out of date: {', '.join(map(str, stale))}; run python tools/render_docs.py")
    return 1 if unmarked or (check and stale) else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
