"""pya2ldb, the tests' independent reader of A2L files, paid once per file.

pya2ldb parses the demo A2L in about a second and takes another two to start in a fresh process (its
import, then SQLAlchemy configuring its mappers on the first query); the oracle tests asked it about
the same few files again and again, each in a child process of its own. Here each distinct file (by
content, with the files it /includes, encoding and pya2ldb's version) is imported once, its parser's
output kept (pya2ldb's C++ parser reports problems on stdout and carries on, so file descriptors 1
and 2 are captured around the import), into a database that every test and every xdist worker then
opens (:meth:`Imported.session`, milliseconds once the process has pya2ldb's mappers configured). A
lock file makes a second worker wait for the first one's import instead of repeating it; a finished
import is renamed into place whole, so an interrupted one leaves nothing. The databases stay in the
temp directory between runs: a changed file is another key.

::

    imported = import_once(path)
    assert imported.errors == []
    with imported.session() as session:
        session.query(model.Measurement).count()
"""

from __future__ import annotations

import contextlib
import ctypes
import getpass
import hashlib
import json
import os
import re
import shutil
import sqlite3
import sys
import tempfile
import traceback
from dataclasses import dataclass
from importlib.metadata import version
from pathlib import Path

__all__ = ["Imported", "import_once"]

_INCLUDE = re.compile(rb'/include\s+"?([^"\s]+)"?')


@dataclass(frozen=True)
class Imported:
    """One A2L as pya2ldb imported it: its database and what its parser printed."""

    database: Path
    output: tuple[str, ...]
    returncode: int

    @property
    def errors(self) -> list[str]:
        """The parser's error lines, and the import's traceback or exit status if it failed."""
        found = [line for line in self.output if "[error]" in line.lower() or "Traceback" in line]
        return found or ([f"the import exited with {self.returncode}"] if self.returncode else [])

    def session(self):
        """A new pya2ldb session on the database (a context manager; close it when done)."""
        import pya2l

        return pya2l.open_existing(str(self.database), loglevel="ERROR")


def import_once(path: Path | str, encoding: str = "utf-8") -> Imported:
    """``path`` imported into pya2ldb, by this call or an earlier one (of any test, worker or run)."""
    path = Path(path).resolve()
    digest = hashlib.sha256(f"{encoding}\0{version('pya2ldb')}".encode())
    _hash_file(digest, path, set())
    key = digest.hexdigest()[:24]
    folder = _cache() / key
    with _locked(_cache() / f"{key}.lock"):
        if not (folder / "done.json").exists():
            _import(path, encoding, folder)
    done = json.loads((folder / "done.json").read_text(encoding="utf-8"))
    return Imported(folder / "file.a2ldb", tuple(done["output"]), done["returncode"])


def _hash_file(digest, path: Path, seen: set[Path]) -> None:
    """The file's bytes, then those of the files it /includes (found beside it), each once."""
    if path in seen or not path.is_file():
        return
    seen.add(path)
    data = path.read_bytes()
    digest.update(path.name.encode() + b"\0" + data + b"\0")
    for name in _INCLUDE.findall(data):
        _hash_file(digest, path.parent / name.decode("latin-1"), seen)


def _cache() -> Path:
    folder = Path(tempfile.gettempdir()) / f"workbench-tests-{getpass.getuser()}" / "pya2ldb"
    folder.mkdir(parents=True, exist_ok=True)
    return folder


def _import(path: Path, encoding: str, folder: Path) -> None:
    """Import ``path`` where it lies (its /include files beside it), the database and the parser's output
    written into ``folder``."""
    import pya2l

    work = Path(tempfile.mkdtemp(prefix=f"{folder.name}.", dir=folder.parent))
    try:
        returncode = 0
        with _fd_output() as output:
            try:  # parsed into memory, then copied to a file whole: writing to the file as it parses costs more
                session = pya2l.import_a2l(str(path), in_memory=True, progress_bar=False, loglevel="ERROR",
                                           encoding=encoding)
                with contextlib.closing(sqlite3.connect(work / "file.a2ldb")) as database:
                    session.get_bind().raw_connection().driver_connection.backup(database)
                session.close()
            except Exception:
                returncode = 1
                failure = traceback.format_exc().splitlines()
        if returncode:
            output += failure
        (work / "done.json").write_text(json.dumps({"output": output, "returncode": returncode}), encoding="utf-8")
        shutil.rmtree(folder, ignore_errors=True)  # a folder an older run left unfinished
        os.replace(work, folder)
    finally:
        shutil.rmtree(work, ignore_errors=True)


@contextlib.contextmanager
def _fd_output():
    """What is written to file descriptors 1 and 2 meanwhile (the C++ parser's log), as lines."""
    lines: list[str] = []
    with tempfile.TemporaryFile() as sink:
        sys.stdout.flush()
        sys.stderr.flush()
        saved = [os.dup(1), os.dup(2)]
        os.dup2(sink.fileno(), 1)
        os.dup2(sink.fileno(), 2)
        try:
            yield lines
        finally:
            ctypes.CDLL(None).fflush(None)  # C stdio buffers of the parser's logger
            sys.stdout.flush()
            sys.stderr.flush()
            os.dup2(saved[0], 1)
            os.dup2(saved[1], 2)
            for fd in saved:
                os.close(fd)
            sink.seek(0)
            lines.extend(sink.read().decode("utf-8", "replace").splitlines())


@contextlib.contextmanager
def _locked(path: Path):
    """An exclusive lock on ``path`` between processes (POSIX); elsewhere two imports of one file may race,
    and the second one's whole folder replaces the first's."""
    try:
        import fcntl
    except ImportError:
        yield
        return
    with open(path, "a") as handle:
        fcntl.flock(handle, fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(handle, fcntl.LOCK_UN)
