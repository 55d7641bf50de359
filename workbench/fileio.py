"""A user's files: read with one-line errors, written so that they are never left half-written.

:func:`read_input` and :func:`write_output` turn the operating system's errors into
:class:`~workbench.errors.InputError` s that name the file (exit code 2: the user named a file
that is missing or a place that cannot be written); a write that fails for another reason (a
full disk) is a :class:`~workbench.errors.WorkbenchError` (exit code 1).
"""

from __future__ import annotations

import os
import stat
from pathlib import Path

from workbench.errors import InputError, WorkbenchError

__all__ = ["atomic_write_bytes", "atomic_write_text", "read_input", "read_text_input", "refuse_read_only", "unreadable",
           "write_output"]

# a write refused because of the place the user named, not because the disk failed
_WRONG_PLACE = (FileNotFoundError, FileExistsError, NotADirectoryError, PermissionError)


def read_input(path: str | Path, what: str) -> bytes:
    """The bytes of the input file ``path``; ``what`` names its kind in errors ("an A2L file").

    :raises InputError: ``path: no such file``, ``path: is a folder, not <what>`` or
        ``path: cannot read (<reason>)``.
    """
    try:
        return Path(path).read_bytes()
    except OSError as exc:
        raise unreadable(path, exc, what) from None


def read_text_input(path: str | Path, what: str) -> str:
    """The text of the input file ``path`` (a CSV, a project file): UTF-8 with or without a BOM, UTF-16 with
    its BOM (a spreadsheet's "Unicode text"), else Windows-1252, which a spreadsheet's CSV export and a
    Windows editor write ("ANSI": ``°C``, ``µs``, umlauts).

    :raises InputError: as :func:`read_input`, or ``path:line: not text`` (bytes none of them decode).
    """
    raw = read_input(path, what)
    if raw.startswith((b"\xff\xfe", b"\xfe\xff")):
        encodings = ("utf-16",)
    else:
        encodings = ("utf-8-sig", "cp1252")
    for encoding in encodings:
        try:
            return raw.decode(encoding)
        except UnicodeDecodeError as exc:
            failed = exc
    line = raw[:failed.start].count(b"\n") + 1
    raise InputError(f"{path}:{line}: not {what} (byte 0x{raw[failed.start]:02X} is not UTF-8, UTF-16 or Windows-1252 "
                     "text)")


def unreadable(path: str | Path, exc: OSError, what: str) -> InputError:
    """The error of an input file the system refused to open or read, in :func:`read_input`'s words."""
    if isinstance(exc, FileNotFoundError):
        return InputError(f"{path}: no such file")
    if isinstance(exc, IsADirectoryError):
        return InputError(f"{path}: is a folder, not {what}")
    return InputError(f"{path}: cannot read ({exc.strerror or exc})")


def write_output(path: str | Path, data: bytes) -> None:
    """:func:`atomic_write_bytes`, its failures as one-line errors naming ``path``.

    A file the user made read-only (a version control system's file not checked out, a released A2L) is
    not replaced, although the rename could: its folder's permission would decide, not the file's.

    :raises InputError: ``path`` is a folder, a read-only file, or its folder cannot hold it (missing
        under a file, not writable): ``path: cannot write (<reason>)``.
    :raises WorkbenchError: the write failed otherwise (e.g. the disk is full).
    """
    refuse_read_only(path)
    try:
        atomic_write_bytes(path, data)
    except IsADirectoryError:
        raise InputError(f"{path}: is a folder; name the file to write") from None
    except _WRONG_PLACE as exc:
        raise InputError(f"{path}: cannot write ({exc.strerror or exc})") from None
    except OSError as exc:
        raise WorkbenchError(f"{path}: cannot write ({exc.strerror or exc})") from None


def refuse_read_only(path: str | Path) -> None:
    """:raises InputError: ``path`` is a file the user made read-only, which a write must not replace."""
    if _read_only(path):
        raise InputError(f"{path}: the file is read-only; not overwritten (make it writable, or write another file)")


def _read_only(path: str | Path) -> bool:
    """Whether ``path`` is an existing file without write permission (its owner's bit: root may write anything)."""
    try:
        mode = os.stat(path).st_mode
    except OSError:  # none yet (or unreachable: the write says why)
        return False
    return stat.S_ISREG(mode) and (not mode & stat.S_IWUSR or not os.access(path, os.W_OK))


def atomic_write_bytes(path: str | Path, data: bytes, *, durable: bool = True) -> None:
    """Write ``data`` to ``path`` through a temporary file in the same folder and a rename.

    Either the old file or the complete new one exists at every moment (``durable``: also after a power loss,
    the data reaching the disk before the rename; a cache that can be rebuilt need not wait for that); the file's
    permission bits are kept when it is replaced; a new file gets the usual 0o666 minus the umask
    (not the 0o600 of a temporary file). A symbolic link is written through: its target gets the
    new content (in the target's folder), the link stays, as an editor saving the file keeps it.
    """
    path = Path(path)
    if path.is_symlink():  # the rename would replace the link itself with a file
        path = Path(os.path.realpath(path))
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f".{path.name}.{os.getpid()}.{os.urandom(4).hex()}.tmp")
    # 0o666 here becomes a new file's usual mode minus the umask (tempfile would give 0o600)
    fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_BINARY", 0), 0o666)
    try:
        with os.fdopen(fd, "wb") as handle:
            handle.write(data)
            if durable:
                handle.flush()
                os.fsync(handle.fileno())
        if path.exists():
            os.chmod(tmp, path.stat().st_mode & 0o7777)
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise


def atomic_write_text(path: str | Path, text: str, encoding: str = "utf-8", newline: str | None = None) -> None:
    """Text flavour of :func:`atomic_write_bytes`; ``newline`` as for :func:`open` (None keeps ``\\n``)."""
    if newline:
        text = text.replace("\n", newline)
    atomic_write_bytes(path, text.encode(encoding))
