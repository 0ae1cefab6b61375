"""Help screens in panels, whole command summaries, and shell completion of values."""

from __future__ import annotations

import os
import re
import subprocess
import sys

import pytest

from coincli.cli._help import BOUNCE_ONLY, BOUNCE_PANEL, PANELS


def _panels(text: str) -> dict[str, list[str]]:
    """The options listed under each panel title of a help screen."""
    out, title = {}, None
    for line in text.splitlines():
        if re.fullmatch(r"[A-Z][^:]*:", line):
            title = line[:-1]
            out[title] = []
        elif title and line.startswith("  -"):
            out[title].append(tuple(re.findall(r"(--[a-z0-9-]+)", line.split("  ")[1])))
    return out


@pytest.mark.parametrize("command", ["design", "simulate", "toss", "table", "check", "book"])
def test_every_option_is_under_its_declared_panel(coin, command):
    code, text, err = coin(command, "--help")
    assert code == 0 and err == ""
    panels = _panels(text)
    declared = dict(PANELS)
    seen = set()
    for title, options in panels.items():
        if title in ("Usage", "Examples", "Arguments"):
            continue
        for names in options:  # the names of one option, e.g. ('--n', '--tosses')
            seen.update(names)
            if set(names) & set(BOUNCE_ONLY.get(command, ())):
                assert title == BOUNCE_PANEL, (names, title)
            elif title in declared:
                assert set(names) & set(declared[title] + ("--help",)), (names, title)
    flat = {k: {n for names in v for n in names} for k, v in panels.items()}
    assert "--format" in flat["Output"] and "--help" in flat["Output"]
    assert "--format" in seen


def test_bounce_only_options_of_design_are_under_the_table_panel(coin):
    text = coin("design", "--help")[1]
    panels = {k: {n for names in v for n in names} for k, v in _panels(text).items()}
    for opt in ("--u", "--omega", "--seed", "--surface", "--max-tosses", "--jobs"):
        assert opt in panels[BOUNCE_PANEL], opt
        assert all(opt not in v for k, v in panels.items() if k != BOUNCE_PANEL), opt


def test_simulate_keeps_its_toss_options_in_the_toss_panel(coin):
    panels = {k: {n for names in v for n in names}
              for k, v in _panels(coin("simulate", "--help")[1]).items()}
    assert {"--u", "--omega", "--seed", "--tosses"} <= set(panels["Toss"])
    assert "--surface" in panels[BOUNCE_PANEL] and "--landing" in panels[BOUNCE_PANEL]


def test_root_summaries_are_whole_at_80_columns(coin):
    text = coin("--help")[1]
    body = text.split("Commands:")[1]
    assert "..." not in body
    assert "chance you want." in " ".join(body.split())


def _complete(words: str) -> list[str]:
    cword = len(words.split()) - (0 if words.endswith(" ") else 1)
    env = {**os.environ, "COMP_WORDS": words, "COMP_CWORD": str(cword),
           "_COIN_COMPLETE": "complete_bash"}
    p = subprocess.run([sys.executable, "-m", "coincli"], env=env, capture_output=True,
                       text=True, timeout=60)
    assert p.returncode == 0, p.stderr
    return [w for w in p.stdout.split("\n") if w]


@pytest.mark.parametrize("words, expected", [
    ("coin simulate --surface ", ["wood", "hard-floor", "felt", "rice"]),
    ("coin simulate --surface h", ["hard-floor"]),
    ("coin design --coin qu", ["quarter"]),
    ("coin toss --landing ", ["catch", "bounce"]),
    ("coin table --format js", ["json", "jsonl"]),
    ("coin design --model d", ["dynamic"]),
    ("coin toss --contact ", ["rim", "thick"]),
])
def test_values_complete(words, expected):
    assert _complete(words) == expected


def test_a_file_argument_completes_as_files():
    # bash falls back to file names (the completion script says -o default) on no candidate
    assert _complete("coin fit ") == []


@pytest.mark.parametrize("option", ["--resolution", "--cols", "--rows"])
def test_an_error_names_the_option_as_typed(coin, option):
    code, out, err = coin("plot", "phase", option, "abc", "--terminal")
    assert code == 2 and out == ""
    assert err.startswith(f"coin: error: {option} must be a whole number"), err
