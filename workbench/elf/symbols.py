"""Sections, load segments and the ``.symtab`` of an ELF file, read fast.

pyelftools reads the headers (ELF, program and section headers); the symbol table is
then read straight from the file into one numpy record array, without pyelftools'
object per symbol, so a 50,000-symbol ELF loads in milliseconds. What the headers say
(:meth:`ElfSymbols.facts`) is small and can be cached with an index: an
:class:`ElfSymbols` made :meth:`~ElfSymbols.from_facts` never imports pyelftools (30 ms).
"""

from __future__ import annotations

import struct
from dataclasses import astuple, dataclass
from pathlib import Path
from typing import NamedTuple

import numpy as np

from workbench.errors import InputError, UnknownSymbolError

STT_OBJECT, STT_FUNC = 1, 2
_KINDS = {STT_OBJECT: "object", STT_FUNC: "function"}
_STB_LOCAL = 0
_SHN_UNDEF, _SHN_LORESERVE = 0, 0xFF00
_SYMBOL_FIELDS = {
    32: [("name", "u4"), ("value", "u4"), ("size", "u4"), ("info", "u1"), ("other", "u1"), ("shndx", "u2")],
    64: [("name", "u4"), ("info", "u1"), ("other", "u1"), ("shndx", "u2"), ("value", "u8"), ("size", "u8")],
}


@dataclass(frozen=True)
class Section:
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
        from elftools.common.exceptions import ELFError  # here: see the module docstring
        from elftools.elf.elffile import ELFFile

        self.path = Path(path)
        try:
            with open(self.path, "rb") as handle:
                elf = ELFFile(handle)
                self.little_endian: bool = elf.little_endian
                self.elfclass: int = elf.elfclass
                self.machine: str = elf["e_machine"]
                self.sections: dict[str, Section] = self._read_sections(elf, self.path.stat().st_size)
                self.has_dwarf: bool = elf.has_dwarf_info()
                self._section_names = [section.name for section in elf.iter_sections()]  # by section index
                self._symtab = self._locate_symtab(elf)
        except FileNotFoundError as exc:
            raise InputError(f"{self.path}: no such file") from exc
        except IsADirectoryError as exc:
            raise InputError(f"{self.path}: is a folder, not an ELF file") from exc
        except (ELFError, ValueError, KeyError, IndexError, struct.error, OSError) as exc:
            # pyelftools raises all of these on a damaged header or section table
            raise InputError(f"{self.path}: not a readable ELF file ({exc})") from exc
        self._symbols: dict[str, Symbol] | None = None
        self._symbol_list: list[Symbol] | None = None
        self._names_text: bytes | None = None

    @classmethod
    def from_facts(cls, path: str | Path, facts: dict) -> "ElfSymbols":
        """The ELF described by :meth:`facts` of an earlier read of the same file, without reading it."""
        elf = cls.__new__(cls)
        elf.path = Path(path)
        elf.little_endian, elf.elfclass, elf.machine, elf.has_dwarf = (
            facts["little_endian"], facts["elfclass"], facts["machine"], facts["has_dwarf"])
        elf.sections = {section[0]: Section(*section) for section in facts["sections"]}
        elf._section_names = facts["section_names"]
        elf._symtab = facts["symtab"]
        elf._symbols = elf._symbol_list = elf._names_text = None
        return elf

    def facts(self) -> dict:
        """What the headers say, as plain data for a cache."""
        return {"little_endian": self.little_endian, "elfclass": self.elfclass, "machine": self.machine,
                "has_dwarf": self.has_dwarf, "sections": [astuple(s) for s in self.sections.values()],
                "section_names": self._section_names, "symtab": self._symtab}

    @staticmethod
    def _read_sections(elf, file_size: int) -> dict[str, Section]:
        """Raises ValueError for a section whose bytes lie outside the file (a damaged ELF)."""
        segments = [seg for seg in elf.iter_segments() if seg["p_type"] == "PT_LOAD"]
        sections = {}
        for sec in elf.iter_sections():
            if not sec.name:
                continue
            address, size = sec["sh_addr"], sec["sh_size"]
            if sec["sh_type"] != "SHT_NOBITS" and sec["sh_offset"] + size > file_size:
                raise ValueError(f"section {sec.name} ({size} bytes at offset {sec['sh_offset']}) "
                                 f"lies outside the file of {file_size} bytes")
            load_address = address
            for seg in segments:  # LMA = segment physical address + offset inside the segment
                if seg["p_vaddr"] <= address < seg["p_vaddr"] + seg["p_memsz"] and seg["p_filesz"]:
                    load_address = seg["p_paddr"] + (address - seg["p_vaddr"])
                    break
            sections[sec.name] = Section(
                name=sec.name,
                address=address,
                load_address=load_address,
                size=size,
                loaded=sec["sh_type"] != "SHT_NOBITS",
                allocated=bool(sec["sh_flags"] & 0x2),
                file_offset=sec["sh_offset"],
            )
        return sections

    @staticmethod
    def _locate_symtab(elf) -> tuple[int, int, int, int] | None:
        """(offset, size) of the symbol table and of its string table in the file; None without one."""
        symtab = elf.get_section_by_name(".symtab")
        if symtab is None:
            return None
        strtab = elf.get_section(symtab["sh_link"])
        return symtab["sh_offset"], symtab["sh_size"], strtab["sh_offset"], strtab["sh_size"]

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
