"""The one grammar of ``coin``, text to values: the options every command spells the same way.

- **A coin**: ``--xi X`` (``0.577``, ``17/30``; lists, ranges and ``-`` where a command takes
  many), ``--coin NAME [--count N]`` (a catalog coin, N of them stacked), ``--quarters N`` (N US
  quarters) or ``--diameter D --thickness H`` (lengths with units, ``--count N`` stacks them);
  ``--diameter D`` with ``--xi X`` gives the coin its size.  :func:`resolve_coin` turns the
  options into :class:`Coins` and refuses every contradiction with the same one-line message
  in every command.  Stacked coins are always ``--count``: the old ``-n`` of ``coin table`` and
  ``coin stack`` fails naming it (:func:`refuse_old_count`).
- **Tosses and seeds**: ``-n N`` (:func:`tosses_value`); ``--seed N``, when absent drawn
  (:func:`seed_value`, kept in :data:`DRAWN_SEED` so that an interrupted run can still name it)
  and reported (:func:`report_seed`).
- **Units typed once** at the end of a range or a distribution (:func:`unit_at_end`,
  :func:`range_unit`).
- **psi**: ``--psi DEG`` (a list or a range where a command takes many) and
  ``--psi-dist SPEC[,SPEC...]``, parsed by :func:`coincli.io.grammar.parse_density` everywhere.

Each function takes the text a command was given (or None) and returns typed values, or raises
the one-line usage error (:class:`coincli.errors.InputError`).  The typer declarations of these
options are in :mod:`coincli.cli._options`; this module declares none (no typer of its own), and
loads no numpy, scipy or rich at import.
"""

from __future__ import annotations

import math

from coincli.errors import shown, usage_error
from coincli.io import notes
from coincli.io import grammar as parse
from coincli.io.batches import values_option, values_stream

__all__ = [
    "Coins", "resolve_coin", "COIN_FORMS", "refuse_old_count", "seed_value", "DRAWN_SEED",
    "report_seed", "report_drawn_seed", "tosses_value", "unit_at_end", "range_unit",
    "typed_range_error", "PSI_AND_DIST", "refuse_psi_and_dist", "psi_angle",
    "psi_angles", "psi_item", "radians", "psi_density", "psi_densities", "level_value",
    "drawn_seed", "reset_drawn_seed",
]

# --------------------------------------------------------------------------- the coin group

#: how a coin is given, for messages
COIN_FORMS = "--xi X, --coin NAME [--count N], --quarters N, or --diameter D --thickness H"

#: what a typed --xi may be, by ``xi_rule``
_XI_RULES = {
    "any": "a number >= 0 like 0.577 or 17/30 (or inf)",
    "finite": "a finite number >= 0 like 0.577 or 17/30",
    "positive": "a finite number > 0 like 0.577 or 17/30",
}


