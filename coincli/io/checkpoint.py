"""``--checkpoint FILE``: the chunks of a bouncing run recorded as they complete, so that the
same command run again computes only what is missing and prints the same bytes.

The file is JSON lines.  The first line is the header: the format, ``coin``'s and MuJoCo's
versions, the command and the values of the options that decide the tosses (the seed among
them), with a checksum.  Each other line is one chunk of
:func:`coincli.core.bounce.runs.simulate`: the digest of what decides its block's tosses (the
coin, the surface, the timestep, the launch distributions, the seed, the block and the stream:
:func:`block_key`), the chunk's first toss in the block, its rows (outcome, catch, bounces, time
to settle, steps, as the engine gives them; floats written exactly) and a checksum.  No toss
depends on how its block is cut into chunks, so a run resumed with other chunks (the local
pool's 16 tosses, a cluster's more: :func:`coincli.core.bounce.cluster.chunk_for`) takes what the
file holds toss by toss, and computes again only the chunks it does not hold whole.  A line of a
calibration's design point is the digest of the task (:func:`task_key`) and its counts.  A line
is appended and fsynced as each chunk completes, so a run killed at any moment leaves every
chunk it finished; a torn or damaged line is dropped (and recomputed) the next time, and so is
one whose checksum matches but whose record is not one this module writes (:func:`_good_record`:
types, field count, outcomes 0-3; a design point's counts also of its task's shape, ``fn.fits``).
A header whose fields are not of their types is a damaged header.

A checkpoint written by another command line, another ``coin`` or another MuJoCo is refused
in one line naming what differs (:class:`Checkpoint`).  It works with the local pool
(``--jobs``) and with a cluster (``--scheduler``) alike: a :class:`Checkpoint` is the executor
``simulate`` takes, in front of the cluster's when there is one.
"""

from __future__ import annotations

import hashlib
import json
import math
import os

from coincli.errors import compute_error, shown, usage_error

__all__ = ["Checkpoint", "block_key", "task_key", "FORMAT", "MAX_BYTES"]

FORMAT = "coin-checkpoint/1"  #: the first field of the header: what reads this file
MAX_BYTES = 1 << 30  #: the largest checkpoint read (10^6 tosses take about 50 MB)


def _canon(value) -> str:
    """A text that is the same for equal values in any process: floats exactly (repr),
    dataclasses by their fields (a psi density by its spec), containers item by item."""
    import dataclasses

    if isinstance(value, float):
        return repr(value)
    if isinstance(value, (list, tuple)):
        return "(" + ",".join(_canon(v) for v in value) + ")"
    if isinstance(value, dict):
        return "{" + ",".join(f"{_canon(k)}:{_canon(v)}" for k, v in value.items()) + "}"
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        fields = []
        for f in dataclasses.fields(value):
            v = getattr(value, f.name)
            if f.name == "density" and v is not None:  # a psi density: its spec says it all
                v = str(getattr(v, "spec", type(v).__name__))
            fields.append(f"{f.name}={_canon(v)}")
        return f"{type(value).__name__}({','.join(fields)})"
    return repr(value)


def block_key(args, job) -> str:
    """The digest of what decides the tosses of a chunk's block: the engine's ``args`` and the
    ``job`` as :func:`coincli.core.bounce.runs.simulate` cuts it, less the chunk's index and
    place (its first and last toss), on which no toss depends."""
    seed, block, _start, _stop, count, dists, stream = job[1]
    return _digest(("block", args, (seed, block, count, dists, stream)))


def task_key(fn, task) -> str:
    """The digest of a task of another kind (a design point of a calibration, ``fn(task)``):
    the function's name and everything it is sent."""
    return _digest(("task", f"{fn.__module__}.{fn.__qualname__}", task))


def _digest(value) -> str:
    return hashlib.sha256(_canon(value).encode()).hexdigest()


def _sum(fields: dict) -> str:
    return hashlib.sha256(json.dumps(fields, sort_keys=True).encode()).hexdigest()[:16]


def _line(fields: dict) -> str:
    return json.dumps({**fields, "sum": _sum(fields)}) + "\n"


def _parse(line: str):
    """A line's fields, or None when it is torn or its checksum does not match (or it nests
    too deep for the JSON reader: a hand-made line of 200,000 brackets)."""
    try:
        fields = json.loads(line)
    except (ValueError, RecursionError):
        return None
    if not isinstance(fields, dict):
        return None
    total = fields.pop("sum", None)
    return fields if total == _sum(fields) else None


def _is_int(v) -> bool:
    return isinstance(v, int) and not isinstance(v, bool)


def _is_text_map(v) -> bool:
    return isinstance(v, dict) and all(isinstance(x, str) for kv in v.items() for x in kv)


def _good_header(head: dict) -> bool:
    """Whether the header's fields have the types this module writes: ``format`` and
    ``command`` texts, ``versions`` and ``options`` maps of text to text."""
    return (isinstance(head.get("format"), str) and isinstance(head.get("command"), str)
            and _is_text_map(head.get("versions")) and _is_text_map(head.get("options")))


