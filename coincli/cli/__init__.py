"""The ``coin`` command: a thin typer layer over :mod:`coincli`.

Each command module registers its commands on :data:`app`; this module only runs it, turning
every failure into one line on stderr and an exit code (:class:`ExitCode`).  Nothing here or in
the command modules imports numpy, scipy or rich at import time: a closed-form answer must not
pay for them.

**Where coin reaches into typer** (typer 0.26 to 0.28, which vendor click as ``typer._click``;
pyproject pins ``typer>=0.26,<0.29``; ``tests/cli/test_typer_internals.py`` checks each
assumption, so a typer that breaks one fails a test that names it):

- :class:`_App` reads ``registered_commands`` and ``registered_groups`` through a descriptor,
  so the command modules are imported when typer first reads them (help, completion), not at
  start-up; and a run builds a copy of the app holding the one command it runs
  (:func:`_click_command`, setting typer's private ``_add_completion``), since turning every
  command into click options costs a fifth of a closed-form run.
- :func:`_listing`: the root's help and click's "did you mean" are built from commands with no
  parameters (the same names and help).
- :func:`coincli.cli._help.prepare` sets click's ``rich_markup_mode`` to None (plain help),
  replaces ``format_options`` (the panels) and ``get_short_help_str`` (whole summaries), sets
  click's private ``_custom_shell_complete`` (the names an option completes to), and inserts a
  ``typer.core.TyperOption`` for ``--no-headers``.
"""

from __future__ import annotations

import errno
import os
import sys

import typer

from coincli import __version__
from coincli.signals import catch_signals, release_signals, stop_line
from coincli.cli._help import prepare as _prepare
from coincli.errors import CoinError, ExitCode, InputError, clip_message


class _Loaded:
    """An attribute of :class:`_App` that imports every command module on its first read."""

    def __set_name__(self, owner, name):
        self.slot = f"_{name}"

    def __get__(self, obj, owner=None):
        if obj is None:
            return self
        if not obj._complete:
            _load(COMMAND_MODULES)
        return getattr(obj, self.slot)

    def __set__(self, obj, value):
        setattr(obj, self.slot, value)


class _App(typer.Typer):
    """The root :class:`typer.Typer`, whose command modules are imported when its commands are
    first read (help, completion, ``typer.main.get_command(app)``), not when ``coin`` starts: a
    run imports only the module of the command it runs (:func:`_click_command`)."""

    _complete = False  #: every command module imported
    registered_commands = _Loaded()
    registered_groups = _Loaded()


