"""The one signal policy of the command line (installed by :mod:`coincli._entry` and
:func:`coincli.cli.run`).

Importing the command line (typer, click) is most of a closed-form run's 60 ms; a Ctrl-C in that
window would otherwise end in a traceback.  This module is tiny and imports nothing of its own, so
the handlers are in place from the first line of coin's code that runs.

**Signals.**  SIGTERM (``kill``, ``timeout(1)``, a CI cancelling a job) and SIGHUP (a closed
terminal) end a run the way Ctrl-C does: :func:`catch_signals` makes each raise :class:`Stopped`
(a :class:`KeyboardInterrupt`) in the main thread, so the same cleanup runs for all three: worker
pools are terminated, a temporary ``.FILE.xxxx.tmp`` is removed, and :func:`coincli.cli.run`
prints one line with the drawn seed and exits ``128 + signal`` (130 SIGINT, 143 SIGTERM, 129
SIGHUP).  A second signal while the run is stopping is ignored, so the cleanup finishes.  Only
the command line installs these handlers (:func:`coincli.cli.run` and :func:`main`): importing
:mod:`coincli` or :mod:`coincli.api` changes no signal disposition.  A process forked by the run
(a worker) that still holds the handler dies of the signal, quietly.
"""

import os
import signal

#: the signals that end a run as Ctrl-C does (besides SIGINT, which Python already raises as
#: KeyboardInterrupt), with the words of the one error line; exit code 128 + the number
STOP_SIGNALS = {"SIGTERM": "terminated (SIGTERM)", "SIGHUP": "hung up (SIGHUP)"}


class Stopped(KeyboardInterrupt):
    """The run was stopped by ``signum`` (SIGTERM or SIGHUP): a KeyboardInterrupt, so that every
    cleanup that Ctrl-C runs runs for it too."""

    def __init__(self, signum: int):
        super().__init__(signum)
        self.signum = signum


_received: list = []  #: the stopping signal's number, once one arrived in this run
_owner: list = []  #: the pid whose main thread installed the handlers


def _on_signal(signum, _frame):
    if _owner and os.getpid() != _owner[0]:  # a forked child kept the handler: die of it
        signal.signal(signum, signal.SIG_DFL)
        os.kill(os.getpid(), signum)
        return
    if _received:  # already stopping: let the cleanup finish
        return
    _received.append(signum)
    raise Stopped(signum)


def catch_signals():
    """Install the handlers of :data:`STOP_SIGNALS` (in the main thread only; elsewhere nothing
    happens) and forget any earlier stop.  Returns what to give :func:`release_signals`."""
    _received.clear()
    previous = {}
    try:
        for name in STOP_SIGNALS:
            num = getattr(signal, name, None)
            if num is not None:
                previous[num] = signal.signal(num, _on_signal)
    except ValueError:  # not the main thread: the caller's process keeps its own handlers
        return previous
    _owner[:] = [os.getpid()]
    return previous


def release_signals(previous) -> None:
    """Put back the handlers :func:`catch_signals` replaced."""
    try:
        for num, handler in previous.items():
            signal.signal(num, handler if handler is not None else signal.SIG_DFL)
    except ValueError:
        pass


def stop_signal():
    """The number of the signal that stopped this run: SIGTERM, SIGHUP, or SIGINT (Ctrl-C)."""
    return _received[0] if _received else int(signal.SIGINT)


def stop_line():
    """``(words, exit code)`` of a stopped run: ``interrupted``, 130 for Ctrl-C; ``terminated
    (SIGTERM)``, 143; ``hung up (SIGHUP)``, 129."""
    num = stop_signal()
    words = "interrupted"
    for name, text in STOP_SIGNALS.items():
        if getattr(signal, name, None) == num:
            words = text
    return words, 128 + int(num)
