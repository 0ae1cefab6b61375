"""The ``coin`` command: a thin typer layer over :mod:`coincli`.

Each command module registers its commands on :data:`app`; this module only runs it, turning
every failure into one line on stderr and an exit code (:class:`ExitCode`).  Nothing here or in
the command modules imports numpy, scipy or rich at import time: a closed-form answer must not
pay for them.
"""

from __future__ import annotations

import errno
import os
import sys

import typer

from coincli import __version__
from coincli.cli._common import CoinError, ExitCode

app = typer.Typer(
    name="coin",
    help="Design thick coins: the chances of heads, sides and tails of a tossed cylinder "
    "(Yong & Mahadevan).  Example: coin design --p-sides 1/3",
    no_args_is_help=True,
    add_completion=True,
    pretty_exceptions_enable=False,
    context_settings={"help_option_names": ["-h", "--help"]},
)


def _version(value: bool):
    if value:
        print(f"coin {__version__}")
        raise typer.Exit()


@app.callback()
def _root(
    version: bool = typer.Option(
        False, "--version", "-V", help="Print the version and exit.", is_eager=True,
        callback=_version,
    ),
    traceback: bool = typer.Option(
        False, "--traceback", help="On an unexpected error, show the Python traceback.",
    ),
):
    """Design thick coins: chances of heads, sides and tails (Yong & Mahadevan)."""
    if traceback:
        os.environ["COIN_TRACEBACK"] = "1"


# Command modules register themselves on import.  Keep their top level free of numpy/scipy/rich.
from coincli.cli import design as _design  # noqa: E402,F401

for _name in ("toss", "check", "plot", "methods", "book"):
    try:
        __import__(f"coincli.cli.{_name}")
    except ModuleNotFoundError as _exc:  # a command module not written yet
        if _exc.name != f"coincli.cli.{_name}":
            raise


def _fail(message: str, code: int) -> int:
    from coincli.cli._common import clip_message

    try:
        sys.stderr.write(f"coin: error: {clip_message(message)}\n")
        sys.stderr.flush()
    except (BrokenPipeError, ValueError, OSError):
        pass
    return int(code)


def run(argv=None) -> int:
    """Run ``coin`` with ``argv`` and return the exit code (never raises, never prints a trace)."""
    saved_traceback = os.environ.get("COIN_TRACEBACK")
    try:
        return _run(argv)
    finally:  # --traceback lasts one run (run() is also called in-process, by tests)
        if saved_traceback is None:
            os.environ.pop("COIN_TRACEBACK", None)
        else:
            os.environ["COIN_TRACEBACK"] = saved_traceback


def _run(argv) -> int:
    from typer.exceptions import TyperException

    try:
        argv = list(sys.argv[1:] if argv is None else argv)
        command = _click_command(argv)
        rv = command.main(argv, prog_name="coin", standalone_mode=False)
        if rv == ExitCode.INTERRUPTED:  # typer turns Ctrl-C into a silent Exit(130)
            return _fail("interrupted", ExitCode.INTERRUPTED)
        _flush_stdout()
        return int(rv) if isinstance(rv, int) else 0
    except CoinError as exc:
        return _fail(exc.message, exc.code)
    except TyperException as exc:
        code = getattr(exc, "exit_code", 2)
        msg = exc.format_message() if hasattr(exc, "format_message") else str(exc)
        msg = " ".join(msg.split())
        if not msg:  # `coin` alone: the help is already on stdout; no empty error line
            _flush_stdout()
            return int(code)
        return _fail(f"{msg} (see coin --help)" if code == 2 else msg, code)
    except typer.Exit as exc:
        return int(exc.exit_code)
    except typer.Abort:
        return _fail("aborted", ExitCode.INTERRUPTED)
    except KeyboardInterrupt:
        return _fail("interrupted", ExitCode.INTERRUPTED)
    except BrokenPipeError:
        return _quiet_broken_pipe()
    except SystemExit as exc:
        # typer turns EPIPE raised inside a command into sys.exit(1), even outside standalone
        # mode; the reader going away (`coin ... | head`) is a success.
        ctx = exc.__context__
        if isinstance(ctx, OSError) and ctx.errno == errno.EPIPE:
            sys.stdout = getattr(sys.stdout, "wrapped", sys.stdout)
            sys.stderr = getattr(sys.stderr, "wrapped", sys.stderr)
            return _quiet_broken_pipe()
        raise
    except (ValueError, ArithmeticError) as exc:
        if os.environ.get("COIN_TRACEBACK"):
            raise
        return _fail(str(exc), ExitCode.ERROR)
    except MemoryError:
        return _fail("out of memory; ask for fewer rows or samples", ExitCode.ERROR)
    except OSError as exc:
        return _fail(f"{exc.strerror or exc}", ExitCode.ERROR)
    except Exception as exc:  # pragma: no cover - a bug; say so in one line
        if os.environ.get("COIN_TRACEBACK"):
            raise
        return _fail(f"internal error: {type(exc).__name__}: {exc} (rerun with --traceback)",
                     ExitCode.ERROR)


def _click_command(argv):
    """The click command for ``argv``: the root group holding only the subcommand named.

    Turning a typer app into click commands inspects every parameter of every command (about
    10 ms for all of them, a fifth of a closed-form run); a run needs one.  The whole tree is
    built for help at the root, an unknown name (click then suggests one) and shell completion.
    """
    import copy

    name = next((a for a in argv if not a.startswith("-")), None)
    before = argv[: argv.index(name)] if name is not None else argv
    if name is None or any(a in ("-h", "--help") for a in before) or any(
            k.startswith("_COIN") and k.endswith("_COMPLETE") for k in os.environ):
        return typer.main.get_command(app)
    commands = [c for c in app.registered_commands
                if (c.name or typer.main.get_command_name(c.callback.__name__)) == name]
    groups = [g for g in app.registered_groups if g.name == name]
    if not commands and not groups:
        return typer.main.get_command(app)
    lean = copy.copy(app)
    lean.registered_commands, lean.registered_groups = commands, groups
    return typer.main.get_command(lean)


def _flush_stdout():
    try:
        sys.stdout.flush()
    except BrokenPipeError:
        _quiet_broken_pipe()


def _quiet_broken_pipe() -> int:
    # The reader went away (`coin ... | head`): stop quietly, and keep Python from complaining
    # when it flushes stdout at exit.
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
    except (OSError, ValueError):
        pass
    return 0


def main() -> None:
    """Console-script entry point."""
    sys.exit(run())
