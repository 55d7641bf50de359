"""Calibration page switching of the CAL RAM segment (XCP segment 0).

Page 0 is the working page (CAL RAM, writable), page 1 the reference page (CAL ROM in
flash, read-only). The ECU (the application) and XCP each have their own active page;
addresses stay CAL RAM addresses and are redirected to CAL ROM while page 1 is active.
"""

from __future__ import annotations

from workbench.sim.memory import AccessFault, MemoryAccessError
from workbench.sim.memory_map import MemoryMap

WORKING_PAGE = 0
REFERENCE_PAGE = 1
PAGES = (WORKING_PAGE, REFERENCE_PAGE)


class CalPageSwitch:
    def __init__(self, memory_map: MemoryMap):
        self.map = memory_map
        self.ecu_page = WORKING_PAGE
        self.xcp_page = WORKING_PAGE

    def reset(self) -> None:
        self.ecu_page = self.xcp_page = WORKING_PAGE

    def translate(self, address: int, size: int, page: int) -> int:
        """The physical address of ``[address, address + size)`` seen through ``page``.

        :raises MemoryAccessError: CROSSES_AREA when the range straddles the CAL RAM window.
        """
        window = self.map.cal_ram
        inside = window.start <= address < window.end
        if inside != (window.start <= address + size - 1 < window.end) and size > 0:
            raise MemoryAccessError(AccessFault.CROSSES_AREA, address, size)
        if inside and page == REFERENCE_PAGE:
            return self.map.rom_address(address)
        return address

    def in_window(self, address: int) -> bool:
        return self.map.cal_ram.start <= address < self.map.cal_ram.end
