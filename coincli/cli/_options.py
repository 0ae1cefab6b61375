"""The typer declarations of the options every command spells the same way.

- **A coin**: ``--xi``, ``--coin``, ``--count``, ``--quarters``, ``--diameter``,
  ``--thickness``;
- **Tosses**: ``-n/--n/--tosses N``; stacked coins are always
  ``--count`` (the old ``-n`` of ``coin table`` and ``coin stack`` fails naming ``--count``:
  :data:`OldCountOpt`, refused by :func:`coincli.io.options.refuse_old_count`);
- **A seed**: ``--seed N``;
- **psi**: ``--psi DEG`` and ``--psi-dist SPEC[,SPEC...]``.

Commands declare the options with these ``Annotated`` aliases, made by :func:`option` (names ``xi``,
``coin``, ``count``, ``quarters``, ``diameter``, ``thickness``, ``tosses``, ``seed``, ``psi``,
``psi_dist``) and pass the typed text to the parsers of :mod:`coincli.io.options` (the coin
group, tosses, seeds, units typed once, psi), which hold the grammar itself.  No numpy, scipy or
rich at import.

Options that travel together are declared once as a :class:`Group` (:data:`COIN`,
:data:`COINS`, :data:`OUTPUT`; :data:`coincli.cli._bounce.BOUNCE`, :data:`coincli.cli._phase.PHASE`
...) and applied by :func:`with_groups`: a command names a group as the default of one of its
parameters, and receives the group's values there as one :class:`Values` (a dict: ``**values``
forwards them to the report).
"""

from __future__ import annotations

import functools
import inspect
from typing import Annotated

import typer

__all__ = [
    "XiOpt", "XisOpt", "CoinOpt", "CountOpt", "CountsOpt", "QuartersOpt", "QuartersManyOpt",
    "DiameterOpt", "ThicknessOpt", "TossesOpt", "OldCountOpt", "SeedOpt", "PsiOpt", "PsisOpt",
    "PsiDistOpt", "PsiDistsOpt", "FormatOpt", "QuietOpt", "Group", "Values", "with_groups",
    "COIN", "COINS", "OUTPUT", "option",
]


def option(names: str, metavar: str | None, help: str | None = None, kind=str | None, **more):
    """The ``Annotated`` type of an option: its ``names`` (space-separated), ``metavar`` and
    ``help``; ``kind`` is the value's type (text, or None when not given), ``more`` any other
    :func:`typer.Option` setting."""
    return Annotated[kind, typer.Option(*names.split(), metavar=metavar, help=help, **more)]


# --------------------------------------------------------------------------- the coin group

XiOpt = option("--xi -x", "XI", "Aspect ratio h/D: 0.577 or 17/30.")
XisOpt = option("--xi -x", "XI", "Aspect ratio h/D: 0.577, 17/30, a list a,b, a range lo:hi:step, "
                "or - (stdin).")
CoinOpt = option("--coin -c", "NAME", "Catalog coin (see coin coins).")
CountOpt = option("--count", "N", "Stack N of the --coin (or --diameter) coins.")
CountsOpt = option("--count", "N", "Stack N coins: N, a list, a range or -.")
QuartersOpt = option("--quarters", "N", "N US quarters stacked (--coin quarter --count N).")
QuartersManyOpt = option("--quarters", "N", "N US quarters stacked: N, a list, a range or -.")
DiameterOpt = option("--diameter -d", "D", "Diameter: 24.26 (mm), 2.4cm or 0.955in.")
ThicknessOpt = option("--thickness -t", "H", "Thickness (mm or a unit), with --diameter.")

# --------------------------------------------------------------------------- tosses, seeds

TossesOpt = option("-n --n --tosses", "N", "Number of tosses.")
#: the retired ``-n`` (stacked coins) of ``coin table`` and ``coin stack``: hidden, it fails
#: naming ``--count`` (``-n`` is always a number of tosses)
OldCountOpt = option("-n", "N", hidden=True)




SeedOpt = option("--seed", "SEED", "Seed, a whole number >= 0 (default: drawn, and reported).")

# --------------------------------------------------------------------------- psi

PsiOpt = option("--psi", "DEG", "Angle psi of the angular momentum to the normal, degrees [0, "
                "180].")
PsisOpt = option("--psi", "DEG", "Angle psi, degrees [0, 180]: a value, a list a,b or a range "
                 "lo:hi:step.")
PsiDistOpt = option("--psi-dist", "SPEC", "psi density: uniform[:LOW:HIGH], cosine, "
                    "normal[:MEAN:SD] (deg), table:FILE.")
PsiDistsOpt = option("--psi-dist", "SPECS", "psi densities, comma-separated: uniform[:LOW:HIGH], "
                     "cosine, normal[:MEAN:SD], table:FILE.")

