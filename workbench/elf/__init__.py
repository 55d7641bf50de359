"""ELF files: sections, load addresses and symbols (``.symtab``), and DWARF behind one facade.

``DebugData(path)`` resolves A2L symbol paths (``a.b[2].c``, ``a._3_``) to address, size
and C type from DWARF, or from ``.symtab`` when the ELF has no DWARF; its index is cached.
The names are imported on first use: an update from a cached index loads no DWARF decoder.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from workbench.lazy_exports import lazy_exports

__all__, __getattr__, __dir__ = lazy_exports(__name__, {
    "workbench.elf.ctypes_model": ("CMember", "CType"),
    "workbench.elf.debugdata": ("DebugData", "ResolvedSymbol"),
    "workbench.elf.symbols": ("ElfSymbols", "Section", "Symbol"),
})

if TYPE_CHECKING:  # for type checkers and IDEs: the same names, imported eagerly
    from workbench.elf.ctypes_model import CMember, CType
    from workbench.elf.debugdata import DebugData, ResolvedSymbol
    from workbench.elf.symbols import ElfSymbols, Section, Symbol
