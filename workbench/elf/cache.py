"""The on-disk cache of an ELF's symbol index: its section headers, DWARF variables, and the
types and symbol paths resolved so far.

An entry is keyed by the ELF's resolved path, size, modification time and a hash of
its first 4 KiB (ELF and program headers), so a rebuilt ELF never meets a stale
index. Entries live in the caller's cache folder, by default the user's cache folder
(``~/.cache/workbench/elf-index`` on Linux), never beside the user's files.
"""

from __future__ import annotations

import hashlib
import logging
import pickle
from pathlib import Path

from workbench.fileio import atomic_write_bytes

log = logging.getLogger(__name__)

FORMAT = 8  # bump when the cached structures or the way names resolve change


def default_cache_dir() -> Path:
    import platformdirs  # here: its import costs more than a cached update's DWARF work

    return Path(platformdirs.user_cache_dir("workbench")) / "elf-index"


class IndexCache:
    """Load and store pickled index data for ELF files in ``directory``."""

    def __init__(self, directory: str | Path | None = None):
        self.directory = Path(directory) if directory is not None else default_cache_dir()

    def key(self, elf_path: Path) -> str:
        stat = elf_path.stat()
        with open(elf_path, "rb") as handle:
            header = handle.read(4096)
        digest = hashlib.sha256()
        digest.update(f"{FORMAT}|{elf_path.resolve()}|{stat.st_size}|{stat.st_mtime_ns}|".encode())
        digest.update(header)
        return digest.hexdigest()[:32]

    def path_for(self, elf_path: Path) -> Path:
        return self.directory / f"{elf_path.name}.{self.key(elf_path)}.pickle"

    def load(self, elf_path: Path) -> dict | None:
        """The cached data for this exact ELF, or None (absent, unreadable or another format)."""
        try:
            raw = self.path_for(elf_path).read_bytes()
        except OSError:
            return None
        try:
            data = pickle.loads(raw)
        except Exception as exc:  # a truncated or foreign file is only a cache miss
            log.debug("ignoring unreadable index cache for %s: %s", elf_path, exc)
            return None
        return data if isinstance(data, dict) and data.get("format") == FORMAT else None

    def store(self, elf_path: Path, data: dict) -> None:
        """Write the data for this ELF; a cache folder that cannot be written is only logged."""
        try:
            atomic_write_bytes(self.path_for(elf_path), pickle.dumps({**data, "format": FORMAT}, protocol=5))
        except OSError as exc:
            log.warning("cannot write the ELF index cache in %s: %s", self.directory, exc)
