"""Files that ``coin`` reads and writes: a file is written whole or not at all, and only regular
files are read or replaced.

Every file ``coin`` writes goes through :func:`write_atomic` (figures of ``coin plot``,
``coin phase`` and ``coin book``; the tables ``coin book --out`` writes, by
:func:`write_text_atomic`; any output file a command adds later):

1. :func:`check_output_path` first, before any computing: a FIFO, a device, a directory or a
   socket is refused with one line (a FIFO is never opened, so nothing blocks), as is a missing
   directory;
2. the bytes go to a temporary file in the target's own directory (``.NAME.XXXXXXXX.tmp``, so
   the rename cannot cross file systems), which is flushed and fsynced;
3. only when that is complete is it renamed over the target (``os.replace``: atomic on POSIX),
   taking the old file's permission bits (a new file gets ``0666`` less the umask, as ``open``
   would give it), and the directory is fsynced.

A failure anywhere (a full disk, ``ulimit -f``, Ctrl-C, SIGTERM or SIGHUP, an error while
drawing) removes the temporary file and leaves the old target byte for byte as it was.  A
symbolic link is followed: the file it points to is replaced, the link stays.

Every file ``coin`` is given (``--psi-dist table:FILE``, ``coin fit FILE``, ``coin plot sides
--data FILE``, or ``-`` for standard input) is read by :func:`read_text`: a named file through
:func:`read_regular`, opened without blocking and checked to be a regular file before a byte is
read, so a FIFO with no writer or a device such as ``/dev/zero`` is one line, not a hang;
reading stops past a byte limit and at a NUL byte (see :func:`read_capped`).  A pipe on
standard input is what the user asked for.  Each failure is an :class:`Unreadable` that the
caller says in its own words.

Errors are :class:`FileKindError` (a ValueError: the path names the wrong kind of file; the
command line turns it into a usage error, exit 2) or OSError (the system refused: no such file
or directory, permission denied, disk full; exit 1).  Only the standard library is imported.
"""

from __future__ import annotations

import os
import stat
from collections.abc import Callable

__all__ = [
    "FileKindError",
    "check_output_path",
    "refuse_unwritable",
    "write_atomic",
    "write_text_atomic",
    "read_regular",
    "read_capped",
    "file_kind",
    "read_text",
    "Unreadable",
    "stream_reader",
    "READ_CHUNK",
    "UTF8_BOM",
]

READ_CHUNK = 1 << 20  #: bytes read at a time
UTF8_BOM = b"\xef\xbb\xbf"  #: the byte-order mark some editors put first; dropped on reading


class Unreadable(ValueError):
    """A file (or stdin) :func:`read_text` could not give as text.  ``reason`` is ``"kind"`` (not
    a regular file: ``detail`` says what it is, 'a FIFO (named pipe)', ...), ``"system"`` (the
    system refused: ``detail`` is its words, 'No such file or directory'), ``"size"`` (more
    than the limit), ``"nul"`` (a NUL byte) or ``"utf8"`` (not UTF-8 text).  Each caller says
    it in its own words."""

    def __init__(self, reason: str, detail: str = ""):
        super().__init__(f"{reason}: {detail}" if detail else reason)
        self.reason, self.detail = reason, detail


class FileKindError(ValueError):
    """The path is not a regular file (or its directory does not exist); ``kind`` says what it
    is in words ('a FIFO (named pipe)', ...)."""

    def __init__(self, message: str, kind: str = ""):
        super().__init__(message)
        self.kind = kind


def file_kind(mode: int) -> str:
    """What ``mode`` (an ``st_mode``) is, in words: 'a FIFO (named pipe)', 'a directory', ..."""
    for test, name in ((stat.S_ISDIR, "a directory"), (stat.S_ISFIFO, "a FIFO (named pipe)"),
                       (stat.S_ISCHR, "a character device"), (stat.S_ISBLK, "a block device"),
                       (stat.S_ISSOCK, "a socket")):
        if test(mode):
            return name
    return "not a regular file"


def _quoted(path) -> str:
    text = os.fsdecode(path)
    r = repr(text)
    return r if len(r) <= 200 else r[:97] + "..." + r[-100:]


