"""File writing that never leaves a user's file half-written."""

from __future__ import annotations

import os
import tempfile
from pathlib import Path


def atomic_write_bytes(path: str | Path, data: bytes) -> None:
    """Write ``data`` to ``path`` through a temporary file in the same folder and a rename.

    Either the old file or the complete new one exists at every moment; the file's
    permission bits are kept when it is replaced; a new file gets the usual 0o666 minus the umask
    (not the 0o600 of a temporary file).
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        with os.fdopen(fd, "wb") as handle:
            handle.write(data)
            handle.flush()
            os.fsync(handle.fileno())
        if path.exists():
            os.chmod(tmp, path.stat().st_mode & 0o7777)
        else:
            umask = os.umask(0)
            os.umask(umask)
            os.chmod(tmp, 0o666 & ~umask)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def atomic_write_text(path: str | Path, text: str, encoding: str = "utf-8", newline: str | None = None) -> None:
    """Text flavour of :func:`atomic_write_bytes`; ``newline`` as for :func:`open` (None keeps ``\\n``)."""
    if newline:
        text = text.replace("\n", newline)
    atomic_write_bytes(path, text.encode(encoding))