class Coins:
    """The coin (or coins) a command was given.

    ``xis`` holds one aspect ratio per coin (a list, or an ndarray for a long stdin batch);
    ``kind`` is "xi", "coin" (catalog, --quarters too) or "size" (--diameter --thickness);
    ``unit`` is the coin stacked (a :class:`coincli.core.coins.Coin`, catalog or custom) and
    ``counts`` how many, one per xi (both None for ``--xi``); ``diameter_mm`` is the coin's
    size when known (a catalog or custom coin, or ``--xi`` with ``--diameter``).  ``typed``
    says how the user gave it, for notes.  A plain class: a NamedTuple costs a fraction of a
    millisecond to create at import, paid by every run.
    """

    __slots__ = ("xis", "kind", "unit", "counts", "diameter_mm", "typed")

    def __init__(self, xis, kind: str, unit=None, counts: list | None = None,
                 diameter_mm: float | None = None, typed: str = ""):
        self.xis, self.kind, self.unit, self.counts = xis, kind, unit, counts
        self.diameter_mm, self.typed = diameter_mm, typed

    def __repr__(self):
        return f"Coins({self.kind}, {len(self.xis) if self.xis is not None else 0} coins)"

    @property
    def xi(self) -> float:
        """The one aspect ratio (commands that take one coin)."""
        return float(self.xis[0])

    @property
    def count(self) -> int | None:
        return None if self.counts is None else self.counts[0]

    @property
    def thickness_mm(self) -> float | None:
        """The whole coin's (or stack's) thickness when its size is known."""
        if self.diameter_mm is None:
            return None
        if self.unit is not None and self.counts is not None:
            return self.counts[0] * self.unit.thickness_mm
        return self.xi * self.diameter_mm

    @property
    def coin_name(self) -> str | None:
        """The coin stacked, as a table cell: its catalog name, or ``custom``."""
        return None if self.unit is None else self.unit.name

    def label(self, k: int = 0) -> str:
        """A short label for coin ``k``: ``xi=17/30``, ``quarter x8``, ``30 x 17 mm``."""
        if self.kind == "xi":
            return self.typed.replace("xi = ", "xi=") if len(self.xis) == 1 else \
                f"xi={self.xis[k]:.10g}"
        n = self.counts[k] if self.counts is not None else 1
        name = self.typed if self.kind == "size" else self.coin_name
        return name if n == 1 else f"{name} x{n}"


def _check_group(xi, coin, count, quarters, diameter, thickness, *, default,
                 takes_xi: bool = True) -> str:
    """The kind of coin the options give ("xi", "coin", "quarters", "size", or "default"),
    or the one usage error every command gives for a contradiction or a missing part."""
    kinds = []
    if xi is not None:
        kinds.append("--xi")
    if coin is not None:
        kinds.append("--coin")
    if quarters is not None:
        kinds.append("--quarters")
    if thickness is not None or (diameter is not None and xi is None):
        kinds.append("--diameter/--thickness")
    if len(kinds) > 1:
        if kinds[:1] == ["--xi"] and kinds[1:] == ["--diameter/--thickness"] and \
                diameter is not None and thickness is not None:
            raise usage_error("--xi with both --diameter and --thickness gives the shape twice; "
                              "drop --xi (xi = thickness/diameter) or --thickness")
        if kinds[:1] == ["--xi"] and thickness is not None:
            raise usage_error("--thickness goes with --diameter (xi = thickness/diameter); with "
                              "--xi, give --diameter D to set the size")
        raise usage_error(f"{kinds[0]} and {kinds[1]} both give the coin; give one of "
                          f"{COIN_FORMS}")
    if count is not None:
        if quarters is not None:
            raise usage_error("--quarters N is already a stack of N quarters; give --quarters N "
                              "or --coin NAME --count N, not --count too")
        if xi is not None:
            raise usage_error("--count N stacks a --coin or a --diameter/--thickness coin; --xi "
                              "is already the whole coin's h/D (drop --count)")
    if diameter is not None and thickness is None and xi is None:
        raise usage_error("--diameter D needs --thickness H" + (" (or --xi X)" if takes_xi else "")
                          + " to make a coin")
    if thickness is not None and diameter is None:
        raise usage_error("--thickness H needs --diameter D to make a coin")
    if not kinds:
        if count is not None and default is None:
            raise usage_error("--count N needs the coin to stack: --coin NAME --count N, "
                              "--diameter D --thickness H --count N, or --quarters N")
        if default is None:
            return "none"
        return "default"
    return {"--xi": "xi", "--coin": "coin", "--quarters": "quarters",
            "--diameter/--thickness": "size"}[kinds[0]]


def _refuse_out_of_doubles(xis, typed: str) -> None:
    """A coin's finite, nonzero sizes whose ratio h/D leaves the doubles (inf, or 0 from a
    thickness > 0) are refused, whatever the command allows of a typed --xi: a size never
    silently becomes xi = inf or 0."""
    if not all(math.isfinite(x) for x in xis):
        raise usage_error(f"the coin's xi = thickness/diameter overflows a double ({typed}); "
                          "give a smaller stack or a thinner coin")
    if min(xis) == 0.0:
        raise usage_error(f"the coin's xi = thickness/diameter underflows to 0 ({typed}); "
                          "give a thicker coin or a smaller diameter")


