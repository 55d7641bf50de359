"""ELF files: sections, load addresses and symbols (``.symtab``); DWARF lookups build on it."""

from workbench.elf.symbols import ElfSymbols, Section, Symbol

__all__ = ["ElfSymbols", "Section", "Symbol"]
