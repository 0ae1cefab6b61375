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

Errors are built by :func:`usage_error` and :func:`compute_error`; a user's value in a message
is quoted by :func:`shown`, and :func:`clip_message` holds every message to one readable line.

This module imports nothing (``re`` only inside the functions that need it): the closed-form path
stays as light as it is.
"""

from __future__ import annotations

import enum

__all__ = [
    "ExitCode",
    "CoinError",
    "InputError",
    "UnknownInput",
    "CoinWarning",
    "NotComputable",
    "Unfollowable",
    "PhysicsMissing",
    "MatplotlibMissing",
    "INSTALL_HINT",
    "usage_error",
    "compute_error",
    "shown",
    "clip_message",
    "MAX_SHOWN_CHARS",
    "MAX_MESSAGE_CHARS",
]

#: how to install an optional extra of this project (never the unrelated ``coincli`` package)
INSTALL_HINT = ("pip install -U 'thickcoin[{extra}]' (from a checkout: pip install '.[{extra}]')")


def install_hint(extra: str) -> str:
    """The one-line install hint for the optional ``extra`` (``physics``, ``plot``, ...)."""
    return INSTALL_HINT.format(extra=extra)


# --------------------------------------------------------------------------- messages

MAX_SHOWN_CHARS = 60  #: the most characters of a user's value that an error message repeats
MAX_MESSAGE_CHARS = 1000  #: an error line longer than this is cut in the middle
_ESCAPE = r"\\(?:x[0-9a-fA-F]{2}|u[0-9a-fA-F]{4}|U[0-9a-fA-F]{8}|N\{[^}]*\}|.)"
_QUOTED = None  # compiled on first use: `re` costs nothing at start-up this way


def _clip_repr(r: str, limit: int) -> str:
    """The repr ``r`` (quotes included) cut to about ``limit`` characters, ending in '...'."""
    import re

    q, body = r[0], r[1:-1]
    keep, n = [], 0
    for m in re.finditer(_ESCAPE + "|.", body, re.S):  # never split an escape like \x00
        tok = m.group()
        if n + len(tok) > limit - 3:
            break
        keep.append(tok)
        n += len(tok)
    return f"{q}{''.join(keep)}...{q}"


def shown(text: str, limit: int = MAX_SHOWN_CHARS) -> str:
    """``repr(text)`` for an error message, cut to about ``limit`` characters with '...'."""
    r = repr(str(text))
    return r if len(r) <= limit + 2 else _clip_repr(r, limit)


def clip_message(message: str) -> str:
    """``message`` with every quoted value ('...' or "...", as repr writes them) longer than
    :data:`MAX_SHOWN_CHARS` cut short with '...', and the whole line held to
    :data:`MAX_MESSAGE_CHARS` (its start and end kept: what was wrong, what is allowed)."""
    global _QUOTED
    if len(message) <= MAX_SHOWN_CHARS + 2:
        return message
    if _QUOTED is None:
        import re

        _QUOTED = re.compile(
            rf"""(?<!\w)(?:'(?:[^'\\\n]|{_ESCAPE})*'|"(?:[^"\\\n]|{_ESCAPE})*")""", re.S)
    message = _QUOTED.sub(
        lambda m: m.group() if len(m.group()) <= MAX_SHOWN_CHARS + 2
        else _clip_repr(m.group(), MAX_SHOWN_CHARS), message)
    if len(message) > MAX_MESSAGE_CHARS:
        head = MAX_MESSAGE_CHARS * 2 // 3
        message = message[:head] + " ... " + message[-(MAX_MESSAGE_CHARS - head - 5):]
    return message


# --------------------------------------------------------------------------- the errors


class ExitCode(enum.IntEnum):
    """Exit codes of ``coin``; part of its public interface."""

    OK = 0
    ERROR = 1  #: the input is valid but the answer cannot be computed
    USAGE = 2  #: the input is wrong: a bad option, value, file line or combination
    HUNG_UP = 129  #: SIGHUP (128 + 1): the terminal closed
    INTERRUPTED = 130  #: Ctrl-C (128 + SIGINT)
    TERMINATED = 143  #: SIGTERM (128 + 15): kill, timeout(1), a cancelled CI job


class CoinError(Exception):
    """An error to print as one line on stderr, with its exit code.

    The message is passed through :func:`clip_message`: a quoted value longer than 60
    characters (a 10,000-character option, a 5 MB stdin line) is cut short.
    """

    code: ExitCode = ExitCode.ERROR

    def __init__(self, message: str, code: ExitCode | None = None):
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


class UnknownInput(InputError, TypeError):
    """An option or keyword that the command does not take, with the nearest it does (a
    ``TypeError`` too, as Python raises for a wrong keyword)."""


class CoinWarning(UserWarning):
    """A result to read with care, issued by :mod:`coincli.api` (the command line prints it as
    ``coin: warning: ...``): ``warnings.simplefilter("error", CoinWarning)`` makes it an
    error."""


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


def usage_error(message: str) -> InputError:
    """The error of a wrong input (exit 2)."""
    return InputError(message)


def compute_error(message: str) -> NotComputable:
    """The error of a valid input whose answer cannot be computed (exit 1)."""
    return NotComputable(message)
