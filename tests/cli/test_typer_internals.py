"""The parts of typer (and its vendored click) that coin's command line relies on beyond typer's
documented interface, each named in :mod:`coincli.cli`'s docstring: a typer release that
changes one fails here, naming it, instead of changing coin's help or completion silently."""

from __future__ import annotations

import importlib.metadata
import inspect

import typer


def test_typer_is_in_the_pinned_range():
    major, minor = (int(p) for p in importlib.metadata.version("typer").split(".")[:2])
    assert (major, minor) >= (0, 26) and (major, minor) < (0, 29)


def test_the_app_attributes_read_lazily_exist():
    app = typer.Typer()
    assert isinstance(app.registered_commands, list)
    assert isinstance(app.registered_groups, list)
    assert hasattr(app, "_add_completion")


def test_the_click_hooks_exist():
    from typer._click.shell_completion import CompletionItem
    from typer.core import TyperOption

    assert "type" in inspect.signature(CompletionItem).parameters
    option = TyperOption(param_decls=["x", "--x"], is_flag=True, default=False, help="h")
    assert hasattr(option, "_custom_shell_complete")
    app = typer.Typer(add_completion=False)
    app.command()(lambda: None)
    command = typer.main.get_command(app)
    for attribute in ("rich_markup_mode", "format_options", "get_short_help_str"):
        assert hasattr(command, attribute), attribute


def test_the_lean_command_is_the_whole_one(coin):
    """A run builds only its command (coincli.cli._click_command): its help is the help the
    whole tree gives (through completion, which builds every command)."""
    from coincli.cli import _click_command, _prepare, app

    lean = _click_command(["fair", "--help"]).commands["fair"]
    whole = _prepare(typer.main.get_command(app)).commands["fair"]
    assert [p.opts for p in lean.params] == [p.opts for p in whole.params]