def _good_toss(row) -> bool:
    """Whether ``row`` is a toss as :func:`coincli.core.bounce.runs._run_block` writes it:
    outcome 0-3, the catch's outcome 0-3, bounces and steps integers >= 0, and the time to
    settle a finite number >= 0 (not a number when the toss did not settle, outcome 3)."""
    if not isinstance(row, list) or len(row) != 5:
        return False
    code, catch, bounces, t_settle, steps = row
    if not all(_is_int(v) for v in (code, catch, bounces, steps)):
        return False
    if not (0 <= code <= 3 and 0 <= catch <= 3 and bounces >= 0 and steps >= 0):
        return False
    if not isinstance(t_settle, (int, float)) or isinstance(t_settle, bool):
        return False
    if code == 3:
        return t_settle != t_settle  # nan
    return math.isfinite(t_settle) and t_settle >= 0


def _good_counts(result) -> bool:
    """Whether ``result`` is a design point's counts as
    :func:`coincli.core.bounce.calibrate._simulate_point` gives them: one or more groups of
    (heads, sides, tails, unsettled), integers >= 0, every group of the same number of tosses."""
    if not isinstance(result, list) or not result:
        return False
    for group in result:
        if not isinstance(group, list) or len(group) != 4 or \
                not all(_is_int(c) and c >= 0 for c in group):
            return False
    return len({sum(group) for group in result}) == 1


def _good_record(rec: dict) -> bool:
    """Whether a line whose checksum matched is a record this module writes: a chunk
    (``key``, ``start``, ``rows``: a 64-digit hex key, a first toss >= 0 and one or more
    tosses, :func:`_good_toss`) or a task (``key``, ``rows``: its counts,
    :func:`_good_counts`), and nothing else."""
    key = rec.get("key")
    if not isinstance(key, str) or len(key) != 64 or \
            any(c not in "0123456789abcdef" for c in key):
        return False
    if set(rec) == {"key", "start", "rows"}:
        rows = rec["rows"]
        return (_is_int(rec["start"]) and rec["start"] >= 0 and isinstance(rows, list)
                and bool(rows) and all(_good_toss(r) for r in rows))
    if set(rec) == {"key", "rows"}:
        return _good_counts(rec["rows"])
    return False


