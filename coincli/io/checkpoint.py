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
chunk it finished; a torn or damaged line is dropped (and recomputed) the next time.

A checkpoint written by another command line, another ``coin`` or another MuJoCo is refused
in one line naming what differs (:class:`Checkpoint`).  It works with the local pool
(``--jobs``) and with a cluster (``--scheduler``) alike: a :class:`Checkpoint` is the executor
``simulate`` takes, in front of the cluster's when there is one.
"""

from __future__ import annotations

import hashlib
import json
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
    """A line's fields, or None when it is torn or its checksum does not match."""
    try:
        fields = json.loads(line)
    except ValueError:
        return None
    if not isinstance(fields, dict):
        return None
    total = fields.pop("sum", None)
    return fields if total == _sum(fields) else None


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
            if head is None or head.get("format") != FORMAT:
                raise usage_error(f"--checkpoint {shown(self.path)} is not a checkpoint of "
                                  "coin (or its first line is damaged); give another file")
            self._compare(head)
            good = [lines[0]]
            for line in lines[1:]:
                rec = _parse(line)
                if rec is None or not isinstance(rec.get("key"), str) or \
                        not isinstance(rec.get("rows"), list):
                    continue
                start = rec.get("start")
                if start is None:
                    self.rows[rec["key"]] = rec["rows"]
                elif isinstance(start, int) and start >= 0:
                    self.rows.setdefault(rec["key"], {})[start] = rec["rows"]
                else:
                    continue
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
        if not parts:
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
        yield from self._supply(items, lambda k, _task: self.rows.get(self.keys[k][0]),
                                lambda missing: self.inner.run(fn, missing))

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
