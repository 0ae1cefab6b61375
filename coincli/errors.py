"""The errors ``coin`` reports, in one place, and the exit code of each.

Every error is one line (its message); the command line prints ``coin: error: MESSAGE`` and exits
with the code its class carries, and :mod:`coincli.api` raises the same object, so a notebook
sees the message a shell user sees.

- :class:`InputError` (a :class:`ValueError`): the input is wrong: an option, a value, a file
  line or a combination.  Exit 2.
- :class:`NotComputable` (an :class:`ArithmeticError`): the input is valid but the answer cannot
  be computed.  Exit 1.  :class:`Unfollowable` is the case of a toss whose motion double
  precision cannot follow; its ``reason`` says why.
- :class:`PhysicsMissing` and :class:`MatplotlibMissing` (both :class:`ImportError`): an optional
  engine is not installed; the message says how to install it.  Exit 1.

This module imports nothing: the closed-form path stays as light as it is.
"""

from __future__ import annotations

import enum

__all__ = [
    "ExitCode",
    "CoinError",
    "InputError",
    "NotComputable",
    "Unfollowable",
    "PhysicsMissing",
    "MatplotlibMissing",
    "INSTALL_HINT",
]

#: how to install an optional extra of this project (never the unrelated ``coincli`` package)
INSTALL_HINT = ("pip install -U 'thickcoin[{extra}]' (from a checkout: pip install '.[{extra}]')")


def install_hint(extra: str) -> str:
    """The one-line install hint for the optional ``extra`` (``physics``, ``plot``, ...)."""
    return INSTALL_HINT.format(extra=extra)


class ExitCode(enum.IntEnum):
    """Exit codes of ``coin``; part of its public interface."""

    OK = 0
    ERROR = 1  #: the input is valid but the answer cannot be computed
    USAGE = 2  #: the input is wrong: a bad option, value, file line or combination
    HANGUP = 129  #: SIGHUP
    INTERRUPTED = 130  #: Ctrl-C
    TERMINATED = 143  #: SIGTERM


class CoinError(Exception):
    """An error to print as one line on stderr, with its exit code.

    The message is passed through :func:`coincli.io.table.clip_message`: a quoted value longer
    than 60 characters (a 10,000-character option, a 5 MB stdin line) is cut short.
    """

    code: ExitCode = ExitCode.ERROR

    def __init__(self, message: str, code: ExitCode | None = None):
        from coincli.io.table import clip_message

        message = clip_message(str(message))
        super().__init__(message)
        self.message = message
        if code is not None:
            self.code = code

    def __reduce__(self):  # picklable across processes (a worker's error reaches the parent)
        return (type(self), (self.message, self.code))


class InputError(CoinError, ValueError):
    """The input is wrong (exit 2): what was wrong and what is allowed, in one line."""

    code = ExitCode.USAGE


class NotComputable(CoinError, ArithmeticError):
    """The input is valid but the answer cannot be computed (exit 1)."""

    code = ExitCode.ERROR


class Unfollowable(NotComputable):
    """A motion that double precision cannot follow; ``reason`` names the cause."""

    def __init__(self, message: str, reason: str = "", code: ExitCode | None = None):
        super().__init__(message, code)
        self.reason = reason


class PhysicsMissing(CoinError, ImportError):
    """MuJoCo (the ``physics`` extra) is not installed; the message says how to install it."""

    code = ExitCode.ERROR


class MatplotlibMissing(CoinError, ImportError):
    """matplotlib (the ``plot`` extra) is not installed; the message says how to install it."""

    code = ExitCode.ERROR


def for_code(message: str, code: int) -> CoinError:
    """The error of exit ``code`` (2: :class:`InputError`, else :class:`NotComputable`)."""
    return InputError(message) if code == ExitCode.USAGE else NotComputable(message, code)
