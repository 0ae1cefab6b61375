"""One declaration per command (issue 36): the typer options of ``coin COMMAND``, the keywords of
``coincli.api.COMMAND`` and the parameters of its report all come from, or are checked against,
its :class:`coincli.requests.fields.Command`; a misspelled keyword is refused as the command
line refuses a misspelled option, naming the nearest."""

from __future__ import annotations

import inspect

import pytest
import typer

from coincli import api
from coincli.cli import app
from coincli.errors import InputError, UnknownInput
from coincli.requests import COMMANDS, command
from coincli.requests.fields import REQUIRED, Arg

#: each command's report function
REPORTS = {
    "design": ("design", "design"), "table": ("design", "table"), "stack": ("design", "stack"),
    "coins": ("design", "coins"), "fair": ("design", "fair"), "toss": ("toss", "toss"),
    "simulate": ("toss", "simulate"), "phase": ("phase", "phase"), "check": ("check", "check"),
    "fit": ("fit", "fit"), "book": ("book", "book"), "plot sides": ("plot", "sides"),
    "plot psi": ("plot", "psi"), "plot map": ("plot", "map"), "plot phase": ("plot", "phase"),
}


def _click(name: str):
    root = typer.main.get_command(app)
    cmd = root
    for word in name.split():
        cmd = cmd.commands[word]
    return cmd


@pytest.mark.parametrize("name", list(COMMANDS))
def test_the_cli_options_are_the_declaration(name):
    """Every click parameter is a declared one: the same python name, names, metavar, help,
    default, flag and hidden, in the declared order (``--no-headers`` and ``--help`` are added
    to every command that prints a table, by coincli.cli._help)."""
    from coincli.cli._help import prepare

    declared = command(name)
    params = [p for p in prepare(_click(name)).params
              if p.name not in ("no_headers", "help")]
    assert [p.name for p in params] == [p.name for p in declared.params]
    for click_param, p in zip(params, declared.params, strict=True):
        decl = p.decl
        if isinstance(decl, Arg):
            assert click_param.param_type_name == "argument"
            assert click_param.metavar == decl.metavar
            continue
        assert tuple(click_param.opts) + tuple(click_param.secondary_opts) == decl.names
        assert click_param.hidden == decl.more.get("hidden", False)
        assert bool(getattr(click_param, "is_flag", False)) == decl.flag
        if decl.metavar is not None:
            assert click_param.metavar == decl.metavar
        assert (click_param.help or None) == (decl.help.replace("\\[", "[") if decl.help
                                              else None)
        if p.default is REQUIRED:
            assert click_param.required
        else:
            assert click_param.default == p.default


API_FUNCTIONS = {name: getattr(api, name) for name in COMMANDS if " " not in name}


@pytest.mark.parametrize("name", list(API_FUNCTIONS))
def test_the_api_keywords_are_the_declaration(name):
    """``coincli.api.NAME``'s parameters are the declaration's api names, in order."""
    sig = inspect.signature(API_FUNCTIONS[name])
    assert tuple(sig.parameters) == command(name).api_names()


@pytest.mark.parametrize("name", list(COMMANDS))
def test_the_report_takes_every_declared_input(name):
    """The report function takes every input of the command, by the same name (the command
    forwards the whole request: ``report(**request)``)."""
    import importlib

    module, fn = REPORTS[name]
    report = getattr(importlib.import_module(f"coincli.reports.{module}"), fn)
    params = inspect.signature(report).parameters
    takes_any = any(p.kind is p.VAR_KEYWORD for p in params.values())
    missing = [p.name for p in command(name).params if p.name not in params]
    assert takes_any or not missing, missing


def test_a_misspelled_keyword_names_the_nearest():
    with pytest.raises(UnknownInput, match=r"coincli\.api\.design\(\) takes no 'diamter'; did "
                       r"you mean 'diameter' \(--diameter\)\?"):
        api.design(p_sides="1/3", diamter=30)
    with pytest.raises(TypeError):  # what Python raises for a wrong keyword
        api.check(xi=0.5, head=3)
    with pytest.raises(InputError, match=r"takes no 'fmt'"):  # a way of printing: cli only
        api.table(xi=0.5, fmt="csv")


def test_a_misspelled_option_names_the_nearest(coin):
    code, out, err = coin("design", "-p", "1/3", "--diamter", "30")
    assert code == 2 and out == ""
    assert "No such option: --diamter (Possible options: --diameter, --dt)" in err


@pytest.mark.parametrize("bad", [123, None, 1.5])
def test_fit_wants_a_path(bad):
    with pytest.raises(InputError, match="FILE: a path"):
        api.fit(bad)


def test_a_path_is_taken_where_a_file_is(tmp_path):
    import pathlib

    path = pathlib.Path(tmp_path) / "t.csv"
    path.write_text("label,xi,heads,sides,tails\nthin,0.3,45,12,43\n")
    assert api.fit(path, no_spread=True) == api.fit(str(path), no_spread=True)


def test_a_request_is_read_only():
    req = command("fair").request({"coin": "nickel"})
    assert req.coin == "nickel" and req.diameter is None and req.fmt == "table"
    with pytest.raises(AttributeError):
        req.coin = "dime"
    assert dict(req.output) == {"fmt": "table", "quiet": False}


def test_path_objects_are_taken_for_checkpoint_and_calibration(tmp_path):
    """Every file keyword takes a path object (os.PathLike), as the api's docstrings say."""
    import pathlib

    ck = pathlib.Path(tmp_path) / "run.ckpt"
    rows = api.simulate(xi=0.5, landing="bounce", tosses=4, seed=1, jobs=1, checkpoint=ck)
    assert ck.exists() and sum(r["count"] for r in rows) == 4
    assert api.simulate(xi=0.5, landing="bounce", tosses=4, seed=1, jobs=1,
                        checkpoint=str(ck)) == rows
    with pytest.raises(InputError, match="--calibration"):  # read as the path it names
        api.simulate(xi=0.5, landing="bounce", tosses=4, seed=1, jobs=1,
                     calibration=pathlib.Path(tmp_path) / "missing.json")