def _xi_item(rule: str):
    allowed = _XI_RULES[rule]

    def item(text: str, what: str) -> float:
        try:
            v = parse.parse_ratio(text, what, allow_inf=True)
        except ValueError as exc:
            if "divides by zero" in str(exc) or "smallest positive double" in str(exc):
                raise
            raise ValueError(f"{what} must be {allowed}, got {text!r}") from None
        if (math.isinf(v) and rule != "any") or (v == 0 and rule == "positive"):
            raise ValueError(f"{what} must be {allowed}, got {text!r}")
        return v

    item.zero_first = True  # --xi 0,5 is a decimal comma (coincli.io.grammar.parse_values)
    return item


def _count_item(text: str, what: str) -> float:
    return float(parse.parse_count(text, what))


_count_item.whole = True  # a list of counts is whole numbers: 1,5 is never a decimal comma


def _many(text: str, what: str, item, bounds, most: int | None):
    """A value, list, range or '-' (stdin) of values; at most ``most`` when given."""
    if most is not None and text.strip() != "-":
        try:
            return parse.parse_values(text, what, item, max_rows=most)
        except ValueError as exc:
            raise usage_error(str(exc)) from None
    vals = values_option(text, what, item, bounds=bounds)
    if most is not None and len(vals) > most:
        raise usage_error(f"{what}: stdin holds {len(vals)} values; at most {most} are allowed")
    return vals


def _one(text: str, what: str, item):
    try:
        return item(text, what)
    except ValueError as exc:
        raise usage_error(str(exc)) from None


def _length(text: str, what: str) -> float:
    try:
        return parse.parse_length_mm(text, what)
    except ValueError as exc:
        raise usage_error(str(exc)) from None


def _catalog(name: str):
    from coincli.core import coins as coin_catalog

    try:
        return coin_catalog.get_coin(name)
    except ValueError as exc:
        raise usage_error(f"--coin: {exc}") from None


