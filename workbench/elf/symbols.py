"""Sections, load segments and the ``.symtab`` of an ELF file, read fast.

:mod:`workbench.elf.headers` reads the headers (ELF, program and section headers); the
symbol table is then read straight from the file into one numpy record array, without an
object per symbol, so a 50,000-symbol ELF loads in milliseconds. What the headers say
(:meth:`ElfSymbols.facts`) is small and can be cached with an index: an
:class:`ElfSymbols` made :meth:`~ElfSymbols.from_facts` reads nothing.
"""

from __future__ import annotations

import struct
from pathlib import Path
from typing import NamedTuple

import numpy as np

from workbench.elf.headers import PT_LOAD, SHF_ALLOC, SHT_NOBITS, ElfHeaders, read_headers, read_section
from workbench.errors import InputError, UnknownSymbolError

__all__ = ["ElfSymbols", "Section", "Symbol"]

STT_OBJECT, STT_FUNC = 1, 2
_KINDS = {STT_OBJECT: "object", STT_FUNC: "function"}
_STB_LOCAL = 0
_SHN_UNDEF, _SHN_LORESERVE = 0, 0xFF00
_SYMBOL_FIELDS = {
    32: [("name", "u4"), ("value", "u4"), ("size", "u4"), ("info", "u1"), ("other", "u1"), ("shndx", "u2")],
    64: [("name", "u4"), ("info", "u1"), ("other", "u1"), ("shndx", "u2"), ("value", "u8"), ("size", "u8")],
}


class Section(NamedTuple):
    name: str
    address: int  # VMA: where the program sees it
    load_address: int  # LMA: where its initial bytes are stored (== address unless relocated by boot)
    size: int
    loaded: bool  # occupies bytes in the file (not NOBITS/.bss)
    allocated: bool  # part of the memory image (SHF_ALLOC)
    file_offset: int = 0  # where its bytes start in the ELF file (when ``loaded``)

    def contains(self, address: int, size: int = 1) -> bool:
        return self.address <= address and address + size <= self.address + self.size


class Symbol(NamedTuple):
    name: str
    address: int
    size: int
    kind: str  # "object", "function" or "other"
    section: str
    external: bool = True  # global or weak binding; False: a file or function static (STB_LOCAL)


