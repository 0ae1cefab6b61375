"""Re-run every example in README.md and paste what the command prints today.

An example is a fenced ```text block whose lines start with ``$ command``; everything after a
``$`` line up to the next ``$`` line or the end of the block is that command's output: stdout
and stderr through one pipe, in the order a terminal shows them (Python unbuffered, so an
error line is not held back behind buffered output).  Commands see an 80 x 24 terminal
(COLUMNS, LINES) unless the example states its own size (``$ COLUMNS=60 coin ...``), and no
colour (NO_COLOR).

    python tools/render_readme.py           # rewrite README.md in place
    python tools/render_readme.py --check   # exit 1 if README.md is out of date
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
BLOCK = re.compile(r"```text\n(.*?)```", re.S)


def run(cmd: str) -> str:
    env = dict(os.environ, NO_COLOR="1", COLUMNS="80", LINES="24", PYTHONUNBUFFERED="1")
    out = subprocess.run(cmd, shell=True, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                         text=True, cwd=ROOT, env=env)
    return out.stdout


def render_block(body: str) -> str:
    cmds = [line[2:] for line in body.splitlines() if line.startswith("$ ")]
    if not cmds:
        return body
    return "".join(f"$ {c}\n{run(c)}" for c in cmds)


def render(text: str) -> str:
    return BLOCK.sub(lambda m: "```text\n" + render_block(m.group(1)) + "```", text)


def main() -> int:
    path = ROOT / "README.md"
    old = path.read_text()
    new = render(old)
    if "--check" in sys.argv[1:]:
        if new != old:
            print("README.md examples are out of date: run python tools/render_readme.py")
            return 1
        return 0
    path.write_text(new)
    return 0


if __name__ == "__main__":
    sys.exit(main())