# --------------------------------------------------------------------------- output

FormatOpt = option("--format -f", "FORMAT", "Output format: table (default: aligned text, folded "
                   "to fit a terminal), csv, tsv, json, jsonl or markdown (a pipe table).",
                   kind=str)
QuietOpt = option("--quiet -q", None, "Print only the main number (for shell scripts).", kind=bool)

# --------------------------------------------------------------------------- groups


class Group:
    """Options that travel together: ``(python name, Annotated type, default)`` triples in the
    order of ``--help``.  Built from triples and other groups (flattened); :meth:`only` and
    :meth:`but` give a command's variant.  Apply one with :func:`with_groups`."""

    __slots__ = ("params",)

    def __init__(self, *parts):
        params = []
        for part in parts:
            params += part.params if isinstance(part, Group) else [part]
        self.params = tuple(params)

    def only(self, *names: str) -> Group:
        """The options ``names``, in that order."""
        by_name = {p[0]: p for p in self.params}
        return Group(*(by_name[n] for n in names))

    def without(self, *names: str) -> Group:
        """The other options, in their order."""
        return Group(*(p for p in self.params if p[0] not in names))

    def but(self, **types) -> Group:
        """The same options, some with another Annotated type (another help text)."""
        group = Group(*((n, types.pop(n, t), d) for n, t, d in self.params))
        if types:
            raise TypeError(f"not in the group: {', '.join(types)}")
        return group


class Values(dict):
    """The values a command was given for one :class:`Group`, by python name: ``values.fmt``
    or ``values["fmt"]``; ``**values`` forwards them all."""

    __slots__ = ()

    def __getattr__(self, name):
        try:
            return self[name]
        except KeyError:
            raise AttributeError(name) from None


def _hint(name: str, text: str, namespace: dict):
    """The annotation ``text`` of parameter ``name``, evaluated in ``namespace`` by
    :func:`typing.get_type_hints` (extras kept: typer reads the ``Annotated`` metadata)."""
    import typing

    def holder():  # pragma: no cover - never called: it only carries the annotation
        pass

    holder.__annotations__ = {name: text}
    return typing.get_type_hints(holder, globalns=namespace, include_extras=True)[name]


def with_groups(fn):
    """The command ``fn`` with each parameter whose default is a :class:`Group` replaced, in
    its place, by the group's options; ``fn`` receives that parameter as their :class:`Values`.

    Typer reads the command's ``__signature__`` and ``__annotations__``, built here once (the
    command's own string annotations, ``from __future__ import annotations``, are looked up
    in its module: plain names cost a dictionary look-up).
    """
    from coincli.cli import _NOT_A_NAME, _named

    namespace, slots, params = fn.__globals__, {}, []
    for p in inspect.signature(fn).parameters.values():
        if isinstance(p.default, Group):
            slots[p.name] = [name for name, _, _ in p.default.params]
            params += [inspect.Parameter(name, p.kind, default=default, annotation=type_)
                       for name, type_, default in p.default.params]
        elif isinstance(p.annotation, str):
            value = _named(p.annotation, namespace)
            # a plain (dotted) name is looked up here; any other annotation text (an inline
            # Annotated[...]) is evaluated by typing, in fn's module, as typer would
            params.append(p.replace(annotation=_hint(p.name, p.annotation, namespace)
                                    if value is _NOT_A_NAME else value))
        else:
            params.append(p)
    clash = set(slots) & {p.name for p in params}
    if clash or len({p.name for p in params}) < len(params):
        raise TypeError(f"{fn.__qualname__}: an option named twice, or as a group: {clash}")

    @functools.wraps(fn)
    def command(**given):
        for slot, names in slots.items():
            given[slot] = Values((name, given.pop(name)) for name in names)
        return fn(**given)

    command.__signature__ = inspect.Signature(params)
    command.__annotations__ = {p.name: p.annotation for p in params
                               if p.annotation is not p.empty}
    return command


#: a coin: ``--xi``, ``--coin``, ``--count``, ``--quarters``, ``--diameter``, ``--thickness``
COIN = Group(("xi", XiOpt, None), ("coin", CoinOpt, None), ("count", CountOpt, None),
             ("quarters", QuartersOpt, None), ("diameter", DiameterOpt, None),
             ("thickness", ThicknessOpt, None))
#: one or more coins: lists, ranges or - for --xi, --count and --quarters
COINS = COIN.but(xi=XisOpt, count=CountsOpt, quarters=QuartersManyOpt)
#: what is printed, and how: ``--format`` and ``-q``
OUTPUT = Group(("fmt", FormatOpt, "table"), ("quiet", QuietOpt, False))