class ElfSymbols:
    """Symbols and sections of one ELF file; raises :class:`InputError` for a non-ELF."""

    def __init__(self, path: str | Path):
        self.path = Path(path)
        try:
            self.headers = read_headers(self.path)
            self._symtab = self._locate_symtab(self.headers)
        except FileNotFoundError as exc:
            raise InputError(f"{self.path}: no such file") from exc
        except IsADirectoryError as exc:
            raise InputError(f"{self.path}: is a folder, not an ELF file") from exc
        except (ValueError, struct.error, OSError) as exc:
            raise InputError(f"{self.path}: not a readable ELF file ({exc})") from exc
        self.little_endian: bool = self.headers.little_endian
        self.elfclass: int = self.headers.elfclass
        self.sections: dict[str, Section] = self._read_sections(self.headers)
        self.has_dwarf: bool = ".debug_info" in self.sections or ".zdebug_info" in self.sections
        self._section_names = [section.name for section in self.headers.sections]  # by section index
        self._symbols: dict[str, Symbol] | None = None
        self._symbol_list: list[Symbol] | None = None
        self._names_text: bytes | None = None

    @classmethod
    def from_facts(cls, path: str | Path, facts: dict) -> "ElfSymbols":
        """The ELF described by :meth:`facts` of an earlier read of the same file, without reading it."""
        elf = cls.__new__(cls)
        elf.path = Path(path)
        elf.headers = None  # read when a section's bytes are (see section_bytes)
        elf.little_endian, elf.elfclass, elf.has_dwarf = facts["little_endian"], facts["elfclass"], facts["has_dwarf"]
        elf.sections = {section[0]: Section(*section) for section in facts["sections"]}
        elf._section_names = facts["section_names"]
        elf._symtab = facts["symtab"]
        elf._symbols = elf._symbol_list = elf._names_text = None
        return elf

    def facts(self) -> dict:
        """What the headers say, as plain data for a cache."""
        return {"little_endian": self.little_endian, "elfclass": self.elfclass, "has_dwarf": self.has_dwarf, "sections": [tuple(s) for s in self.sections.values()],
                "section_names": self._section_names, "symtab": self._symtab}

    @staticmethod
    def _read_sections(headers: ElfHeaders) -> dict[str, Section]:
        segments = [segment for segment in headers.segments if segment.type == PT_LOAD]
        sections = {}
        for section in headers.sections:
            if not section.name:
                continue
            address, size = section.address, section.size
            load_address = address
            for segment in segments:  # LMA = segment physical address + offset inside the segment
                if segment.vaddr <= address < segment.vaddr + segment.memsz and segment.filesz:
                    load_address = segment.paddr + (address - segment.vaddr)
                    break
            sections[section.name] = Section(section.name, address, load_address, size, section.type != SHT_NOBITS,
                                             bool(section.flags & SHF_ALLOC), section.offset)
        return sections

    @staticmethod
    def _locate_symtab(headers: ElfHeaders) -> tuple[int, int, int, int] | None:
        """(offset, size) of the symbol table and of its string table in the file; None without one."""
        symtab = next((section for section in headers.sections if section.name == ".symtab"), None)
        if symtab is None:
            return None
        if symtab.link >= len(headers.sections):
            raise ValueError("the symbol table's string table is not a section")
        strtab = headers.sections[symtab.link]
        return symtab.offset, symtab.size, strtab.offset, strtab.size

    def _read_symtab(self) -> list[Symbol]:
        """The defined symbols, decoded column by column; raises :class:`InputError` for a damaged table."""
        if self._symtab is None:
            return []
        table_offset, table_size, strings_offset, strings_size = self._symtab
        dtype = np.dtype([(name, ("<" if self.little_endian else ">") + kind) for name, kind in _SYMBOL_FIELDS[self.elfclass]])
        with open(self.path, "rb") as handle:
            handle.seek(table_offset)
            raw = handle.read(table_size)
            handle.seek(strings_offset)
            strings = handle.read(strings_size)
        table = np.frombuffer(raw, dtype=dtype, count=len(raw) // dtype.itemsize)
        table = table[(table["name"] > 0) & (table["shndx"] != _SHN_UNDEF) & (table["shndx"] < _SHN_LORESERVE)]
        name_starts = table["name"].astype(np.int64)
        terminators = np.flatnonzero(np.frombuffer(strings, np.uint8) == 0)
        after = np.searchsorted(terminators, name_starts)  # the NUL that ends each name
        if len(table) and (after.max() >= len(terminators) or table["shndx"].max() >= len(self._section_names)):
            raise InputError(f"{self.path}: damaged .symtab (a symbol names a string or a section that does not exist)")
        name_ends = terminators[after] if len(table) else name_starts
        names = b"\0".join([strings[a:b] for a, b in zip(name_starts.tolist(), name_ends.tolist())])
        section_names = self._section_names
        return [Symbol(name, address, size, _KINDS.get(info & 0xF, "other"), section_names[shndx],
                       info >> 4 != _STB_LOCAL)
                for name, address, size, info, shndx in zip(
                    names.decode("utf-8", "replace").split("\0"), table["value"].tolist(), table["size"].tolist(),
                    table["info"].tolist(), table["shndx"].tolist())]

    def section_bytes(self, name: str) -> bytes | None:
        """The bytes of the section ``name`` (decompressed), None without one; raises ValueError when they
        cannot be read."""
        if self.headers is None:
            self.headers = read_headers(self.path)
        # a .debug_* section may be GNU-compressed under the name .zdebug_*
        names = (name, ".zdebug_" + name[len(".debug_"):]) if name.startswith(".debug_") else (name,)
        section = next((section for section in self.headers.sections if section.name in names), None)
        return None if section is None else read_section(self.path, section, self.headers)

    def names_text(self) -> bytes:
        """The string table of ``.symtab`` (every symbol name, NUL-terminated; b"" without one): a name
        that does not occur in it is no symbol's, nor part of one's (a demangled name's)."""
        if self._names_text is None:
            self._names_text = b""
            if self._symtab is not None:
                with open(self.path, "rb") as handle:
                    handle.seek(self._symtab[2])
                    self._names_text = handle.read(self._symtab[3])
        return self._names_text

    @property
    def symbol_list(self) -> list[Symbol]:
        """Every defined symbol, in table order (a name may repeat: statics of several units)."""
        if self._symbol_list is None:
            self._symbol_list = self._read_symtab()
        return self._symbol_list

    @property
    def symbols(self) -> dict[str, Symbol]:
        """Defined symbols by name (decoded on first use: a DWARF lookup may never need them); of
        several with one name, a global definition wins over the local ones (statics of other units)."""
        if self._symbols is None:
            symbols: dict[str, Symbol] = {}
            for symbol in self.symbol_list:
                if symbol.name not in symbols or symbol.external:
                    symbols[symbol.name] = symbol
            self._symbols = symbols
        return self._symbols

    def symbol(self, name: str) -> Symbol:
        try:
            return self.symbols[name]
        except KeyError:
            raise UnknownSymbolError(name, str(self.path)) from None

    def read(self, address: int, size: int) -> bytes | None:
        """The initial bytes at ``address`` (a VMA) from the file, or None when no loaded
        section holds all of them (``.bss``, or outside every section)."""
        section = self.section_of(address)
        if section is None or not section.loaded or not section.contains(address, size) or size < 0:
            return None
        with open(self.path, "rb") as handle:
            handle.seek(section.file_offset + address - section.address)
            return handle.read(size)

    def section_of(self, address: int) -> Section | None:
        for section in self.sections.values():
            if section.allocated and section.size and section.contains(address):
                return section
        return None
