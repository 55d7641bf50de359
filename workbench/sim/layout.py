"""What the boot code and the XCP slave need to know about the application build (from its ELF).

* the ranges of CAL RAM the application defines (``.cal_ram``): XCP may write only there;
* the initialised data to copy from flash (LMA) to RAM (VMA) at start-up (``.data``);
* the zero-initialised ranges (``.bss``);
* the symbol addresses the Python twin of the application uses.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

from workbench.elf import ElfSymbols
from workbench.image import AddressRange
from workbench.sim.memory_map import MemoryMap

__all__ = ["ApplicationLayout", "InitCopy"]


@dataclass(frozen=True)
class InitCopy:
    """``size`` bytes the boot copies from flash ``load_address`` to RAM ``address``."""

    address: int
    load_address: int
    size: int


@dataclass(frozen=True)
class ApplicationLayout:
    cal_ram: tuple[AddressRange, ...] = ()
    init_copies: tuple[InitCopy, ...] = ()
    zero_ranges: tuple[AddressRange, ...] = ()
    symbols: Mapping[str, int] = field(default_factory=dict)

    def xcp_writable_cal(self, address: int, size: int) -> bool:
        """True when ``[address, address + size)`` lies inside one ``.cal_ram`` range."""
        return any(r.start <= address and address + size <= r.end for r in self.cal_ram)

    @classmethod
    def from_elf(cls, elf: ElfSymbols, memory_map: MemoryMap) -> ApplicationLayout:
        """Sections inside the CAL RAM window become writable calibration ranges; RAM sections
        with bytes in the file and a load address elsewhere become init copies; RAM sections
        without bytes (NOBITS) are zeroed."""
        cal_ram, copies, zeros = [], [], []
        for section in elf.sections.values():
            if not (section.allocated and section.size):
                continue
            span = AddressRange(section.address, section.address + section.size)
            if _inside(span, memory_map.cal_ram):
                cal_ram.append(span)
            elif _inside(span, memory_map.ram):
                if not section.loaded:
                    zeros.append(span)
                elif section.load_address != section.address:
                    copies.append(InitCopy(section.address, section.load_address, section.size))
        symbols = {name: sym.address for name, sym in elf.symbols.items() if sym.kind == "object"}
        return cls(tuple(sorted(cal_ram)), tuple(copies), tuple(sorted(zeros)), symbols)


def _inside(span: AddressRange, window: AddressRange) -> bool:
    return window.start <= span.start and span.end <= window.end
