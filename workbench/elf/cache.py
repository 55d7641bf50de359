"""The on-disk cache of an ELF's symbol index: its section headers, DWARF variables, and the
types and symbol paths resolved so far.

An entry is keyed by the ELF's resolved path, size, modification time and a checksum
of its first 4 KiB (ELF and program headers), and holds that identity, so a rebuilt
ELF never meets a stale index. Entries live in the caller's cache folder, by default the user's cache folder
(``~/.cache/workbench/elf-index`` on Linux; ``$WORKBENCH_CACHE_DIR/elf-index`` when that is set), never beside
the user's files.
"""

from __future__ import annotations

import os
import pickle
import sys
import time
import zlib
from pathlib import Path

from workbench.fileio import atomic_write_bytes

__all__ = ["IndexCache", "default_cache_dir"]

FORMAT = 12  # bump when the cached structures or the way names resolve change
ENTRIES = 32  # the most entries a cache folder keeps (the ELFs used most recently)


def default_cache_dir() -> Path:
    """``$WORKBENCH_CACHE_DIR/elf-index`` when that is set (a CI job's persistent volume, a test run's own folder),
    else ``~/.cache/workbench/elf-index`` on Linux (``$XDG_CACHE_HOME`` when it is absolute), the user's cache
    folder that ``platformdirs`` names elsewhere."""
    chosen = os.environ.get("WORKBENCH_CACHE_DIR")
    if chosen:
        return Path(chosen) / "elf-index"
    if sys.platform.startswith("linux"):  # platformdirs' rule, without its imports (tempfile, shutil: 5-10 ms)
        base, home = os.environ.get("XDG_CACHE_HOME", ""), os.environ.get("HOME", "")
        if not os.path.isabs(base):
            if not os.path.isabs(home):  # unset or relative: the account's home, as platformdirs takes it
                import pwd

                home = pwd.getpwuid(os.getuid()).pw_dir
            base = os.path.join(home, ".cache")
        return Path(base) / "workbench" / "elf-index"
    import platformdirs

    return Path(platformdirs.user_cache_dir("workbench")) / "elf-index"


class IndexCache:
    """Load and store pickled index data for ELF files in ``directory``."""

    def __init__(self, directory: str | Path | None = None):
        self.directory = Path(directory) if directory is not None else default_cache_dir()

    def identity(self, elf_path: Path) -> str:
        """What the entry of an ELF is valid for: this format, the file's resolved path, size, modification
        time and a checksum of its first 4 KiB (the entry holds it too: a file name shared by two is a miss)."""
        stat = elf_path.stat()
        with open(elf_path, "rb") as handle:
            header = handle.read(4096)
        return f"{FORMAT}|{elf_path.resolve()}|{stat.st_size}|{stat.st_mtime_ns}|{zlib.crc32(header):08x}"

    def path_for(self, elf_path: Path, identity: str) -> Path:
        data = identity.encode("utf-8", "surrogateescape")
        return self.directory / f"{_stem(elf_path, identity)}{zlib.crc32(data):08x}{zlib.adler32(data):08x}.pickle"

    def load(self, elf_path: Path) -> dict | None:
        """The cached data for this exact ELF, or None (absent, unreadable, another format or file)."""
        try:
            identity = self.identity(elf_path)
            raw = self.path_for(elf_path, identity).read_bytes()
        except OSError:  # no entry; or no readable ELF, which reading it then reports
            return None
        try:
            data = pickle.loads(raw)
        except Exception as exc:  # a truncated or foreign file is only a cache miss
            from workbench.logs import logger  # here: a batch a2l command never imports logging

            logger(__name__).debug("ignoring unreadable index cache for %s: %s", elf_path, exc)
            return None
        if not isinstance(data, dict) or data.get("identity") != identity:
            return None
        try:  # its access time says it was used (the last to go when the folder is pruned); it stays unwritten
            entry = self.path_for(elf_path, identity)
            os.utime(entry, ns=(time.time_ns(), entry.stat().st_mtime_ns))
        except OSError:
            pass
        return data

    def store(self, elf_path: Path, data: dict) -> None:
        """Write the data for this ELF; a cache folder that cannot be written is only logged."""
        identity = self.identity(elf_path)
        entry = self.path_for(elf_path, identity)
        try:
            # not durable: an entry lost with a power loss is only a miss (an fsync cost a first update 2-8 ms)
            atomic_write_bytes(entry, pickle.dumps({**data, "identity": identity}, protocol=5), durable=False)
        except OSError as exc:
            from workbench.logs import logger

            logger(__name__).warning("cannot write the ELF index cache in %s: %s", self.directory, exc)
            return
        self._prune(entry, _stem(elf_path, identity))

    def _prune(self, kept: Path, stem: str) -> None:
        """Remove the entries of earlier builds of the same ELF (its path: they cannot match again), then the
        least recently used beyond :data:`ENTRIES`: a build's every ELF would otherwise add one for good (a few
        MiB each for 50,000 variables)."""
        try:
            entries = [entry for entry in self.directory.glob("*.pickle") if entry != kept]
            for entry in [entry for entry in entries if entry.name.startswith(stem)]:
                entry.unlink(missing_ok=True)
                entries.remove(entry)
            entries.sort(key=lambda entry: entry.stat().st_atime_ns)
            for entry in entries[: max(len(entries) + 1 - ENTRIES, 0)]:
                entry.unlink(missing_ok=True)
        except OSError:  # another process pruning at the same time, or a folder we may not change
            pass


def _stem(elf_path: Path, identity: str) -> str:
    """The start of the entry names of every build of one ELF path (and cache format)."""
    where = identity.rsplit("|", 3)[0].encode("utf-8", "surrogateescape")
    return f"{elf_path.name}.{zlib.crc32(where):08x}."