class Checkpoint:
    """The checkpoint ``path`` of a run described by ``header`` (``command``: the command as
    the user would type it, ``options``: option name -> value as text, ``versions``: name ->
    version), and ``inner``, the executor of the chunks it does not hold (a
    :class:`coincli.core.bounce.cluster.Cluster`, or None: they run in the local pool, which
    hands them to :meth:`keep`)."""

    def __init__(self, path: str, header: dict, inner=None):
        self.path, self.inner = path, inner
        self.header = {"format": FORMAT, **header}
        self.rows: dict = {}  # block key -> {first toss: rows}; task key -> result
        self.keys: dict = {}  # chunk or task index -> (key, first toss or None), this run
        self.fh = None
        self.held = 0  #: records (chunks, tasks) found in the file when it was opened

    def __enter__(self):
        self.open()
        return self

    def __exit__(self, *exc):
        self.close()
        return False

    def open(self) -> None:
        """Read the file (if any): refuse another run's, keep the good lines (rewriting the
        file without a torn or damaged one), then open it for appending."""
        from coincli.io.files import FileKindError, check_output_path, write_text_atomic

        try:
            check_output_path(self.path)
        except FileKindError as exc:
            raise usage_error(f"--checkpoint: {exc}") from None
        except OSError as exc:
            raise compute_error(f"cannot write {self.path!r}: {exc.strerror or exc}") from None
        lines = self._read()
        good = []
        if lines:
            head = _parse(lines[0])
            if head is None or head.get("format") != FORMAT or not _good_header(head):
                raise usage_error(f"--checkpoint {shown(self.path)} is not a checkpoint of "
                                  "coin (or its first line is damaged); give another file")
            self._compare(head)
            good = [lines[0]]
            for line in lines[1:]:
                rec = _parse(line)
                if rec is None or not _good_record(rec):  # torn, damaged or ill-formed
                    continue
                start, held = rec.get("start"), self.rows.get(rec["key"])
                if start is None:
                    if isinstance(held, dict):  # a task's key on a chunk's: not this module's
                        continue
                    self.rows[rec["key"]] = rec["rows"]
                else:
                    if isinstance(held, list):
                        continue
                    self.rows.setdefault(rec["key"], {})[start] = rec["rows"]
                good.append(line if line.endswith("\n") else line + "\n")
                self.held += 1
        try:
            if not lines or len(good) < len(lines) or not lines[-1].endswith("\n"):
                body = good or [_line(self.header)]
                write_text_atomic(self.path, lambda fh: fh.writelines(body))
            self.fh = open(self.path, "a", encoding="utf-8")  # noqa: SIM115 - closed in close()
        except OSError as exc:
            raise compute_error(f"cannot write {self.path!r}: {exc.strerror or exc}") from None

    def _read(self) -> list:
        from coincli.io.files import Unreadable, read_text

        if not os.path.exists(self.path):
            return []
        try:
            text = read_text(self.path, MAX_BYTES)
        except Unreadable as exc:
            raise usage_error(f"--checkpoint: {exc}") from None
        return text.splitlines(keepends=True)

    def _compare(self, head: dict) -> None:
        """Refuse a checkpoint of another run, naming the first things that differ."""
        mine = self.header
        where = f"--checkpoint {shown(self.path)}"
        for name, version in mine["versions"].items():
            theirs = head.get("versions", {}).get(name)
            if theirs != version:
                raise usage_error(f"{where} was written by {name} {theirs}, this is {name} "
                                  f"{version}: give another file (or delete it)")
        if head.get("command") != mine["command"]:
            raise usage_error(f"{where} was written by {head.get('command')!r}, not "
                              f"{mine['command']!r}: give another file (or delete it)")
        old, new = head.get("options", {}), mine["options"]
        diff = [f"{name} {old.get(name, '(not given)')} there, "
                f"{new.get(name, '(not given)')} here"
                for name in dict.fromkeys([*new, *old]) if old.get(name) != new.get(name)]
        if diff:
            raise usage_error(f"{where} holds another run: {'; '.join(diff[:4])}"
                              f"{'; ...' if len(diff) > 4 else ''}: run the same command "
                              "to resume it, or give another file")

    def close(self) -> None:
        if self.fh is not None:
            self.fh.close()
            self.fh = None

    # -- the executor of runs.simulate

    def chunk(self, n: int) -> int:
        """The chunk of a run of ``n`` tosses: the cluster's, else the local pool's.  A chunk
        is found in the file whatever chunks wrote it (:meth:`_held`)."""
        from coincli.core.bounce.runs import CHUNK

        return self.inner.chunk(n) if hasattr(self.inner, "chunk") else CHUNK

    def blocks(self, args, work):
        """The chunks of ``work`` this file holds, then (with ``inner``) the others, each
        recorded as it arrives: ``(k, rows)`` pairs."""
        self.keys = {k: (block_key(args, (k, job)), job[2]) for k, job in work}
        yield from self._supply(work, lambda k, job: self._held(self.keys[k][0], job[2], job[3]),
                                lambda missing: self.inner.blocks(args, missing))

    def _supply(self, items, held, compute):
        """``(k, result)``: what ``held(k, item)`` finds in the file, then what ``compute`` (the
        inner executor) gives for the rest, each recorded as it arrives."""
        missing = []
        for k, item in items:
            got = held(k, item)
            if got is None:
                missing.append((k, item))
            else:
                yield k, got
        if self.inner is not None and missing:
            for k, got in compute(missing):
                self.keep(k, got)
                yield k, got

    def _held(self, key, start, stop):
        """Tosses ``start`` to ``stop`` of the block ``key`` as the file holds them, from
        chunks of any size (a run of chunks of 16 resumed in chunks of 64, or the reverse), or
        None when one is missing."""
        parts = self.rows.get(key)
        if not parts or not isinstance(parts, dict):
            return None
        out = []
        at = start
        while at < stop:
            for first, rows in parts.items():
                if first <= at < first + len(rows):
                    take = rows[at - first:stop - first]
                    out.extend(tuple(r) for r in take)
                    at += len(take)
                    break
            else:
                return None
        return out

    def tasks(self, fn, items):
        """The results of ``fn(task)`` for the ``(k, task)`` pairs ``items`` (a calibration's
        design points) this file holds, then (with ``inner``, a cluster) the others, each
        recorded as it arrives: ``(k, result)`` pairs; the caller computes the rest and hands
        them to :meth:`keep`."""
        self.keys = {k: (task_key(fn, task), None) for k, task in items}
        fits = getattr(fn, "fits", None)  # whether a result is one of this task's

        def held(k, task):
            got = self.rows.get(self.keys[k][0])
            if not isinstance(got, list) or (fits is not None and not fits(task, got)):
                return None  # not held, or not of this task's shape: computed again
            return got

        yield from self._supply(items, held, lambda missing: self.inner.run(fn, missing))

    def keep(self, k, rows) -> None:
        """Record chunk (or task) ``k`` of the run in progress: appended, flushed and
        fsynced."""
        key, start = self.keys[k]
        rows = [list(r) if isinstance(r, (list, tuple)) else r for r in rows]
        if start is None:
            self.rows[key] = rows
            fields = {"key": key, "rows": rows}
        else:
            self.rows.setdefault(key, {})[start] = rows
            fields = {"key": key, "start": start, "rows": rows}
        try:
            self.fh.write(_line(fields))
            self.fh.flush()
            os.fsync(self.fh.fileno())
        except OSError as exc:
            raise compute_error(f"cannot write the checkpoint {self.path!r}: "
                                f"{exc.strerror or exc}") from None