def check_output_path(path) -> str:
    """The real path to write ``path`` to (symbolic links followed); :class:`FileKindError`
    when it exists as anything but a regular file, FileNotFoundError when its directory does
    not exist, PermissionError when that directory cannot be written (a file is written beside
    its name, then renamed over it).  Nothing is opened."""
    path = os.fspath(path)
    if not path:
        raise FileKindError("the output file name is empty")
    real = os.path.realpath(path)
    try:
        st = os.stat(real)
    except FileNotFoundError:
        st = None
    except NotADirectoryError:
        raise FileKindError(f"cannot write {_quoted(path)}: a part of its directory is not a "
                            "directory", "not a directory") from None
    if st is not None and not stat.S_ISREG(st.st_mode):
        kind = file_kind(st.st_mode)
        raise FileKindError(f"cannot write {_quoted(path)}: it is {kind}; give the name of a "
                            "regular file (it is replaced whole)", kind)
    parent = os.path.dirname(real) or "."
    try:
        pst = os.stat(parent)
    except OSError:
        pst = None
    if pst is None or not stat.S_ISDIR(pst.st_mode):
        import errno

        raise FileNotFoundError(errno.ENOENT, f"its directory {_quoted(parent)} does not exist")
    if not os.access(parent, os.W_OK | os.X_OK):  # the file is written beside, then renamed
        import errno

        raise PermissionError(errno.EACCES, f"its directory {_quoted(parent)} is not writable")
    return real


def write_atomic(path, write: Callable | bytes) -> int:
    """Write ``path`` whole or not at all; return the number of bytes written.

    ``write`` is the bytes, or a function called with a binary file object to write them
    (e.g. ``lambda fh: fig.savefig(fh, ...)``).  See the module docstring for the steps.
    Raises :class:`FileKindError` (wrong kind of path) or OSError (the write failed: the
    target is then untouched and no temporary file is left).
    """
    import tempfile

    real = check_output_path(path)
    parent = os.path.dirname(real) or "."
    try:
        mode = stat.S_IMODE(os.stat(real).st_mode)
    except FileNotFoundError:
        umask = os.umask(0)
        os.umask(umask)
        mode = 0o666 & ~umask
    held = _hold_signals()  # a stop (Ctrl-C, SIGTERM, SIGHUP) here would leave tmp unnamed
    try:
        fd, tmp = tempfile.mkstemp(dir=parent, prefix="." + os.path.basename(real) + ".",
                                   suffix=".tmp")
    except BaseException:
        _release_signals(held)
        raise
    fh = None
    try:
        _release_signals(held)  # a stop held until now is raised here, and cleaned up below
        fh = os.fdopen(fd, "wb")
        with fh:
            if callable(write):
                write(fh)
            else:
                fh.write(write)
            fh.flush()
            os.fsync(fh.fileno())
            size = fh.tell()
        os.chmod(tmp, mode)
        os.replace(tmp, real)
    except BaseException:
        if fh is None:
            os.close(fd)
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise
    _fsync_dir(parent)
    return size


def write_text_atomic(path, write: Callable) -> int:
    """:func:`write_atomic` for text: ``write`` is called with a UTF-8 text file (no newline
    translation: the lines end as written) whose text is streamed into the temporary file, so
    a long output never sits in memory.  Returns the number of bytes written."""
    import io

    def write_bytes(fh):
        text = io.TextIOWrapper(fh, encoding="utf-8", newline="", write_through=False)
        write(text)
        text.flush()
        text.detach()

    return write_atomic(path, write_bytes)


_STOP_SIGNALS = ("SIGINT", "SIGTERM", "SIGHUP")


def _hold_signals():
    """Block SIGINT, SIGTERM and SIGHUP while a temporary file is created and named; the mask
    to restore (None where it cannot be set)."""
    import signal

    if not hasattr(signal, "pthread_sigmask"):
        return None
    held = {getattr(signal, n) for n in _STOP_SIGNALS if hasattr(signal, n)}
    return signal.pthread_sigmask(signal.SIG_BLOCK, held)


def _release_signals(mask) -> None:
    """Restore the signal mask :func:`_hold_signals` saved: a signal that arrived meanwhile is
    delivered now."""
    if mask is not None:
        import signal

        signal.pthread_sigmask(signal.SIG_SETMASK, mask)


def _fsync_dir(path: str) -> None:
    """Make the rename durable (best effort: some file systems refuse to fsync a directory)."""
    try:
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_DIRECTORY", 0))
    except OSError:
        return
    try:
        os.fsync(fd)
    except OSError:
        pass
    finally:
        os.close(fd)