app = _App(
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


# Command modules register their commands on ``app`` when imported, in this order (the order of
# the root's help).  Keep their top level free of numpy/scipy/rich.
COMMAND_MODULES = ("design", "toss", "check", "plot", "book")

#: the module that registers each command: a run imports that one alone.  Only a shortcut: a
#: name missing here, or registered elsewhere, is found by importing every module.
COMMAND_MODULE = {"design": "design", "table": "design", "stack": "design", "coins": "design",
                  "fair": "design", "toss": "toss", "simulate": "toss", "phase": "toss",
                  "check": "check", "fit": "check", "plot": "plot", "book": "book"}


#: what a word after a command that takes no argument was probably meant for
EXTRA_ARGUMENT_HINTS = {
    "coin check": "coin check takes counts (--heads, --sides, --tails; --same, --different); "
                  "a file of experiments is read by coin fit FILE",
}


def _load(modules) -> None:
    """Import command ``modules`` (names under ``coincli.cli``); all of them completes ``app``,
    its commands then in the order of :data:`COMMAND_MODULES` whatever was imported first."""
    complete = tuple(modules) == COMMAND_MODULES
    saved, app._complete = app._complete, True  # the modules' decorators append, not load
    try:
        for name in modules:
            __import__(f"coincli.cli.{name}")
    finally:
        app._complete = saved or complete
    if complete:
        rank = {f"coincli.cli.{m}": k for k, m in enumerate(COMMAND_MODULES)}

        def order(info):
            fn = info.callback if hasattr(info, "callback") and info.callback else None
            if fn is None and getattr(info, "typer_instance", None) is not None:
                fn = info.typer_instance.registered_callback
                fn = fn.callback if fn is not None else None
            return rank.get(getattr(fn, "__module__", ""), len(rank))

        app._registered_commands.sort(key=order)
        app._registered_groups.sort(key=order)


def _stopped() -> int:
    """One line for a run stopped by Ctrl-C, SIGTERM or SIGHUP (:mod:`coincli.signals`):
    ``interrupted``, ``terminated (SIGTERM)`` or ``hung up (SIGHUP)``, with the seed the run
    drew (if it drew one) so that it can be repeated; the exit code, 128 + the signal."""
    words, code = stop_line()
    options = sys.modules.get("coincli.io.options")  # loaded only if the run parsed a seed
    seed = options.drawn_seed() if options is not None else None
    if seed is not None:
        words += f" (seed {seed}: --seed {seed} repeats this run)"
    return _fail(words, code)


def _fail(message: str, code: int) -> int:
    if "\n" in message:  # a library's message over several lines: one line, always
        message = " ".join(line.strip() for line in message.splitlines() if line.strip())
    try:
        sys.stderr.write(f"coin: error: {clip_message(message)}\n")
        sys.stderr.flush()
    except (AttributeError, ValueError, OSError):  # stderr closed: the exit code still says it
        pass
    return int(code)


class StdoutClosed(OSError):
    """Standard output was closed when ``coin`` started (``coin ... >&-``)."""


class _ClosedStdout:
    """sys.stdout when fd 1 was closed: writing is an error, exit 1; a command that writes only
    a file (``--out``) still runs."""

    encoding, errors = "utf-8", "strict"

    def write(self, _text):
        raise StdoutClosed(errno.EBADF, "standard output is closed; nothing can be written")

    def isatty(self):
        return False

    def fileno(self):
        raise ValueError("standard output is closed")

    def flush(self):
        pass


class _Discard:
    """sys.stderr when fd 2 was closed: messages go nowhere, exit codes are unchanged."""

    encoding, errors = "utf-8", "backslashreplace"

    def write(self, text):
        return len(text)

    def isatty(self):
        return False

    def fileno(self):
        raise ValueError("standard error is closed")

    def flush(self):
        pass


def _guard_standard_streams() -> None:
    """Closed fds 0, 1 and 2 are held open on /dev/null (so no file ``coin`` opens can take
    their numbers, and a library writing to fd 2 writes nowhere), and Python's None streams are
    replaced: stdout by one whose writes fail (exit 1, one line), stderr by one that discards.
    A closed stdin stays None: a command that reads '-' says there is no standard input."""
    for fd in (0, 1, 2):
        try:
            os.fstat(fd)
        except OSError:
            try:
                got = os.open(os.devnull, os.O_RDWR)
                if got != fd:
                    os.dup2(got, fd)
                    os.close(got)
            except OSError:
                pass
    if sys.stdout is None:
        sys.stdout = _ClosedStdout()
    if sys.stderr is None:
        sys.stderr = _Discard()


def run(argv=None, *, gc_paused: bool = False) -> int:
    """Run ``coin`` with ``argv`` and return the exit code (never raises, never prints a trace).

    ``gc_paused``: the console script paused the garbage collector while starting up
    (:mod:`coincli.signals`); it is resumed, with every object so far frozen, once the command is
    built.

    SIGTERM and SIGHUP stop the run as Ctrl-C does (:mod:`coincli.signals`: workers ended,
    temporary files removed, the drawn seed said, exit 143 and 129); the handlers are this
    call's only, put back when it returns.

    No Python warning reaches stderr (``PYTHONWARNINGS=error`` cannot turn one into a failure):
    a library's warning is not the user's business once the answer is right; ``--traceback``
    shows them again.
    """
    import warnings

    saved_traceback = os.environ.get("COIN_TRACEBACK")
    _guard_standard_streams()
    previous = catch_signals()  # SIGTERM and SIGHUP end the run as Ctrl-C does
    try:
        with warnings.catch_warnings():
            if not saved_traceback and "--traceback" not in (argv or sys.argv):
                warnings.simplefilter("ignore")
            return _run(argv, gc_paused)
    finally:  # --traceback lasts one run (run() is also called in-process, by tests)
        release_signals(previous)
        if saved_traceback is None:
            os.environ.pop("COIN_TRACEBACK", None)
        else:
            os.environ["COIN_TRACEBACK"] = saved_traceback


def _run(argv, gc_paused: bool = False) -> int:
    from typer.exceptions import TyperException

    try:
        argv = list(sys.argv[1:] if argv is None else argv)
        if os.environ.get(COMPLETE_VAR):
            return _complete(os.environ[COMPLETE_VAR])
        command = _click_command(argv)
        options = sys.modules.get("coincli.io.options")
        if options is not None:  # run() may be called again in one process (tests)
            options.reset_drawn_seed()
        if gc_paused:
            _resume_gc()
        rv = command.main(argv, prog_name="coin", standalone_mode=False)
        if rv == ExitCode.INTERRUPTED:  # typer turns Ctrl-C (any Stopped) into Exit(130)
            return _stopped()
        _flush_stdout()
        return int(rv) if isinstance(rv, int) else 0
    except CoinError as exc:
        return _fail(exc.message, exc.code)
    except TyperException as exc:
        code = getattr(exc, "exit_code", 2)
        if type(exc).__name__ == "NoArgsIsHelpError":  # `coin`, `coin plot`: the help, exit 2
            sys.stdout.write(exc.format_message() + "\n")
            _flush_stdout()
            return int(code)
        msg = exc.format_message() if hasattr(exc, "format_message") else str(exc)
        msg = " ".join(msg.split())
        if not msg:  # `coin` alone: the help is already on stdout; no empty error line
            _flush_stdout()
            return int(code)
        ctx = getattr(exc, "ctx", None)
        where = getattr(ctx, "command_path", None) or "coin"
        hint = EXTRA_ARGUMENT_HINTS.get(where) if "unexpected extra argument" in msg else None
        if hint:
            msg = f"{msg}: {hint}"
        return _fail(f"{msg} (see '{where} --help')" if code == 2 else msg, code)
    except typer.Exit as exc:
        return int(exc.exit_code)
    except typer.Abort as exc:
        if isinstance(exc.__context__, KeyboardInterrupt):
            return _stopped()
        return _fail("aborted", ExitCode.INTERRUPTED)
    except KeyboardInterrupt:  # Ctrl-C, or SIGTERM/SIGHUP (coincli.signals.Stopped)
        return _stopped()
    except BrokenPipeError:
        return _quiet_broken_pipe()
    except StdoutClosed as exc:
        return _fail(exc.strerror, ExitCode.ERROR)
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


def _resume_gc() -> None:
    """Collect again, for the command's own work; what start-up built is frozen (it lives until
    exit, so scanning it would find nothing)."""
    import gc

    gc.freeze()
    gc.enable()


def _click_command(argv):
    """The click command for ``argv``: the root group holding only the subcommand named.

    Turning a typer app into click commands inspects every parameter of every command (about
    10 ms for all of them, a fifth of a closed-form run); a run needs one.  Help at the root and
    an unknown name (click then suggests one) need only each command's name and help: they get
    a listing (:func:`_listing`).  Shell completion builds the whole tree.
    """
    import copy

    name = next((a for a in argv if not a.startswith("-")), None)
    before = argv[: argv.index(name)] if name is not None else argv
    if name is None or any(a in ("-h", "--help") for a in before):
        return _prepare(typer.main.get_command(_listing(app)))
    if name in COMMAND_MODULE:
        _load([COMMAND_MODULE[name]])
    commands = [c for c in app._registered_commands if _command_name(c) == name]
    groups = [g for g in app._registered_groups if g.name == name]
    if not commands and not groups:  # not in the map: look in every module
        commands = [c for c in app.registered_commands if _command_name(c) == name]
        groups = [g for g in app.registered_groups if g.name == name]
    if not commands and not groups:  # an unknown name: click says so, suggesting one
        return _prepare(typer.main.get_command(_listing(app)))
    lean = copy.copy(app)
    lean._complete = True
    lean.registered_commands, lean.registered_groups = commands, groups
    if not before:  # no root option given: --install/--show-completion cannot be asked for
        lean._add_completion = False
    return _prepare(typer.main.get_command(lean))


def _command_name(info) -> str:
    return info.name or typer.main.get_command_name(info.callback.__name__)


def _listing(typer_app):
    """``typer_app`` with every command and group replaced by one without parameters: the same
    name, help, short help and flags, so the root's help and click's suggestions read exactly as
    from the whole tree, without turning every command's parameters into click options (about
    two thirds of the time of ``coin --help``)."""
    import copy
    import inspect

    def no_parameters():  # pragma: no cover - a listing is never invoked
        raise AssertionError("a command listing is only for help")

    commands = []
    for info in typer_app.registered_commands:
        stub = copy.copy(info)
        stub.name = _command_name(info)
        stub.help = info.help if info.help is not None else inspect.getdoc(info.callback)
        stub.callback = no_parameters
        commands.append(stub)
    groups = []
    for info in typer_app.registered_groups:
        stub, sub = copy.copy(info), copy.copy(info.typer_instance)
        sub.registered_commands, sub.registered_groups = [], []
        stub.typer_instance = sub
        groups.append(stub)
    lean = copy.copy(typer_app)
    lean._complete = True
    lean.registered_commands, lean.registered_groups = commands, groups
    return lean


COMPLETE_VAR = "_COIN_COMPLETE"
SHELLS = ("bash", "zsh", "fish")


def _complete(instruction: str) -> int:
    """Shell completion (``_COIN_COMPLETE=source_bash coin`` prints the script; the script sets
    ``complete_SHELL`` and the words).  Anything else is one error line, exit 2."""
    action, _, shell = instruction.partition("_")
    if action not in ("source", "complete") or shell not in SHELLS:
        raise InputError(f"{COMPLETE_VAR} must be source_SHELL or complete_SHELL with SHELL one "
                        f"of {', '.join(SHELLS)}; got {instruction!r}")
    if action == "complete" and shell == "bash":
        words, cword = os.environ.get("COMP_WORDS"), os.environ.get("COMP_CWORD", "")
        if words is None or not cword.strip().isdigit():
            raise InputError(f"{COMPLETE_VAR}=complete_bash needs COMP_WORDS and COMP_CWORD (a "
                            "whole number), as bash's completion sets them; to install it: "
                            f"eval \"$({COMPLETE_VAR}=source_bash coin)\"")
    from typer.completion import shell_complete

    return shell_complete(_prepare(typer.main.get_command(app), complete=True), {}, "coin",
                          COMPLETE_VAR, instruction)


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
