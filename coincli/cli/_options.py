"""The typer side of a declaration: :func:`declared` turns a command's one declaration
(:class:`coincli.requests.fields.Command`, in :mod:`coincli.requests`) into the typer options of
its function, which then receives what it was given as one
:class:`~coincli.requests.fields.Request`.

The options themselves (names, metavar, help, default) are declared in :mod:`coincli.requests`,
once for the command line and :mod:`coincli.api` alike; what a value *means* is parsed in
:mod:`coincli.io.options` and :mod:`coincli.io.grammar`.  No numpy, scipy or rich at import.
"""

from __future__ import annotations

import functools
import inspect
from typing import Annotated

import typer

from coincli.requests.fields import REQUIRED, Arg, Command, Request

__all__ = ["declared", "annotation"]


def annotation(decl):
    """The ``Annotated`` type typer reads for one declared option or argument."""
    if isinstance(decl, Arg):
        return Annotated[decl.kind, typer.Argument(help=decl.help, metavar=decl.metavar)]
    return Annotated[decl.kind, typer.Option(*decl.names, metavar=decl.metavar, help=decl.help,
                                             **decl.more)]


def declared(command: Command):
    """The function of ``command`` with the command's options as its typer signature; it is
    called with one :class:`~coincli.requests.fields.Request` of what was given."""
    params = [inspect.Parameter(p.name, inspect.Parameter.POSITIONAL_OR_KEYWORD,
                                default=inspect.Parameter.empty if p.default is REQUIRED
                                else p.default, annotation=annotation(p.decl))
              for p in command.params]

    def wrap(fn):
        @functools.wraps(fn)
        def run(**given):
            return fn(Request(command, given))

        run.__signature__ = inspect.Signature(params)
        run.__annotations__ = {p.name: p.annotation for p in params}
        run.declaration = command
        return run

    return wrap