def read_regular(path, limit: int, max_line: int | None = None) -> tuple[bytes, str | None]:
    """The bytes of the regular file ``path``, at most ``limit`` of them, as
    :func:`read_capped` returns them (``(data, why)``).

    The file is opened non-blocking (a FIFO with no writer does not hang the open) and checked
    with ``fstat`` before anything is read: anything but a regular file is a
    :class:`FileKindError` naming what it is.  OSError when it cannot be opened.
    """
    flags = os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_NOCTTY", 0) | \
        getattr(os, "O_CLOEXEC", 0)
    fd = os.open(path, flags)
    try:
        st = os.fstat(fd)
        if not stat.S_ISREG(st.st_mode):
            kind = file_kind(st.st_mode)
            raise FileKindError(f"{_quoted(path)} is {kind}, not a regular file; give a file "
                                "(or '-' and a pipe on standard input)", kind)
        os.set_blocking(fd, True)
        fh = os.fdopen(fd, "rb", buffering=0)
    except BaseException:
        os.close(fd)
        raise
    with fh:
        return read_capped(fh.read, limit, max_line)


def read_capped(read: Callable[[int], bytes], limit: int,
                max_line: int | None = None) -> tuple[bytes, str | None]:
    """Read chunks of ``read(n)`` until the end, never more than ``limit + 1`` bytes in all.

    Returns ``(data, why)``, a leading UTF-8 byte-order mark dropped.  ``why`` is None when all
    was read; ``"size"`` when there are more than ``limit`` bytes (``data`` is then empty);
    ``"nul"`` at a NUL byte, ``"line"`` when a line runs past ``max_line`` bytes: reading stops
    there and ``data`` ends just past the bad byte, so a line-by-line check of ``data`` finds the
    first bad line (the long-line watch only sees lines that cross a chunk boundary; a shorter
    one is the line check's).  /dev/zero, or a pipe that never ends, costs one chunk.
    """
    parts: list[bytes] = []
    total = run = 0  # run: bytes since the last newline
    while total <= limit:
        chunk = read(min(READ_CHUNK, limit + 1 - total))
        if not chunk:
            break
        total += len(chunk)
        if not parts and chunk.startswith(UTF8_BOM):
            chunk = chunk[len(UTF8_BOM):]
        why = None
        nul = chunk.find(b"\0")
        if nul >= 0:
            chunk, why = chunk[:nul + 1], "nul"
        if max_line is not None:
            first = chunk.find(b"\n")
            if run + (len(chunk) if first < 0 else first) > max_line:  # the open line runs on
                chunk, why = chunk[:max_line - run + 1], "line"
            elif first >= 0:
                last = chunk.rfind(b"\n")
                run = len(chunk) - last - 1
                if run > max_line:
                    chunk, why = chunk[:last + max_line + 2], "line"
            else:
                run += len(chunk)
        parts.append(chunk)
        if why is not None:
            return b"".join(parts), why
    if total > limit:
        return b"", "size"
    return b"".join(parts), None


def read_text(source, limit: int) -> str:
    """The UTF-8 text of the regular file ``source`` (a path) or of the stream ``source`` (stdin:
    anything with ``read``), at most ``limit`` bytes, a leading byte-order mark dropped: the one
    reader of the files a command is given (``coin fit FILE``, ``coin plot sides --data FILE``,
    ``--psi-dist table:FILE``).

    A named file is read by :func:`read_regular` (a FIFO or a device is refused without
    blocking), a stream by :func:`read_capped`: never more than ``limit + 1`` bytes, and reading
    stops at a NUL byte.  Every failure is :class:`Unreadable`, whose ``reason`` the caller
    turns into its message.
    """
    try:
        if hasattr(source, "read"):
            data, why = read_capped(stream_reader(source), limit)
        else:
            data, why = read_regular(source, limit)
    except FileKindError as exc:
        raise Unreadable("kind", exc.kind) from None
    except OSError as exc:
        raise Unreadable("system", str(exc.strerror or exc)) from None
    if why is not None:
        raise Unreadable(why)
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError:
        raise Unreadable("utf8") from None


def stream_reader(stream) -> Callable[[int], bytes]:
    """``read(n) -> bytes`` for a binary or text stream (stdin, or a file opened ``"rb"``)."""
    buf = getattr(stream, "buffer", None)
    read = (buf if buf is not None else stream).read

    def read_bytes(n: int) -> bytes:
        chunk = read(n)
        return chunk.encode("utf-8", "surrogateescape") if isinstance(chunk, str) else chunk

    return read_bytes


def refuse_unwritable(path: str, what: str) -> None:
    """Refuse, before any work, an output ``path`` that cannot be written: a FIFO, a device, a
    directory or a missing directory is a wrong input of option ``what`` (``--out``,
    ``--trajectory``); a system error (permissions) is exit 1."""
    from coincli.errors import compute_error, usage_error

    try:
        check_output_path(path)
    except ValueError as exc:
        raise usage_error(f"{what}: {exc}") from None
    except OSError as exc:
        raise compute_error(f"cannot write {path!r}: {exc.strerror or exc}") from None
