"""The simulated HDS9's memory map (docs/demo-ecu.md, linker script assets/ecu/flcu.ld).

This is the chip, not the application: flash regions with their sectors, the CAL RAM
window that overlays CAL ROM, ordinary RAM, where the application-valid key lives, and
the boot ROM that holds the XCP driver's strings.
"""

from __future__ import annotations

from dataclasses import dataclass

from workbench.image import AddressRange, Region


@dataclass(frozen=True)
class MemoryMap:
    flash: tuple[Region, ...]
    cal_ram: AddressRange  # the working page; mirrors CAL ROM byte for byte
    cal_rom_start: int  # where CAL ROM (the reference page) starts in flash
    ram: AddressRange
    app_key_address: int
    app_key: bytes  # the application-valid key as stored in flash
    info_rom_start: int  # read-only strings of the XCP driver (event/sector names, GET_ID texts)

    def region(self, name: str) -> Region:
        return next(r for r in self.flash if r.name == name)

    @property
    def cal_rom(self) -> AddressRange:
        return AddressRange(self.cal_rom_start, self.cal_rom_start + self.cal_ram.size)

    def rom_address(self, cal_ram_address: int) -> int:
        """The CAL ROM address that mirrors a CAL RAM address."""
        return cal_ram_address - self.cal_ram.start + self.cal_rom_start

    @property
    def ram_windows(self) -> dict[str, AddressRange]:
        return {"CALRAM": self.cal_ram, "RAM": self.ram}

    @property
    def sectors(self) -> list[tuple[str, AddressRange]]:
        """Every flash sector as ``(region name, range)``, numbered in this order by GET_SECTOR_INFO."""
        return [(region.name, sector) for region in self.flash for sector in region.sectors]


APP_VALID_KEY = 0x5AA5C33C  # boot_key.h

HDS9 = MemoryMap(
    flash=(
        Region("BOOT", 0x800000, 0x40000, sector_size=0x10000),
        Region("APPLICATIVE", 0x840000, 0x780000, sector_size=0x40000),
        Region("CALIB", 0xFC0000, 0x20000, sector_size=0x4000),
        Region("SHARED", 0xFE0000, 0x4000, sector_size=0x4000),
    ),
    cal_ram=AddressRange(0x40000000, 0x40020000),
    cal_rom_start=0xFC0000,
    ram=AddressRange(0x40020000, 0x40080000),
    app_key_address=0xFE0000,
    app_key=APP_VALID_KEY.to_bytes(4, "little"),
    info_rom_start=0x7FF000,
)
