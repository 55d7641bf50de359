"""One view of an ELF's debug information, whichever source answers (a2ltool's ``DebugData``).

:class:`DebugData` resolves A2L symbol paths (``a.b[2].c``) to address, size and C
type: from DWARF when the ELF has it, from ``.symtab`` otherwise (plain names only).
The ELF's section headers, its DWARF variables, and every type and symbol path
resolved are cached on disk, so a second run against the same ELF reads no DWARF and
answers most paths with one dict lookup.
"""

from __future__ import annotations

import struct
from pathlib import Path
from typing import NamedTuple

from workbench.elf import dwarf
from workbench.elf.cache import IndexCache
from workbench.elf.ctypes_model import CType, TypeResolver
from workbench.elf.paths import PathError, split_path, walk
from workbench.elf.symbols import ElfSymbols
from workbench.errors import InputError, UnknownSymbolError
from workbench.progress import Progress, report

_DWARF_SECTIONS = (".debug_info", ".debug_abbrev", ".debug_str", ".debug_line_str", ".debug_str_offsets",
                   ".debug_addr")
# what decoding damaged DWARF raises: reads past a section's end, unknown codes, bad struct reads
_DAMAGED_DWARF = (dwarf.DwarfError, IndexError, ValueError, KeyError, struct.error)


class ResolvedSymbol(NamedTuple):
    """Where a symbol path lives: ``address`` and ``size`` in bytes."""

    path: str
    address: int
    size: int
    type: CType | None  # None when only .symtab knew the symbol
    source: str  # "dwarf" or "symtab"
    bit_size: int | None = None  # bitfield members
    bit_position: int | None = None  # lowest bit of a bitfield in its storage unit


