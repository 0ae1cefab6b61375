"""One record style for the core's small result classes: :func:`record`, a light dataclass.

``@record()`` gives a class of annotated fields an ``__init__`` (fields by position or name, with
defaults; :data:`NEW_LIST` for a fresh empty list an instance), a ``repr`` and ``==``; with
``frozen=True`` also a ``hash`` and fields that cannot be changed.  Decorating costs a few
microseconds, where the dataclasses module costs most of a millisecond of start-up a class: the
toss modules (:mod:`coincli.core.toss`), which ``coin toss`` and ``coin simulate`` import, use it.
"""

from __future__ import annotations

NEW_LIST = object()  #: a record field's default: a new empty list for each instance


def record(frozen=False, skip_compare=()):
    """A light dataclass: ``__init__`` (fields by position or name, defaults), ``repr``,
    ``==`` (and ``hash`` when frozen) from the class's annotated fields.  Decorating costs a few
    microseconds, where the dataclasses module costs most of a millisecond of start-up a
    class."""

    def wrap(cls):
        names = tuple(cls.__dict__.get("__annotations__", {}))
        defaults = {}
        for k in names:
            if k in cls.__dict__:
                defaults[k] = cls.__dict__[k]
                delattr(cls, k)
        cls._fields, cls._defaults = names, defaults
        cls._compared = tuple(k for k in names if k not in skip_compare)
        cls.__init__, cls.__repr__, cls.__eq__ = _rec_init, _rec_repr, _rec_eq
        if frozen:
            cls.__setattr__ = _rec_frozen
            cls.__delattr__ = _rec_frozen
            cls.__hash__ = _rec_hash
        else:
            cls.__hash__ = None
        return cls

    return wrap


def _rec_init(self, *args, **kwargs):
    names = self._fields
    if len(args) > len(names):
        raise TypeError(f"{type(self).__name__}() takes at most {len(names)} arguments")
    values = dict(zip(names, args))
    for k, v in kwargs.items():
        if k not in names or k in values:
            raise TypeError(f"{type(self).__name__}() got an unexpected or repeated argument "
                            f"{k!r}")
        values[k] = v
    for k in names:
        if k not in values:
            if k not in self._defaults:
                raise TypeError(f"{type(self).__name__}() missing argument {k!r}")
            d = self._defaults[k]
            values[k] = [] if d is NEW_LIST else d
        object.__setattr__(self, k, values[k])


def _rec_repr(self):
    inner = ", ".join(f"{k}={getattr(self, k)!r}" for k in self._fields)
    return f"{type(self).__name__}({inner})"


def _rec_eq(self, other):
    if other.__class__ is not self.__class__:
        return NotImplemented
    return all(getattr(self, k) == getattr(other, k) for k in self._compared)


def _rec_hash(self):
    return hash(tuple(getattr(self, k) for k in self._compared))


def _rec_frozen(self, *args):
    raise AttributeError(f"{type(self).__name__} is frozen: its fields cannot be changed")
