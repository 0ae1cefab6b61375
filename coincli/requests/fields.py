"""The parts of a declaration: an option (:class:`Opt`), an argument (:class:`Arg`), a named
place for one in a command (:class:`Param`), options that travel together (:class:`Group`), a
whole command (:class:`Command`) and what it was given (:class:`Request`).

Typer-free and import-free: :mod:`coincli.cli` turns a :class:`Command` into typer options
(:func:`coincli.cli._options.declared`), :mod:`coincli.api` checks its keywords against the same
:class:`Command` (:func:`Command.request`), so an option is written once.
"""

from __future__ import annotations

import difflib
from collections.abc import Mapping
from typing import NamedTuple

__all__ = ["Opt", "Arg", "Param", "Group", "Command", "Request", "Values", "REQUIRED"]


class _Required:
    """The default of a parameter that has none (``coin design``'s ``--p-sides``)."""

    __slots__ = ()

    def __repr__(self) -> str:
        return "REQUIRED"


REQUIRED = _Required()


class Opt:
    """An option: its ``names`` (space-separated, the first long one is its name in messages),
    ``metavar``, ``help``, ``kind`` (``str | None`` for a value, ``bool`` for a flag, ``str`` for
    a value with a text default) and any other setting of :func:`typer.Option` (``hidden``)."""

    __slots__ = ("names", "metavar", "help", "kind", "more")

    def __init__(self, names: str, metavar: str | None, help: str | None = None,
                 kind=str | None, **more):
        self.names, self.metavar, self.help, self.kind, self.more = (
            tuple(names.split()), metavar, help, kind, more)

    @property
    def flag(self) -> bool:
        """A flag (True or False), not a value."""
        return self.kind is bool

    @property
    def long(self) -> str:
        """The option's name in messages: its first long name (``--p-sides``)."""
        return next((n for n in self.names if n.startswith("--")), self.names[0])

    def __repr__(self) -> str:
        return f"Opt({' '.join(self.names)!r})"


class Arg:
    """A positional argument: its ``metavar`` and ``help`` (``coin fit FILE``)."""

    __slots__ = ("metavar", "help", "kind")

    flag = False

    def __init__(self, metavar: str, help: str, kind=str):
        self.metavar, self.help, self.kind = metavar, help, kind

    @property
    def long(self) -> str:
        return self.metavar

    def __repr__(self) -> str:
        return f"Arg({self.metavar!r})"


class Param(NamedTuple):
    """A place in a command: its python ``name``, its declaration ``decl`` (an :class:`Opt` or
    :class:`Arg`) and ``default``; ``api`` False for an option of the command line only (a way
    of printing: ``--stream``, ``--out`` of a picture, a hidden old spelling)."""

    name: str
    decl: Opt | Arg
    default: object = None
    api: bool = True


class Group:
    """Options that travel together, in the order of ``--help``: built from :class:`Param`
    (or plain ``(name, decl, default)`` triples) and other groups (flattened); :meth:`only`,
    :meth:`without` and :meth:`but` give a command's variant."""

    __slots__ = ("params",)

    def __init__(self, *parts):
        params: list[Param] = []
        for part in parts:
            params += part.params if isinstance(part, Group) else [Param(*part)]
        self.params = tuple(params)

    def only(self, *names: str) -> Group:
        """The options ``names``, in that order."""
        by_name = {p.name: p for p in self.params}
        return Group(*(by_name[n] for n in names))

    def without(self, *names: str) -> Group:
        """The other options, in their order."""
        return Group(*(p for p in self.params if p.name not in names))

    def but(self, **decls) -> Group:
        """The same options, some with another declaration (another help text)."""
        group = Group(*(p._replace(decl=decls.pop(p.name, p.decl)) for p in self.params))
        if decls:
            raise TypeError(f"not in the group: {', '.join(decls)}")
        return group

    def names(self) -> tuple[str, ...]:
        return tuple(p.name for p in self.params)


class Values(dict):
    """The values given for one :class:`Group` of a command, by python name: ``values.fmt``
    or ``values["fmt"]``; ``**values`` forwards them all."""

    __slots__ = ()

    def __getattr__(self, name):
        try:
            return self[name]
        except KeyError:
            raise AttributeError(name) from None


