"""Where an ECU's flash lies and how it is erased: regions from the A2L's MEMORY_SEGMENTs, sectors from
its PGM SECTORs or from the ECU itself (GET_SECTOR_INFO), and the application-valid key.

A region (BOOT, APPLICATIVE, CALIB ...) is what a user chooses to flash; a sector is what
PROGRAM_CLEAR erases. Without any SECTOR description each region is erased as one sector.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

from workbench.errors import InputError
from workbench.image import AddressRange, MemoryImage, Region, split_by_region

if TYPE_CHECKING:
    from workbench.a2l import A2lDocument, XcpConfig

__all__ = ["DEMO_APP_KEY", "AppKey", "FlashLayout", "FlashRegion", "Sector"]

FLASH_MEMORY_TYPES = frozenset({"FLASH", "EEPROM", "EPROM"})
FLASHABLE_PRG_TYPES = frozenset({"CODE", "DATA", "OFFLINE_DATA"})  # RESERVED (the key's sector) is not a target


@dataclass(frozen=True)
class AppKey:
    """The application-valid key: the boot starts the application only while these bytes are in flash."""

    address: int
    value: bytes

    @property
    def range(self) -> AddressRange:
        return AddressRange(self.address, self.address + len(self.value))

    def __str__(self) -> str:
        return f"{self.value.hex(' ').upper()} at {self.address:X}h"


# The demo ECU's key (docs/demo-ecu.md, boot_key.h APP_VALID_KEY): 0x5AA5C33C little-endian at 0xFE0000,
# in the SHARED sector that boot and application share. Other ECUs name theirs (or none) to the flash.
DEMO_APP_KEY = AppKey(0xFE0000, (0x5AA5C33C).to_bytes(4, "little"))


@dataclass(frozen=True)
class Sector:
    """What one PROGRAM_CLEAR erases; ``clear_sequence``/``program_sequence`` order the work (lowest first)."""

    name: str
    number: int
    range: AddressRange
    clear_sequence: int = 0
    program_sequence: int = 0

    def __str__(self) -> str:
        return f"sector {self.name or self.number} {self.range}"


@dataclass(frozen=True)
class FlashRegion:
    """A flash MEMORY_SEGMENT: ``selectable`` when it holds code or data a user flashes (not RESERVED)."""

    name: str
    start: int
    size: int
    description: str = ""
    selectable: bool = True
    holds_code: bool = False  # PRG_TYPE CODE: the application's code (or the boot loader's)

    @property
    def end(self) -> int:
        return self.start + self.size

    @property
    def range(self) -> AddressRange:
        return AddressRange(self.start, self.end)

    @property
    def is_boot(self) -> bool:
        """The boot loader's region: a failed flash there cannot be repaired over XCP."""
        return "BOOT" in self.name.upper()

    @property
    def as_region(self) -> Region:
        return Region(self.name, self.start, self.size)


@dataclass(frozen=True)
class FlashLayout:
    regions: tuple[FlashRegion, ...]
    sectors: tuple[Sector, ...]  # empty: every region is erased as one sector
    sectors_from: str = "A2L"  # "A2L", "ECU" (GET_SECTOR_INFO) or "" (none known)
    epk: str | None = None
    addr_epk: int | None = None  # the first ADDR_EPK (GET_ID type 5 reads it)
    epk_addresses: tuple[int, ...] = ()  # every ADDR_EPK
    epk_parts: tuple[tuple[int, FlashRegion], ...] = ()  # (ADDR_EPK, its region) of each part with its own EPK

    @classmethod
    def from_a2l(cls, doc: A2lDocument, config: XcpConfig | None = None, module: str | None = None) -> FlashLayout:
        """Regions from the flash MEMORY_SEGMENTs, sectors from IF_DATA XCP PGM SECTORs (if ``config`` has them)."""
        regions = tuple(
            FlashRegion(s.name, s.address, s.size, s.long_identifier, s.prg_type in FLASHABLE_PRG_TYPES,
                        s.prg_type == "CODE")
            for s in doc.memory_segments(module) if s.memory_type in FLASH_MEMORY_TYPES
        )
        pgm = config.pgm if config is not None else None
        sectors = tuple(
            Sector(s.name, s.number, AddressRange(s.address, s.address + s.length), s.clear_sequence,
                   s.program_sequence)
            for s in (pgm.sectors if pgm is not None else ())
        )
        addresses = tuple(epk.address for epk in doc.epk_addresses(module))
        by_name = {r.name: r for r in regions if r.selectable}
        parts = tuple((epk.address, by_name[epk.part]) for epk in doc.epk_parts(module) if epk.part in by_name)
        return cls(regions, sectors, "A2L" if sectors else "", doc.epk(module), addresses[0] if addresses else None,
                   addresses, parts if len({r for _, r in parts}) > 1 else ())

    def with_sectors(self, sectors: tuple[Sector, ...], source: str) -> FlashLayout:
        """The same regions erased in other sectors (the ECU's own, from GET_SECTOR_INFO)."""
        named = {s.range: s.name for s in self.sectors}
        return replace(self, sectors=tuple(replace(s, name=s.name or named.get(s.range, "")) for s in sectors),
                       sectors_from=source)

    def region(self, name: str) -> FlashRegion:
        """:raises InputError: no flash region of that name (the message lists the ones there are)."""
        for region in self.regions:
            if region.name.upper() == name.upper():
                return region
        choices = ", ".join(r.name for r in self.regions if r.selectable) or "none"
        raise InputError(f"the A2L has no flash region {name!r} (MEMORY_SEGMENTs in flash: {choices})")

    def region_at(self, address: int) -> FlashRegion | None:
        return next((r for r in self.regions if r.start <= address < r.end), None)

    def erase_units(self) -> tuple[Sector, ...]:
        """The sectors, or each region as one sector when no sector is known."""
        if self.sectors:
            return self.sectors
        return tuple(Sector(r.name, n, r.range) for n, r in enumerate(self.regions))

    def sectors_touching(self, ranges: list[AddressRange]) -> list[Sector]:
        """The sectors holding a byte of ``ranges``, in clear order."""
        found = {s for s in self.erase_units() for r in ranges if s.range.start < r.end and r.start < s.range.end}
        return sorted(found, key=lambda s: (s.clear_sequence, s.range.start))

    def uncovered(self, image: MemoryImage) -> list[AddressRange]:
        """The parts of ``image`` no sector covers (the ECU cannot erase, so not program, them)."""
        units = [Region(s.name or str(s.number), s.range.start, s.range.size) for s in self.erase_units()]
        return split_by_region(image, units)[1]

    def application_regions(self) -> tuple[FlashRegion, ...]:
        """The regions holding the application's code (CODE, not the boot loader's)."""
        return tuple(r for r in self.regions if r.holds_code and r.selectable and not r.is_boot)

    def sector_of(self, address: int) -> Sector | None:
        return next((s for s in self.erase_units() if s.range.start <= address < s.range.end), None)
