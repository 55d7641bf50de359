"""The simulated ECU's memory: flash regions with sectors, CAL RAM, RAM and small ROMs.

Flash reads 0xFF where erased and is changed only by :meth:`EcuMemory.program` (into
erased bytes of one region) and :meth:`EcuMemory.erase` (whole sectors). RAM areas are
plain bytes; a power loss clears them and keeps the flash. ROM areas (mask-programmed
constants such as the XCP driver's strings) can only be read.
"""

from __future__ import annotations

import bisect
import re
from dataclasses import dataclass
from enum import Enum

from workbench.image import ERASED, AddressRange, MemoryImage, Region

__all__ = ["AccessFault", "Area", "EcuMemory", "MemoryAccessError"]


_PROGRAMMED = re.compile(rb"[^\xff]+")


class AccessFault(Enum):
    """Why a memory access was refused; the XCP slave maps each to its error code."""

    UNMAPPED = "no memory at this address"
    READ_ONLY = "flash is changed only by programming"
    NOT_ERASED = "flash byte not erased (clear the sector before programming)"
    NOT_SECTOR_ALIGNED = "clear range does not start and end on sector boundaries"
    CROSSES_AREA = "access crosses the end of a memory area"


class MemoryAccessError(Exception):
    def __init__(self, fault: AccessFault, address: int, size: int):
        super().__init__(f"0x{address:X}+{size}: {fault.value}")
        self.fault = fault
        self.address = address
        self.size = size


@dataclass
class Area:
    name: str
    start: int
    data: bytearray
    flash: Region | None = None  # set for flash areas
    rom: bool = False

    @property
    def end(self) -> int:
        return self.start + len(self.data)


class EcuMemory:
    """Flash ``regions`` (initially erased), RAM windows ``ram`` (name -> range, initially zero)
    and read-only ``rom`` contents (name -> (address, bytes))."""

    def __init__(
        self,
        regions: list[Region],
        ram: dict[str, AddressRange],
        rom: dict[str, tuple[int, bytes]] | None = None,
    ):
        areas = [Area(r.name, r.start, bytearray([ERASED]) * r.size, r) for r in regions]
        areas += [Area(name, rng.start, bytearray(rng.size)) for name, rng in ram.items()]
        areas += [Area(name, start, bytearray(data), rom=True) for name, (start, data) in (rom or {}).items()]
        areas.sort(key=lambda a: a.start)
        for before, after in zip(areas, areas[1:]):
            if before.end > after.start:
                raise ValueError(f"memory areas {before.name} and {after.name} overlap")
        self._areas = areas
        self._starts = [a.start for a in areas]

    def area_at(self, address: int, size: int = 1) -> Area:
        """The area holding all of ``[address, address + size)``.

        :raises MemoryAccessError: UNMAPPED or CROSSES_AREA.
        """
        index = bisect.bisect_right(self._starts, address) - 1
        if index < 0 or address >= self._areas[index].end or size < 0:
            raise MemoryAccessError(AccessFault.UNMAPPED, address, size)
        area = self._areas[index]
        if address + size > area.end:
            raise MemoryAccessError(AccessFault.CROSSES_AREA, address, size)
        return area

    def read(self, address: int, size: int) -> bytes:
        area = self.area_at(address, size)
        offset = address - area.start
        return bytes(area.data[offset : offset + size])

    def write(self, address: int, data: bytes) -> None:
        """Write RAM (CAL RAM included); flash and ROM refuse with READ_ONLY."""
        area = self.area_at(address, len(data))
        if area.flash is not None or area.rom:
            raise MemoryAccessError(AccessFault.READ_ONLY, address, len(data))
        offset = address - area.start
        area.data[offset : offset + len(data)] = data

    def check_program(self, address: int, size: int) -> Area:
        """Raise what :meth:`program` would raise for ``size`` bytes at ``address``; returns the flash area."""
        area = self.area_at(address, size)
        if area.flash is None:
            raise MemoryAccessError(AccessFault.UNMAPPED, address, size)
        offset = address - area.start
        if area.data[offset : offset + size].count(ERASED) != size:
            raise MemoryAccessError(AccessFault.NOT_ERASED, address, size)
        return area

    def program(self, address: int, data: bytes) -> None:
        """Program flash bytes that are erased; refuses RAM (UNMAPPED) and written bytes (NOT_ERASED)."""
        area = self.check_program(address, len(data))
        offset = address - area.start
        area.data[offset : offset + len(data)] = data

    def erase(self, address: int, size: int) -> list[AddressRange]:
        """Erase the whole sectors ``[address, address + size)`` of one region; returns them."""
        area = self.area_at(address, size)
        if area.flash is None:
            raise MemoryAccessError(AccessFault.UNMAPPED, address, size)
        sectors = [s for s in area.flash.sectors if address <= s.start and s.end <= address + size]
        if not size or sum(s.size for s in sectors) != size:
            raise MemoryAccessError(AccessFault.NOT_SECTOR_ALIGNED, address, size)
        offset = address - area.start
        area.data[offset : offset + size] = bytes([ERASED]) * size
        return sectors

    def load_flash(self, image: MemoryImage) -> None:
        """Put an image into flash as a factory programmer would (each byte must land in a region).

        :raises MemoryAccessError: part of the image lies outside every flash region.
        """
        for start, data in image.segments:
            cursor = start
            while cursor < start + len(data):
                area = self.area_at(cursor)
                if area.flash is None:
                    raise MemoryAccessError(AccessFault.UNMAPPED, cursor, start + len(data) - cursor)
                chunk = data[cursor - start : min(start + len(data), area.end) - start]
                area.data[cursor - area.start : cursor - area.start + len(chunk)] = chunk
                cursor += len(chunk)

    def flash_image(self) -> MemoryImage:
        """The programmed flash content as an image (a programmed 0xFF reads as erased)."""
        image = MemoryImage()
        for area in self._areas:
            if area.flash is not None:
                for run in _PROGRAMMED.finditer(area.data):
                    image.add(area.start + run.start(), run.group())
        return image

    def clear_ram(self) -> None:
        """What a power loss does: every RAM byte is lost (reads 0 after the next power-on)."""
        for area in self._areas:
            if area.flash is None and not area.rom:
                area.data[:] = bytes(len(area.data))