class DebugData:
    """Symbols and types of one ELF file.

    ``cache_dir``: folder of the index cache (None: the user's cache folder);
    ``use_cache=False`` neither reads nor writes it. Raises :class:`InputError` for a
    file that is not an ELF.
    """

    def __init__(self, elf_path: str | Path, *, cache_dir: str | Path | None = None, use_cache: bool = True,
                 progress: Progress | None = None):
        self.path = Path(elf_path)
        self._cache = IndexCache(cache_dir) if use_cache else None
        self._reader: dwarf.DwarfReader | None = None
        cached = self._cache.load(self.path) if self._cache is not None else None
        self.from_cache = cached is not None and self._take_cached(cached)
        if not self.from_cache:
            self.elf = ElfSymbols(self.path)
            variables = self._read_variables(progress) if self.elf.has_dwarf else {}
            # symbol path -> address: the variables with a static address, then every path resolved since
            self._addresses = {name: address for name, (address, _) in variables.items() if address is not None}
            # variable -> DIE offset of its type (None: no type); also the variables without an address
            self._variable_types = {name: type_offset for name, (_, type_offset) in variables.items()}
            self._types = {}
        self._resolver: TypeResolver | None = None
        self._walks: dict[tuple, tuple | PathError] = {}
        self._stored = self._index_size() if self.from_cache else None

    def _take_cached(self, cached: dict) -> bool:
        """Use a cache entry; False (a miss) when it does not have the expected shape."""
        try:
            self.elf = ElfSymbols.from_facts(self.path, cached["elf"])
            self._addresses: dict[str, int] = cached["addresses"]
            self._variable_types: dict[str, int | None] = cached["variable_types"]
            self._types: dict[int, CType] = cached["types"]
        except (KeyError, TypeError, ValueError):
            return False
        return all(isinstance(part, dict) for part in (self._addresses, self._variable_types, self._types))

    def __enter__(self) -> "DebugData":
        return self

    def __exit__(self, *exc) -> None:
        self.save()

    @property
    def has_dwarf(self) -> bool:
        return bool(self._variable_types)

    def resolve(self, path: str) -> ResolvedSymbol:
        """Address, size and type of an A2L symbol path; raises :class:`UnknownSymbolError`
        (with the reason) when the ELF does not have it. The address is remembered (and cached
        with the index) for :meth:`addresses`."""
        found = self._resolve(path)
        self._addresses[path] = found.address
        return found

    def _resolve(self, path: str) -> ResolvedSymbol:
        cut = _base_length(path)
        base, suffix = path[:cut], path[cut:]
        if base in self._variable_types:
            address, type_offset = self._addresses.get(base), self._variable_types[base]
            if address is None:  # DWARF without a location: the symbol table may still know it
                symbol = self.elf.symbols.get(base)
                if symbol is None:
                    raise UnknownSymbolError(path, "the variable has no static address (optimised out?)")
                address = symbol.address
            offset, reached, bit_size, bit_position = self._walk(path, type_offset, suffix)
            return ResolvedSymbol(path, address + offset, reached.size, reached, "dwarf", bit_size, bit_position)
        try:
            base, steps = split_path(path)
        except PathError as exc:
            raise UnknownSymbolError(path, str(exc)) from None
        symbol = self.elf.symbols.get(base)
        if symbol is not None and symbol.kind != "function":
            if steps:
                raise UnknownSymbolError(path, f"{self.path.name} has no DWARF type of {base!r} to find members in")
            return ResolvedSymbol(path, symbol.address, symbol.size, None, "symtab")
        raise UnknownSymbolError(path, self.path.name)

    def _walk(self, path: str, type_offset: int | None, suffix: str) -> tuple[int, CType, int | None, int | None]:
        """The member/element ``suffix`` (".b[2].c") of a variable of this type, memoised: many
        variables share a type, so ``x.in.phys`` is worked out once for all of them."""
        key = (type_offset, suffix)
        found = self._walks.get(key)
        if found is None:
            ctype = self._type(type_offset)
            try:
                _, steps = split_path("x" + suffix)
                found = walk(ctype, steps)
            except PathError as exc:
                found = exc
            self._walks[key] = found
        if isinstance(found, PathError):
            raise UnknownSymbolError(path, str(found))
        return found

    def addresses(self, paths: list[str], progress: Progress | None = None) -> list[int | None]:
        """The address of every symbol path (None where the ELF does not have it): the hot path of
        an address update. Plain names and paths resolved before cost one dict lookup each."""
        found = list(map(self._addresses.get, paths))
        unknown = [row for row, address in enumerate(found) if address is None]
        for done, row in enumerate(unknown):
            if done % 2000 == 0:
                report(progress, done, len(unknown), "resolving symbol paths")
            symbol = self.find(paths[row])
            if symbol is not None:
                found[row] = symbol.address
        return found

    def find(self, path: str) -> ResolvedSymbol | None:
        try:
            return self.resolve(path)
        except UnknownSymbolError:
            return None

    def resolve_error(self, path: str) -> str:
        """Why ``path`` cannot be resolved ("" when it can)."""
        try:
            self.resolve(path)
        except UnknownSymbolError as exc:
            return f"not in {exc.where}" if exc.where == self.path.name else exc.where
        return ""

    def save(self) -> None:
        """Write the index cache if this run added to it (an ELF without DWARF is not cached)."""
        if self._cache is None or not self._variable_types or self._index_size() == self._stored:
            return
        self._cache.store(self.path, {"elf": self.elf.facts(), "addresses": self._addresses,
                                      "variable_types": self._variable_types, "types": self._types})
        self._stored = self._index_size()

    def _index_size(self) -> tuple[int, int]:
        return len(self._addresses), len(self._types)

    # -- DWARF ------------------------------------------------------------------------------
    def _dwarf(self) -> dwarf.DwarfReader:
        if self._reader is None:
            from elftools.common.exceptions import ELFError  # here: a cached index never reads DWARF
            from elftools.elf.elffile import ELFFile

            try:
                with open(self.path, "rb") as handle:
                    elf = ELFFile(handle)
                    sections = {}
                    for name in _DWARF_SECTIONS:
                        section = elf.get_section_by_name(name)
                        if section is not None:
                            sections[name] = section.data()
            except OSError as exc:
                raise InputError(f"{self.path}: cannot read ({exc.strerror})") from None
            except ELFError as exc:  # e.g. a compressed section that does not decompress
                raise InputError(f"{self.path}: unreadable DWARF section ({exc})") from None
            try:
                self._reader = dwarf.DwarfReader(sections, self.elf.little_endian)
            except _DAMAGED_DWARF as exc:
                raise InputError(f"{self.path}: unreadable DWARF ({exc})") from None
        return self._reader

    def _read_variables(self, progress: Progress | None) -> dict[str, tuple[int | None, int | None]]:
        try:
            found = self._dwarf().global_variables(progress)
        except _DAMAGED_DWARF as exc:
            raise InputError(f"{self.path}: unreadable DWARF ({exc})") from None
        variables: dict[str, tuple[int | None, int | None]] = {}
        for variable in found:
            known = variables.get(variable.name)
            # a definition (with an address) wins over a declaration met earlier
            if known is None or (known[0] is None and variable.address is not None):
                variables[variable.name] = (variable.address, variable.type_offset)
        return variables

    def _type(self, offset: int | None) -> CType:
        if offset is not None and offset in self._types:
            return self._types[offset]
        if self._resolver is None:
            self._resolver = TypeResolver(self._dwarf(), self._types)
        try:
            return self._resolver.resolve(offset)
        except _DAMAGED_DWARF as exc:
            raise InputError(f"{self.path}: unreadable DWARF type at 0x{offset or 0:x} ({exc})") from None


def _base_length(path: str) -> int:
    """Length of the variable name at the start of a path (up to the first '.' or '[')."""
    dot, bracket = path.find("."), path.find("[")
    if dot < 0:
        return bracket if bracket >= 0 else len(path)
    return dot if bracket < 0 or dot < bracket else bracket
