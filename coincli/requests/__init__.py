"""What each command takes, declared once.

A command's inputs are one :class:`~coincli.requests.fields.Command`: its options (names,
metavar, help, default) in the order of ``--help``, built from the groups that several commands
share (:mod:`coincli.requests.common`: the coin, the output, the table of ``--landing bounce``,
...).  From it come the typer options of :mod:`coincli.cli` (:func:`coincli.cli._options.declared`)
and the keywords of :mod:`coincli.api` (:meth:`~coincli.requests.fields.Command.request`, which
refuses a name the command does not take and suggests the nearest); ``tests/cli/test_requests.py``
checks the three against each other.  What a value *means* is parsed by :mod:`coincli.io`.

This layer imports only :mod:`coincli.limits` and :mod:`coincli.errors`: no typer, numpy or rich.
"""

from __future__ import annotations

#: every command: its module under ``coincli.requests`` and the name of its declaration
COMMANDS = {
    "design": ("design", "DESIGN"), "table": ("design", "TABLE"), "stack": ("design", "STACK"),
    "coins": ("design", "COINS_LIST"), "fair": ("design", "FAIR"),
    "toss": ("toss", "TOSS"), "simulate": ("toss", "SIMULATE"), "phase": ("toss", "PHASE_PICTURE"),
    "check": ("check", "CHECK"), "fit": ("check", "FIT"), "book": ("book", "BOOK"),
    "plot sides": ("plot", "SIDES"), "plot psi": ("plot", "PSI"), "plot map": ("plot", "MAP"),
    "plot phase": ("plot", "PHASE_FIGURE"),
}


def command(name: str):
    """The :class:`~coincli.requests.fields.Command` of ``coin NAME`` (``"plot sides"``)."""
    import importlib

    module, attr = COMMANDS[name]
    return getattr(importlib.import_module(f"coincli.requests.{module}"), attr)