def resolve_coin(xi: str | None = None, coin: str | None = None, count: str | None = None,
                 quarters: str | None = None, diameter: str | None = None,
                 thickness: str | None = None, *, many: bool = False,
                 default: str | None = None, required: bool = True, xi_rule: str = "finite",
                 need_size: bool = False, need_count: bool = True,
                 max_values: int | None = None, command: str = "this command",
                 stream: bool = False, takes_xi: bool = True) -> Coins | None:
    """The coin(s) given by the options of the coin group, or the one-line usage error.

    ``many``: ``--xi``, ``--count`` and ``--quarters`` take lists, ranges and ``-`` (stdin).
    ``default``: the catalog coin used when none is given (``coin stack``: ``quarter``);
    without one, a missing coin is an error when ``required``, else None is returned.
    ``xi_rule``: what a typed --xi may be: ``any`` (>= 0, inf too), ``finite`` (>= 0) or
    ``positive`` (> 0, finite).  ``need_size``: the coin's diameter must be known (a bare
    --xi is refused).  ``need_count``: a catalog or custom coin without --count is one coin;
    with ``need_count=False`` its ``counts`` stay None (the command finds the count itself).
    ``max_values``: the most coins a list, range or stdin may give (``coin plot``'s marks).
    ``stream`` (with ``many``): several ``--xi`` values, or several counts, come back as a
    :class:`coincli.io.table.Values` (``xis`` None for counts), read and checked whole but
    held in chunks, for a command that computes a chunk at a time.  ``takes_xi``: False for a
    command that refuses --xi itself (``coin stack``): its errors then never suggest one.
    """
    kind = _check_group(xi, coin, count, quarters, diameter, thickness, default=default,
                        takes_xi=takes_xi)
    if kind == "none":
        if required:
            raise usage_error(f"give a coin: {COIN_FORMS}")
        return None
    if kind == "xi":
        item = _xi_item(xi_rule)
        bounds = (5e-324 if xi_rule == "positive" else 0.0,
                  math.inf if xi_rule == "any" else 1.7976931348623157e308)
        if many and stream and max_values is None:
            xis = values_stream(xi, "--xi", item, bounds=bounds)
            if len(xis) == 1:
                xis = [xis.values()]
        else:
            xis = (_many(xi, "--xi", item, bounds, max_values) if many
                   else [_one(xi, "--xi", item)])
        dia = _length(diameter, "--diameter") if diameter is not None else None
        if need_size and dia is None:
            raise usage_error(f"{command} needs the coin's size: give --coin NAME, --quarters N, "
                              "--diameter D --thickness H, or --xi X with --diameter D")
        return Coins(xis, "xi", None, None, dia, f"xi = {xi.strip()}")
    from coincli.core import coins as coin_catalog

    if kind == "size":
        d, h = _length(diameter, "--diameter"), _length(thickness, "--thickness")
        try:
            unit = coin_catalog.custom_coin(d, h)
        except ValueError as exc:
            raise usage_error(str(exc)) from None
        typed = f"{diameter.strip()} x {thickness.strip()}"
        count_text, what = count, "--count"
    elif kind == "quarters":
        unit, typed, count_text, what = _catalog("quarter"), "quarter", quarters, "--quarters"
    else:
        unit = _catalog(coin if kind == "coin" else default)
        typed, count_text, what = unit.name, count, "--count"
    if count_text is None:
        if not need_count:
            return Coins(None, "coin" if kind != "size" else "size", unit, None,
                         unit.diameter_mm, typed)
        count_text = "1"
    if ":" in count_text:
        try:
            whole = parse.parse_range(count_text, what).whole
        except ValueError:
            whole = True  # the range's own error comes from the parse below
        if not whole:
            raise usage_error(f"{what} range must be whole numbers start:stop:step (like "
                              f"1:12:1), got {count_text.strip()!r}")
    if many and stream and max_values is None:
        batch = values_stream(count_text, what, _count_item,
                              bounds=(1.0, float(parse.MAX_COUNT)))
        if len(batch) > 1:
            top = max(float(c.max()) for c in batch.chunks())
            _refuse_out_of_doubles([coin_catalog.stack_xi(unit, 1),
                                    coin_catalog.stack_xi(unit, int(top))], typed)
            return Coins(None, "size" if kind == "size" else "coin", unit, batch,
                         unit.diameter_mm, typed)
        count_text = repr(int(batch.values()))
    counts = ([int(k) for k in _many(count_text, what, _count_item, None, max_values)] if many
              else [_one(count_text, what, parse.parse_count)])
    if many and len(counts) > 1:
        import numpy as np

        xis = coin_catalog.stack_xis(unit, np.asarray(counts, dtype=float)).tolist()
    else:
        xis = [coin_catalog.stack_xi(unit, k) for k in counts]
    _refuse_out_of_doubles(xis, typed)
    return Coins(xis, "size" if kind == "size" else "coin", unit, counts, unit.diameter_mm,
                 typed)


# --------------------------------------------------------------------------- stacked coins, seeds


def tosses_value(text: str, *, low: int = 1, high: int = parse.MAX_COUNT,
                 what: str = "-n") -> int:
    """A number of tosses, a whole number from ``low`` to ``high``."""
    s = str(text).strip()
    digits = s.removeprefix("+")
    if not (digits.isascii() and digits.isdigit()):
        raise usage_error(f"{what} must be a whole number from {low} to {high}, got "
                          f"{_shown(text)}")
    digits = digits.lstrip("0") or "0"
    if len(digits) > 19 or not low <= int(digits) <= high:  # and no int() of 5000 digits
        raise usage_error(f"{what} must be a whole number from {low} to {high}, got "
                          f"{_shown(text)}")
    return int(digits)


def _shown(text: str) -> str:
    from coincli.errors import shown

    return shown(text)


