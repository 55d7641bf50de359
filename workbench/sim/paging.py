"""Calibration page switching of the CAL RAM window, split into one or more XCP segments.

Page 0 is the working page (CAL RAM, writable), page 1 the reference page (CAL ROM in
flash, read-only). Every segment has two active pages, the ECU's (the application's) and
XCP's; addresses stay CAL RAM addresses and are redirected to CAL ROM where page 1 is active.
The demo has one segment, the whole window; a profile may split it (an EPK segment of its own).
"""

from __future__ import annotations

from collections.abc import Sequence

from workbench.image import AddressRange
from workbench.sim.memory import AccessFault, MemoryAccessError
from workbench.sim.memory_map import MemoryMap

__all__ = ["PAGES", "REFERENCE_PAGE", "CalPageSwitch"]

WORKING_PAGE = 0
REFERENCE_PAGE = 1
PAGES = (WORKING_PAGE, REFERENCE_PAGE)


class CalPageSwitch:
    """``segments``: the XCP segments' address ranges by number, inside the CAL RAM window (default: the window)."""

    def __init__(self, memory_map: MemoryMap, segments: Sequence[AddressRange] = ()):
        self.map = memory_map
        self.segments = tuple(segments) or (memory_map.cal_ram,)
        window = memory_map.cal_ram
        if any(not (window.start <= s.start < s.end <= window.end) for s in self.segments):
            raise ValueError(f"calibration segments must lie inside the CAL RAM window {window}")
        self.reset()

    def reset(self) -> None:
        self.ecu_pages = [WORKING_PAGE] * len(self.segments)
        self.xcp_pages = [WORKING_PAGE] * len(self.segments)

    def translate(self, address: int, size: int, pages: Sequence[int]) -> int:
        """The physical address of ``[address, address + size)`` seen through ``pages`` (one per segment,
        :attr:`ecu_pages` or :attr:`xcp_pages`).

        :raises MemoryAccessError: CROSSES_AREA when the range straddles the CAL RAM window's edge, or
            segments that are on different pages.
        """
        window = self.map.cal_ram
        inside = window.start <= address < window.end
        if inside != (window.start <= address + size - 1 < window.end) and size > 0:
            raise MemoryAccessError(AccessFault.CROSSES_AREA, address, size)
        if not inside:
            return address
        end = address + max(size, 1)
        touched = {pages[n] for n, s in enumerate(self.segments) if s.start < end and address < s.end}
        if len(touched) > 1:
            raise MemoryAccessError(AccessFault.CROSSES_AREA, address, size)
        if touched == {REFERENCE_PAGE}:
            return self.map.rom_address(address)
        return address

    def in_window(self, address: int) -> bool:
        return self.map.cal_ram.start <= address < self.map.cal_ram.end