class Command:
    """One command's inputs, declared once: ``name`` (``design``, ``plot sides``) and its
    ``parts`` in the order of ``--help``: a :class:`Param` (or a ``(name, decl, default)``
    triple) is one input; a ``slot=Group`` keyword is a group whose values the command takes
    together (``request.table``).

    :mod:`coincli.cli` builds the typer options from it; :mod:`coincli.api` takes the same
    names as keywords (those with ``api`` true), checked by :meth:`request`.
    """

    __slots__ = ("name", "params", "slots")

    def __init__(self, name: str, *parts, **slots: Group):
        self.name = name
        params: list[Param] = []
        self.slots: dict[str, tuple[str, ...]] = {}
        for part in parts:
            if isinstance(part, Group):
                params += part.params
            else:
                params.append(Param(*part))
        for slot, group in slots.items():
            self.slots[slot] = group.names()
            params += group.params
        names = [p.name for p in params]
        if len(set(names)) < len(names) or set(slots) & set(names):
            raise TypeError(f"coin {name}: an input named twice: {names}")
        self.params = tuple(params)

    def param(self, name: str) -> Param:
        return next(p for p in self.params if p.name == name)

    def api_names(self) -> tuple[str, ...]:
        """The keywords of the command's :mod:`coincli.api` function, in order."""
        return tuple(p.name for p in self.params if p.api)

    def request(self, given: Mapping, *, api: bool = False) -> Request:
        """The :class:`Request` of the values ``given`` by name (the rest at their defaults).

        A name the command does not take is an :class:`UnknownInput` (a ``TypeError`` and an
        ``InputError``) that suggests the nearest, as the command line does; with ``api``, the
        options of the command line only are not taken either."""
        allowed = self.api_names() if api else tuple(p.name for p in self.params)
        unknown = [k for k in given if k not in allowed]
        if unknown:
            raise unknown_input(self, unknown[0], allowed, api)
        missing = [p for p in self.params if p.default is REQUIRED and given.get(p.name) is None]
        if missing:
            from coincli.errors import InputError

            raise InputError(f"coin {self.name} needs {missing[0].decl.long}")
        values = {p.name: given[p.name] if given.get(p.name) is not None
                  else (None if p.default is REQUIRED else p.default) for p in self.params}
        return Request(self, values)


def unknown_input(command: Command, name: str, allowed, api: bool):
    """The error for an input ``name`` that ``command`` does not take, with the nearest one
    (click's rule: :func:`difflib.get_close_matches`)."""
    from coincli.errors import UnknownInput

    near = difflib.get_close_matches(name, allowed, n=1)
    what = f"coincli.api.{command.name.replace(' ', '_')}()" if api else f"coin {command.name}"
    hint = f"; did you mean {near[0]!r} (--{near[0].replace('_', '-')})?" if near else ""
    return UnknownInput(f"{what} takes no {name!r}{hint}; it takes "
                        f"{', '.join(allowed) or 'nothing'}")


class Request(Mapping):
    """What one run of a command was given: every input of its :class:`Command` by python name
    (text as typed on the command line, Python values from :mod:`coincli.api`; None where not
    given), read-only.  ``request.xi`` or ``request["xi"]``; a slot's group as one
    :class:`Values` (``request.table``); ``**request.only(...)`` forwards some."""

    __slots__ = ("command", "_values")

    def __init__(self, command: Command, values: dict):
        object.__setattr__(self, "command", command)
        object.__setattr__(self, "_values", dict(values))

    def __getitem__(self, name):
        return self._values[name]

    def __iter__(self):
        return iter(self._values)

    def __len__(self):
        return len(self._values)

    def __getattr__(self, name):
        slots = self.command.slots
        if name in slots:
            return Values((k, self._values[k]) for k in slots[name])
        try:
            return self._values[name]
        except KeyError:
            raise AttributeError(name) from None

    def __setattr__(self, name, value):
        raise AttributeError("a Request is read-only")

    def only(self, *names: str) -> Values:
        """The values of ``names`` (python names or slots), as one :class:`Values`."""
        out = Values()
        for name in names:
            if name in self.command.slots:
                out.update(getattr(self, name))
            else:
                out[name] = self._values[name]
        return out

    def but(self, *names: str) -> Values:
        """Every value but those of ``names`` (python names or slots)."""
        left = set()
        for name in names:
            left.update(self.command.slots.get(name, (name,)))
        return Values((k, v) for k, v in self._values.items() if k not in left)

    def __repr__(self) -> str:
        given = ", ".join(f"{k}={v!r}" for k, v in self._values.items()
                          if v is not None and v is not False)
        return f"<coin {self.command.name} request: {given}>"