def unit_at_end(nums: list[str], units, what: str, example: str, text: str) -> list[str]:
    """The numbers of a range or distribution with a unit typed once at the end applied to each
    (``normal:38:4rev/s`` is ``normal:38rev/s:4rev/s``), as typed when every number or none has
    one; a unit on some numbers only is ambiguous and refused in one line."""
    has = [parse.split_unit(p, units)[1] is not None for p in nums]
    if any(has) and not all(has):
        if not has[-1] or any(has[:-1]):
            raise usage_error(f"{what}: give the unit once at the end ({example}) or after "
                              f"every number, got {text!r}")
        unit = parse.split_unit(nums[-1], units)[1]
        nums = [p + unit for p in nums[:-1]] + nums[-1:]
    return nums


def range_unit(text: str, units, what: str, example: str) -> tuple[str, str | None]:
    """A range ``start:stop:step`` with its unit typed once at the end (``0:500:100ms``) or the
    same after every number (``0ms:500ms:100ms``), as ``(numbers, unit)``; ``unit`` None when
    no number has one.  A unit on some numbers only, or two different units, is refused in one
    line that shows the forms allowed."""
    parts = [p.strip() for p in text.strip().split(":")]
    split = [parse.split_unit(p, units) for p in parts]
    found = [u for _, u in split]
    if not any(found):
        return text.strip(), None
    unit = found[-1]
    if unit is None or (any(found[:-1]) and set(found) != {unit}):
        raise usage_error(f"{what}: give a range's unit once at the end ({example}) or the same "
                          f"after every number, got {text.strip()!r}")
    return ":".join(num for num, _ in split), unit


def typed_range_error(exc: Exception, head: str, text: str) -> Exception:
    """A range error about the numbers ``head`` of a range typed as ``text`` (with its unit),
    shown as typed."""
    return usage_error(str(exc).replace(repr(head), repr(text.strip())))


def refuse_old_count(value: str | None, example: str) -> None:
    """The old ``-n N`` of table/stack: a usage error naming ``--count N``."""
    if value is not None:
        n = value.strip()
        n = n if n.isascii() and n.isdigit() and len(n) < 20 else "N"
        raise usage_error(f"-n is a number of tosses; stacked coins are --count N (e.g. "
                          f"{example.format(n=n)})")


def seed_value(text: str | None) -> int:
    """The seed typed, or a fresh one drawn from the operating system's entropy (63 bits, so
    that it prints short and any tool reads it back); the caller reports it.  A drawn seed is
    kept (:func:`drawn_seed`)."""
    global DRAWN_SEED
    if text is None:
        from coincli.core._numerics.backend import randbits

        DRAWN_SEED = randbits(63)
        return DRAWN_SEED
    return _one(text, "--seed", parse.parse_seed)


#: The seed this run drew, if it drew one, so that an interrupted run still reports it
#: (coincli.cli's signal handler).  The one piece of state this module keeps: it is the
#: record of a run, set by :func:`seed_value` and read by :func:`drawn_seed`; a process that
#: runs several commands (the tests, a notebook) clears it between runs with
#: :func:`reset_drawn_seed`.
DRAWN_SEED: int | None = None


def drawn_seed() -> int | None:
    """The seed this run drew (:func:`seed_value` without a seed), or None."""
    return DRAWN_SEED


def reset_drawn_seed() -> None:
    """Forget the drawn seed: a new run starts (one process may run several commands)."""
    global DRAWN_SEED
    DRAWN_SEED = None


def level_value(text: str, what: str) -> float:
    """A level strictly between 0 and 1 (``--alpha``, ``--confidence``): a probability as the
    grammar reads it (``0.95``, ``95%``, ``19/20``), or the usage error that says so."""
    try:
        v = parse.parse_probability(text, what)
    except ValueError as exc:
        if "must be in [0, 1]" not in str(exc):
            raise usage_error(str(exc)) from None
        v = math.nan  # out of [0, 1]: the message below states what a level may be
    if not 0.0 < v < 1.0:
        like = "0.05, 1/20 or 5%" if what == "--alpha" else "0.95 or 95%"
        raise usage_error(f"{what} must be strictly between 0 and 1 ({like}), got {text!r}")
    return v


