"""The simulated HDS9's memory map (docs/demo-ecu.md, linker script assets/ecu/flcu.ld).

This is the chip, not the application: flash regions with their sectors, the CAL RAM
window that overlays CAL ROM, ordinary RAM, where the application-valid key lives, and
the boot ROM that holds the XCP driver's strings, and which flash XCP may program.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from functools import cached_property

from workbench.image import AddressRange, Region

__all__ = ["HDS9", "FlashSector", "MemoryMap"]


@dataclass(frozen=True)
class FlashSector:
    """A sector of XCP programming (GET_SECTOR_INFO numbers them in :attr:`MemoryMap.sectors` order)."""

    name: str
    range: AddressRange
    clear_sequence: int  # the order a flash tool clears sectors in
    program_sequence: int  # the order it programs them in
    functional_bit: int  # PROGRAM_CLEAR functional mode: 0x01 calibration, 0x02 code, 0x04 NVRAM


@dataclass(frozen=True)
class MemoryMap:
    flash: tuple[Region, ...]
    sectors: tuple[FlashSector, ...]  # what XCP may clear and program; flash outside them is protected
    cal_ram: AddressRange  # the working page; mirrors CAL ROM byte for byte
    cal_rom_start: int  # where CAL ROM (the reference page) starts in flash
    ram: AddressRange
    app_key_address: int
    app_key: bytes  # the application-valid key as stored in flash
    info_rom_start: int  # read-only strings of the XCP driver (event/sector names, GET_ID texts)

    def region(self, name: str) -> Region:
        return next(r for r in self.flash if r.name == name)

    def with_sector_sizes(self, sizes: dict[str, int]) -> MemoryMap:
        """This chip with the flash of the regions named in ``sizes`` erased in sectors of that many bytes: the
        XCP sector of such a region becomes as many sectors (named after it with a number, in the same clear and
        program order)."""
        flash = tuple(replace(r, sector_size=sizes.get(r.name, r.sector_size)) for r in self.flash)
        sectors = []
        for sector in self.sectors:
            size = sizes.get(self.region_at(sector.range.start).name, sector.range.size)
            sectors += [FlashSector(f"{sector.name[:3]}{n}", AddressRange(start, start + size), sector.clear_sequence,
                                    sector.program_sequence, sector.functional_bit)
                        for n, start in enumerate(range(sector.range.start, sector.range.end, size))]
        return replace(self, flash=flash, sectors=tuple(sectors))

    def region_at(self, address: int) -> Region:
        return next(r for r in self.flash if r.contains(address))

    def rom_address(self, cal_ram_address: int) -> int:
        """The CAL ROM address that mirrors a CAL RAM address."""
        return cal_ram_address - self.cal_ram.start + self.cal_rom_start

    @property
    def ram_windows(self) -> dict[str, AddressRange]:
        return {"CALRAM": self.cal_ram, "RAM": self.ram}

    def protected(self, address: int, size: int) -> bool:
        """True when part of ``[address, address + size)`` is flash that no programmable sector covers."""
        end = address + size
        return any(lo < end and address < hi for lo, hi in self._unprogrammable)

    @cached_property  # asked for every PROGRAM frame
    def _unprogrammable(self) -> list[tuple[int, int]]:
        gaps = []
        for region in self.flash:
            cursor = region.start
            for sector in sorted((s.range for s in self.sectors if region.contains(s.range.start)), key=lambda r: r.start):
                if sector.start > cursor:
                    gaps.append((cursor, sector.start))
                cursor = max(cursor, sector.end)
            if cursor < region.end:
                gaps.append((cursor, region.end))
        return gaps

APP_VALID_KEY = 0x5AA5C33C  # boot_key.h

# One sector per region, as the A2L's PGM block lists them; BOOT is not programmable over XCP.
# A flash tool clears the key (SHARED) first and programs it last.
HDS9 = MemoryMap(
    flash=(
        Region("BOOT", 0x800000, 0x40000),
        Region("APPLICATIVE", 0x840000, 0x780000),
        Region("CALIB", 0xFC0000, 0x20000),
        Region("SHARED", 0xFE0000, 0x4000),
    ),
    sectors=(
        FlashSector("APPLICATIVE", AddressRange(0x840000, 0xFC0000), 1, 0, 0x02),
        FlashSector("CALIB", AddressRange(0xFC0000, 0xFE0000), 2, 1, 0x01),
        FlashSector("SHARED", AddressRange(0xFE0000, 0xFE4000), 0, 2, 0x04),
    ),
    cal_ram=AddressRange(0x40000000, 0x40020000),
    cal_rom_start=0xFC0000,
    ram=AddressRange(0x40020000, 0x40080000),
    app_key_address=0xFE0000,
    app_key=APP_VALID_KEY.to_bytes(4, "little"),
    info_rom_start=0x7FF000,
)
