"""Render what the docs show from what the code does: the examples of README.md and of every
page under docs/, and the commands reference, docs/reference/commands.md.

**Examples.**  An example is a fenced ```text block whose lines start with ``$ command``;
everything after a ``$`` line up to the next ``$`` line or the end of the block is that
command's output: stdout and stderr through one pipe, in the order a terminal shows them
(Python unbuffered, so an error line is not held back behind buffered output).  Commands run
from the repository root and see an 80 x 24 terminal (COLUMNS, LINES) unless the example states
its own size (``$ COLUMNS=60 coin ...``), and no colour (NO_COLOR).  Other blocks (```sh, an
untagged block of output, ```python) are left as they are: that is how a slow example (a
bounce simulation) shows a run without re-running it.

**Commands reference.**  docs/reference/commands.md is written whole from ``coin --help`` and
every ``coin COMMAND --help`` and ``coin plot SUBCOMMAND --help``, all read in one child
process at a fixed width (COLUMNS=80, TERM=dumb, NO_COLOR), in the order ``coin --help`` lists
them.

    python tools/render_docs.py                 # rewrite every page that is out of date
    python tools/render_docs.py --check         # exit 1 if any page is out of date
    python tools/render_docs.py --check README.md docs/reference/commands.md   # these only

A page named on the command line is rendered alone (README.md, docs/PAGE.md, or
docs/reference/commands.md for the help reference).
"""

from __future__ import annotations

import difflib
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
    check = "--check" in argv
    named = [a for a in argv if a != "--check"]
    targets = [(ROOT / a).resolve() for a in named] if named else pages()
    stale = []
    for path in targets:
        old = path.read_text() if path.exists() else ""
        new = rendered(path)
        if new == old:
            continue
        rel = path.relative_to(ROOT)
        stale.append(rel)
        if check:
            diff = list(difflib.unified_diff(old.splitlines(), new.splitlines(), f"{rel} (now)",
                                             f"{rel} (rendered)", lineterm="", n=1))
            print("\n".join(diff[:40] + (["..."] if len(diff) > 40 else [])))
        else:
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_text(new)
            print(f"wrote {rel}", file=sys.stderr)
    if check and stale:
        print(f"out of date: {', '.join(map(str, stale))}; run python tools/render_docs.py")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