def report_seed(seed: int, given: bool) -> None:
    """A drawn seed on stderr, where the output itself has no room for it (``-q``,
    ``--stream``): every random result can be repeated.  A seed the user gave is not repeated."""
    if not given:
        notes.seed(seed)


def report_drawn_seed() -> None:
    """The seed this run drew (:data:`DRAWN_SEED`), if it drew one, on stderr: after output
    that has no room for the note naming it (``-q``)."""
    if DRAWN_SEED is not None:
        report_seed(DRAWN_SEED, False)


# --------------------------------------------------------------------------- psi


def psi_item(text: str, what: str) -> float:
    """One angle of psi in degrees, in [0, 180] (a ValueError otherwise): an item of
    :func:`coincli.io.batches.values_option` and :func:`coincli.io.grammar.parse_values`."""
    try:
        v = parse.parse_number(text, what)
    except ValueError:
        v = math.nan
    if not 0.0 <= v <= 180.0:  # NaN fails
        raise ValueError(f"{what} must be an angle in [0, 180] degrees, got {text!r}")
    return v + 0.0


PSI_AND_DIST = "give --psi DEG (a fixed angle) or --psi-dist SPEC (a distribution), not both"


def refuse_psi_and_dist(psi, psi_dist) -> None:
    """The one usage error for --psi and --psi-dist given together."""
    if psi is not None and psi_dist is not None:
        raise usage_error(PSI_AND_DIST)


def _a_list(text: str) -> bool:
    return any(c in text for c in ",:") and str(text).strip() != "-"


def psi_angle(text: str, what: str = "--psi") -> float:
    """One angle in degrees, in [0, 180]; a list or range is refused as such (a command that
    takes many uses :func:`psi_angles`)."""
    try:
        return psi_item(text, what)
    except ValueError as exc:
        if _a_list(text):
            raise usage_error(f"{what} takes one angle here (degrees, 0 to 180), not a list or "
                              f"range; got {shown(text)}") from None
        raise usage_error(str(exc)) from None


def psi_angles(text: str, what: str = "--psi", *, max_rows: int = parse.MAX_ROWS) -> list[float]:
    """Angles in degrees: a value, a list ``a,b`` or a range ``lo:hi:step`` (no stdin)."""
    try:
        return [float(v) for v in parse.parse_values(text, what, psi_item, max_rows=max_rows)]
    except ValueError as exc:
        raise usage_error(str(exc)) from None


def radians(deg: float) -> float:
    """Degrees to radians, 180 to the double nearest pi (as :func:`parse.parse_angle_deg`)."""
    return math.pi if deg == 180.0 else math.radians(deg)


def psi_density(spec: str, what: str = "--psi-dist"):
    """One psi density (:func:`coincli.io.grammar.parse_density`), or a usage error."""
    from coincli.io.grammar import parse_density

    try:
        return parse_density(spec)
    except ValueError as exc:
        if "," in spec and not spec.strip().lower().startswith("table:"):
            raise usage_error(f"{what} takes one density here, not a list; got {shown(spec)} "
                              "(give one SPEC, e.g. normal:90:18)") from None
        raise usage_error(f"{what}: {exc}") from None


def psi_densities(specs: str, what: str = "--psi-dist") -> list:
    """Densities from a comma list (``uniform,normal:90:18``), each once, in order."""
    parts = [s for s in specs.split(",") if s.strip()]
    if not parts:
        raise usage_error(f"{what} is empty; give e.g. normal:90:18 (or uniform, cosine, "
                          "normal, uniform:LOW:HIGH, table:FILE)")
    out, seen = [], set()
    for s in parts:
        d = psi_density(s, what)
        if d.spec not in seen:
            seen.add(d.spec)
            out.append(d)
    return out
