"""ELF files: sections, load addresses and symbols (``.symtab``), and DWARF behind one facade.

``DebugData(path)`` resolves A2L symbol paths (``a.b[2].c``, ``a._3_``) to address, size
and C type from DWARF, or from ``.symtab`` when the ELF has no DWARF; its index is cached.
"""

from workbench.elf.ctypes_model import CMember, CType
from workbench.elf.debugdata import DebugData, ResolvedSymbol
from workbench.elf.symbols import ElfSymbols, Section, Symbol

__all__ = ["CMember", "CType", "DebugData", "ElfSymbols", "ResolvedSymbol", "Section", "Symbol"]
